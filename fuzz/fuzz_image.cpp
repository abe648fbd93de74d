// libFuzzer target: PNG and Radiance .hdr loading (golden::load_png, golden::load_hdr).
//
// The first byte chooses the loader (even: load_png into fuzz.png, odd: load_hdr into
// fuzz.hdr); the rest is the file, written to a private temporary folder. A
// std::runtime_error whose text starts with the path is a fine outcome; anything else is a
// finding, as is a loaded image whose size is outside 1x1 .. kMaxTargetSize² or whose
// pixel count disagrees with its size. A hostile header may claim up to 16384² pixels
// (1 GiB of RGBA8, 4 GiB of float): the run's -rss_limit_mb decides whether such claims
// are bounded well enough.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "fuzz_support.h"

#include "softpbr/golden/image.h"

namespace fs = std::filesystem;
namespace golden = softpbr::golden;
namespace raster = softpbr::raster;

namespace {

[[noreturn]] void finding(const char* what) { softpbr::fuzz::finding("fuzz_image", what); }

const fs::path& folder() { return softpbr::fuzz::private_folder("image"); }

void check_size(int width, int height, std::size_t values, std::size_t per_pixel) {
  if (width < 1 || height < 1 || width > raster::kMaxTargetSize || height > raster::kMaxTargetSize)
    finding("loaded image size outside the limits");
  if (values != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * per_pixel)
    finding("pixel count disagrees with the size");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool hdr = (data[0] & 1) != 0;
  const fs::path path = folder() / (hdr ? "fuzz.hdr" : "fuzz.png");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
    if (!out) finding("cannot write the temporary input file");
  }
  try {
    if (hdr) {
      const golden::ImageF image = golden::load_hdr(path);
      check_size(image.width, image.height, image.rgba.size(), 4);
      for (std::size_t i = 0; i < image.rgba.size(); ++i)
        if (!std::isfinite(image.rgba[i]) || image.rgba[i] < 0.0f) finding("HDR value negative or not finite");
    } else {
      const golden::Image8 image = golden::load_png(path);
      check_size(image.width, image.height, image.rgba.size(), 4);
    }
  } catch (const std::runtime_error& e) {
    if (std::string_view(e.what()).substr(0, path.string().size()) != path.string())
      finding("an error that does not start with the file name");
  }
  return 0;
}
