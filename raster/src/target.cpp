// Render targets, resolve to 8 bits and content hashes.
#include "softpbr/raster/target.h"

#include <cstring>
#include <stdexcept>
#include <string>

#include "softpbr/raster/color.h"

namespace softpbr::raster {

Target::Target(int width, int height) : width_(width), height_(height) {
  if (width < 1 || height < 1 || width > kMaxTargetSize || height > kMaxTargetSize)
    throw std::invalid_argument("Target: size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is outside 1x1 .. " + std::to_string(kMaxTargetSize) + "x" +
                                std::to_string(kMaxTargetSize));
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  color_.assign(n, glm::vec4(0, 0, 0, 1));
  depth_.assign(n, 1.0f);
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

Image8 resolve_srgb8(const Target& target) {
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
// FNV-1a, 64 bit (offset basis 14695981039346656037, prime 1099511628211), over the bytes
// of each float in little-endian order regardless of the host's byte order.
std::uint64_t fnv1a_floats(const float* values, std::size_t count) {
  std::uint64_t h = 14695981039346656037ull;
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, &values[i], sizeof bits);
    for (int b = 0; b < 4; ++b) {
      h ^= (bits >> (8 * b)) & 0xffu;
      h *= 1099511628211ull;
    }
  }
  return h;
}
}  // namespace

std::uint64_t hash_colors(const Target& target) {
  static_assert(sizeof(glm::vec4) == 4 * sizeof(float));
  return fnv1a_floats(&target.colors().data()->x, target.colors().size() * 4);
}

std::uint64_t hash_depths(const Target& target) {
  return fnv1a_floats(target.depths().data(), target.depths().size());
}

}  // namespace softpbr::raster
