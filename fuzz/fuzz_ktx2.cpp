// libFuzzer target: KTX2 textures (image::load_ktx2, every level; then image::load_image8,
// level 0 as the texture loaders read it): the container walk (ktx2_scan), Zstandard
// levels (libzstd), UASTC blocks and BasisLZ/ETC1S slices.
//
// The input is the file, read from memory under the name "fuzz.ktx2". A std::runtime_error
// whose text starts with the name is a fine outcome; anything else is a finding, as is a
// level whose size is not max(1, w >> l) × max(1, h >> l) of a base within 1x1 .. kMaxSide²,
// or whose pixel count disagrees with its size, or a load_image8 result other than level 0,
// or a decode whose tasks (image::ParallelFor) run in reverse order giving other bytes or
// another error.
// Limits: 64 MiB decoded (a 4096² texture), so that hostile headers stay cheap to test.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "fuzz_support.h"

#include "softpbr/image/ktx2.h"
#include "softpbr/image/load.h"

namespace image = softpbr::image;

namespace {
[[noreturn]] void finding(const char* what) { softpbr::fuzz::finding("fuzz_ktx2", what); }

// The decoder's tasks on this thread, last first.
void reversed(std::size_t count, const std::function<void(std::size_t)>& task) {
  for (std::size_t i = count; i-- > 0;) task(i);
}

// load_ktx2's levels, or its error's text in `error`.
image::Ktx2Image decode(std::span<const std::uint8_t> bytes, std::string_view name, const image::Limits& limits,
                        const image::ParallelFor& parallel, std::string& error) {
  try {
    return image::load_ktx2(bytes, name, limits, nullptr, parallel);
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  return {};
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  constexpr std::string_view kName = "fuzz.ktx2";
  image::Limits limits;
  limits.max_decoded_bytes = std::uint64_t{64} << 20;
  std::string error, error_reversed;
  const image::Ktx2Image k = decode(bytes, kName, limits, {}, error);
  const image::Ktx2Image r = decode(bytes, kName, limits, reversed, error_reversed);
  if (error != error_reversed) finding("tasks in reverse order give another error");
  if (r.levels.size() != k.levels.size()) finding("tasks in reverse order give other levels");
  for (std::size_t l = 0; l < k.levels.size(); ++l)
    if (r.levels[l].rgba != k.levels[l].rgba) finding("tasks in reverse order give other bytes");
  if (!error.empty()) {
    if (std::string_view(error).substr(0, kName.size() + 2) != "fuzz.ktx2: ")
      finding("an error that does not start with the file name");
  } else {
    if (k.levels.empty()) finding("a texture without levels");
    const int w = k.levels[0].width, h = k.levels[0].height;
    if (w < 1 || h < 1 || w > image::kMaxSide || h > image::kMaxSide) finding("level 0 outside the limits");
    for (std::size_t l = 0; l < k.levels.size(); ++l) {
      const image::Image8& im = k.levels[l];
      if (im.width != (w >> l > 0 ? w >> l : 1) || im.height != (h >> l > 0 ? h >> l : 1)) finding("a level of the wrong size");
      if (im.rgba.size() != static_cast<std::size_t>(im.width) * static_cast<std::size_t>(im.height) * 4)
        finding("pixel count disagrees with the size");
    }
    try {
      if (image::load_image8(bytes, kName, limits).rgba != k.levels[0].rgba) finding("load_image8 differs from level 0");
    } catch (const std::runtime_error& e) {
      if (std::string_view(e.what()).substr(0, kName.size() + 2) != "fuzz.ktx2: ")
        finding("an error that does not start with the file name");
    }
  }
  (void)image::read_image_header(bytes);  // never throws, whatever the bytes
  return 0;
}
