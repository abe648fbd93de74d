// libFuzzer target: AVIF textures (image::load_avif, then image::load_image8 as the texture
// loaders read them, and read_image_header): the header checks and size limits before
// decoding, libavif's decoder, and softpbr's integer Y'CbCr conversion (image/src/yuv.h).
//
// The input is the file, read from memory under the name "fuzz.avif". A std::runtime_error
// whose text starts with the name and holds one line is a fine outcome; anything else is a
// finding, as is an image outside 1x1 .. kMaxSide², pixels that disagree with its size, a
// load_image8 result that differs, or a header whose size differs from the decoded one.
// Limits: 64 MiB decoded, so that hostile headers stay cheap to test.
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string_view>

#include "fuzz_support.h"

#include "softpbr/image/load.h"

namespace image = softpbr::image;

namespace {
[[noreturn]] void finding(const char* what) { softpbr::fuzz::finding("fuzz_avif", what); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  constexpr std::string_view kName = "fuzz.avif";
  image::Limits limits;
  limits.max_decoded_bytes = std::uint64_t{64} << 20;
  try {
    const image::Image8 im = image::load_avif(bytes, kName, limits);
    if (im.width < 1 || im.height < 1 || im.width > image::kMaxSide || im.height > image::kMaxSide)
      finding("an image outside the limits");
    if (im.rgba.size() != static_cast<std::size_t>(im.width) * static_cast<std::size_t>(im.height) * 4)
      finding("pixel count disagrees with the size");
    if (image::load_image8(bytes, kName, limits).rgba != im.rgba) finding("load_image8 differs from load_avif");
    const image::ImageHeader h = image::read_image_header(bytes);
    if (h.format != "avif" || h.width != im.width || h.height != im.height) finding("the header's size differs from the image's");
  } catch (const std::runtime_error& e) {
    const std::string_view what(e.what());
    if (what.substr(0, kName.size() + 2) != "fuzz.avif: ") finding("an error that does not start with the file name");
    if (what.find('\n') != std::string_view::npos) finding("an error of more than one line");
  }
  (void)image::read_image_header(bytes);  // never throws, whatever the bytes
  return 0;
}
