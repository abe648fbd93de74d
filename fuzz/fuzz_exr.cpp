// libFuzzer target: OpenEXR loading (image::load_exr: `softpbr diff` inputs, environment
// maps), with tinyexr compiled in.
//
// The input is the file, written to a private temporary folder as fuzz.exr. A
// std::runtime_error whose text starts with the path is a fine outcome; anything else is a
// finding, as is a loaded image whose pixel count disagrees with its size.
#include <unistd.h>

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

#include "softpbr/image/load.h"

namespace fs = std::filesystem;

namespace {

[[noreturn]] void finding(const char* what) { softpbr::fuzz::finding("fuzz_exr", what); }

const fs::path& folder() { return softpbr::fuzz::private_folder("exr"); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path path = folder() / "fuzz.exr";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) finding("cannot write the temporary input file");
  }
  try {
    const softpbr::image::ImageF image = softpbr::image::load_exr(path);
    if (image.width < 1 || image.height < 1 ||
        image.rgba.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4)
      finding("loaded image size disagrees with its pixels");
  } catch (const std::runtime_error& e) {
    if (std::string_view(e.what()).substr(0, path.string().size()) != path.string())
      finding("an error that does not start with the file name");
  }
  return 0;
}
