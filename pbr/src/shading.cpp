// Material validation for shading (see shading.h).
#include "softpbr/pbr/shading.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "softpbr/dmath/dmath.h"
#include "softpbr/pbr/textured_shading.h"

namespace softpbr::pbr {

namespace {
void require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("material ") + field + ": " + what);
}
bool in01(float x) { return x >= 0.0f && x <= 1.0f; }  // false for NaN
bool color_ok(const glm::vec3& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && c.r >= 0 && c.g >= 0 && c.b >= 0;
}
}  // namespace

ShadingMaterial prepare_material(const Material& m) {
  require(color_ok(m.base_color), "base_color", "must be finite and non-negative");
  require(color_ok(m.emissive), "emissive", "must be finite and non-negative");
  require(in01(m.metallic), "metallic", "must be a number in [0, 1]");
  require(in01(m.roughness), "roughness", "must be a number in [0, 1]");
  require(in01(m.ao), "ao", "must be a number in [0, 1]");
  ShadingMaterial s;
  s.albedo = m.base_color;
  s.f0 = f0_of(m.base_color, m.metallic);
  s.metallic = m.metallic;
  s.roughness = std::max(m.roughness, kMinRoughness);
  s.alpha = s.roughness * s.roughness;
  s.k = k_direct(s.roughness);
  s.ao = m.ao;
  s.emissive = m.emissive;
  return s;
}

namespace {
PreparedSlot prepare_slot(const TextureSlot& slot, const std::string& name) {
  PreparedSlot p;
  if (!slot) return p;
  const std::string field = name + "_texture";
  try {
    raster::validate(slot.sampler);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("material " + field + ": " + e.what());
  }
  require(slot.uv_set == 0 || slot.uv_set == 1, field.c_str(), "uv_set must be 0 or 1");
  const UvTransform& t = slot.transform;
  require(std::isfinite(t.offset.x) && std::isfinite(t.offset.y) && std::isfinite(t.rotation) &&
              std::isfinite(t.scale.x) && std::isfinite(t.scale.y),
          field.c_str(), "the UV transform must be finite");
  p.texture = slot.texture.get();
  p.bound = raster::BoundTexture(*slot.texture, slot.sampler);
  p.uv_set = slot.uv_set;
  p.transformed = !(t.offset == glm::vec2(0.0f) && t.rotation == 0.0f && t.scale == glm::vec2(1.0f));
  if (p.transformed) {
    // KHR_texture_transform: uv' = T(offset) · R(rotation) · S(scale) · uv, with
    // R = [cos −sin; sin cos] (its GLSL mat3, column-major). dmath: the same bits everywhere.
    const double c = dmath::cos(t.rotation), sn = dmath::sin(t.rotation);
    p.a = static_cast<float>(c * t.scale.x);
    p.b = static_cast<float>(-sn * t.scale.y);
    p.c = t.offset.x;
    p.d = static_cast<float>(sn * t.scale.x);
    p.e = static_cast<float>(c * t.scale.y);
    p.f = t.offset.y;
  }
  return p;
}
}  // namespace

TexturedMaterial prepare_textured_material(const Material& m) {
  TexturedMaterial t;
  t.base = prepare_material(m);
  t.roughness_factor = m.roughness;
  require(in01(m.alpha), "alpha", "must be a number in [0, 1]");
  require(m.alpha_mode == AlphaMode::Opaque || m.alpha_mode == AlphaMode::Mask || m.alpha_mode == AlphaMode::Blend,
          "alpha_mode", "must be opaque, mask or blend");
  require(in01(m.alpha_cutoff), "alpha_cutoff", "must be a number in [0, 1]");
  require(std::isfinite(m.normal_scale), "normal_scale", "must be finite");
  require(in01(m.occlusion_strength), "occlusion_strength", "must be a number in [0, 1]");
  t.alpha = m.alpha;
  t.alpha_mode = m.alpha_mode;
  t.alpha_cutoff = m.alpha_cutoff;
  t.double_sided = m.double_sided;
  t.unlit = m.unlit;
  t.normal_scale = m.normal_scale;
  t.occlusion_strength = m.occlusion_strength;
  t.base_color = prepare_slot(m.base_color_texture, "base_color");
  t.metallic_roughness = prepare_slot(m.metallic_roughness_texture, "metallic_roughness");
  t.normal = prepare_slot(m.normal_texture, "normal");
  t.occlusion = prepare_slot(m.occlusion_texture, "occlusion");
  t.emissive = prepare_slot(m.emissive_texture, "emissive");
  for (const TextureSlot* s : {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
                               &m.occlusion_texture, &m.emissive_texture})
    if (s->texture) t.keep.push_back(s->texture);
  t.layered = m.layered() && !m.unlit;
  if (t.layered) t.layers = prepare_layers(m, t.keep);
  return t;
}

