// softpbr/raster/write.h — a target's linear colour as a float image file (Radiance .hdr,
// OpenEXR), through softpbr::image's writers. The 8-bit output is resolve_srgb8 (target.h)
// or pbr's tone mapping (pbr/tonemap.h, which also names these two as pbr::write_hdr and
// pbr::write_exr).
#pragma once

#include <filesystem>

#include "softpbr/raster/target.h"

namespace softpbr::raster {

// Writes the linear colour (× 2^exposure, no tone map) as a Radiance RGBE .hdr file
// (image::write_hdr: alpha dropped, negative and non-finite values stored as 0),
// atomically; a multisampled target is resolved (resolve_box) first. Throws std::invalid_argument for a non-finite exposure, std::runtime_error
// naming the path when writing fails.
void write_hdr(const std::filesystem::path& path, const Target& target, float exposure = 0.0f);

// The same as OpenEXR (image::write_exr): float R, G, B × 2^exposure and A, kept exactly,
// negatives included, non-finite values as 0; ZIP compressed.
void write_exr(const std::filesystem::path& path, const Target& target, float exposure = 0.0f);

}  // namespace softpbr::raster
