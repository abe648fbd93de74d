// softpbr/raster/target.h — render targets (float RGBA colour + float depth, 1, 4 or 8
// samples a pixel) and their resolve to 8-bit sRGB images.
//
// A Target is what a frame draws into: linear float RGBA (straight values as the shaders
// write them; the "over" blend expects premultiplied alpha) and a float depth buffer,
// row-major with row 0 at the top of the image. A multisampled target (MSAA, 4 or 8
// samples) holds a colour and a depth per sample, at the standard D3D/Vulkan positions
// (sample_positions()); the rasterizer tests coverage, depth and blends per sample and
// shades once per pixel, and resolve_box() averages the samples into one colour a pixel.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "softpbr/image/image.h"

namespace softpbr::raster {

class ThreadPool;

// Largest width or height of a target: keeps fixed-point edge functions inside int64
// (see detail/setup.h) and a 1-sample target under 16384² × 20 bytes ≈ 5 GiB (8× MSAA: 40 GiB,
// which memory estimates such as the command's --max-memory refuse first).
inline constexpr int kMaxTargetSize = 16384;

// Samples a pixel of a target: 1 (no MSAA, the sample at the pixel centre), 4 or 8.
inline constexpr int kMaxSamples = 8;
constexpr bool valid_sample_count(int samples) { return samples == 1 || samples == 4 || samples == 8; }

// A sample's offset from its pixel centre in 1/16 pixel (+x right, +y down), as D3D's
// standard sample patterns and Vulkan's standardSampleLocations give them: 4× (−2, −6),
// (6, −2), (−6, 2), (2, 6); 8× (1, −3), (−1, 3), (5, 1), (−3, −5), (−5, 5), (−7, −1),
// (3, 7), (7, −7). On the rasterizer's grid of 1/256 pixel they are exact (× 16).
struct SampleOffset {
  int x, y;
};
inline constexpr SampleOffset kSamplePattern4[4] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
inline constexpr SampleOffset kSamplePattern8[8] = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5},
                                                    {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
// The offsets of a pattern of `samples` (1: the centre only). Throws std::invalid_argument
// unless valid_sample_count(samples).
std::span<const SampleOffset> sample_offsets(int samples);
// Largest |offset| of any sample of the pattern, in 1/256 pixel (0, 96 or 112).
int sample_reach(int samples);

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

// Where a buffer of `width` × `height` pixels and `samples` samples a pixel keeps the
// depth of sample s of pixel (x, y) (0 ≤ x < width, 0 ≤ y < height). With one sample,
// row-major: y · width + x. A multisampled buffer keeps its depths by 2×2 quads of pixels
// (the rasterizer tests a quad's samples as one vector: at 4× one 64-byte line, not eight
// scattered pairs): quad (x / 2, y / 2) of ⌈width / 2⌉ a row holds 4 · samples depths in a
// row, sample by sample, each sample's four pixels top-left, top-right, bottom-left,
// bottom-right. An odd width or height pads the last quads (they keep the clear value).
constexpr std::size_t depth_index(int width, int samples, int x, int y, int s) {
  if (samples == 1) return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
  const std::size_t quad = static_cast<std::size_t>(y >> 1) * static_cast<std::size_t>((width + 1) / 2) +
                           static_cast<std::size_t>(x >> 1);
  return quad * 4 * static_cast<std::size_t>(samples) + static_cast<std::size_t>(4 * s + 2 * (y & 1) + (x & 1));
}
// The depths such a buffer holds (the padding included).
constexpr std::size_t depth_count(int width, int height, int samples) {
  if (samples == 1) return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  return static_cast<std::size_t>((width + 1) / 2) * static_cast<std::size_t>((height + 1) / 2) * 4 *
         static_cast<std::size_t>(samples);
}

// The pixels of a target as the tile kernels write them: the renderer hands them out
// while a frame owns the target. Pixel (x, y) is i = y · width + x − origin, and sample s
// of pixel i is colors[s · plane + i]; its depth is depths[depth_index(x, y, s)] (the
// layout of raster::depth_index, relative to the top-left pixel (x0, y0)). A whole target
// has origin 0 and plane = width × height; a multisampled tile's samples held apart while
// it is rasterized (a block of width × height pixels whose top-left pixel is (x0, y0),
// both even) has origin y0 · width + x0.
struct TargetPixels {
  glm::vec4* colors;
  float* depths;
  int width;
  int height;
  int samples = 1;
  std::size_t plane = 0;   // width × height
  std::size_t origin = 0;  // y0 · width + x0 (0 for a whole target)
  int x0 = 0, y0 = 0;      // the top-left pixel
  std::size_t depth_index(int x, int y, int s) const {
    return raster::depth_index(width, samples, x - x0, y - y0, s);
  }
};

// What a multisampled target keeps of a frame (GPUs call the second a transient or
// memoryless attachment with a "don't care" store).
//   Kept       every sample, readable after the frame (colors(), hash_colors(),
//              resolve_box(), ...): width × height × samples × 20 bytes.
//   Transient  nothing: a frame's samples live only in the renderer's tile blocks while
//              each tile is drawn, and reach the caller through Renderer::end_frame's tile
//              callback (pbr::render_rgba8 resolves and tone maps there). No sample
//              planes are allocated and none are written back: the same image bytes,
//              ~166 MB less memory and about a fifth less frame time at 1080p 4×.
//              Reading the samples afterwards throws std::logic_error, and a frame must
//              begin by clearing (begin_frame(target, clear)). Planes are allocated (and
//              then kept with the target) only for a frame that needs them: one that goes
//              over the renderer's geometry budget (drawn in several passes) or tiles
//              too large for a block (more than 64 × 64 × 8 samples).
// A 1-sample target is the image itself: it is always Kept.
enum class SampleStorage : std::uint8_t { Kept, Transient };

class Target {
 public:
  // Every sample starts as colour (0, 0, 0, 1), depth 1. With a pool, the pixels are
  // written by its threads: the first touch of a large buffer is the costly part (each
  // page is zeroed by the kernel first; image/memory.h), and at 1080p 4× it is 166 MB.
  // A Transient multisampled target allocates nothing here (see SampleStorage).
  // Throws std::invalid_argument unless 1 <= width, height <= kMaxTargetSize and
  // valid_sample_count(samples).
  Target(int width, int height, int samples = 1, ThreadPool* pool = nullptr,
         SampleStorage storage = SampleStorage::Kept);
  // A depth-only target (a shadow map's): one sample a pixel and its depth alone, 4 bytes a
  // pixel, every depth starting at 1. Only depth-only shaders (shader.h, kDepthOnly) draw
  // into it (Renderer::draw throws std::invalid_argument for others); colors() is empty and
  // read_pixels(), resolve_box() and resolve_srgb8() throw std::logic_error. Throws as the
  // constructor for a size out of range.
  static Target depth_only(int width, int height, ThreadPool* pool = nullptr);
  // Bytes such a target holds.
  static std::uint64_t depth_only_bytes(int width, int height) {
    return static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) * sizeof(float);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }
  // Whether the target keeps no samples between frames (SampleStorage::Transient with
  // more than one sample).
  bool transient() const { return transient_; }
  // Whether the target holds depth alone (depth_only()).
  bool is_depth_only() const { return depth_only_; }
  // Bytes of sample planes the target holds now: bytes(width, height, samples) for a kept
  // target; for a transient one 0 until a frame needed planes (see SampleStorage).
  std::uint64_t allocated_bytes() const {
    return static_cast<std::uint64_t>(color_.size()) * sizeof(glm::vec4) +
           static_cast<std::uint64_t>(depth_.size()) * sizeof(float);
  }

  // Bytes a target of this size holds (colour and depth of every sample), for estimates
  // made before allocating one.
  static std::uint64_t bytes(int width, int height, int samples = 1) {
    return static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) *
               static_cast<std::uint64_t>(samples) * sizeof(glm::vec4) +
           static_cast<std::uint64_t>(depth_count(width, height, samples)) * sizeof(float);
  }

  // The accessors below and clear*() throw std::logic_error for a transient target.
  void clear(glm::vec4 color = {0, 0, 0, 1}, float depth = 1.0f);
  void clear_color(glm::vec4 color);
  void clear_depth(float depth);

  // Direct access to the pixels: index y * width() + x. A multisampled target stores its
  // colour samples as planes: sample s of pixel i at index s * width() * height() + i, so
  // colors() holds samples() planes; its depths by 2×2 quads, sample s of pixel (x, y) at
  // depth_index(width(), samples(), x, y, s) of depths(). color(x, y)/depth(x, y) are
  // sample 0's.
  //
  // A target remembers which of its tiles a renderer's last frame left holding only the
  // frame's clear values; the next frame that clears to the same values leaves those
  // tiles alone instead of writing the same bytes again (GPUs call this a fast clear).
  // The non-const accessors and clear*() forget it, so a span or reference they return
  // may be written freely until the next frame begins on this target (as an iterator,
  // it is not to be written through after that). The const accessors forget nothing.
  std::span<glm::vec4> colors() { forget_cleared_tiles(); return color_; }
  std::span<const glm::vec4> colors() const { require_kept(); return color_; }
  std::span<float> depths() { forget_cleared_tiles(); return depth_; }
  std::span<const float> depths() const { require_kept(); return depth_; }
  glm::vec4& color(int x, int y) { forget_cleared_tiles(); return color_[index(x, y)]; }
  const glm::vec4& color(int x, int y) const { require_kept(); return color_[index(x, y)]; }
  float& depth(int x, int y) { forget_cleared_tiles(); return depth_[depth_at(x, y, 0)]; }
  float depth(int x, int y) const { require_kept(); return depth_[depth_at(x, y, 0)]; }
  const glm::vec4& sample_color(int x, int y, int sample) const {
    require_kept();
    return color_[sample_index(x, y, sample)];
  }
  float sample_depth(int x, int y, int sample) const {
    require_kept();
    return depth_[depth_at(x, y, sample)];
  }

 private:
  friend struct detail::FrameAccess;
  void forget_cleared_tiles() {
    require_kept();
    cleared_.tiles.clear();
  }
  void require_kept() const {
    if (transient_) [[unlikely]]
      throw_transient();
  }
  [[noreturn]] static void throw_transient();
  // A transient target's planes, for a frame that needs them (uninitialized: such a frame
  // clears every tile first).
  void allocate_planes();

  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
  }
  std::size_t sample_index(int x, int y, int sample) const {
    return static_cast<std::size_t>(sample) * static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) +
           index(x, y);
  }
  std::size_t depth_at(int x, int y, int sample) const { return depth_index(width_, samples_, x, y, sample); }
  int width_;
  int height_;
  int samples_;
  bool transient_ = false;
  bool depth_only_ = false;
  // Elements are left unwritten by resize() (the constructor writes each once), not
  // value-initialized; copies are copies.
  template <class T>
  struct ForOverwrite : image::PixelAllocator<T> {
    template <class U>
    struct rebind {
      using other = ForOverwrite<U>;
    };
    ForOverwrite() = default;
    template <class U>
    ForOverwrite(const ForOverwrite<U>&) noexcept {}  // NOLINT: implicit, as std::allocator
    template <class U>
    void construct(U* p) noexcept {
      ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
  };
  std::vector<glm::vec4, ForOverwrite<glm::vec4>> color_;
  std::vector<float, ForOverwrite<float>> depth_;
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
  // A transient target's pixels are its planes once allocate_planes() made them, else
  // null pointers (the renderer then draws every tile in a block).
  static void allocate_planes(Target& t) { t.allocate_planes(); }
  static TargetPixels pixels(Target& t) {
    return {t.depth_only_ ? nullptr : t.color_.data(), t.depth_.data(), t.width_, t.height_, t.samples_,
            static_cast<std::size_t>(t.width_) * static_cast<std::size_t>(t.height_), 0};
  }
};
}  // namespace detail

