// Y'CbCr to RGBA8 in integer arithmetic (see yuv.h).
#include "yuv.h"

#include <algorithm>
#include <cstring>

namespace softpbr::image::detail {

namespace {
// 16 fractional bits in the coefficients; the upsampled chroma (and luma, to match) carry 4
// more: one rounding shift of 20 bits a channel.
constexpr int kCoeffBits = 16;
constexpr int kUpBits = 4;
constexpr int kShift = kCoeffBits + kUpBits;

// round(num / den) for num, den > 0.
constexpr std::int64_t div_round(std::int64_t num, std::int64_t den) { return (num + den / 2) / den; }

struct Coefficients {
  std::int64_t y_offset, c_offset;  // in samples
  std::int64_t k_y;                 // 255 · 2^16 / Y's scale
  std::int64_t k_rv, k_gu, k_gv, k_bu;
};

// ITU-T H.273 (8.3): E'R = Y + 2(1 − Kr)·Cr, E'B = Y + 2(1 − Kb)·Cb,
// E'G = Y − (2Kb(1 − Kb)/Kg)·Cb − (2Kr(1 − Kr)/Kg)·Cr, Kg = 1 − Kr − Kb; (8.2) the
// quantisation: full range Y = Ymax·E'Y, C = Ymax·E'C + 2^(d−1); narrow range Y = (219·E'Y + 16)·2^(d−8),
// C = (224·E'C + 128)·2^(d−8). Kr and Kb are exact decimals: rationals over 10 000.
Coefficients coefficients(const YuvPlanes& in) {
  const std::int64_t f = std::int64_t{1} << (in.depth - 8);
  const std::int64_t ymax = (std::int64_t{1} << in.depth) - 1;
  const std::int64_t y_scale = in.full_range ? ymax : 219 * f;
  const std::int64_t c_scale = in.full_range ? ymax : 224 * f;
  Coefficients c{};
  c.y_offset = in.full_range ? 0 : 16 * f;
  c.c_offset = std::int64_t{1} << (in.depth - 1);
  constexpr std::int64_t one = std::int64_t{255} << kCoeffBits;
  c.k_y = div_round(one, y_scale);
  std::int64_t kr = 2990, kb = 1140;
  switch (in.matrix) {
    case YuvMatrix::Bt709: kr = 2126, kb = 722; break;
    case YuvMatrix::Bt2020: kr = 2627, kb = 593; break;
    case YuvMatrix::Bt601:
    case YuvMatrix::Identity: break;
  }
  const std::int64_t kg = 10000 - kr - kb;
  c.k_rv = div_round(one * 2 * (10000 - kr), 10000 * c_scale);
  c.k_bu = div_round(one * 2 * (10000 - kb), 10000 * c_scale);
  c.k_gu = div_round(one * 2 * kb * (10000 - kb), 10000 * kg * c_scale);
  c.k_gv = div_round(one * 2 * kr * (10000 - kr), 10000 * kg * c_scale);
  return c;
}

std::int32_t sample(const std::uint8_t* row, int x, bool wide) {
  if (!wide) return row[x];
  std::uint16_t v;
  std::memcpy(&v, row + 2 * static_cast<std::size_t>(x), 2);
  return v;
}

std::uint8_t to_byte(std::int64_t acc) {
  const std::int64_t v = (acc + (std::int64_t{1} << (kShift - 1))) >> kShift;  // C++20: arithmetic shift
  return static_cast<std::uint8_t>(std::clamp<std::int64_t>(v, 0, 255));
}

// A chroma plane's value at luma column x of the chroma rows `near` and `far` (vertical
// weights 3 and 1, or `near` alone), times 16: the bilinear upsampling of yuv.h.
struct ChromaRow {
  const std::uint8_t* near = nullptr;
  const std::uint8_t* far = nullptr;  // null: no vertical subsampling
  int shift_x = 0, width = 0;
  bool wide = false;

