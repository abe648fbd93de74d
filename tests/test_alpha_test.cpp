// The alpha test (DrawState::alpha_test): discarded fragments write neither colour nor
// depth, depth is written after shading in submission order, and the result is the same
// for the scalar form and packets of every width, with dispatch on and off.
#include <doctest/doctest.h>

#include <vector>

#include <glm/vec4.hpp>

#include "softpbr/raster/raster.h"

namespace raster = softpbr::raster;

namespace {

// A flat colour whose alpha is the varying `a`.
struct AlphaShader {
  struct Vertex {
    glm::vec4 clip;
    float a;
  };
  struct Varyings {
    float a;
  };
  static constexpr bool kUsesDerivatives = false;
  glm::vec3 rgb{1.0f, 0.0f, 0.0f};
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.a = in.a;
    return in.clip;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return {rgb, f.v.a}; }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return {F(rgb.r), F(rgb.g), F(rgb.b), p.v[0]};
  }
};

// A scalar-only copy: the renderer calls fragment() one pixel at a time.
struct ScalarAlphaShader {
  using Vertex = AlphaShader::Vertex;
  using Varyings = AlphaShader::Varyings;
  static constexpr bool kUsesDerivatives = false;
  AlphaShader inner;
  glm::vec4 vertex(const Vertex& in, Varyings& out) const { return inner.vertex(in, out); }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return inner.fragment(f); }
};

// A quad over the whole target at depth z (NDC), alpha from a_left to a_right along x.
std::vector<AlphaShader::Vertex> quad(float z, float a_left, float a_right) {
  return {{{-1, -1, z, 1}, a_left}, {{1, -1, z, 1}, a_right}, {{1, 1, z, 1}, a_right},
          {{-1, -1, z, 1}, a_left}, {{1, 1, z, 1}, a_right},  {{-1, 1, z, 1}, a_left}};
}

template <class S>
raster::Target render(const raster::RendererOptions& options) {
  raster::Renderer renderer(options);
  raster::Target target(32, 16);
  renderer.begin_frame(target, raster::ClearValues{{0, 0, 1, 1}, 1.0f});
  raster::DrawState tested;
  tested.alpha_test = true;
  tested.alpha_ref = 0.5f;
  S red{}, green{};
  if constexpr (requires { red.inner; }) {
    green.inner.rgb = {0, 1, 0};
  } else {
    green.rgb = {0, 1, 0};
  }
  // In front, alpha 0 → 1 from left to right: the left half is discarded.
  const auto front = quad(0.0f, 0.0f, 1.0f);
  renderer.draw(red, std::span<const AlphaShader::Vertex>(front), tested);
  // Behind: it shows through where the front was discarded, because no depth was written there.
  const auto back = quad(0.5f, 1.0f, 1.0f);
  renderer.draw(green, std::span<const AlphaShader::Vertex>(back));
  // In front of everything, alpha 1 → 0 and tested: the right half is discarded.
  const auto right_cut = quad(-0.5f, 1.0f, 0.0f);
  S blue{};
  if constexpr (requires { blue.inner; }) {
    blue.inner.rgb = {1, 1, 1};
  } else {
    blue.rgb = {1, 1, 1};
  }
  renderer.draw(blue, std::span<const AlphaShader::Vertex>(right_cut), tested);
  renderer.end_frame();
  return target;
}

}  // namespace

TEST_CASE("alpha-tested fragments below the reference write neither colour nor depth") {
  const raster::Target t = render<ScalarAlphaShader>({.threads = 1});
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      CAPTURE(x);
      CAPTURE(y);
      // Alpha at the pixel centre: (x + ½)/32 for the red quad, 1 − that for the white one.
      const float a = (x + 0.5f) / 32.0f;
      const glm::vec4 c = t.color(x, y);
      if (1.0f - a >= 0.5f) {  // white quad kept (left half)
        CHECK(c.r == 1.0f);
        CHECK(c.g == 1.0f);
        CHECK(t.depths()[static_cast<std::size_t>(y) * 32 + x] == doctest::Approx(0.25f));
      } else if (a >= 0.5f) {  // red kept, in front of green
        CHECK(c.r == 1.0f);
        CHECK(c.g == 0.0f);
        CHECK(t.depths()[static_cast<std::size_t>(y) * 32 + x] == doctest::Approx(0.5f));
      } else {
        CHECK(c.g == 1.0f);
      }
    }
}

TEST_CASE("the alpha test gives the same bits at every packet width, thread count and dispatch") {
  const raster::Target ref = render<ScalarAlphaShader>({.threads = 1});
  for (int lanes : {1, 4, 8, 16})
    for (bool dispatch : {false, true})
      for (unsigned threads : {1u, 2u})
        for (int tile : {8, 16}) {
          CAPTURE(lanes);
          CAPTURE(dispatch);
          const raster::Target t =
              render<AlphaShader>({.threads = threads, .tile_size = tile, .lanes = lanes, .dispatch = dispatch});
          CHECK(std::equal(t.colors().begin(), t.colors().end(), ref.colors().begin(), ref.colors().end()));
          CHECK(std::equal(t.depths().begin(), t.depths().end(), ref.depths().begin(), ref.depths().end()));
        }
}
