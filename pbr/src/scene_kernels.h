// scene_kernels.h — internal to softpbr::pbr: the shaders render() draws with, and their
// tile kernels compiled once each in a file of its own.
//
// A packet shader's tile kernels (raster::raster_tile<S>: every lane width and sample
// count, per instruction set) are most of the library's build time. Declared here as
// explicit instantiations (extern template), they are compiled in files of their own —
// scene_kernels_<shader>.cpp (the entry and the 1-sample kernels), _ms4.cpp and _ms8.cpp
// for the pbr, textured and textured_uv0 shaders, scene_kernels_background.cpp — in
// parallel, each once, and scene.cpp calls them. The code is the same as instantiating
// them in scene.cpp.
#pragma once

#include <cstddef>

#include "softpbr/pbr/environment_lookup.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/pbr/textured_shading.h"
#include "softpbr/raster/renderer.h"
#include "occlusion.h"
#include "shadows.h"

namespace softpbr::pbr::detail {

// The background pass: one triangle over the whole target (clip x, y in {−1, 3}) at the far
// plane (clip z = w = 1), each vertex carrying the world direction of the camera ray through it.
// The direction is linear in screen space (w = 1), so the interpolated varying is the
// ray through each pixel; the shader reads the environment along it.
struct BackgroundShader {
  struct Vertex {
    glm::vec4 clip;
    glm::vec3 direction;
  };
  struct Varyings {
    glm::vec3 direction;
  };
  static constexpr bool kUsesDerivatives = false;

  const PreparedEnvironment* environment = nullptr;
  float roughness = 0.0f;

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.direction = in.direction;
    return in.clip;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const raster::Color<float> c = color<float>(f.v.direction.x, f.v.direction.y, f.v.direction.z);
    return {c.r, c.g, c.b, c.a};
  }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return color<F>(p.v[0], p.v[1], p.v[2]);
  }

 private:
  template <class F>
  raster::Color<F> color(F x, F y, F z) const {
    const EnvVec3<F> c = env_radiance_uniform(*environment, to_environment(*environment, x, y, z), roughness);
    return {c.x, c.y, c.z, F(1.0f)};
  }
};

}  // namespace softpbr::pbr::detail

// The explicit instantiation of raster::raster_tile for shader S (declaration or definition):
// the entry that picks a tile kernel by lane count, sample count and instruction set.
#define SOFTPBR_PBR_SCENE_KERNEL(S)                                                                     \
  template ::softpbr::raster::ShadeCounts softpbr::raster::raster_tile<S>(                                  \
      const S&, const ::softpbr::raster::DrawGeometry&, std::size_t, const ::softpbr::raster::TileRect&,  \
      const ::softpbr::raster::TargetPixels&, int, ::softpbr::simd::Isa)

// The tile kernels of shader S for kMs samples a pixel, each copy that
// raster::detail::tile_kernel can pick (rast.h): the baseline copy at 1 and 4 lanes (and at
// the build's native width, kBaselineMaxWidth, in a build for AVX2 or AVX-512), the AVX2
// copy at 8 and the AVX-512 copy at 16. EXTERN is `extern` (a declaration) or empty (the
// definition). A packet shader's kernels are compiled in three files, one per sample
// count, so that the build's cores share them.
#define SOFTPBR_PBR_TILE_KERNEL(EXTERN, NS, W, kMs, S)                                                      \
  EXTERN template ::softpbr::raster::ShadeCounts softpbr::raster::detail::NS::raster_tile<W, kMs, S>(         \
      const S&, const ::softpbr::raster::DrawGeometry&, std::size_t, const ::softpbr::raster::TileRect&,     \
      const ::softpbr::raster::TargetPixels&)
#if SOFTPBR_SIMD_X86_TARGETS
#define SOFTPBR_PBR_X86_TILE_KERNELS(EXTERN, kMs, S) \
  SOFTPBR_PBR_TILE_KERNEL(EXTERN, avx2, 8, kMs, S);  \
  SOFTPBR_PBR_TILE_KERNEL(EXTERN, avx512, 16, kMs, S)
#else
#define SOFTPBR_PBR_X86_TILE_KERNELS(EXTERN, kMs, S) static_assert(true)
#endif
// The baseline copy at the build's native width when it is above 4: the width tile_kernel
// picks for a request wider than the CPU's targets (raster::detail::kBaselineMaxWidth).
#if defined(__AVX512F__)
#define SOFTPBR_PBR_BASELINE_WIDE 16
#elif defined(__AVX2__)
#define SOFTPBR_PBR_BASELINE_WIDE 8
#else
#define SOFTPBR_PBR_BASELINE_WIDE 4
#endif
static_assert(::softpbr::raster::detail::kBaselineMaxWidth == SOFTPBR_PBR_BASELINE_WIDE);
#if SOFTPBR_PBR_BASELINE_WIDE > 4
#define SOFTPBR_PBR_BASELINE_WIDE_TILE_KERNEL(EXTERN, kMs, S) \
  SOFTPBR_PBR_TILE_KERNEL(EXTERN, baseline, SOFTPBR_PBR_BASELINE_WIDE, kMs, S)
#else
#define SOFTPBR_PBR_BASELINE_WIDE_TILE_KERNEL(EXTERN, kMs, S) static_assert(true)
#endif
#define SOFTPBR_PBR_TILE_KERNELS(EXTERN, kMs, S)           \
  SOFTPBR_PBR_TILE_KERNEL(EXTERN, baseline, 1, kMs, S);    \
  SOFTPBR_PBR_TILE_KERNEL(EXTERN, baseline, 4, kMs, S);    \
  SOFTPBR_PBR_BASELINE_WIDE_TILE_KERNEL(EXTERN, kMs, S);   \
  SOFTPBR_PBR_X86_TILE_KERNELS(EXTERN, kMs, S)
// A packet shader's entry and its kernels, declared.
#define SOFTPBR_PBR_EXTERN_PACKET_KERNELS(S)   \
  extern SOFTPBR_PBR_SCENE_KERNEL(S);          \
  SOFTPBR_PBR_TILE_KERNELS(extern, 1, S);      \
  SOFTPBR_PBR_TILE_KERNELS(extern, 4, S);      \
  SOFTPBR_PBR_TILE_KERNELS(extern, 8, S)

SOFTPBR_PBR_EXTERN_PACKET_KERNELS(::softpbr::pbr::PbrShader);
SOFTPBR_PBR_EXTERN_PACKET_KERNELS(::softpbr::pbr::TexturedPbrShader);
SOFTPBR_PBR_EXTERN_PACKET_KERNELS(::softpbr::pbr::TexturedUv0PbrShader);
SOFTPBR_PBR_EXTERN_PACKET_KERNELS(::softpbr::pbr::LayeredPbrShader);
extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::BackgroundShader);
extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::GBufferShader);
extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::MaskedGBufferShader<::softpbr::pbr::TexturedPbrShader>);
extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::MaskedGBufferShader<::softpbr::pbr::TexturedUv0PbrShader>);
extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::MaskedShadowDepthShader<::softpbr::pbr::TexturedPbrShader>);
extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::MaskedShadowDepthShader<::softpbr::pbr::TexturedUv0PbrShader>);
