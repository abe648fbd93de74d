// softpbr/image/image.h — softpbr::image, the images the other libraries share: 8-bit and
// float RGBA pixels, const views of them, and the limits a loader checks before decoding.
//
// Both pixel types are RGBA, row-major, row 0 at the top:
//   Image8 — 8-bit codes, what a PNG or JPEG holds (sRGB-encoded colour, linear alpha);
//   ImageF — 32-bit floats, linear, what a render target, an .hdr or an .exr file holds.
// Loading is in load.h, writing in write.h. The library sits below raster, pbr and golden
// (image ← raster ← pbr ← golden, cli) and depends on nothing of theirs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "softpbr/image/memory.h"

namespace softpbr::image {

// Largest width or height of an image: raster::kMaxTargetSize, the largest render.
inline constexpr int kMaxSide = 16384;

// An 8-bit RGBA image.
// The pixels live in a PixelVector (memory.h: large buffers in huge pages); a std::vector
// of pixels is accepted too, and copied.
struct Image8 {
  int width = 0;
  int height = 0;
  PixelVector<std::uint8_t> rgba;  // width * height * 4 bytes

  Image8() = default;
  Image8(int w, int h, PixelVector<std::uint8_t> pixels) : width(w), height(h), rgba(std::move(pixels)) {}
  template <class Allocator>  // a template, so that {w, h, {}} picks the PixelVector
  Image8(int w, int h, const std::vector<std::uint8_t, Allocator>& pixels)
      : width(w), height(h), rgba(pixels.begin(), pixels.end()) {}
};

// A linear float RGBA image.
struct ImageF {
  int width = 0;
  int height = 0;
  PixelVector<float> rgba;  // width * height * 4 floats

  ImageF() = default;
  ImageF(int w, int h, PixelVector<float> pixels) : width(w), height(h), rgba(std::move(pixels)) {}
  template <class Allocator>
  ImageF(int w, int h, const std::vector<float, Allocator>& pixels)
      : width(w), height(h), rgba(pixels.begin(), pixels.end()) {}
};

// A const, non-owning view of RGBA samples: an Image8/ImageF, a render target's colour
// buffer, or a texture's pixels elsewhere. It does not own the samples; they must outlive it.
template <class Sample>
struct ImageView {
  int width = 0;
  int height = 0;
  std::span<const Sample> rgba;  // width * height * 4 samples

  ImageView() = default;
  ImageView(int w, int h, std::span<const Sample> samples) : width(w), height(h), rgba(samples) {}
  template <class Image>
    requires requires(const Image& im) { std::span<const Sample>(im.rgba); }
  ImageView(const Image& image) : width(image.width), height(image.height), rgba(image.rgba) {}  // NOLINT: implicit
};
using ImageView8 = ImageView<std::uint8_t>;
using ImageViewF = ImageView<float>;

// Throws std::invalid_argument("<what>: image size WxH and pixel data (N samples) disagree")
// unless the image holds width × height × 4 samples and neither side is negative.
void check_pixels(const ImageView8& image, std::string_view what);
void check_pixels(const ImageViewF& image, std::string_view what);

// What a loader accepts, checked from the file's header before anything is decoded.
struct Limits {
  // Largest width or height; values above kMaxSide mean kMaxSide.
  int max_side = kMaxSide;
  // Largest number of bytes of decoded pixels: width × height × 4 (Image8) or × 16
  // (ImageF), plus the decoder's planes where they can outgrow that — a JPEG's component
  // planes (1 byte a sample, 3 in a progressive file, which keeps 16-bit coefficients too)
  // and an OpenEXR file's channel planes (4 bytes a channel a pixel; a file may hold any
  // number of channels). The default, 1 GiB, admits a 16384² PNG, an 8192² JPEG or an
  // 8192² float image. stb_image also holds its own copy of the result while it runs, so
  // the peak is below twice the bound.
  std::uint64_t max_decoded_bytes = std::uint64_t{1} << 30;
  // Largest file the path overloads read into memory (the buffer overloads do not check it).
  std::uint64_t max_file_bytes = std::uint64_t{1} << 30;
};

}  // namespace softpbr::image
