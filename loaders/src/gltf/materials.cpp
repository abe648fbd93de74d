// The glTF reader's materials, textures and samplers (see materials.h).
#include "gltf/materials.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>

#include <glm/vec2.hpp>

namespace softpbr::pbr::gltf {

raster::Sampler Materials::sampler(int index, const std::string& referrer) {
  raster::Sampler s;
  s.max_anisotropy = kAnisotropy;
  if (index < 0) return s;  // glTF: repeat, filters "auto" → trilinear
  if (static_cast<std::size_t>(index) >= m_.samplers.size())
    fail(referrer, "sampler " + std::to_string(index) + " does not exist");
  const tg::Sampler& g = m_.samplers[static_cast<std::size_t>(index)];
  const std::string pointer = "/samplers/" + std::to_string(index);
  auto wrap = [&](int w, const char* name) {
    switch (w) {
      case TINYGLTF_TEXTURE_WRAP_REPEAT: return raster::Wrap::Repeat;
      case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return raster::Wrap::ClampToEdge;
      case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return raster::Wrap::MirroredRepeat;
      default: fail(pointer + "/" + name, "unknown wrap mode " + std::to_string(w));
    }
  };
  s.wrap_u = wrap(g.wrapS, "wrapS");
  s.wrap_v = wrap(g.wrapT, "wrapT");
  switch (g.magFilter) {
    case -1:
    case TINYGLTF_TEXTURE_FILTER_LINEAR: s.mag_filter = raster::Filter::Linear; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST: s.mag_filter = raster::Filter::Nearest; break;
    default: fail(pointer + "/magFilter", "unknown filter " + std::to_string(g.magFilter));
  }
  using F = raster::Filter;
  using M = raster::MipFilter;
  switch (g.minFilter) {
    case -1:
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR: s.min_filter = F::Linear, s.mip_filter = M::Linear; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST: s.min_filter = F::Nearest, s.mip_filter = M::None; break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR: s.min_filter = F::Linear, s.mip_filter = M::None; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST: s.min_filter = F::Nearest, s.mip_filter = M::Nearest; break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST: s.min_filter = F::Linear, s.mip_filter = M::Nearest; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR: s.min_filter = F::Nearest, s.mip_filter = M::Linear; break;
    default: fail(pointer + "/minFilter", "unknown filter " + std::to_string(g.minFilter));
  }
  if (s.mip_filter == M::None) s.max_anisotropy = 1;
  return s;
}

// Fills `slot` from a textureInfo: the texture's image (queued for decoding), sampler,
// UV set and KHR_texture_transform.
void Materials::texture_slot(TextureSlot& slot, int texture, int tex_coord, const tg::ExtensionMap& extensions,
                             raster::ColorSpace space, const std::string& pointer) {
  if (texture < 0) return;
  if (static_cast<std::size_t>(texture) >= m_.textures.size())
    fail(pointer + "/index", "texture " + std::to_string(texture) + " does not exist");
  const tg::Texture& t = m_.textures[static_cast<std::size_t>(texture)];
  const std::string tp = "/textures/" + std::to_string(texture);
  if (t.source < 0) {
    warn(tp + ": has no image (no source, nor one of KHR_texture_basisu, EXT_texture_webp or EXT_texture_avif); "
              "the slot is left empty");
    return;
  }
  if (static_cast<std::size_t>(t.source) >= m_.images.size())
    fail(tp + "/source", "image " + std::to_string(t.source) + " does not exist");
  slot.sampler = sampler(t.sampler, tp + "/sampler");
  int uv_set = tex_coord;
  if (auto it = extensions.find("KHR_texture_transform"); it != extensions.end()) {
    const tg::Value& x = it->second;
    const std::string xp = pointer + "/extensions/KHR_texture_transform";
    auto number = [&](const tg::Value& v, const std::string& where) {
      if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) fail(where, "expected a finite number");
      return static_cast<float>(v.GetNumberAsDouble());
    };
    auto vec2 = [&](const char* key, glm::vec2 fallback) {
      if (!x.Has(key)) return fallback;
      const tg::Value& v = x.Get(key);
      if (!v.IsArray() || v.ArrayLen() != 2) fail(xp + "/" + key, "expected two numbers");
      return glm::vec2(number(v.Get(0), xp + "/" + key + "/0"), number(v.Get(1), xp + "/" + key + "/1"));
    };
    slot.transform.offset = vec2("offset", {0.0f, 0.0f});
    slot.transform.scale = vec2("scale", {1.0f, 1.0f});
    if (x.Has("rotation")) slot.transform.rotation = number(x.Get("rotation"), xp + "/rotation");
    if (x.Has("texCoord")) uv_set = x.Get("texCoord").GetNumberAsInt();
  }
  if (uv_set != 0 && uv_set != 1) {
    warn(pointer + ": TEXCOORD_" + std::to_string(uv_set) + " is not supported; the slot is left empty");
    return;
  }
  slot.uv_set = uv_set;
  // The texture itself is made once per image and colour space, after every material is
  // known, so that all images decode in parallel.
  pending_.push_back({&slot, t.source, space});
}

