// The integer Y'CbCr → RGBA8 conversion of lossy WebP and AVIF (image/src/yuv.h) against
// ITU-T H.273's equations in double precision: for every matrix, range, depth and
// subsampling, each channel within 1 of the rounded oracle (the fixed-point coefficients'
// error), and exact at the ends of the ranges; the bilinear chroma upsampling's weights.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "yuv.h"

namespace detail = softpbr::image::detail;

namespace {

struct Planes {
  std::vector<std::uint8_t> bytes[4];
  detail::YuvPlanes p;
};

// Planes of samples from `sample(plane, x, y)` (plane 3: alpha), in the layout yuv.h reads.
template <class Sample>
Planes make(int w, int h, int depth, int sx, int sy, Sample sample) {
  Planes out;
  detail::YuvPlanes& p = out.p;
  p.width = w, p.height = h, p.depth = depth, p.chroma_shift_x = sx, p.chroma_shift_y = sy;
  const int size = depth > 8 ? 2 : 1;
  for (int k = 0; k < 4; ++k) {
    const int pw = k == 1 || k == 2 ? (w + sx) >> sx : w;
    const int ph = k == 1 || k == 2 ? (h + sy) >> sy : h;
    out.bytes[k].resize(static_cast<std::size_t>(pw * ph * size));
    for (int y = 0; y < ph; ++y)
      for (int x = 0; x < pw; ++x) {
        const std::uint16_t v = static_cast<std::uint16_t>(sample(k, x, y));
        std::memcpy(out.bytes[k].data() + static_cast<std::size_t>((y * pw + x) * size), &v, static_cast<std::size_t>(size));
      }
    if (k < 3) {
      p.plane[k] = out.bytes[k].data();
      p.row_bytes[k] = static_cast<std::size_t>(pw * size);
    } else {
      p.alpha = out.bytes[3].data();
      p.alpha_row_bytes = static_cast<std::size_t>(pw * size);
    }
  }
  return out;
}

// H.273 (8.2, 8.3) in double, chroma upsampled with yuv.h's weights.
void oracle(const detail::YuvPlanes& p, int x, int y, double rgb[3]) {
  auto at = [&](int k, int cx, int cy) {
    const int pw = (p.width + p.chroma_shift_x) >> p.chroma_shift_x;
    const std::uint8_t* row = p.plane[k] + static_cast<std::size_t>(cy) * p.row_bytes[k];
    if (p.depth == 8) return double(row[cx]);
    std::uint16_t v;
    std::memcpy(&v, row + 2 * cx, 2);
    (void)pw;
    return double(v);
  };
  auto chroma = [&](int k) {
    const int cw = (p.width + p.chroma_shift_x) >> p.chroma_shift_x;
    const int ch = (p.height + p.chroma_shift_y) >> p.chroma_shift_y;
    auto axis = [](int v, int shift, int n, int& near, int& far) {
      near = v >> shift;
      far = shift == 0 ? near : std::clamp(near + ((v & 1) != 0 ? 1 : -1), 0, n - 1);
    };
    int xn, xf, yn, yf;
    axis(x, p.chroma_shift_x, cw, xn, xf);
    axis(y, p.chroma_shift_y, ch, yn, yf);
    const double row_n = 0.75 * at(k, xn, yn) + 0.25 * at(k, xf, yn);
    const double row_f = 0.75 * at(k, xn, yf) + 0.25 * at(k, xf, yf);
    return 0.75 * row_n + 0.25 * row_f;
  };
  const double f = std::ldexp(1.0, p.depth - 8), ymax = std::ldexp(1.0, p.depth) - 1;
  const double yn = p.full_range ? at(0, x, y) / ymax : (at(0, x, y) - 16 * f) / (219 * f);
  double kr = 0.299, kb = 0.114;
  if (p.matrix == detail::YuvMatrix::Bt709) kr = 0.2126, kb = 0.0722;
  if (p.matrix == detail::YuvMatrix::Bt2020) kr = 0.2627, kb = 0.0593;
  const double cb = (chroma(1) - std::ldexp(1.0, p.depth - 1)) / (p.full_range ? ymax : 224 * f);
  const double cr = (chroma(2) - std::ldexp(1.0, p.depth - 1)) / (p.full_range ? ymax : 224 * f);
  const double kg = 1 - kr - kb;
  rgb[0] = yn + 2 * (1 - kr) * cr;
  rgb[1] = yn - 2 * kb * (1 - kb) / kg * cb - 2 * kr * (1 - kr) / kg * cr;
  rgb[2] = yn + 2 * (1 - kb) * cb;
}

int expected_byte(double v) { return static_cast<int>(std::clamp(std::floor(v * 255 + 0.5), 0.0, 255.0)); }

}  // namespace

