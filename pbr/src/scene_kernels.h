// scene_kernels.h — internal to softpbr::pbr: the shaders render() draws with, and their
// tile kernels compiled once each in a file of its own.
//
// A packet shader's tile kernels (raster::raster_tile<S>: every lane width and sample
// count, per instruction set) are most of the library's build time. Declared here as
// explicit instantiations (extern template), they are compiled in scene_kernels_pbr.cpp,
// scene_kernels_textured.cpp, scene_kernels_textured_uv0.cpp and
// scene_kernels_background.cpp — in parallel, each once —
// and scene.cpp calls them. The code is the same as instantiating them in scene.cpp.
#pragma once

#include <cstddef>

#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/pbr/textured_shading.h"
#include "softpbr/raster/renderer.h"

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

// The explicit instantiation of raster::raster_tile for shader S (declaration or definition).
#define SOFTPBR_PBR_SCENE_KERNEL(S)                                                                     \
  template ::softpbr::raster::ShadeCounts softpbr::raster::raster_tile<S>(                                  \
      const S&, const ::softpbr::raster::DrawGeometry&, std::size_t, const ::softpbr::raster::TileRect&,  \
      const ::softpbr::raster::TargetPixels&, int, ::softpbr::simd::Isa)

extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::PbrShader);
extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::TexturedPbrShader);
extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::TexturedUv0PbrShader);
extern SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::BackgroundShader);