const Material& Materials::material(int index, const std::string& referrer) {
  if (auto it = materials_.find(index); it != materials_.end()) return *it->second;
  if (index < 0) {
    // The default material (glTF 2.0, §3.9.6): metallic 1, roughness 1, white.
    auto m = std::make_unique<Material>();
    m->base_color = {1.0f, 1.0f, 1.0f};
    m->metallic = 1.0f;
    m->roughness = 1.0f;
    return *(materials_[index] = std::move(m));
  }
  if (static_cast<std::size_t>(index) >= m_.materials.size())
    fail(referrer, "material " + std::to_string(index) + " does not exist");
  const tg::Material& g = m_.materials[static_cast<std::size_t>(index)];
  const std::string pointer = "/materials/" + std::to_string(index);
  auto unit = [&](double x, const std::string& where) {
    if (!std::isfinite(x)) fail(where, "is not finite");
    return static_cast<float>(std::clamp(x, 0.0, 1.0));
  };
  auto m = std::make_unique<Material>();
  const auto& pbr = g.pbrMetallicRoughness;
  const std::string pp = pointer + "/pbrMetallicRoughness";
  if (pbr.baseColorFactor.size() != 4) fail(pp + "/baseColorFactor", "must have 4 numbers");
  m->base_color = {unit(pbr.baseColorFactor[0], pp + "/baseColorFactor/0"), unit(pbr.baseColorFactor[1], pp + "/baseColorFactor/1"),
                   unit(pbr.baseColorFactor[2], pp + "/baseColorFactor/2")};
  m->alpha = unit(pbr.baseColorFactor[3], pp + "/baseColorFactor/3");
  m->metallic = unit(pbr.metallicFactor, pp + "/metallicFactor");
  m->roughness = unit(pbr.roughnessFactor, pp + "/roughnessFactor");
  if (g.emissiveFactor.size() != 3) fail(pointer + "/emissiveFactor", "must have 3 numbers");
  float strength = 1.0f;
  if (auto it = g.extensions.find("KHR_materials_emissive_strength"); it != g.extensions.end() &&
                                                                    it->second.Has("emissiveStrength")) {
    const double s = it->second.Get("emissiveStrength").GetNumberAsDouble();
    if (!std::isfinite(s) || s < 0.0)
      fail(pointer + "/extensions/KHR_materials_emissive_strength/emissiveStrength", "must be a finite number ≥ 0");
    strength = static_cast<float>(s);
  }
  m->emissive = glm::vec3(unit(g.emissiveFactor[0], pointer + "/emissiveFactor/0"),
                          unit(g.emissiveFactor[1], pointer + "/emissiveFactor/1"),
                          unit(g.emissiveFactor[2], pointer + "/emissiveFactor/2")) *
                strength;
  if (g.alphaMode == "OPAQUE" || g.alphaMode.empty()) m->alpha_mode = AlphaMode::Opaque;
  else if (g.alphaMode == "MASK") m->alpha_mode = AlphaMode::Mask;
  else if (g.alphaMode == "BLEND") m->alpha_mode = AlphaMode::Blend;
  else fail(pointer + "/alphaMode", "must be OPAQUE, MASK or BLEND, got " + g.alphaMode);
  if (!std::isfinite(g.alphaCutoff) || g.alphaCutoff < 0.0) fail(pointer + "/alphaCutoff", "must be a number ≥ 0");
  m->alpha_cutoff = static_cast<float>(std::min(g.alphaCutoff, 1.0));
  m->double_sided = g.doubleSided;
  m->unlit = g.extensions.count("KHR_materials_unlit") != 0;
  if (!std::isfinite(g.normalTexture.scale)) fail(pointer + "/normalTexture/scale", "is not finite");
  m->normal_scale = static_cast<float>(g.normalTexture.scale);
  m->occlusion_strength = unit(g.occlusionTexture.strength, pointer + "/occlusionTexture/strength");
  using CS = raster::ColorSpace;
  // KHR_materials_pbrSpecularGlossiness replaces the metal/roughness factors and textures
  // (layers() converts it): their textures are then not read.
  if (g.extensions.count(kSpecularGlossiness) == 0) {
    texture_slot(m->base_color_texture, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                 pbr.baseColorTexture.extensions, CS::Srgb, pp + "/baseColorTexture");
    texture_slot(m->metallic_roughness_texture, pbr.metallicRoughnessTexture.index,
                 pbr.metallicRoughnessTexture.texCoord, pbr.metallicRoughnessTexture.extensions, CS::Linear,
                 pp + "/metallicRoughnessTexture");
  }
  texture_slot(m->normal_texture, g.normalTexture.index, g.normalTexture.texCoord, g.normalTexture.extensions,
               CS::Linear, pointer + "/normalTexture");
  texture_slot(m->occlusion_texture, g.occlusionTexture.index, g.occlusionTexture.texCoord,
               g.occlusionTexture.extensions, CS::Linear, pointer + "/occlusionTexture");
  texture_slot(m->emissive_texture, g.emissiveTexture.index, g.emissiveTexture.texCoord, g.emissiveTexture.extensions,
               CS::Srgb, pointer + "/emissiveTexture");
  layers(*m, g, pointer);
  return *(materials_[index] = std::move(m));
}

