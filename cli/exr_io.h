// exr_io.h — OpenEXR output and input for the command line, through tinyexr (Debian's
// libtinyexr-dev): 32-bit float RGBA, ZIP compressed, written atomically.
#pragma once

#include <filesystem>

#include "softpbr/golden/image.h"
#include "softpbr/raster/target.h"

namespace softpbr::cli {

// Writes the target's linear colour × 2^exposure and its alpha as float R, G, B, A
// channels (values kept exactly, including negatives; non-finite ones become 0, as in
// .hdr output). Throws std::runtime_error naming the path.
void write_exr(const std::filesystem::path& path, const raster::Target& target, float exposure);

// Reads an OpenEXR file's R, G, B(, A) channels as linear float RGBA (alpha 1 when
// absent): single-part scan-line files, half or float, uncompressed, RLE, ZIPS or ZIP
// (PIZ is refused: tinyexr's PIZ decoder is unsafe on damaged files). Throws
// std::runtime_error naming the path.
golden::ImageF load_exr(const std::filesystem::path& path);

}  // namespace softpbr::cli