// An 8-bit RGBA image, row-major, row 0 at the top: softpbr::image's (image/image.h), which
// also writes it (image::write_png).
using Image8 = image::Image8;

// Box-filter resolve of a multisampled target: the mean of each pixel's samples, as a
// pairwise sum in sample order ((s0 + s1) + (s2 + s3), …) times 1/samples, so a pixel whose
// samples are all equal resolves to exactly that value and one half covered by 1 and half
// by 0 to exactly 0.5. Pixels [x0, x1) × [y0, y1) of `source` go to `out` (row-major,
// `out_width` pixels a row, the rectangle's top-left pixel at out[0]). A 1-sample target
// is copied.
void resolve_box(const Target& source, int x0, int y0, int x1, int y1, glm::vec4* out, std::size_t out_width);
// The same from pixels as the renderer hands them out (TargetPixels: a whole target or a
// tile's block of samples); only read.
void resolve_box(const TargetPixels& source, int x0, int y0, int x1, int y1, glm::vec4* out, std::size_t out_width);
// The pixels of a target, to be read only (a view for the functions above).
TargetPixels read_pixels(const Target& target);
// The whole target resolved into a 1-sample target of its size (depth: sample 0's).
Target resolve_box(const Target& source);

// Linear colour → 8-bit sRGB (colour channels through the exact sRGB curve, alpha
// linear). Values are clamped to [0, 1]; NaN becomes 0. Tone mapping belongs to pbr/. A
// multisampled target is resolved first (resolve_box).
Image8 resolve_srgb8(const Target& target);

// XXH3-64 (xxHash, seed 0) over the colour buffer's float bits (little-endian byte order,
// row-major, RGBA; every sample plane in order): equal hashes mean equal pixels, for
// determinism tests and golden checks. The value is the same on every platform.
std::uint64_t hash_colors(const Target& target);
// The same over the depth buffer.
std::uint64_t hash_depths(const Target& target);

}  // namespace softpbr::raster
