// softpbr/raster/target.h — render targets (float RGBA colour + float depth) and their
// resolve to 8-bit sRGB images.
//
// A Target is what a frame draws into: linear float RGBA (straight values as the shaders
// write them; the "over" blend expects premultiplied alpha) and a float depth buffer,
// row-major with row 0 at the top of the image.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "softpbr/image/image.h"

namespace softpbr::raster {

// Largest width or height of a target: keeps fixed-point edge functions inside int64
// (see detail/setup.h) and a full target under 16384² × 20 bytes ≈ 5 GiB.
inline constexpr int kMaxTargetSize = 16384;

namespace detail {
struct FrameAccess;
// What a renderer's last frame left in a target: for tiles of tile_size pixels (the
// renderer's grid), tiles[t] != 0 when every pixel of tile t holds exactly `color` and
// `depth`.
struct ClearedTiles {
  int tile_size = 0;
  glm::vec4 color{0.0f};
  float depth = 0.0f;
  std::vector<std::uint8_t> tiles;  // empty: nothing known
};
}  // namespace detail

// The pixels of a target as the tile kernels write them: the renderer hands them out
// while a frame owns the target.
struct TargetPixels {
  glm::vec4* colors;
  float* depths;
  int width;
  int height;
};

class Target {
 public:
  // Throws std::invalid_argument unless 1 <= width, height <= kMaxTargetSize.
  Target(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }

  void clear(glm::vec4 color = {0, 0, 0, 1}, float depth = 1.0f);
  void clear_color(glm::vec4 color);
  void clear_depth(float depth);

  // Direct access to the pixels: index y * width() + x.
  //
  // A target remembers which of its tiles a renderer's last frame left holding only the
  // frame's clear values; the next frame that clears to the same values leaves those
  // tiles alone instead of writing the same bytes again (GPUs call this a fast clear).
  // The non-const accessors and clear*() forget it, so a span or reference they return
  // may be written freely until the next frame begins on this target (as an iterator,
  // it is not to be written through after that). The const accessors forget nothing.
  std::span<glm::vec4> colors() { forget_cleared_tiles(); return color_; }
  std::span<const glm::vec4> colors() const { return color_; }
  std::span<float> depths() { forget_cleared_tiles(); return depth_; }
  std::span<const float> depths() const { return depth_; }
  glm::vec4& color(int x, int y) { forget_cleared_tiles(); return color_[index(x, y)]; }
  const glm::vec4& color(int x, int y) const { return color_[index(x, y)]; }
  float& depth(int x, int y) { forget_cleared_tiles(); return depth_[index(x, y)]; }
  float depth(int x, int y) const { return depth_[index(x, y)]; }

 private:
  friend struct detail::FrameAccess;
  void forget_cleared_tiles() { cleared_.tiles.clear(); }

  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
  }
  int width_;
  int height_;
  std::vector<glm::vec4> color_;
  std::vector<float> depth_;
  detail::ClearedTiles cleared_;
};

namespace detail {
// All a Renderer may do to a target beyond its public interface, while a frame runs: take
// its record of cleared tiles when the frame begins and give back the new one when it
// ends, and write its pixels without that record being forgotten (the renderer keeps the
// record of what the frame writes itself).
struct FrameAccess {
  static ClearedTiles take_cleared_tiles(Target& t) {
    ClearedTiles known = std::move(t.cleared_);
    t.cleared_ = {};
    return known;
  }
  static void set_cleared_tiles(Target& t, ClearedTiles known) { t.cleared_ = std::move(known); }
  static TargetPixels pixels(Target& t) { return {t.color_.data(), t.depth_.data(), t.width_, t.height_}; }
};
}  // namespace detail

// An 8-bit RGBA image, row-major, row 0 at the top: softpbr::image's (image/image.h), which
// also writes it (image::write_png).
using Image8 = image::Image8;

// Linear colour → 8-bit sRGB (colour channels through the exact sRGB curve, alpha
// linear). Values are clamped to [0, 1]; NaN becomes 0. Tone mapping belongs to pbr/.
Image8 resolve_srgb8(const Target& target);

// 64-bit FNV-1a over the colour buffer's float bits (little-endian byte order, row-major,
// RGBA): equal hashes mean equal pixels, for determinism tests and golden checks.
std::uint64_t hash_colors(const Target& target);
// The same over the depth buffer.
std::uint64_t hash_depths(const Target& target);

}  // namespace softpbr::raster
