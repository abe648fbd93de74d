// occlusion.h — internal to softpbr::pbr: screen-space ambient occlusion of the
// environment's light (docs/design.md, "Image-based lighting", "Occlusion").
//
// render() draws the frame's opaque objects once more, before the frame, into a 1-sample
// target of the frame's size with GBufferShader (colour = view-space unit normal and the
// view depth), then compute_occlusion() turns that into one factor a pixel, which the
// main pass's shaders read at their pixel (env_occlusion, environment_lookup.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "softpbr/pbr/mesh.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/pbr/textured_shading.h"
#include "softpbr/raster/pool.h"
#include "softpbr/raster/shader.h"
#include "softpbr/raster/target.h"
#include "softpbr/simd/simd.h"

namespace softpbr::pbr::detail {

// The depth and normal buffer: colour (n.x, n.y, n.z, d) with n the interpolated normal in
// view space (unit; flipped on back faces, which only double-sided objects show) and d the
// distance in front of the eye along the view direction (−z in view space, > 0), so that a
// cleared pixel (0, 0, 0, 0) is "no surface". Clip positions are the main pass's, computed
// the same way (view_projection · model · p), so the same pixels are covered.
struct GBufferShader {
  using Vertex = MeshVertex;
  struct Varyings {
    glm::vec3 normal;  // view space
    float depth;       // −z in view space
  };
  static constexpr bool kUsesDerivatives = false;

  glm::mat4 model{1.0f};
  glm::mat4 view{1.0f};
  glm::mat3 normal_matrix{1.0f};  // view's rotation × the model's inverse transpose
  glm::mat4 view_projection{1.0f};

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    const glm::vec4 world = model * glm::vec4(in.position, 1.0f);
    out.normal = normal_matrix * in.normal;
    out.depth = -(view * world).z;
    return view_projection * world;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    raster::FragmentPacket<float, Varyings> p;
    __builtin_memcpy(p.v, &f.v, sizeof p.v);
    p.front_facing = f.front_facing;
    const raster::Color<float> c = fragment_packet<float>(p);
    return {c.r, c.g, c.b, c.a};
  }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    const Vec3L<F> n_in(p.v[0], p.v[1], p.v[2]);
    Vec3L<F> n = normalize_or(n_in, Vec3L<F>(F(0.0f), F(0.0f), F(1.0f)));
    if (!p.front_facing) n = -n;
    return {n.x, n.y, n.z, p.v[3]};
  }
};

// The same for an alpha-masked object (glTF's MASK): its textured shader `inner` finds the
// alpha of each pixel (cut to 1 or 0 at 1 sample: its alpha_to_coverage is off), and the
// colour is GBufferShader's where it is 1, 0 where it is 0. Drawn with the alpha test at
// a reference just above 0 (kMaskedAlphaRef), which keeps every depth > 0 and discards the
// zeros. The full shading runs for the alpha (only for masked objects).
inline constexpr float kMaskedAlphaRef = 1e-30f;
template <class Inner>
struct MaskedGBufferShader {
  using Vertex = typename Inner::Vertex;
  using Varyings = typename Inner::Varyings;
  static constexpr bool kUsesDerivatives = raster::kUsesDerivatives<Inner>;
  static constexpr std::uint32_t kDerivativeMask = raster::kDerivativeMask<Inner>;

  Inner inner;
  glm::mat4 view{1.0f};
  glm::mat3 view_rotation{1.0f};

  glm::vec4 vertex(const Vertex& in, Varyings& out) const { return inner.vertex(in, out); }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    raster::FragmentPacket<float, Varyings> p;
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
    const raster::Color<F> shaded = inner.template fragment_packet<F>(p);
    const Vec3L<F> w(p.v[kPosition], p.v[kPosition + 1], p.v[kPosition + 2]);
    const Vec3L<F> n_world(p.v[kNormal], p.v[kNormal + 1], p.v[kNormal + 2]);
    // View space: the rotation's rows (glm is column-major: m[c][r]) and the translation.
    const glm::mat3& r = view_rotation;
    const Vec3L<F> n_in(F(r[0][0]) * n_world.x + F(r[1][0]) * n_world.y + F(r[2][0]) * n_world.z,
                        F(r[0][1]) * n_world.x + F(r[1][1]) * n_world.y + F(r[2][1]) * n_world.z,
                        F(r[0][2]) * n_world.x + F(r[1][2]) * n_world.y + F(r[2][2]) * n_world.z);
    Vec3L<F> n = normalize_or(n_in, Vec3L<F>(F(0.0f), F(0.0f), F(1.0f)));
    if (!p.front_facing) n = -n;
    const F z = F(view[0][2]) * w.x + F(view[1][2]) * w.y + F(view[2][2]) * w.z + F(view[3][2]);
    const auto kept = shaded.a >= F(0.5f);
    const F zero(0.0f);
    return {simd::select(kept, n.x, zero), simd::select(kept, n.y, zero), simd::select(kept, n.z, zero),
            simd::select(kept, zero - z, zero)};
  }
};

// How compute_occlusion reads the buffer and what it computes.
struct OcclusionSettings {
  int width = 0, height = 0;
  bool orthographic = false;
  float p00 = 1.0f, p11 = 1.0f;  // the projection's x and y scales (ndc = p · view / w)
  float radius = 1.0f;           // world units
  float strength = 1.0f;
  // The lanes a row is computed in (1: one pixel at a time; 4, 8, 16) and the instruction
  // set of that code (the renderer's: Renderer::lanes(), isa()). The same bits for all.
  int lanes = 1;
  simd::Isa isa = simd::Isa::Baseline;
};

// The occlusion factor of every pixel of `gbuffer` (GBufferShader's colours, 1 sample a
// pixel), in [0, 1], 1 where no surface is, row-major into `out` (resized): normal-
// oriented hemisphere samples (a fixed kernel turned by a fixed 4×4 pattern of rotations),
// each asking whether the surface seen at the sample's pixel rises above the pixel's
// tangent plane within the radius, then a 4×4 blur of the pixels of the same surface.
// Rows are split over `pool`; each pixel is IEEE basic operations in a fixed order, so the
// bits do not depend on the thread count.
void compute_occlusion(const raster::Target& gbuffer, const OcclusionSettings& settings, raster::ThreadPool& pool,
                       std::vector<float>& out);

}  // namespace softpbr::pbr::detail