  std::int32_t column(int cx) const {
    const std::int32_t n = sample(near, cx, wide);
    return far == nullptr ? 4 * n : 3 * n + sample(far, cx, wide);
  }
  std::int32_t at(int x) const {
    if (shift_x == 0) return 4 * column(x);
    const int cn = x >> 1;
    const int cf = std::clamp(cn + ((x & 1) != 0 ? 1 : -1), 0, width - 1);
    return 3 * column(cn) + column(cf);
  }
};
}  // namespace

void yuv_to_rgba8(const YuvPlanes& in, std::uint8_t* rgba) {
  const Coefficients k = coefficients(in);
  const bool wide = in.depth > 8;
  const int cw = (in.width + in.chroma_shift_x) >> in.chroma_shift_x;
  const int ch = (in.height + in.chroma_shift_y) >> in.chroma_shift_y;
  const std::int64_t amax = (std::int64_t{1} << in.depth) - 1;
  for (int y = 0; y < in.height; ++y) {
    const std::uint8_t* luma = in.plane[0] + static_cast<std::size_t>(y) * in.row_bytes[0];
    ChromaRow u, v;
    if (!in.monochrome) {
      const int cn = y >> in.chroma_shift_y;
      const int cf = std::clamp(cn + ((y & 1) != 0 ? 1 : -1), 0, ch - 1);
      for (int p = 1; p <= 2; ++p) {
        ChromaRow& r = p == 1 ? u : v;
        r.near = in.plane[p] + static_cast<std::size_t>(cn) * in.row_bytes[p];
        r.far = in.chroma_shift_y != 0 ? in.plane[p] + static_cast<std::size_t>(cf) * in.row_bytes[p] : nullptr;
        r.shift_x = in.chroma_shift_x;
        r.width = cw;
        r.wide = wide;
      }
    }
    const std::uint8_t* alpha = in.alpha != nullptr ? in.alpha + static_cast<std::size_t>(y) * in.alpha_row_bytes : nullptr;
    std::uint8_t* out = rgba + static_cast<std::size_t>(y) * static_cast<std::size_t>(in.width) * 4;
    for (int x = 0; x < in.width; ++x, out += 4) {
      const std::int64_t y16 = (std::int64_t{sample(luma, x, wide)} - k.y_offset) << kUpBits;
      if (in.monochrome) {
        out[0] = out[1] = out[2] = to_byte(k.k_y * y16);
      } else if (in.matrix == YuvMatrix::Identity) {
        // G, B and R coded as they are, each quantised as Y is (H.273, MatrixCoefficients 0).
        out[0] = to_byte(k.k_y * (std::int64_t{v.at(x)} - (k.y_offset << kUpBits)));
        out[1] = to_byte(k.k_y * y16);
        out[2] = to_byte(k.k_y * (std::int64_t{u.at(x)} - (k.y_offset << kUpBits)));
      } else {
        const std::int64_t cb = std::int64_t{u.at(x)} - (k.c_offset << kUpBits);
        const std::int64_t cr = std::int64_t{v.at(x)} - (k.c_offset << kUpBits);
        out[0] = to_byte(k.k_y * y16 + k.k_rv * cr);
        out[1] = to_byte(k.k_y * y16 - k.k_gu * cb - k.k_gv * cr);
        out[2] = to_byte(k.k_y * y16 + k.k_bu * cb);
      }
      std::int64_t a = 255;
      if (alpha != nullptr) a = wide ? div_round(std::int64_t{sample(alpha, x, true)} * 255, amax) : alpha[x];
      out[3] = static_cast<std::uint8_t>(a);
      if (in.alpha_premultiplied && a < 255)
        for (int c = 0; c < 3; ++c)
          out[c] = a == 0 ? 0 : static_cast<std::uint8_t>(std::min<std::int64_t>(255, div_round(std::int64_t{out[c]} * 255, a)));
    }
  }
}

}  // namespace softpbr::image::detail
