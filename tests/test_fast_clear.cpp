// Fast clear: a target remembers which tiles its last frame left holding only the clear
// values, and the next frame clearing to the same bits does not rewrite them. Whatever
// happened to the target in between, every frame must give the bits a fresh target gives.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include <doctest/doctest.h>

#include "softpbr/raster/raster.h"

namespace {

namespace raster = softpbr::raster;

// Flat-coloured rectangles at a depth, in pixel coordinates.
struct Rect {
  float x0, y0, x1, y1, depth;
  glm::vec4 color;
};

struct RectShader {
  struct Vertex {
    glm::vec4 position;
    glm::vec4 color;
  };
  struct Varyings {
    glm::vec4 color;
  };
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.color = in.color;
    return in.position;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return f.v.color; }
};

void draw_rects(raster::Renderer& renderer, const raster::Target& target, const std::vector<Rect>& rects) {
  std::vector<RectShader::Vertex> vertices;
  std::vector<std::uint32_t> indices;
  const float w = static_cast<float>(target.width()), h = static_cast<float>(target.height());
  for (const Rect& r : rects) {
    const auto base = static_cast<std::uint32_t>(vertices.size());
    const float z = 2.0f * r.depth - 1.0f;
    for (const auto& [x, y] : {std::pair{r.x0, r.y0}, {r.x1, r.y0}, {r.x1, r.y1}, {r.x0, r.y1}})
      vertices.push_back({{2.0f * x / w - 1.0f, 1.0f - 2.0f * y / h, z, 1.0f}, r.color});
    for (const std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) indices.push_back(base + i);
  }
  renderer.draw(RectShader{}, std::span<const RectShader::Vertex>(vertices), indices);
}

void frame(raster::Renderer& renderer, raster::Target& target, const std::vector<Rect>& rects,
           const raster::ClearValues& clear) {
  renderer.begin_frame(target, clear);
  draw_rects(renderer, target, rects);
  renderer.end_frame();
}

// What a fresh target holds after the frame.
raster::Target fresh(int tile, const std::vector<Rect>& rects, const raster::ClearValues& clear, int w = 200,
                     int h = 120) {
  raster::Renderer renderer({.threads = 1, .tile_size = tile});
  raster::Target target(w, h);
  frame(renderer, target, rects, clear);
  return target;
}

bool same_bits(const raster::Target& a, const raster::Target& b) {
  return std::memcmp(a.colors().data(), b.colors().data(), a.colors().size_bytes()) == 0 &&
         std::memcmp(a.depths().data(), b.depths().data(), a.depths().size_bytes()) == 0;
}

const raster::ClearValues kBlue{{0.1f, 0.2f, 0.7f, 1.0f}, 1.0f};
const std::vector<Rect> kLeft = {{5, 5, 90, 60, 0.5f, {1, 0, 0, 1}}, {20, 70, 70, 115, 0.3f, {0, 1, 0, 1}}};
const std::vector<Rect> kRight = {{110, 10, 195, 110, 0.4f, {1, 1, 0, 1}}};
const std::vector<Rect> kNone = {};

}  // namespace

TEST_CASE("frames on a reused target give a fresh target's bits, whichever tiles the last frame left clear") {
  const std::vector<Rect>* scenes[] = {&kLeft, &kRight, &kNone, &kLeft, &kLeft, &kRight, &kNone, &kNone};
  for (const int tile : {8, 16, 64})
    for (const unsigned threads : {1u, 2u, 3u}) {
      CAPTURE(tile);
      CAPTURE(threads);
      raster::Renderer renderer({.threads = threads, .tile_size = tile});
      raster::Target target(200, 120);
      for (const std::vector<Rect>* scene : scenes) {
        frame(renderer, target, *scene, kBlue);
        CHECK(same_bits(target, fresh(tile, *scene, kBlue)));
      }
    }
}

TEST_CASE("a different clear value, or the same colour with other bits (-0 for 0), rewrites every tile") {
  raster::Renderer renderer({.threads = 2, .tile_size = 16});
  raster::Target target(200, 120);
  const raster::ClearValues zero{{0.0f, 0.0f, 0.0f, 1.0f}, 1.0f};
  const raster::ClearValues negative_zero{{-0.0f, 0.0f, 0.0f, 1.0f}, 1.0f};
  const raster::ClearValues nearer{{0.0f, 0.0f, 0.0f, 1.0f}, 0.75f};
  for (const raster::ClearValues* clear : {&zero, &negative_zero, &zero, &nearer, &kBlue, &zero}) {
    frame(renderer, target, kLeft, *clear);
    CHECK(same_bits(target, fresh(16, kLeft, *clear)));
  }
  CHECK(std::signbit(fresh(16, kLeft, negative_zero).color(199, 119).r));
}

