// Content hashes and difference statistics of two images.
#include "softpbr/golden/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "samples.h"

namespace softpbr::golden {

namespace {

// 64-bit FNV-1a (Fowler, Noll, Vo; http://www.isthe.com/chongo/tech/comp/fnv/):
// offset basis and prime of the 64-bit variant.
constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

struct Fnv {
  std::uint64_t h = kFnvOffset;
  void byte(std::uint8_t b) {
    h ^= b;
    h *= kFnvPrime;
  }
  void u32(std::uint32_t v) {  // little-endian whatever the host's byte order
    for (int i = 0; i < 4; ++i) byte(static_cast<std::uint8_t>(v >> (8 * i)));
  }
};

Fnv header(int width, int height, std::uint32_t bytes_per_channel) {
  Fnv f;
  f.u32(static_cast<std::uint32_t>(width));
  f.u32(static_cast<std::uint32_t>(height));
  f.u32(4);
  f.u32(bytes_per_channel);
  return f;
}

template <class Image>
Comparison compare_samples(const Image& expected, const Image& actual, double threshold, double peak) {
  image::check_pixels(expected, "expected");
  image::check_pixels(actual, "actual");
  Comparison c;
  c.expected_width = expected.width;
  c.expected_height = expected.height;
  c.actual_width = actual.width;
  c.actual_height = actual.height;
  c.threshold = threshold;
  c.peak = peak;
  if (!c.same_size()) return c;
  c.pixels = static_cast<std::uint64_t>(expected.width) * static_cast<std::uint64_t>(expected.height);
  std::array<double, 4> sum{};
  double sum_sq = 0;
  for (std::size_t i = 0; i < expected.rgba.size(); i += 4) {
    double largest = 0;
    for (std::size_t ch = 0; ch < 4; ++ch) {
      const double d = detail::sample_diff(expected.rgba[i + ch], actual.rgba[i + ch]);
      c.max_abs_diff[ch] = std::max(c.max_abs_diff[ch], d);
      sum[ch] += d;
      sum_sq += d * d;
      largest = std::max(largest, d);
    }
    if (largest > threshold) ++c.pixels_above;
  }
  const double n = static_cast<double>(c.pixels);
  double all = 0;
  for (std::size_t ch = 0; ch < 4; ++ch) {
    c.mean_abs_diff[ch] = n > 0 ? sum[ch] / n : 0.0;
    all += sum[ch];
  }
  c.mean_abs_diff_all = n > 0 ? all / (4 * n) : 0.0;
  c.rmse = n > 0 ? std::sqrt(sum_sq / (4 * n)) : 0.0;
  c.identical = c.max_diff() == 0;
  c.psnr = c.rmse == 0 ? std::numeric_limits<double>::infinity() : 20.0 * std::log10(peak / c.rmse);
  c.fraction_above = n > 0 ? static_cast<double>(c.pixels_above) / n : 0.0;
  return c;
}

}  // namespace

std::uint64_t content_hash(const Image8& image) {
  image::check_pixels(image, "content_hash");
  Fnv f = header(image.width, image.height, 1);
  for (std::uint8_t b : image.rgba) f.byte(b);
  return f.h;
}

std::uint64_t content_hash(const ImageF& image) {
  image::check_pixels(image, "content_hash");
  Fnv f = header(image.width, image.height, 4);
  for (float v : image.rgba) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    f.u32(bits);
  }
  return f.h;
}

std::uint64_t content_hash(const raster::Target& target) {
  Fnv f = header(target.width(), target.height(), 4);
  for (const glm::vec4& c : target.colors())
    for (int ch = 0; ch < 4; ++ch) {
      std::uint32_t bits;
      std::memcpy(&bits, &c[ch], 4);
      f.u32(bits);
    }
  return f.h;
}

std::string hash_hex(std::uint64_t hash) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash));
  return buf;
}

double Comparison::max_diff() const { return *std::max_element(max_abs_diff.begin(), max_abs_diff.end()); }

std::string Comparison::describe() const {
  std::ostringstream s;
  if (!same_size()) {
    s << "size differs: expected " << expected_width << "x" << expected_height << ", actual " << actual_width << "x"
      << actual_height;
    return s.str();
  }
  s.precision(6);
  if (identical) {
    s << "identical (" << expected_width << "x" << expected_height << ")";
    return s.str();
  }
  s << pixels_above << " of " << pixels << " pixels (" << 100.0 * fraction_above << "%) differ by more than "
    << threshold << "; max |diff| R G B A = " << max_abs_diff[0] << " " << max_abs_diff[1] << " " << max_abs_diff[2]
    << " " << max_abs_diff[3] << "; mean |diff| = " << mean_abs_diff_all << " (R G B A " << mean_abs_diff[0] << " "
    << mean_abs_diff[1] << " " << mean_abs_diff[2] << " " << mean_abs_diff[3] << "); RMSE = " << rmse
    << "; PSNR = " << psnr << " dB (peak " << peak << ")";
  return s.str();
}

Comparison compare(const Image8& expected, const Image8& actual, double threshold) {
  return compare_samples(expected, actual, threshold, 255.0);
}
Comparison compare(const ImageF& expected, const ImageF& actual, double threshold) {
  return compare_samples(expected, actual, threshold, 1.0);
}
Comparison compare(const raster::Target& expected, const raster::Target& actual, double threshold) {
  return compare(to_image(expected), to_image(actual), threshold);
}

}  // namespace softpbr::golden