void Materials::make_textures(Resources& resources) {
  std::map<std::pair<int, raster::ColorSpace>, std::size_t> job_of;
  std::vector<std::pair<int, raster::ColorSpace>> jobs;
  for (const Pending& p : pending_) {
    const auto key = std::make_pair(p.image, p.space);
    if (job_of.emplace(key, jobs.size()).second) jobs.push_back(key);
  }
  const std::vector<std::shared_ptr<const raster::Texture>> textures = resources.textures(jobs);
  std::map<std::pair<int, float>, std::shared_ptr<const raster::Texture>> roughness;
  for (const Pending& p : pending_) {
    const std::shared_ptr<const raster::Texture>& t = textures[job_of.at({p.image, p.space})];
    if (p.glossiness < 0.0f || t == nullptr) {
      p.slot->texture = t;
      continue;
    }
    std::shared_ptr<const raster::Texture>& r = roughness[{p.image, p.glossiness}];
    if (r == nullptr) r = roughness_from_glossiness(*t, p.glossiness);
    p.slot->texture = r;
  }
}

// Deterministic: a float product of two exact values rounded once, then integers. The
// metal/roughness slot reads G × roughness (factor 1) and B × metallic (factor 0).
std::shared_ptr<const raster::Texture> Materials::roughness_from_glossiness(const raster::Texture& image,
                                                                           float glossiness) {
  if (image.is_float()) throw LoadError("a specular-glossiness texture must be 8-bit");
  const raster::Texture::Level& base = image.level(0);
  const std::size_t n = static_cast<std::size_t>(base.width) * static_cast<std::size_t>(base.height);
  const std::span<const std::uint8_t> in = image.texels8().subspan(base.offset * 4, n * 4);
  image::Image8 out;
  out.width = base.width;
  out.height = base.height;
  out.rgba.resize(n * 4);
  for (std::size_t i = 0; i < n; ++i) {
    const float g = glossiness * static_cast<float>(in[i * 4 + 3]);  // in [0, 255]
    const int rounded = static_cast<int>(g + 0.5f);
    out.rgba[i * 4 + 0] = 0;
    out.rgba[i * 4 + 1] = static_cast<std::uint8_t>(255 - rounded);
    out.rgba[i * 4 + 2] = 0;
    out.rgba[i * 4 + 3] = 255;
  }
  return std::make_shared<const raster::Texture>(std::move(out), raster::ColorSpace::Linear);
}

}  // namespace softpbr::pbr::gltf