TEST_CASE("yuv: every matrix, range, depth and subsampling is within 1 of H.273 in double precision") {
  std::mt19937 rng(48);
  int checked = 0, off = 0;
  for (detail::YuvMatrix m : {detail::YuvMatrix::Bt601, detail::YuvMatrix::Bt709, detail::YuvMatrix::Bt2020})
    for (bool full : {false, true})
      for (int depth : {8, 10, 12})
        for (const std::pair<int, int>& sub : {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}}) {
          const int sx = sub.first, sy = sub.second;  // not bindings: CAPTURE's lambda (clang 14)
          CAPTURE(static_cast<int>(m));
          CAPTURE(full);
          CAPTURE(depth);
          CAPTURE(sx);
          CAPTURE(sy);
          std::uniform_int_distribution<int> any(0, (1 << depth) - 1);
          Planes planes = make(9, 7, depth, sx, sy, [&](int, int, int) { return any(rng); });
          planes.p.matrix = m;
          planes.p.full_range = full;
          std::vector<std::uint8_t> rgba(9 * 7 * 4);
          detail::yuv_to_rgba8(planes.p, rgba.data());
          for (int y = 0; y < 7; ++y)
            for (int x = 0; x < 9; ++x) {
              double rgb[3];
              oracle(planes.p, x, y, rgb);
              for (int c = 0; c < 3; ++c) {
                const int got = rgba[static_cast<std::size_t>((y * 9 + x) * 4 + c)];
                const int want = expected_byte(rgb[c]);
                CHECK(std::abs(got - want) <= 1);
                off += got != want;
                ++checked;
              }
              const std::uint8_t* a = planes.p.alpha + static_cast<std::size_t>(y) * planes.p.alpha_row_bytes +
                                      static_cast<std::size_t>(x) * (depth > 8 ? 2 : 1);
              std::uint16_t av = a[0];
              if (depth > 8) std::memcpy(&av, a, 2);
              CHECK(rgba[static_cast<std::size_t>((y * 9 + x) * 4 + 3)] ==
                    expected_byte(double(av) / (std::ldexp(1.0, depth) - 1)));
            }
        }
  // Off by one only where the exact value is within the coefficients' error of a half.
  CHECK(off * 100 <= checked);
}

TEST_CASE("yuv: black, white and grey are exact at the ends of each range and depth") {
  for (bool full : {false, true})
    for (int depth : {8, 10, 12}) {
      CAPTURE(full);
      CAPTURE(depth);
      const int f = 1 << (depth - 8), mid = 1 << (depth - 1), top = (1 << depth) - 1;
      const int black = full ? 0 : 16 * f, white = full ? top : 235 * f;
      for (const std::pair<int, int>& code : {std::pair{black, 0}, std::pair{white, 255}, std::pair{full ? 0 : 0, 0}, std::pair{top, 255}}) {
        const int luma = code.first, want = code.second;  // not bindings: captured by a lambda (clang 14)
        Planes planes = make(1, 1, depth, 0, 0, [&](int k, int, int) { return k == 0 ? luma : k == 3 ? top : mid; });
        planes.p.full_range = full;
        std::uint8_t rgba[4];
        detail::yuv_to_rgba8(planes.p, rgba);
        CHECK(int(rgba[0]) == want);
        CHECK(int(rgba[1]) == want);
        CHECK(int(rgba[2]) == want);
        CHECK(int(rgba[3]) == 255);
      }
    }
}

TEST_CASE("yuv: 4:2:2 chroma is upsampled with weights 3/4 and 1/4, centred, edges clamped") {
  // Identity matrix, full range: R is the upsampled Cr itself.
  const int cr[2] = {0, 252};
  Planes planes = make(4, 1, 8, 1, 0, [&](int k, int x, int) { return k == 2 ? cr[x] : k == 3 ? 255 : 0; });
  planes.p.matrix = detail::YuvMatrix::Identity;
  planes.p.full_range = true;
  std::uint8_t rgba[16];
  detail::yuv_to_rgba8(planes.p, rgba);
  CHECK(int(rgba[0]) == 0);     // x 0: its own sample and its clamped left neighbour
  CHECK(int(rgba[4]) == 63);    // x 1: 3/4 · 0 + 1/4 · 252
  CHECK(int(rgba[8]) == 189);   // x 2: 3/4 · 252 + 1/4 · 0
  CHECK(int(rgba[12]) == 252);  // x 3: clamped right
}

TEST_CASE("yuv: premultiplied colour is divided back by alpha") {
  Planes planes = make(1, 1, 8, 0, 0, [](int k, int, int) { return k == 0 ? 64 : k == 3 ? 128 : 128; });
  planes.p.full_range = true;
  planes.p.alpha_premultiplied = true;
  std::uint8_t rgba[4];
  detail::yuv_to_rgba8(planes.p, rgba);
  CHECK(int(rgba[0]) == 128);  // 64 · 255 / 128 = 127.5 → 128
  CHECK(int(rgba[3]) == 128);
}
