// Internal to softpbr_image: Y'CbCr planes to RGBA8 in integer arithmetic, the same bits on
// every CPU — the colour conversion of lossy WebP (VP8) and AVIF (AV1). libwebp and libavif
// convert with SIMD paths of their own (libavif through libyuv when it is there), whose
// rounding this project does not control; their AV1 and VP8 decoders are bit-exact by their
// bitstreams' specifications (integer transforms and filters), so the planes they return are
// the same everywhere and this file makes the rest so (docs/design.md, "WebP and AVIF").
#pragma once

#include <cstddef>
#include <cstdint>

namespace softpbr::image::detail {

// ITU-T H.273 MatrixCoefficients the conversion knows: Kr and Kb in ten-thousandths.
enum class YuvMatrix {
  Identity,  // 0: G = Y, B = Cb, R = Cr (AVIF's lossless RGB; 4:4:4 only)
  Bt709,     // 1: Kr 0.2126, Kb 0.0722
  Bt601,     // 5, 6 (and 2, unspecified, as libavif and browsers read it): Kr 0.299, Kb 0.114
  Bt2020,    // 9 (non-constant luminance): Kr 0.2627, Kb 0.0593
};

struct YuvPlanes {
  int width = 0, height = 0;  // the luma plane's
  int depth = 8;              // 8, 10 or 12 bits a sample; above 8, samples are uint16_t
  // Chroma subsampling: 4:4:4 (0, 0), 4:2:2 (1, 0), 4:2:0 (1, 1); chroma planes are
  // ((width + sx) >> sx) × ((height + sy) >> sy).
  int chroma_shift_x = 0, chroma_shift_y = 0;
  bool monochrome = false;   // 4:0:0: no chroma planes, R = G = B
  bool full_range = false;   // false: "studio swing", Y in 16..235 and C in 16..240 (× 2^(depth − 8))
  YuvMatrix matrix = YuvMatrix::Bt601;
  const std::uint8_t* plane[3] = {nullptr, nullptr, nullptr};  // Y, Cb (U), Cr (V)
  std::size_t row_bytes[3] = {0, 0, 0};
  const std::uint8_t* alpha = nullptr;  // null: opaque; else full range, `depth` bits
  std::size_t alpha_row_bytes = 0;
  bool alpha_premultiplied = false;     // the colour was multiplied by alpha: divided back
};

// width × height × 4 bytes of RGBA8 into `rgba`. Chroma is upsampled bilinearly with the
// chroma samples centred between their luma samples (JPEG's and VP8's siting; AV1's
// chroma_sample_position is not consulted): weights 3/4
// and 1/4 along each subsampled axis (9, 3, 3, 1 sixteenths for 4:2:0), edges clamped. The
// upsampled chroma keeps its 4 extra bits into the conversion, whose coefficients are
// 16-bit fixed point from the matrix's rational Kr and Kb; each channel is rounded once, to
// nearest, and clamped to 0..255.
void yuv_to_rgba8(const YuvPlanes& in, std::uint8_t* rgba);

}  // namespace softpbr::image::detail
