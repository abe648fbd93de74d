// softpbr/pbr/textured_shading.h — the PBR shader with glTF's textured metal/roughness
// material: base colour, metallic-roughness, normal, occlusion and emissive maps, vertex
// colours, a second UV set, alpha modes and double-sided surfaces.
//
// render() uses it for objects whose material has a texture, an alpha mode other than
// opaque or double_sided, or whose mesh has vertex colours; every other object keeps
// PbrShader, so an untextured material costs what it always did. Inside the shader an
// empty slot is skipped by a branch on a uniform (once per packet of pixels, the same way
// for every lane), never per pixel. The shader comes in two forms, chosen per draw the same
// way: TexturedPbrShader carries every stream to the pixels (18 varyings: both UV sets,
// the tangent, the vertex colour), TexturedUv0PbrShader only UV set 0 (8 varyings) for the
// common case (no normal map, no second UV set, no vertex colours), with the same bits.
//
// Per pixel, with the factors of the material (glTF 2.0, §3.9):
//   base   = base_color × vertex colour × texture.rgb     alpha = alpha × colour.a × texture.a
//   rough  = roughness × texture.g,  metal = metallic × texture.b,  rough ≥ kMinRoughness
//   ao     = ao × (1 + occlusion_strength · (texture.r − 1))      (ambient term only)
//   emit   = emissive × texture.rgb
//   n      = normalize(T·x + B·y + N·z), (x, y, z) = (2·texture − 1) × (scale, scale, 1),
//            T the interpolated tangent made orthogonal to N, B = w · (N × T)
// Back faces of a double-sided material flip N, T and B. An unlit material
// (KHR_materials_unlit) outputs base and alpha without lighting. Output: opaque → alpha 1; mask →
// alpha 1 where alpha ≥ alpha_cutoff, else 0 (the draw's alpha test discards it), or with
// alpha_to_coverage (render() sets it on multisampled targets), where alpha varies across
// the pixel, (alpha − cutoff) / fwidth(alpha) + 0.5, which the draw's alpha to coverage
// turns into samples; blend →
// premultiplied (rgb · alpha, alpha).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "softpbr/pbr/layered_shading.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/raster/texture.h"

namespace softpbr::pbr {

// What the textured shader reads per vertex: MeshVertex and the optional streams of Mesh
// (absent streams read as tangent (1, 0, 0, 1), uv1 = uv, colour (1, 1, 1, 1)).
struct TexturedVertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
  glm::vec2 uv1;
  glm::vec4 tangent;
  glm::vec4 color;
};

// Throws std::invalid_argument when a non-empty optional stream of `mesh` (tangents, uv1,
// colours) has a length other than the vertex count.
void check_textured_streams(const Mesh& mesh);

// The vertices of `mesh` for TexturedPbrShader (check_textured_streams first).
std::vector<TexturedVertex> textured_vertices(const Mesh& mesh);

// A texture slot ready for lookups: uv' = (a·u + b·v + c, d·u + e·v + f).
struct PreparedSlot {
  const raster::Texture* texture = nullptr;
  raster::BoundTexture bound;  // the texture and the slot's sampler, bound once per draw
  int uv_set = 0;
  bool transformed = false;  // false: the identity (skipped)
  float a = 1, b = 0, c = 0, d = 0, e = 1, f = 0;
};

// The material extensions' layers ready for lookups (Material::layered(); each factor
// multiplies its slot's channel, as Material's comments say).
struct PreparedLayers {
  float f0_ior = kDielectricF0;  // f0_from_ior(ior)
  float specular = 1.0f;
  glm::vec3 specular_color{1.0f};
  PreparedSlot specular_slot, specular_color_slot;
  bool coat = false;  // factor > 0
  float coat_factor = 0.0f, coat_roughness = 0.0f, coat_normal_scale = 1.0f;
  PreparedSlot coat_slot, coat_roughness_slot, coat_normal;
  bool sheen = false;  // colour not black
  glm::vec3 sheen_color{0.0f};
  float sheen_roughness = 0.0f;
  PreparedSlot sheen_color_slot, sheen_roughness_slot;
  bool anisotropy = false;  // strength > 0
  float anisotropy_strength = 0.0f;
  float anisotropy_cos = 1.0f, anisotropy_sin = 0.0f;  // of the rotation (dmath)
  PreparedSlot anisotropy_slot;
  bool film = false;  // iridescence factor > 0
  float film_factor = 0.0f, film_ior = 1.3f, film_thickness_min = 100.0f, film_thickness_max = 400.0f;
  PreparedSlot film_slot, film_thickness_slot;
  bool transmission = false;  // transmission factor > 0 (Material::transmissive())
  float transmission_factor = 0.0f, thickness = 0.0f;
  PreparedSlot transmission_slot, thickness_slot;
  float eta = 1.0f / 1.5f, lod_scale = 0.0f;  // TransmissionUniforms' (layered_shading.h)
  bool attenuated = false;
  glm::vec3 sigma{0.0f};
  bool dispersed = false;  // dispersion > 0
  glm::vec3 eta_rgb{1.0f / 1.5f}, lod_scale_rgb{0.0f};
};

