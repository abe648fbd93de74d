// A target's linear colour as .hdr and .exr files (write.h); moved from pbr's tonemap.cpp,
// since it needs only the target and softpbr::image.
#include "softpbr/raster/write.h"

#include <cmath>
#include <span>
#include <stdexcept>

#include <glm/vec4.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/image/write.h"

namespace softpbr::raster {

namespace {
// 2^stops, as pbr::ToneMapper applies an exposure (dmath: the same bits everywhere).
float exposure_scale(float stops) {
  if (!std::isfinite(stops)) throw std::invalid_argument("exposure: must be a finite number of stops");
  return static_cast<float>(dmath::exp2(stops));
}

// The colour buffer of a target as float RGBA samples (a glm::vec4 is four floats), for
// the image library's writers: no copy of the buffer is made.
image::ImageViewF colour_view(const Target& target) {
  static_assert(sizeof(glm::vec4) == 4 * sizeof(float));
  const std::span<const glm::vec4> colors = target.colors();
  return {target.width(), target.height(),
          std::span<const float>(reinterpret_cast<const float*>(colors.data()), colors.size() * 4)};
}
}  // namespace

void write_hdr(const std::filesystem::path& path, const Target& target, float exposure) {
  if (target.samples() > 1) return write_hdr(path, resolve_box(target), exposure);
  image::write_hdr(path, colour_view(target), exposure_scale(exposure));
}

void write_exr(const std::filesystem::path& path, const Target& target, float exposure) {
  if (target.samples() > 1) return write_exr(path, resolve_box(target), exposure);
  image::write_exr(path, colour_view(target), exposure_scale(exposure));
}

}  // namespace softpbr::raster