TEST_CASE("pixels written through the target's non-const accessors between frames are cleared by the next frame") {
  // (199, 119) and its neighbours lie in tiles no rectangle of kLeft touches.
  struct Write {
    const char* how;
    void (*apply)(raster::Target&);
  };
  const Write writes[] = {
      {"color(x, y)", [](raster::Target& t) { t.color(199, 119) = {9, 9, 9, 9}; }},
      {"depth(x, y)", [](raster::Target& t) { t.depth(150, 100) = 0.25f; }},
      {"colors()", [](raster::Target& t) { t.colors()[119 * 200 + 198] = {5, 5, 5, 5}; }},
      {"depths()", [](raster::Target& t) { t.depths()[110 * 200 + 190] = 0.0f; }},
      {"clear_color()", [](raster::Target& t) { t.clear_color({3, 3, 3, 3}); }},
      {"clear_depth()", [](raster::Target& t) { t.clear_depth(0.5f); }},
      {"clear()", [](raster::Target& t) { t.clear({2, 2, 2, 2}, 0.0f); }},
  };
  for (const Write& w : writes) {
    CAPTURE(w.how);
    raster::Renderer renderer({.threads = 2, .tile_size = 16});
    raster::Target target(200, 120);
    frame(renderer, target, kLeft, kBlue);
    w.apply(target);
    frame(renderer, target, kLeft, kBlue);
    CHECK(same_bits(target, fresh(16, kLeft, kBlue)));
  }
}

TEST_CASE("a frame that does not clear keeps what it finds, and the next clearing frame still clears it") {
  raster::Renderer renderer({.threads = 2, .tile_size = 16});
  raster::Target target(200, 120);
  frame(renderer, target, kLeft, kBlue);
  renderer.begin_frame(target);  // no clear: draws over the last frame
  draw_rects(renderer, target, kRight);
  renderer.end_frame();
  raster::Target both = fresh(16, kLeft, kBlue);
  {
    raster::Renderer over({.threads = 1, .tile_size = 16});
    over.begin_frame(both);
    draw_rects(over, both, kRight);
    over.end_frame();
  }
  CHECK(same_bits(target, both));
  frame(renderer, target, kNone, kBlue);
  CHECK(same_bits(target, fresh(16, kNone, kBlue)));
}

TEST_CASE("renderers with other tile sizes, and frames drawn in several passes, share a target safely") {
  raster::Renderer small({.threads = 2, .tile_size = 8});
  raster::Renderer large({.threads = 2, .tile_size = 64});
  raster::Renderer passes({.threads = 2, .tile_size = 16, .geometry_budget = 1});  // a pass per draw
  raster::Target target(200, 120);
  frame(small, target, kLeft, kBlue);
  frame(large, target, kRight, kBlue);
  CHECK(same_bits(target, fresh(8, kRight, kBlue)));
  frame(small, target, kNone, kBlue);
  CHECK(same_bits(target, fresh(8, kNone, kBlue)));
  for (const std::vector<Rect>* scene : {&kLeft, &kRight, &kNone}) {
    passes.begin_frame(target, kBlue);
    for (const Rect& r : *scene) draw_rects(passes, target, {r});
    passes.end_frame();
    CHECK(same_bits(target, fresh(16, *scene, kBlue)));
  }
}

TEST_CASE("the fast clear skips work: a tile left clear is not written by the next frame") {
  // Observable only through a stale write (see Target): a pixel changed behind the
  // target's back in a clear tile survives the next frame. This proves the skip happens;
  // the accessors' documented contract forbids doing this.
  raster::Renderer renderer({.threads = 1, .tile_size = 16});
  raster::Target target(200, 120);
  frame(renderer, target, kLeft, kBlue);
  glm::vec4* stale = target.colors().data();  // forgets the clear tiles...
  frame(renderer, target, kLeft, kBlue);      // ...which this frame learns again
  stale[119 * 200 + 199] = {7, 7, 7, 7};      // written after the frame: not allowed
  frame(renderer, target, kLeft, kBlue);
  CHECK(target.color(199, 119).r == 7.0f);
}