struct TexturedMaterial {
  ShadingMaterial base;  // the factors, validated (as PbrShader's)
  float roughness_factor;  // unclamped: the texture multiplies it before the clamp
  float alpha;
  AlphaMode alpha_mode;
  float alpha_cutoff;
  bool double_sided;
  bool unlit;
  float normal_scale;
  float occlusion_strength;
  PreparedSlot base_color, metallic_roughness, normal, occlusion, emissive;
  bool layered = false;  // Material::layered(): drawn by LayeredPbrShader
  PreparedLayers layers;
  // Keeps the textures alive while a frame holds the shader.
  std::vector<std::shared_ptr<const raster::Texture>> keep;
};

// Validates the factors (as prepare_material), the slots' samplers and UV sets and the
// texture transform; computes the transform's matrix with dmath (the same bits everywhere).
// Throws std::invalid_argument naming the field.
TexturedMaterial prepare_textured_material(const Material& m);
// The layers of a layered material (prepare_textured_material calls it): validates the
// extensions' factors and slots; adds the slots' textures to `keep`.
PreparedLayers prepare_layers(const Material& m, std::vector<std::shared_ptr<const raster::Texture>>& keep);

// The uniforms of a draw of a transmissive material (layers.transmission) with model matrix
// `model`: the frame's `source` and view-projection, the model's scale (the lengths of its
// columns), the material's refraction and attenuation.
TransmissionUniforms transmission_uniforms(const PreparedLayers& layers, const TransmissionSource* source,
                                           const glm::mat4& view_projection, const glm::mat4& model);

// Which vertex streams the textured shader carries to its pixels. Every varying costs
// interpolation per pixel (and its derivatives, for the UVs): the full set is 18 floats,
// UV set 0 alone 8.
enum class TexturedStreams {
  All,  // uv, uv1, tangent and colour: any material and mesh (TexturedPbrShader)
  Uv0,  // uv only: every texture on UV set 0, no normal map, no vertex colours
        // (TexturedUv0PbrShader, drawing MeshVertex as is)
  Layered,  // All, and the material extensions' layers (LayeredPbrShader): the materials
            // whose layered() is true, and only those, pay for them
};

// The streams `material` drawn on a mesh with or without vertex colours needs: Uv0 where
// it suffices. render() draws each object with the shader this names; the two shaders give
// the same bits where Uv0 applies (the colour and alpha factors times 1, the same UVs and
// derivatives).
TexturedStreams textured_streams(const TexturedMaterial& material, bool vertex_colors);

struct NoLayers {};

template <TexturedStreams kStreams>
struct BasicTexturedPbrShader {
  static constexpr bool kAllStreams = kStreams != TexturedStreams::Uv0;
  static constexpr bool kLayered = kStreams == TexturedStreams::Layered;
  using Vertex = std::conditional_t<kAllStreams, TexturedVertex, MeshVertex>;
  struct AllVaryings {
    glm::vec3 world_position;
    glm::vec3 normal;
    glm::vec2 uv;
    glm::vec2 uv1;
    glm::vec4 tangent;
    glm::vec4 color;
  };
  struct Uv0Varyings {
    glm::vec3 world_position;
    glm::vec3 normal;
    glm::vec2 uv;
  };
  using Varyings = std::conditional_t<kAllStreams, AllVaryings, Uv0Varyings>;
  // Texture lookups need the derivatives of the UVs (each set carried), and only those.
  static constexpr bool kUsesDerivatives = true;
  static constexpr std::uint32_t kDerivativeMask =
      raster::varying_bits(offsetof(Varyings, uv), (kAllStreams ? 2 : 1) * sizeof(glm::vec2));

