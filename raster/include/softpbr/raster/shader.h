// softpbr/raster/shader.h — the shader interface: C++ types inlined into the pipeline.
//
// A shader is a plain type with
//   using Vertex   = ...;   // what the user's vertex buffer holds
//   using Varyings = ...;   // what the vertex stage hands to the fragment stage: a
//                           // trivially copyable struct of floats only (glm vectors are
//                           // fine), at most kMaxVaryings floats, or an empty struct
//   glm::vec4 vertex(const Vertex& in, Varyings& out) const;   // → clip-space position
//   glm::vec4 fragment(const Fragment<Varyings>& f) const;     // → colour
// draw<Shader>() instantiates the tile kernel for the type, so both stages inline; no
// virtual call happens per vertex or per pixel. Uniforms are the shader's members; the
// renderer keeps a copy of the shader until the frame ends.
//
// Fragments are shaded in 2×2 quads. Each fragment gets its varyings interpolated
// (perspective-correct) at its pixel centre and the quad's screen-space derivatives
// (coarse: ddx = v(x+1, y) − v(x, y), ddy = v(x, y+1) − v(x, y) taken at the quad's
// top-left pixel, as GL's dFdxCoarse). Lanes of a quad outside the triangle ("helper
// lanes") only feed the derivatives: they are never shaded and never write.
//
// Packet shaders. A shader may also provide, written once against a lane type F (float or
// simd::Vec<N>, see simd.h):
//   template <class F> Color<F> fragment_packet(const FragmentPacket<F, Varyings>& p) const;
// Each lane of a packet is one covered pixel of a triangle, with exactly the values a
// Fragment would hold for it. The renderer then shades N pixels per call (RendererOptions::
// lanes); with lanes = 1 it calls fragment_packet<float>. Every lane computes the same
// IEEE operations as the scalar code, so images are bit-identical at every width.
#pragma once

#include <concepts>
#include <cstdint>
#include <type_traits>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace softpbr::raster {

// Most floats one vertex may pass to the fragment stage.
inline constexpr int kMaxVaryings = 32;

template <class V>
struct Fragment {
  V v;             // varyings at the pixel centre
  V ddx;           // quad derivative along +x (one pixel right)
  V ddy;           // quad derivative along +y (one pixel down)
  glm::vec2 pos;   // pixel centre in pixels, (0.5, 0.5) at the top-left pixel
  float depth;     // window depth in [0, 1]
  bool front_facing;
};

// Lanes of pixels for packet shaders: varying k of every lane is v[k] (declaration order
// of the Varyings struct's floats), likewise ddx/ddy.
template <class F, class V>
struct FragmentPacket {
  static constexpr int kCount = std::is_empty_v<V> ? 0 : static_cast<int>(sizeof(V) / sizeof(float));
  F v[kCount > 0 ? kCount : 1];
  F ddx[kCount > 0 ? kCount : 1];
  F ddy[kCount > 0 ? kCount : 1];
  F pos_x, pos_y;  // pixel centres
  F depth;
  bool front_facing;  // one facing per packet (lanes may come from several triangles)
};

template <class F>
struct Color {
  F r, g, b, a;
};

template <class V>
concept VaryingsType = std::is_trivially_copyable_v<V> && std::is_default_constructible_v<V> &&
                       (std::is_empty_v<V> || (sizeof(V) % sizeof(float) == 0 &&
                                               sizeof(V) <= kMaxVaryings * sizeof(float)));

template <class S>
concept Shader = VaryingsType<typename S::Varyings> && std::is_copy_constructible_v<S> &&
                 requires(const S& s, const typename S::Vertex& in, typename S::Varyings& out,
                          const Fragment<typename S::Varyings>& f) {
                   { s.vertex(in, out) } -> std::convertible_to<glm::vec4>;
                   { s.fragment(f) } -> std::convertible_to<glm::vec4>;
                 };

template <class S, class F>
concept PacketShaderFor = requires(const S& s, const FragmentPacket<F, typename S::Varyings>& p) {
  { s.template fragment_packet<F>(p) } -> std::same_as<Color<F>>;
};

// Per-draw uniforms in lanes. A packet shader may also provide
//   template <class F> U<F> packet_uniforms() const;   // any copyable type, from its members
//   template <class F> Color<F> fragment_packet(const FragmentPacket<F, Varyings>& p,
//                                               const U<F>& u) const;
// The renderer then builds the uniforms once per draw and tile, not once per packet, and
// calls the two-argument form: what a shader derives from its members alone (a material's
// terms, a broadcast eye position) is not re-derived for every N pixels. The one-argument
// form stays required and must give the same bits — fragment_packet(p, packet_uniforms<F>()).
template <class S, class F>
concept PacketUniformsFor = requires(const S& s, const FragmentPacket<F, typename S::Varyings>& p) {
  { s.template fragment_packet<F>(p, s.template packet_uniforms<F>()) } -> std::same_as<Color<F>>;
};

