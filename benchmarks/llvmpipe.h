// benchmarks/llvmpipe.h — the same scenes through Mesa's llvmpipe (OSMesa), for the
// side-by-side comparison of compare_llvmpipe. Built only when Mesa's OSMesa headers are
// found (Debian: apt-get install libosmesa6-dev).
//
// The GLSL below is softpbr's equation, term for term (pbr/shading.h, pbr/brdf.h,
// pbr/light.h: GGX D, Schlick-GGX G with k = (r+1)²/8, Schlick F, kD = max(1 − F, 0)
// (1 − metallic), Lambert, inverse-square point lights, ambient · c · ao + emissive), then
// Reinhard and the gamma curve in the fragment shader, written to an RGBA8 buffer. The
// vertex stage is the same (world position, normal matrix, view-projection), the meshes
// the same vertex and index buffers, back faces culled, depth test less.
//
// Objects with a base colour texture (TexturedPbrShader's in softpbr) are drawn by a second
// program: the mesh's uv as a vertex attribute, softpbr's own mip chain uploaded level by
// level (GL_SRGB8_ALPHA8 for sRGB textures), a sampler object with the Sampler's wrap
// modes, filters, LOD bias and limits and, when llvmpipe has anisotropic filtering, its
// max_anisotropy; the base colour is u_albedo × texture(...).rgb where TexturedPbrShader
// multiplies it, and F0 follows from it per pixel.
//
// A scene with an environment (issue 15) is drawn from the same prefiltered data: the
// Environment's 6 octahedral levels (one-texel borders included) and pbr::dfg_table() as
// GL_RGBA32F textures (linear, clamp to edge, level 0), the 9 SH coefficients, rotation and
// intensity as uniforms; the GLSL is pbr/shading.h's ibl() and environment.h's lookups term
// for term in place of the ambient term, and the background pass (BackgroundShader: one
// triangle carrying the camera rays, no depth test) first. The output transform is
// Reinhard or ACES, then a gamma or the exact sRGB curve, as OutputSettings says.
//
// Directional lights (issue 51) are light.h's sample_light(): the direction to the light
// −normalize(direction) (pbr::prepare_light's unit direction, negated on the CPU) and
// falloff 1, compiled in (DIRECTIONAL) only for scenes that have one. A directional light
// with `shadows` gets a shadow map as softpbr's: the same fit (pbr/src/shadows.cpp's
// shadow_setup(), copied: an orthographic face around the corners of every object's
// transformed mesh bounds, 4 texels of border, in double rounded once to float) and the
// same size (2048²), one layer of a GL_DEPTH_COMPONENT32F 2D array texture drawn every
// frame inside render() — before the lit pass, so its cost is timed as softpbr's, which
// redraws its maps every frame — through a framebuffer with only that depth attachment:
// cleared to 1, the objects with cast_shadows with back faces culled (the only culling
// llvmpipe's side draws), depth test less. The lit pass (SHADOWS) multiplies the light's
// falloff by shadow.h's shadow_visibility() in GLSL for objects with receive_shadows: the
// 4 sin θ texel normal offset and 1.5 texel light offset, softpbr's window coordinates
// (rows from the top, so the GL row is flipped) clamped to [1, size − 3], the 4×4 texels
// from ⌊g⌋ − 1 by texelFetch compared in the shader (z ≤ depth), weights 1 − f, 1, 1, f
// per axis, lit / (lit + shadowed) — not GL's hardware comparison or filtering. Spot
// lights, lights with range and point lights with shadows are not ported.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"

namespace softpbr::bench {

class LlvmpipeRenderer {
 public:
  // Creates an OSMesa core-profile (3.3) context rendering into a width × height RGBA8
  // buffer. llvmpipe reads LP_NUM_THREADS when its screen is created, i.e. with the first
  // context of the process: set it before. With samples > 1 (4 or 8) frames draw into a
  // multisampled framebuffer object (RGBA8 and 24-bit depth renderbuffers) and are resolved
  // into the RGBA8 buffer by glBlitFramebuffer, inside render(). Throws std::runtime_error
  // on failure.
  LlvmpipeRenderer(int width, int height, int samples = 1);
  ~LlvmpipeRenderer();
  LlvmpipeRenderer(const LlvmpipeRenderer&) = delete;
  LlvmpipeRenderer& operator=(const LlvmpipeRenderer&) = delete;

  // Uploads the scene's meshes, textures and environment, compiles the shader variants it
  // needs and sets its uniforms (outside any timing). Point lights without range and
  // directional lights (with or without shadows; at most 8 lights), of the textures
  // only a base colour texture (uv set 0, no UV transform) on an opaque single-sided
  // material and not under an environment, tone map Reinhard or ACES with exposure 0 (the
  // benchmark scenes have nothing else); throws std::invalid_argument otherwise.
  void load(const pbr::Scene& scene, const pbr::OutputSettings& output);

  // One frame: the shadow maps' depth passes (a clear + one draw per caster each), clear +
  // one draw per object (+ the resolve blit when multisampled) + glFinish.
  void render();

  // The last frame, RGBA8, row 0 at the top (as softpbr's Image8).
  const std::vector<std::uint8_t>& pixels() const { return pixels_; }

  // "llvmpipe (LLVM 15.0.6, 256 bits)" or the like.
  std::string renderer_name() const;

  // The extension string through which anisotropic filtering is set
  // ("GL_ARB_texture_filter_anisotropic" or "GL_EXT_texture_filter_anisotropic"), empty
  // when llvmpipe reports neither (samplers are then isotropic), and
  // GL_MAX_TEXTURE_MAX_ANISOTROPY (1 without).
  std::string anisotropy_extension() const;
  float max_anisotropy() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<std::uint8_t> pixels_;
};

}  // namespace softpbr::bench
