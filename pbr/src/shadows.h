// shadows.h — internal to softpbr::pbr: where a light's shadow map looks from, and the
// shaders that draw its casters (docs/design.md, "Shadows"; the lookup is shadow.h).
//
// render() asks shadow_setup() for each light with shadows: the faces' view-projections,
// fitted to the scene's bounds, and the map's lookup values (ShadowMap); it draws the
// casters into one depth-only target a face with ShadowDepthShader (opaque) or
// MaskedShadowDepthShader (alpha-masked and blended: the cut-out), then points the light's
// PreparedLight::shadow at the map.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "softpbr/pbr/light.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/pbr/shadow.h"
#include "softpbr/raster/shader.h"

namespace softpbr::pbr::detail {

// Texels a side: one map for a directional or spot light (16 MiB of depth), each of a point
// light's six faces (24 MiB together). A directional map fitted to the bounds of a model
// or of the gallery gives texels of 1/2048 of the scene's width (docs/design.md, "Shadows").
inline constexpr int kShadowMapSize = 2048;
inline constexpr int kShadowCubeSize = 1024;
// Texels kept free around the fitted region (the 4×4 pattern reaches 2 beyond a point).
inline constexpr int kShadowBorder = 4;
// A spot light whose outer cone is wider than this (60°) is drawn as a point light's six
// faces: one perspective face of 120° or more spends most of its texels near its rim.
inline constexpr float kSpotMaxCone = 1.0471975511965976f;
// The near plane of a perspective face at this fraction of its far plane: the window
// depth's resolution at the far plane is then about 16 float steps of 1 a texel.
inline constexpr double kShadowNearFraction = 1e-3;

// The faces a light's map is drawn with (one, or six for ShadowMap::Kind::Cube) and the
// map's lookup values (`map.faces` still null).
struct ShadowSetup {
  ShadowMap map;
  std::vector<glm::mat4> view_projection;
};

// Fits `light`'s map to `world` (the bounds of every object: receivers, too, must lie in a
// directional light's map). False when there is nothing to fit (no bounds; a spot or point
// light with every object at its own position).
bool shadow_setup(const PreparedLight& light, const Bounds& world, ShadowSetup& out);

// Bytes of depth the map of `light` holds (0 without shadows).
std::uint64_t shadow_map_bytes(const Light& light);

// An opaque caster: its depth alone (raster::kDepthOnly), clip positions computed as the
// PBR shaders' (view_projection · (model · p)).
struct ShadowDepthShader {
  using Vertex = MeshVertex;
  struct Varyings {};
  static constexpr bool kUsesDerivatives = false;
  static constexpr bool kDepthOnly = true;

  glm::mat4 model{1.0f};
  glm::mat4 view_projection{1.0f};

  glm::vec4 vertex(const Vertex& in, Varyings&) const {
    const glm::vec4 world = model * glm::vec4(in.position, 1.0f);
    return view_projection * world;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>&) const { return glm::vec4(0.0f); }  // not called
};

// An alpha-masked or blended caster: its textured shader `inner` (unlit, so that it finds
// only the base colour and alpha) decides per pixel, with the draw's alpha test at ½, which
// depths are kept (raster::kDepthOnly with the alpha test).
template <class Inner>
struct MaskedShadowDepthShader {
  using Vertex = typename Inner::Vertex;
  using Varyings = typename Inner::Varyings;
  static constexpr bool kUsesDerivatives = raster::kUsesDerivatives<Inner>;
  static constexpr std::uint32_t kDerivativeMask = raster::kDerivativeMask<Inner>;
  static constexpr bool kDepthOnly = true;

  Inner inner;

  glm::vec4 vertex(const Vertex& in, Varyings& out) const { return inner.vertex(in, out); }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return inner.fragment(f); }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return inner.template fragment_packet<F>(p);
  }
};

}  // namespace softpbr::pbr::detail