// A shader that reads no derivatives (Fragment::ddx/ddy, FragmentPacket::ddx/ddy) may say
//   static constexpr bool kUsesDerivatives = false;
// The rasterizer then interpolates only the covered pixels of a quad, not the helper
// lanes, and hands it zero derivatives: less work per quad, the same image, since the
// shader never reads them.
template <class S>
inline constexpr bool kUsesDerivatives = true;
template <class S>
  requires requires { S::kUsesDerivatives; }
inline constexpr bool kUsesDerivatives<S> = S::kUsesDerivatives;

// A depth-only shader (a shadow map's casters) says
//   static constexpr bool kDepthOnly = true;
// Its draws run the pipeline of every draw — the vertex stage, clipping, setup, coverage
// and the depth test, with the same rules and the same bits — and write depth alone: no
// colour is written, and without the alpha test nothing is shaded (fragment() and
// fragment_packet() are not called, no varying is interpolated). With the alpha test the
// shader runs for its alpha only, and the depth of the fragments it keeps is written after
// it (an alpha-masked caster's cut-out). It draws into a 1-sample target: a depth-only one
// (Target::depth_only) or any other, whose colour it leaves alone.
template <class S>
inline constexpr bool kDepthOnly = false;
template <class S>
  requires requires { S::kDepthOnly; }
inline constexpr bool kDepthOnly<S> = S::kDepthOnly;

// Number of floats in a varyings struct.
template <class V>
inline constexpr int kVaryingCount = std::is_empty_v<V> ? 0 : static_cast<int>(sizeof(V) / sizeof(float));

// The varying floats [offset, offset + size) of a varyings struct (in bytes, as offsetof and
// sizeof give them) as a set of derivatives: bit k is float k.
constexpr std::uint32_t varying_bits(std::size_t offset, std::size_t size) {
  std::uint32_t bits = 0;
  for (std::size_t k = offset / sizeof(float); k < (offset + size) / sizeof(float) && k < 32; ++k)
    bits |= std::uint32_t{1} << k;
  return bits;
}

// A shader that reads the derivatives of only some varyings (a texture lookup's UVs) may
// name them, bit k for varying float k:
//   static constexpr std::uint32_t kDerivativeMask = raster::varying_bits(offsetof(Varyings, uv), sizeof(glm::vec2));
// The rasterizer then computes and passes only those; the others read as zero. Without it
// every varying has its derivatives (none with kUsesDerivatives = false); bits past the
// varyings are ignored.
template <class S>
inline constexpr std::uint32_t kDerivativeMask = kUsesDerivatives<S> ? ~std::uint32_t{0} : 0;
template <class S>
  requires requires { S::kDerivativeMask; }
inline constexpr std::uint32_t kDerivativeMask<S> = kUsesDerivatives<S> ? std::uint32_t{S::kDerivativeMask} : 0;

enum class DepthTest : std::uint8_t { Less, LessEqual, Always };
enum class Cull : std::uint8_t { None, Back, Front };
enum class FrontFace : std::uint8_t { CounterClockwise, Clockwise };  // as seen on screen
enum class Blend : std::uint8_t {
  Replace,  // dst = src
  Over      // premultiplied "over": dst = src + dst · (1 − src.a)
};

struct DrawState {
  DepthTest depth_test = DepthTest::Less;
  bool depth_write = true;
  Cull cull = Cull::None;
  FrontFace front_face = FrontFace::CounterClockwise;
  Blend blend = Blend::Replace;
  // Alpha test, as GL's legacy glAlphaFunc(GL_GEQUAL, alpha_ref): a fragment whose alpha
  // is below alpha_ref (or NaN) is discarded — it writes neither colour nor depth. The
  // depth of such a draw is tested early (a hidden pixel is not shaded) but written after
  // shading, in submission order. glTF's alphaMode MASK is this test.
  bool alpha_test = false;
  float alpha_ref = 0.5f;
  // Alpha to coverage (implies the alpha test; docs/design.md, MSAA): on a target of N
  // samples a pixel keeps sample s (of those covered and passing depth) when
  //   alpha ≥ alpha_ref + (s + 0.5) / N − 0.5,
  // so alpha_ref ± 0.5 spans none to all of them (k = ⌊N·(alpha − alpha_ref) + N/2 + 0.5⌋
  // samples, the first k of the pattern's order) and N = 1 is exactly the alpha test. The
  // kept samples are written with alpha 1 (the coverage carries the alpha: Vulkan's
  // alphaToOne). A shader sharpens its alpha for it, as (alpha − cutoff) / fwidth(alpha)
  // + 0.5 (TexturedPbrShader does for glTF's MASK on multisampled targets).
  bool alpha_to_coverage = false;
};

}  // namespace softpbr::raster