PreparedLayers prepare_layers(const Material& m, std::vector<std::shared_ptr<const raster::Texture>>& keep) {
  require(m.ior == 0.0f || m.ior >= 1.0f, "ior", "must be 0 or a number ≥ 1");  // NaN fails, +∞ passes
  require(in01(m.specular.factor), "specular.factor", "must be a number in [0, 1]");
  require(color_ok(m.specular.color), "specular.color", "must be finite and non-negative");
  require(in01(m.clearcoat.factor), "clearcoat.factor", "must be a number in [0, 1]");
  require(in01(m.clearcoat.roughness), "clearcoat.roughness", "must be a number in [0, 1]");
  require(std::isfinite(m.clearcoat.normal_scale), "clearcoat.normal_scale", "must be finite");
  require(color_ok(m.sheen.color), "sheen.color", "must be finite and non-negative");
  require(in01(m.sheen.roughness), "sheen.roughness", "must be a number in [0, 1]");
  require(in01(m.anisotropy.strength), "anisotropy.strength", "must be a number in [0, 1]");
  require(std::isfinite(m.anisotropy.rotation), "anisotropy.rotation", "must be finite");
  require(in01(m.iridescence.factor), "iridescence.factor", "must be a number in [0, 1]");
  require(m.iridescence.ior >= 1.0f && std::isfinite(m.iridescence.ior), "iridescence.ior", "must be a finite number ≥ 1");
  require(m.iridescence.thickness_min >= 0.0f && std::isfinite(m.iridescence.thickness_min), "iridescence.thickness_min",
          "must be a finite number ≥ 0");
  require(m.iridescence.thickness_max >= 0.0f && std::isfinite(m.iridescence.thickness_max), "iridescence.thickness_max",
          "must be a finite number ≥ 0");
  require(in01(m.transmission.factor), "transmission.factor", "must be a number in [0, 1]");
  require(m.volume.thickness >= 0.0f && std::isfinite(m.volume.thickness), "volume.thickness",
          "must be a finite number ≥ 0");
  require(m.volume.attenuation_distance > 0.0f, "volume.attenuation_distance", "must be a number > 0 (or +∞)");
  require(in01(m.volume.attenuation_color.r) && in01(m.volume.attenuation_color.g) &&
              in01(m.volume.attenuation_color.b),
          "volume.attenuation_color", "must be in [0, 1]");
  require(m.dispersion >= 0.0f && std::isfinite(m.dispersion), "dispersion", "must be a finite number ≥ 0");
  PreparedLayers l;
  l.f0_ior = f0_from_ior(m.ior);
  l.specular = m.specular.factor;
  l.specular_color = m.specular.color;
  l.specular_slot = prepare_slot(m.specular.texture, "specular");
  l.specular_color_slot = prepare_slot(m.specular.color_texture, "specular_color");
  l.coat = m.clearcoat.factor > 0.0f;
  l.coat_factor = m.clearcoat.factor;
  l.coat_roughness = m.clearcoat.roughness;
  l.coat_normal_scale = m.clearcoat.normal_scale;
  l.sheen = m.sheen.color != glm::vec3(0.0f);
  l.sheen_color = m.sheen.color;
  l.sheen_roughness = m.sheen.roughness;
  const auto keep_slot = [&](const TextureSlot& slot) {
    if (slot.texture) keep.push_back(slot.texture);
  };
  keep_slot(m.specular.texture);
  keep_slot(m.specular.color_texture);
  if (l.coat) {
    l.coat_slot = prepare_slot(m.clearcoat.texture, "clearcoat");
    l.coat_roughness_slot = prepare_slot(m.clearcoat.roughness_texture, "clearcoat_roughness");
    l.coat_normal = prepare_slot(m.clearcoat.normal_texture, "clearcoat_normal");
    keep_slot(m.clearcoat.texture);
    keep_slot(m.clearcoat.roughness_texture);
    keep_slot(m.clearcoat.normal_texture);
  }
  l.anisotropy = m.anisotropy.strength > 0.0f;
  if (l.anisotropy) {
    l.anisotropy_strength = m.anisotropy.strength;
    l.anisotropy_cos = static_cast<float>(dmath::cos(m.anisotropy.rotation));
    l.anisotropy_sin = static_cast<float>(dmath::sin(m.anisotropy.rotation));
    l.anisotropy_slot = prepare_slot(m.anisotropy.texture, "anisotropy");
    keep_slot(m.anisotropy.texture);
  }
  l.film = m.iridescence.factor > 0.0f;
  if (l.film) {
    l.film_factor = m.iridescence.factor;
    l.film_ior = m.iridescence.ior;
    l.film_thickness_min = m.iridescence.thickness_min;
    l.film_thickness_max = m.iridescence.thickness_max;
    l.film_slot = prepare_slot(m.iridescence.texture, "iridescence");
    l.film_thickness_slot = prepare_slot(m.iridescence.thickness_texture, "iridescence_thickness");
    keep_slot(m.iridescence.texture);
    keep_slot(m.iridescence.thickness_texture);
  }
  l.transmission = m.transmissive();
  if (l.transmission) {
    l.transmission_factor = m.transmission.factor;
    l.thickness = m.volume.thickness;
    l.transmission_slot = prepare_slot(m.transmission.texture, "transmission");
    l.thickness_slot = prepare_slot(m.volume.thickness_texture, "volume_thickness");
    keep_slot(m.transmission.texture);
    keep_slot(m.volume.thickness_texture);
    // refract()'s η = 1/ior (an ior of 0 stands for +∞: η = 0, the ray along −n), and the
    // Sample Viewer's applyIorToRoughness: LOD × clamp(2 ior − 2, 0, 1).
    const auto eta_of = [](double ior) { return ior == 0.0 ? 0.0f : static_cast<float>(1.0 / ior); };
    const auto lod_scale_of = [](double ior) {
      return ior == 0.0 ? 1.0f : static_cast<float>(std::clamp(2.0 * ior - 2.0, 0.0, 1.0));
    };
    l.eta = eta_of(m.ior);
    l.lod_scale = lod_scale_of(m.ior);
    // KHR_materials_dispersion (with a volume: a thin wall does not refract): red and blue
    // at ior ∓ (ior − 1) · 0.025 · dispersion (the Sample Viewer's), green at ior. An ior of
    // 0 (+∞) does not disperse.
    l.dispersed = m.dispersion > 0.0f && m.volume.thickness > 0.0f && m.ior != 0.0f && std::isfinite(m.ior);
    if (l.dispersed) {
      const double ior = m.ior, half_spread = (ior - 1.0) * 0.025 * static_cast<double>(m.dispersion);
      const double iors[3] = {std::max(1.0, ior - half_spread), ior, ior + half_spread};
      for (int c = 0; c < 3; ++c) {
        l.eta_rgb[c] = eta_of(iors[c]);
        l.lod_scale_rgb[c] = lod_scale_of(iors[c]);
      }
    }
    // Beer–Lambert: colour^(d / distance) = exp(−σ d), σ = −ln(colour) / distance (dmath,
    // in double, rounded once), capped so that a black colour keeps σ · 0 = 0.
    l.attenuated = std::isfinite(m.volume.attenuation_distance) && m.volume.attenuation_color != glm::vec3(1.0f);
    if (l.attenuated) {
      for (int c = 0; c < 3; ++c) {
        const double colour = m.volume.attenuation_color[c];
        const double sigma = colour <= 0.0 ? static_cast<double>(kMaxSigma)
                                            : -dmath::log(colour) / static_cast<double>(m.volume.attenuation_distance);
        l.sigma[c] = static_cast<float>(std::min(sigma, static_cast<double>(kMaxSigma)));
      }
    }
  }
  if (l.sheen) {
    l.sheen_color_slot = prepare_slot(m.sheen.color_texture, "sheen_color");
    l.sheen_roughness_slot = prepare_slot(m.sheen.roughness_texture, "sheen_roughness");
    keep_slot(m.sheen.color_texture);
    keep_slot(m.sheen.roughness_texture);
  }
  return l;
}

