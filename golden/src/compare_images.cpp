// Images to look at: a heat map of the difference of two images, and the two images with
// the heat map side by side.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "softpbr/golden/compare.h"
#include "samples.h"

namespace softpbr::golden {

namespace {

template <class Image>
void check_same_size(const Image& expected, const Image& actual) {
  image::check_pixels(expected, "diff_image: expected");
  image::check_pixels(actual, "diff_image: actual");
  if (expected.width != actual.width || expected.height != actual.height)
    throw std::invalid_argument("diff_image: sizes differ: expected " + std::to_string(expected.width) + "x" +
                                std::to_string(expected.height) + ", actual " + std::to_string(actual.width) + "x" +
                                std::to_string(actual.height));
}

std::uint8_t code(double v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5); }

template <class Image>
Image8 heat_map(const Image& expected, const Image& actual, double scale) {
  check_same_size(expected, actual);
  const std::size_t n = expected.rgba.size() / 4;
  std::vector<double> d(n, 0.0);
  double largest_finite = 0;
  for (std::size_t p = 0; p < n; ++p) {
    for (std::size_t ch = 0; ch < 4; ++ch) d[p] = std::max(d[p], detail::sample_diff(expected.rgba[4 * p + ch], actual.rgba[4 * p + ch]));
    if (std::isfinite(d[p])) largest_finite = std::max(largest_finite, d[p]);
  }
  if (!(scale > 0)) scale = largest_finite;
  Image8 out{expected.width, expected.height, image::PixelVector<std::uint8_t>(n * 4)};
  for (std::size_t p = 0; p < n; ++p) {
    std::uint8_t* px = &out.rgba[4 * p];
    px[3] = 255;
    if (d[p] == 0) continue;  // black
    // s in (1/3, 1]: the ramp black → red (1/3) → yellow (2/3) → white (1).
    const double t = (std::isfinite(d[p]) && scale > 0) ? std::min(d[p] / scale, 1.0) : 1.0;
    const double s = 1.0 / 3.0 + 2.0 / 3.0 * t;
    px[0] = code(3 * s);
    px[1] = code(3 * s - 1);
    px[2] = code(3 * s - 2);
  }
  return out;
}

Image8 black(int width, int height) {
  Image8 out{width, height, image::PixelVector<std::uint8_t>(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4, 0)};
  for (std::size_t i = 3; i < out.rgba.size(); i += 4) out.rgba[i] = 255;
  return out;
}

// Copies `src` into `dst` with its top-left corner at column x0.
void blit(Image8& dst, const Image8& src, int x0) {
  for (int y = 0; y < src.height; ++y)
    std::memcpy(&dst.rgba[(static_cast<std::size_t>(y) * dst.width + x0) * 4],
                &src.rgba[static_cast<std::size_t>(y) * src.width * 4], static_cast<std::size_t>(src.width) * 4);
}

Image8 columns(const Image8& a, const Image8& b, const Image8* diff) {
  const int width = a.width + b.width + (diff ? diff->width : 0);
  Image8 out = black(width, std::max(a.height, b.height));
  blit(out, a, 0);
  blit(out, b, a.width);
  if (diff) blit(out, *diff, a.width + b.width);
  return out;
}

}  // namespace

Image8 diff_image(const Image8& expected, const Image8& actual, double scale) {
  return heat_map(expected, actual, scale);
}
Image8 diff_image(const ImageF& expected, const ImageF& actual, double scale) {
  return heat_map(expected, actual, scale);
}
Image8 diff_image(const raster::Target& expected, const raster::Target& actual, double scale) {
  return heat_map(to_image(expected), to_image(actual), scale);
}

Image8 side_by_side(const Image8& expected, const Image8& actual, double scale) {
  image::check_pixels(expected, "side_by_side: expected");
  image::check_pixels(actual, "side_by_side: actual");
  if (expected.width != actual.width || expected.height != actual.height) return columns(expected, actual, nullptr);
  const Image8 diff = diff_image(expected, actual, scale);
  return columns(expected, actual, &diff);
}

Image8 side_by_side(const ImageF& expected, const ImageF& actual, double scale) {
  const Image8 e = to_srgb8(expected), a = to_srgb8(actual);
  if (e.width != a.width || e.height != a.height) return columns(e, a, nullptr);
  const Image8 diff = diff_image(expected, actual, scale);
  return columns(e, a, &diff);
}

Image8 side_by_side(const raster::Target& expected, const raster::Target& actual, double scale) {
  return side_by_side(to_image(expected), to_image(actual), scale);
}

}  // namespace softpbr::golden
