// libFuzzer target: PNG, JPEG and Radiance .hdr loading (image::load_image8, which reads
// PNG or JPEG by the first bytes, and image::load_hdr), with stb_image compiled in.
//
// The first byte chooses the loader (even: load_image8 on fuzz.img, and with bit 1 set
// also load_png16 on the buffer, `softpbr diff`'s 16-bit reading; odd: load_hdr on
// fuzz.hdr); the rest is the file, written to a private temporary folder (the path form
// reads it and runs the buffer form). A std::runtime_error whose text starts with the path
// is a fine outcome; anything else is a finding, as is a loaded image whose size is outside
// 1x1 .. kMaxSide² or whose pixel count disagrees with its size. A hostile header may claim
// up to the default Limits (1 GiB decoded): the run's -rss_limit_mb decides whether such
// claims are bounded well enough.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <span>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "fuzz_support.h"

#include "softpbr/image/load.h"

namespace fs = std::filesystem;
namespace image = softpbr::image;

namespace {

[[noreturn]] void finding(const char* what) { softpbr::fuzz::finding("fuzz_image", what); }

const fs::path& folder() { return softpbr::fuzz::private_folder("image"); }

void check_size(int width, int height, std::size_t values, std::size_t per_pixel) {
  if (width < 1 || height < 1 || width > image::kMaxSide || height > image::kMaxSide)
    finding("loaded image size outside the limits");
  if (values != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * per_pixel)
    finding("pixel count disagrees with the size");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool hdr = (data[0] & 1) != 0;
  const fs::path path = folder() / (hdr ? "fuzz.hdr" : "fuzz.img");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
    if (!out) finding("cannot write the temporary input file");
  }
  try {
    if (hdr) {
      const image::ImageF loaded = image::load_hdr(path);
      check_size(loaded.width, loaded.height, loaded.rgba.size(), 4);
      for (std::size_t i = 0; i < loaded.rgba.size(); ++i)
        if (!std::isfinite(loaded.rgba[i]) || loaded.rgba[i] < 0.0f) finding("HDR value negative or not finite");
    } else if ((data[0] & 2) != 0) {
      const image::ImageF loaded = image::load_png16(std::span<const std::uint8_t>(data + 1, size - 1), path.string());
      check_size(loaded.width, loaded.height, loaded.rgba.size(), 4);
      for (const float v : loaded.rgba)
        if (!(v >= 0.0f && v <= 65535.0f) || v != std::floor(v)) finding("a 16-bit sample that is not a code 0..65535");
    } else {
      const image::Image8 loaded = image::load_image8(path);
      check_size(loaded.width, loaded.height, loaded.rgba.size(), 4);
    }
  } catch (const std::runtime_error& e) {
    if (std::string_view(e.what()).substr(0, path.string().size()) != path.string())
      finding("an error that does not start with the file name");
  }
  return 0;
}