TransmissionUniforms transmission_uniforms(const PreparedLayers& layers, const TransmissionSource* source,
                                           const glm::mat4& view_projection, const glm::mat4& model) {
  TransmissionUniforms t;
  t.source = source;
  t.view_projection = view_projection;
  for (int c = 0; c < 3; ++c) {
    const glm::vec3 column(model[c]);
    t.scale[c] = std::sqrt(column.x * column.x + column.y * column.y + column.z * column.z);
  }
  t.eta = layers.eta;
  t.lod_scale = layers.lod_scale;
  t.attenuated = layers.attenuated;
  t.sigma = layers.sigma;
  t.dispersed = layers.dispersed;
  t.eta_rgb = layers.eta_rgb;
  t.lod_scale_rgb = layers.lod_scale_rgb;
  return t;
}

TexturedStreams textured_streams(const TexturedMaterial& m, bool vertex_colors) {
  if (m.layered) return TexturedStreams::Layered;
  if (vertex_colors || m.normal.texture != nullptr) return TexturedStreams::All;
  for (const PreparedSlot* s : {&m.base_color, &m.metallic_roughness, &m.occlusion, &m.emissive})
    if (s->texture != nullptr && s->uv_set != 0) return TexturedStreams::All;
  return TexturedStreams::Uv0;
}

void check_textured_streams(const Mesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  auto check = [&](std::size_t size, const char* name) {
    if (size != 0 && size != n)
      throw std::invalid_argument(std::string("mesh ") + name + ": " + std::to_string(size) + " entries for " +
                                  std::to_string(n) + " vertices");
  };
  check(mesh.tangents.size(), "tangents");
  check(mesh.uv1.size(), "uv1");
  check(mesh.colors.size(), "colors");
}

std::vector<TexturedVertex> textured_vertices(const Mesh& mesh) {
  check_textured_streams(mesh);
  const std::size_t n = mesh.vertices.size();
  std::vector<TexturedVertex> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const MeshVertex& v = mesh.vertices[i];
    out[i] = {v.position,
              v.normal,
              v.uv,
              mesh.uv1.empty() ? v.uv : mesh.uv1[i],
              mesh.tangents.empty() ? glm::vec4(1.0f, 0.0f, 0.0f, 1.0f) : mesh.tangents[i],
              mesh.colors.empty() ? glm::vec4(1.0f) : mesh.colors[i]};
  }
  return out;
}

}  // namespace softpbr::pbr
