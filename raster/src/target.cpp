// Render targets, resolve to 8 bits and content hashes.
#include "softpbr/raster/target.h"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "softpbr/raster/color.h"
#include "softpbr/raster/pool.h"

// xxHash (Debian's libxxhash-dev), compiled into this file: no link dependency.
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace softpbr::raster {

namespace {
constexpr SampleOffset kCentre[1] = {{0, 0}};
void check_samples(int samples) {
  if (!valid_sample_count(samples))
    throw std::invalid_argument("samples: " + std::to_string(samples) + " is not 1, 4 or 8");
}
}  // namespace

std::span<const SampleOffset> sample_offsets(int samples) {
  check_samples(samples);
  if (samples == 4) return kSamplePattern4;
  if (samples == 8) return kSamplePattern8;
  return kCentre;
}

int sample_reach(int samples) {
  int reach = 0;
  for (const SampleOffset& o : sample_offsets(samples)) reach = std::max({reach, std::abs(o.x), std::abs(o.y)});
  return reach * 16;
}

Target::Target(int width, int height, int samples, ThreadPool* pool, SampleStorage storage)
    : width_(width), height_(height), samples_(samples) {
  if (width < 1 || height < 1 || width > kMaxTargetSize || height > kMaxTargetSize)
    throw std::invalid_argument("Target: size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is outside 1x1 .. " + std::to_string(kMaxTargetSize) + "x" +
                                std::to_string(kMaxTargetSize));
  if (!valid_sample_count(samples))
    throw std::invalid_argument("Target: " + std::to_string(samples) + " samples a pixel: expected 1, 4 or 8");
  if (storage == SampleStorage::Transient && samples > 1) {
    transient_ = true;
    return;  // no planes (allocate_planes(), when a frame needs them)
  }
  const std::size_t n =
      static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(samples);
  const std::size_t depths = depth_count(width, height, samples);  // n, or a little more (padding)
  color_.resize(n);
  depth_.resize(depths);
  // Pieces of 2^18 samples (4 MiB of colour, about 1 MiB of depth).
  constexpr std::size_t kPiece = std::size_t{1} << 18;
  const std::size_t pieces = (n + kPiece - 1) / kPiece;
  auto fill = [&](std::size_t k) {
    const std::size_t begin = k * kPiece, end = std::min(n, begin + kPiece);
    std::fill(color_.begin() + static_cast<std::ptrdiff_t>(begin), color_.begin() + static_cast<std::ptrdiff_t>(end),
              glm::vec4(0, 0, 0, 1));
    const std::size_t depth_begin = depths / pieces * k, depth_end = k + 1 == pieces ? depths : depth_begin + depths / pieces;
    std::fill(depth_.begin() + static_cast<std::ptrdiff_t>(depth_begin),
              depth_.begin() + static_cast<std::ptrdiff_t>(depth_end), 1.0f);
  };
  if (pool != nullptr && pieces > 1) {
    pool->parallel_for(pieces, fill);
  } else {
    for (std::size_t k = 0; k < pieces; ++k) fill(k);
  }
}

Target Target::depth_only(int width, int height, ThreadPool* pool) {
  Target t(width, height, 4, nullptr, SampleStorage::Transient);  // checks the size; allocates nothing
  t.samples_ = 1;
  t.transient_ = false;
  t.depth_only_ = true;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  t.depth_.resize(n);
  // Pieces of 2^20 depths (4 MiB), written by the pool's threads as the constructor's.
  constexpr std::size_t kPiece = std::size_t{1} << 20;
  const std::size_t pieces = (n + kPiece - 1) / kPiece;
  auto fill = [&](std::size_t k) {
    const std::size_t begin = k * kPiece, end = std::min(n, begin + kPiece);
    std::fill(t.depth_.begin() + static_cast<std::ptrdiff_t>(begin), t.depth_.begin() + static_cast<std::ptrdiff_t>(end),
              1.0f);
  };
  if (pool != nullptr && pieces > 1) {
    pool->parallel_for(pieces, fill);
  } else {
    for (std::size_t k = 0; k < pieces; ++k) fill(k);
  }
  return t;
}

void Target::throw_transient() {
  throw std::logic_error(
      "Target: a transient multisampled target keeps no samples to read or clear "
      "(SampleStorage::Transient: read the frame in Renderer::end_frame's tile callback)");
}

void Target::allocate_planes() {
  const std::size_t n =
      static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * static_cast<std::size_t>(samples_);
  if (color_.size() != n) color_.resize(n), depth_.resize(depth_count(width_, height_, samples_));
}

void Target::clear(glm::vec4 color, float depth) {
  clear_color(color);
  clear_depth(depth);
}
void Target::clear_color(glm::vec4 color) {
  forget_cleared_tiles();
  std::fill(color_.begin(), color_.end(), color);
}
void Target::clear_depth(float depth) {
  forget_cleared_tiles();
  std::fill(depth_.begin(), depth_.end(), depth);
}

TargetPixels read_pixels(const Target& target) {
  if (target.is_depth_only()) throw std::logic_error("Target: a depth-only target has no colour to read");
  const std::span<const glm::vec4> colors = target.colors();
  const std::span<const float> depths = target.depths();
  return {const_cast<glm::vec4*>(colors.data()), const_cast<float*>(depths.data()), target.width(), target.height(),
          target.samples(), static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(target.height()), 0};
}

void resolve_box(const TargetPixels& source, int x0, int y0, int x1, int y1, glm::vec4* out, std::size_t out_width) {
  const std::size_t plane = source.plane;
  const glm::vec4* c = source.colors;
  const int samples = source.samples;
  for (int y = y0; y < y1; ++y) {
    glm::vec4* o = out + static_cast<std::size_t>(y - y0) * out_width;
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(source.width);
    for (int x = x0; x < x1; ++x, ++o) {
      const glm::vec4* p = c + (row + static_cast<std::size_t>(x) - source.origin);
      if (samples == 1) {
        *o = *p;
      } else if (samples == 4) {
        *o = ((p[0] + p[plane]) + (p[2 * plane] + p[3 * plane])) * 0.25f;
      } else {
        *o = (((p[0] + p[plane]) + (p[2 * plane] + p[3 * plane])) +
              ((p[4 * plane] + p[5 * plane]) + (p[6 * plane] + p[7 * plane]))) *
             0.125f;
      }
    }
  }
}

void resolve_box(const Target& source, int x0, int y0, int x1, int y1, glm::vec4* out, std::size_t out_width) {
  resolve_box(read_pixels(source), x0, y0, x1, y1, out, out_width);
}

Target resolve_box(const Target& source) {
  Target out(source.width(), source.height());
  resolve_box(source, 0, 0, source.width(), source.height(), out.colors().data(), static_cast<std::size_t>(source.width()));
  const std::span<float> depths = out.depths();
  for (int y = 0; y < source.height(); ++y)
    for (int x = 0; x < source.width(); ++x)
      depths[static_cast<std::size_t>(y) * static_cast<std::size_t>(source.width()) + static_cast<std::size_t>(x)] =
          source.sample_depth(x, y, 0);
  return out;
}

Image8 resolve_srgb8(const Target& source) {
  if (source.is_depth_only()) throw std::logic_error("Target: a depth-only target has no colour to resolve");
  if (source.samples() > 1) return resolve_srgb8(resolve_box(source));
  const Target& target = source;
  Image8 image;
  image.width = target.width();
  image.height = target.height();
  const auto colors = target.colors();
  image.rgba.resize(colors.size() * 4);
  std::uint8_t* out = image.rgba.data();
  for (const glm::vec4& c : colors) {
    *out++ = linear_to_srgb8(c.r);
    *out++ = linear_to_srgb8(c.g);
    *out++ = linear_to_srgb8(c.b);
    *out++ = unorm8(c.a);
  }
  return image;
}

namespace {
// XXH3-64 (seed 0) over the bytes of the floats in little-endian order regardless of the
// host's byte order (on a big-endian host in byte-swapped chunks).
std::uint64_t xxh3_floats(const float* values, std::size_t count) {
  static_assert(sizeof(float) == 4);
  if constexpr (std::endian::native == std::endian::little) {
    return XXH3_64bits(values, count * sizeof(float));
  } else {
    XXH3_state_t state;
    XXH3_INITSTATE(&state);
    XXH3_64bits_reset(&state);
    constexpr std::size_t kChunk = 4096;
    std::uint32_t swapped[kChunk];
    for (std::size_t at = 0; at < count; at += kChunk) {
      const std::size_t n = std::min(kChunk, count - at);
      for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, &values[at + i], sizeof bits);
        swapped[i] = (bits >> 24) | ((bits >> 8) & 0xff00u) | ((bits << 8) & 0xff0000u) | (bits << 24);
      }
      XXH3_64bits_update(&state, swapped, n * sizeof(float));
    }
    return XXH3_64bits_digest(&state);
  }
}
}  // namespace

std::uint64_t hash_colors(const Target& target) {
  static_assert(sizeof(glm::vec4) == 4 * sizeof(float));
  return xxh3_floats(&target.colors().data()->x, target.colors().size() * 4);
}

std::uint64_t hash_depths(const Target& target) {
  return xxh3_floats(target.depths().data(), target.depths().size());
}

}  // namespace softpbr::raster