  glm::mat4 model{1.0f};
  glm::mat3 normal_matrix{1.0f};
  float handedness = 1.0f;  // sign of det(model): a mirroring transform flips the bitangent
  glm::mat4 view_projection{1.0f};
  glm::vec3 eye{0.0f};
  bool orthographic = false;                      // as PbrShader's
  glm::vec3 view_direction{0.0f, 0.0f, 1.0f};
  glm::vec3 ambient{0.0f};
  std::shared_ptr<const TexturedMaterial> material;
  std::shared_ptr<const std::vector<PreparedLight>> lights;
  const PreparedEnvironment* environment = nullptr;  // as PbrShader's
  // MASK on a multisampled target: alpha is sharpened for the draw's alpha to coverage
  // (raster::DrawState::alpha_to_coverage) instead of cut to 0 or 1. render() sets both.
  bool alpha_to_coverage = false;
  // A transmissive material's uniforms (LayeredPbrShader; render() sets them): its source,
  // the view-projection, the object's scale; the material's part is copied from its layers.
  TransmissionUniforms transmission;
  static constexpr float kMinAlphaWidth = 1.0f / 1024.0f;  // fwidth(alpha)'s floor

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    const glm::vec4 world = model * glm::vec4(in.position, 1.0f);
    out.world_position = glm::vec3(world);
    out.normal = normal_matrix * in.normal;
    out.uv = in.uv;
    if constexpr (kAllStreams) {
      out.uv1 = in.uv1;
      // Tangents are directions on the surface: they transform with the model matrix.
      out.tangent = glm::vec4(glm::mat3(model) * glm::vec3(in.tangent), in.tangent.w * handedness);
      out.color = in.color;
    }
    return view_projection * world;
  }

  // One pixel: the packet code with F = float.
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    raster::FragmentPacket<float, Varyings> p;
    static_assert(sizeof(Varyings) == sizeof(p.v));
    __builtin_memcpy(p.v, &f.v, sizeof p.v);
    __builtin_memcpy(p.ddx, &f.ddx, sizeof p.ddx);
    __builtin_memcpy(p.ddy, &f.ddy, sizeof p.ddy);
    p.pos_x = f.pos.x;
    p.pos_y = f.pos.y;
    p.depth = f.depth;
    p.front_facing = f.front_facing;
    const raster::Color<float> c = fragment_packet<float>(p);
    return {c.r, c.g, c.b, c.a};
  }

  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    constexpr int kPosition = offsetof(Varyings, world_position) / sizeof(float);
    constexpr int kNormal = offsetof(Varyings, normal) / sizeof(float);
    const TexturedMaterial& m = *material;

    // `channels`: the ones read below (Texture::kRed …); the lane kernel skips the rest.
    // `step` 1 or 2: the lookup one pixel to the right or below (uv + its derivative, the
    // same LOD), for alpha's screen derivatives.
    auto lookup = [&](const PreparedSlot& slot, unsigned channels, int step = 0) {
      // UV set 1 exists only in the full set (Uv0: textured_streams() saw none).
      constexpr int kUv0 = offsetof(Varyings, uv) / sizeof(float);
      int k = kUv0;
      if constexpr (kAllStreams) k = slot.uv_set == 0 ? kUv0 : int{offsetof(AllVaryings, uv1) / sizeof(float)};
      F u = p.v[k], v = p.v[k + 1];
      F dudx = p.ddx[k], dvdx = p.ddx[k + 1], dudy = p.ddy[k], dvdy = p.ddy[k + 1];
      if (slot.transformed) {
        const F tu = F(slot.a) * u + F(slot.b) * v + F(slot.c);
        const F tv = F(slot.d) * u + F(slot.e) * v + F(slot.f);
        const F tdudx = F(slot.a) * dudx + F(slot.b) * dvdx, tdvdx = F(slot.d) * dudx + F(slot.e) * dvdx;
        const F tdudy = F(slot.a) * dudy + F(slot.b) * dvdy, tdvdy = F(slot.d) * dudy + F(slot.e) * dvdy;
        u = tu, v = tv, dudx = tdudx, dvdx = tdvdx, dudy = tdudy, dvdy = tdvdy;
      }
      if (step == 1) u = u + dudx, v = v + dvdx;
      if (step == 2) u = u + dudy, v = v + dvdy;
      return raster::sample(slot.bound, u, v, dudx, dvdx, dudy, dvdy, channels);
    };

    // Base colour and alpha.
    Vec3L<F> base = lanes<F>(m.base.albedo);
    F alpha(m.alpha);
    if constexpr (kAllStreams) {
      constexpr int kColor = offsetof(AllVaryings, color) / sizeof(float);
      base = base * Vec3L<F>(p.v[kColor], p.v[kColor + 1], p.v[kColor + 2]);
      alpha = alpha * p.v[kColor + 3];
    }
    F alpha_width(0.0f);  // fwidth(alpha), for alpha to coverage
    if (m.base_color.texture != nullptr) {
      // Alpha only where the alpha mode reads it.
      const unsigned channels = m.alpha_mode == AlphaMode::Opaque ? raster::Texture::kRgb : raster::Texture::kRgba;
      const raster::Color<F> c = lookup(m.base_color, channels);
      base = base * Vec3L<F>(c.r, c.g, c.b);
      if (alpha_to_coverage && m.alpha_mode == AlphaMode::Mask) {
        // |∂α/∂x| + |∂α/∂y| by forward differences, as a GPU's quad gives fwidth: the
        // texture's alpha one pixel to the right and one below, times the factors here.
        const F dx = lookup(m.base_color, raster::Texture::kAlpha, 1).a - c.a;
        const F dy = lookup(m.base_color, raster::Texture::kAlpha, 2).a - c.a;
        const F zero(0.0f);
        alpha_width = (simd::max(dx, zero - dx) + simd::max(dy, zero - dy)) * simd::max(alpha, zero - alpha);
      }
      alpha = alpha * c.a;
    }
    if (m.unlit) return output(m, base, alpha, alpha_width);
    // Metallic and roughness.
    F metallic(m.base.metallic), roughness(m.roughness_factor);
    if (m.metallic_roughness.texture != nullptr) {
      const raster::Color<F> c = lookup(m.metallic_roughness, raster::Texture::kGreen | raster::Texture::kBlue);
      roughness = roughness * c.g;
      metallic = metallic * c.b;
    }
    [[maybe_unused]] const F roughness_in = roughness;  // the transmission's LOD reads it unclamped
    roughness = simd::clamp(roughness, F(kMinRoughness), F(1.0f));
    metallic = simd::clamp(metallic, F(0.0f), F(1.0f));
    MaterialLanes<F> ml;
    ml.albedo = base;
    // The layers' lanes, in the layered shader only (the others carry an empty struct).
    [[maybe_unused]] std::conditional_t<kLayered, LayerLanes<F>, NoLayers> layers;
    if constexpr (kLayered) {
      layers = layer_lanes(m.layers, lookup, metallic);
      ml.f0 = layered_f0(layers.dielectric, base, metallic);
      if (layers.transmission) {
        layers.transmission_lanes.roughness = simd::clamp(roughness_in, F(0.0f), F(1.0f));
        layers.transmission_uniforms = &transmission;
      }
    } else {
      ml.f0 = f0_of(base, metallic);
    }
    ml.one_minus_metallic = F(1.0f) - metallic;
    ml.alpha = roughness * roughness;
    ml.k = k_direct(roughness);
    ml.roughness = roughness;
    ml.ao = F(m.base.ao);
    if (m.occlusion.texture != nullptr) {
      const raster::Color<F> c = lookup(m.occlusion, raster::Texture::kRed);
      ml.ao = ml.ao * (F(1.0f) + F(m.occlusion_strength) * (c.r - F(1.0f)));
    }
    ml.emissive = lanes<F>(m.base.emissive);
    if (m.emissive.texture != nullptr) {
      const raster::Color<F> c = lookup(m.emissive, raster::Texture::kRgb);
      ml.emissive = ml.emissive * Vec3L<F>(c.r, c.g, c.b);
    }

    // The frame: eye direction, geometric normal (flipped on back faces), normal map.
    const Vec3L<F> position(p.v[kPosition], p.v[kPosition + 1], p.v[kPosition + 2]);
    const Vec3L<F> v = orthographic ? lanes<F>(view_direction)
                                    : normalize_or(lanes<F>(eye) - position, Vec3L<F>(F(0.0f), F(0.0f), F(1.0f)));
    Vec3L<F> n(p.v[kNormal], p.v[kNormal + 1], p.v[kNormal + 2]);
    const float facing = p.front_facing ? 1.0f : -1.0f;  // one facing per packet
    if (!p.front_facing) n = -n;
    if constexpr (kLayered) {
      // The coat's normal: the interpolated one, or its own map's (not the base's map).
      if (layers.coat) {
        layers.coat_lanes.normal = n;
        if (m.layers.coat_normal.texture != nullptr)
          layers.coat_lanes.normal = normal_mapped(m.layers.coat_normal, m.layers.coat_normal_scale, p, lookup, n, v, facing);
      }
    }
    if constexpr (kLayered) {
      if (layers.anisotropy) layers.anisotropy_lanes = anisotropy_frame(m.layers, p, lookup, n, v, facing);
    }
    if constexpr (kAllStreams) {
      if (m.normal.texture != nullptr) n = normal_mapped(m.normal, m.normal_scale, p, lookup, n, v, facing);
    }
    if constexpr (kLayered) {
      F o(1.0f);
      const bool occluded = environment != nullptr && environment->occlusion != nullptr;
      if (occluded) o = env_occlusion(*environment, p.pos_x, p.pos_y);
      return output(m, shade_layered(ml, layers, *lights, ambient, position, n, v, environment, occluded ? &o : nullptr),
                    alpha, alpha_width);
    }
    if (environment != nullptr && environment->occlusion != nullptr) {
      const F o = env_occlusion(*environment, p.pos_x, p.pos_y);
      return output(m, shade(ml, *lights, ambient, position, n, v, environment, &o), alpha, alpha_width);
    }
    return output(m, shade(ml, *lights, ambient, position, n, v, environment), alpha, alpha_width);
  }

 private:
  // The layers' lanes at this pixel: the factors times their textures (layered_shading.h).
  template <class F, class Lookup>
  static LayerLanes<F> layer_lanes(const PreparedLayers& L, const Lookup& lookup, F metallic) {
    LayerLanes<F> out{};  // the layers that are off stay zero (GCC: -Wmaybe-uninitialized)
    Vec3L<F> specular_color = lanes<F>(L.specular_color);
    F weight(L.specular);
    if (L.specular_color_slot.texture != nullptr) {
      const raster::Color<F> c = lookup(L.specular_color_slot, raster::Texture::kRgb);
      specular_color = specular_color * Vec3L<F>(c.r, c.g, c.b);
    }
    if (L.specular_slot.texture != nullptr) weight = weight * lookup(L.specular_slot, raster::Texture::kAlpha).a;
    out.dielectric = dielectric_lanes(L.f0_ior, specular_color, weight, metallic);
    out.anisotropy = L.anisotropy;
    out.coat = L.coat;
    if (L.coat) {
      CoatLanes<F>& c = out.coat_lanes;
      c.factor = F(L.coat_factor);
      if (L.coat_slot.texture != nullptr) c.factor = c.factor * lookup(L.coat_slot, raster::Texture::kRed).r;
      F r(L.coat_roughness);
      if (L.coat_roughness_slot.texture != nullptr) r = r * lookup(L.coat_roughness_slot, raster::Texture::kGreen).g;
      c.roughness = simd::clamp(r, F(kMinRoughness), F(1.0f));
      c.alpha = c.roughness * c.roughness;
      c.k = k_direct(c.roughness);
    }
    out.sheen = L.sheen;
    if (L.sheen) {
      SheenLanes<F>& sh = out.sheen_lanes;
      sh.color = lanes<F>(L.sheen_color);
      if (L.sheen_color_slot.texture != nullptr) {
        const raster::Color<F> c = lookup(L.sheen_color_slot, raster::Texture::kRgb);
        sh.color = sh.color * Vec3L<F>(c.r, c.g, c.b);
      }
      F r(L.sheen_roughness);
      if (L.sheen_roughness_slot.texture != nullptr) r = r * lookup(L.sheen_roughness_slot, raster::Texture::kAlpha).a;
      sh.roughness = simd::clamp(r, F(kMinSheenRoughness), F(1.0f));
    }
    out.film = L.film;
    if (L.film) {
      FilmLanes<F>& fl = out.film_lanes;
      fl.factor = F(L.film_factor);
      if (L.film_slot.texture != nullptr) fl.factor = fl.factor * lookup(L.film_slot, raster::Texture::kRed).r;
      fl.thickness = F(L.film_thickness_max);
      if (L.film_thickness_slot.texture != nullptr) {
        const F g = lookup(L.film_thickness_slot, raster::Texture::kGreen).g;
        fl.thickness = F(L.film_thickness_min) + F(L.film_thickness_max - L.film_thickness_min) * g;
      }
      fl.ior = L.film_ior;
      const Vec3L<F> f0 = specular_color * F(L.f0_ior);
      out.dielectric_color = Vec3L<F>(simd::min(f0.x, F(1.0f)), simd::min(f0.y, F(1.0f)), simd::min(f0.z, F(1.0f)));
    }
    out.transmission = L.transmission;
    if (L.transmission) {
      TransmissionLanes<F>& tl = out.transmission_lanes;
      tl.factor = F(L.transmission_factor);
      if (L.transmission_slot.texture != nullptr) tl.factor = tl.factor * lookup(L.transmission_slot, raster::Texture::kRed).r;
      tl.thickness = F(L.thickness);
      if (L.thickness_slot.texture != nullptr) tl.thickness = tl.thickness * lookup(L.thickness_slot, raster::Texture::kGreen).g;
    }
    return out;
  }

  // The anisotropy's frame at this pixel (KHR_materials_anisotropy): the direction
  // (cos ρ, sin ρ) of its rotation ρ in the tangent frame — or the texture's RG × 2 − 1,
  // normalised, rotated by ρ, its B times the strength — taken to the surface by the
  // interpolated tangent made orthogonal to the geometric normal ng and the bitangent
  // w (ng × t), as the extension's reference does. Where the tangent degenerates (parallel
  // to ng, or zero) any unit vector across ng stands in for it.
  template <class F, class Lookup>
  static AnisotropyLanes<F> anisotropy_frame(const PreparedLayers& L, const raster::FragmentPacket<F, Varyings>& p,
                                             const Lookup& lookup, const Vec3L<F>& n_in, const Vec3L<F>& v,
                                             float facing) {
    constexpr int kTangent = offsetof(AllVaryings, tangent) / sizeof(float);
    const F zero(0.0f), one(1.0f);
    AnisotropyLanes<F> a;
    const Vec3L<F> ng = normalize_or(n_in, v);
    F dx(L.anisotropy_cos), dy(L.anisotropy_sin);
    a.strength = F(L.anisotropy_strength);
    if (L.anisotropy_slot.texture != nullptr) {
      const raster::Color<F> c = lookup(L.anisotropy_slot, raster::Texture::kRgb);
      const F x = c.r * F(2.0f) - one, y = c.g * F(2.0f) - one;
      const F len2 = x * x + y * y;
      const auto some = len2 > F(1e-12f);
      const F inv = one / simd::sqrt(simd::select(some, len2, one));
      const F ux = simd::select(some, x * inv, one), uy = simd::select(some, y * inv, zero);
      dx = F(L.anisotropy_cos) * ux - F(L.anisotropy_sin) * uy;
      dy = F(L.anisotropy_sin) * ux + F(L.anisotropy_cos) * uy;
      a.strength = a.strength * c.b;
    }
    const Vec3L<F> t_in = Vec3L<F>(p.v[kTangent], p.v[kTangent + 1], p.v[kTangent + 2]) * F(facing);
    // Any unit vector across ng: ng × e_z, or ng × e_x where ng is near e_z.
    const auto near_z = simd::max(ng.z, zero - ng.z) > F(0.9f);
    const Vec3L<F> across = simd::select(near_z, Vec3L<F>(zero, ng.z, zero - ng.y), Vec3L<F>(ng.y, zero - ng.x, zero));
    const Vec3L<F> t = normalize_or(t_in - ng * simd::dot(ng, t_in), normalize_or(across, Vec3L<F>(one, zero, zero)));
    const F w = simd::select(p.v[kTangent + 3] < zero, F(-1.0f), one);
    const Vec3L<F> b = cross(ng, t) * w;
    a.t = normalize_or(t * dx + b * dy, t);
    a.b = normalize_or(cross(ng, a.t), b);
    return a;
  }

  // The normal map of `slot` (scaled by `normal_scale`) applied to the interpolated normal
  // n (facing: −1 on a back face).
  template <class F, class Lookup>
  static Vec3L<F> normal_mapped(const PreparedSlot& slot, float normal_scale, const raster::FragmentPacket<F, Varyings>& p,
                                const Lookup& lookup, Vec3L<F> n, const Vec3L<F>& v, float facing) {
    constexpr int kTangent = offsetof(AllVaryings, tangent) / sizeof(float);
    n = normalize_or(n, v);
    const raster::Color<F> c = lookup(slot, raster::Texture::kRgb);
    const F scale(normal_scale);
    const F x = (c.r * F(2.0f) - F(1.0f)) * scale, y = (c.g * F(2.0f) - F(1.0f)) * scale;
    const F z = c.b * F(2.0f) - F(1.0f);
    const Vec3L<F> t_in = Vec3L<F>(p.v[kTangent], p.v[kTangent + 1], p.v[kTangent + 2]) * F(facing);
    // Gram–Schmidt: the interpolated tangent made orthogonal to the normal; where it
    // degenerates (parallel to n or zero) the map is not applied.
    const Vec3L<F> t_perp = t_in - n * simd::dot(n, t_in);
    const Vec3L<F> t = normalize_or(t_perp, Vec3L<F>(F(0.0f)));
    const F w = simd::select(p.v[kTangent + 3] < F(0.0f), F(-1.0f), F(1.0f));
    const Vec3L<F> b = cross(n, t) * w;
    const Vec3L<F> mapped = t * x + b * y + n * z;
    n = normalize_or(mapped, n);
    return n;
  }

  // The colour and alpha written for the material's alpha mode.
  // One result object written in place (see sample_light: no copies of temporaries).
  template <class F>
  raster::Color<F> output(const TexturedMaterial& m, const Vec3L<F>& c, F alpha, F alpha_width) const {
    raster::Color<F> out{c.x, c.y, c.z, F(1.0f)};
    if (m.alpha_mode == AlphaMode::Mask) {
      // Kept (1) or discarded (0) by the cutoff, as glTF says (alpha ≥ cutoff: opaque). With
      // alpha to coverage (the draw's alpha_ref 0.5), where alpha varies across the pixel
      // (a width above 0), sharpened to a ramp one pixel wide around the cutoff instead
      // (Filament's masked alpha). Where it does not (a constant alpha, no alpha texture)
      // there is no edge to smooth: the cut keeps all samples or none, as at 1×, even for
      // alpha at or within 1/2048 of the cutoff, which the ramp would split.
      const F cut = simd::select(alpha >= F(m.alpha_cutoff), F(1.0f), F(0.0f));
      out.a = alpha_to_coverage ? simd::select(alpha_width > F(0.0f),
                                               (alpha - F(m.alpha_cutoff)) / simd::max(alpha_width, F(kMinAlphaWidth)) +
                                                   F(0.5f),
                                               cut)
                                : cut;
    } else if (m.alpha_mode == AlphaMode::Blend) {
      const F a = simd::clamp(alpha, F(0.0f), F(1.0f));
      out = {c.x * a, c.y * a, c.z * a, a};
    }
    return out;
  }

  template <class F>
  static Vec3L<F> cross(const Vec3L<F>& a, const Vec3L<F>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  }
};

// The textured shader for any material and mesh.
using TexturedPbrShader = BasicTexturedPbrShader<TexturedStreams::All>;
// The same where textured_streams() says Uv0: 8 varyings instead of 18, MeshVertex drawn as is.
using TexturedUv0PbrShader = BasicTexturedPbrShader<TexturedStreams::Uv0>;
// The shader of the materials with layers (Material::layered()): TexturedPbrShader's streams
// and the layers of layered_shading.h, chosen per draw.
using LayeredPbrShader = BasicTexturedPbrShader<TexturedStreams::Layered>;

}  // namespace softpbr::pbr
