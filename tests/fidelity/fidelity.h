// tests/fidelity/fidelity.h — softpbr measured against the fidelity references of
// ../shared/fidelity (README.md there gives the protocol): for each of four Khronos models,
// the exact camera, the model's mask, three.js r187's render and Blender Cycles' path-traced
// render at 256 samples a pixel, all through three.js's ACES display transform.
//
// measure() renders a model as the protocol says — studio_small_03_1k.hdr at intensity 1,
// turned -90° (the protocol's orientation in softpbr's convention), seen as the background,
// 512×512, 4× MSAA, the model's own materials, no other light — takes its linear colour
// through three.js's ACES (aces_threejs) and returns the PSNR of its model pixels against
// each reference. Used by the `softpbr_fidelity` tool (the README's table) and by the test
// that holds the targets (test_fidelity.cpp, skipped without ../shared).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "softpbr/image/image.h"
#include "softpbr/job/render_job.h"
#include "softpbr/raster/renderer.h"

namespace softpbr::fidelity {

// The models of the protocol, in the README's order.
const std::vector<std::string>& models();

// ../shared relative to the source tree, or empty when it is not there.
std::filesystem::path find_shared(const std::filesystem::path& source_dir);

// three.js r187's ACESFilmic display transform of one linear Rec.709 colour (exposure 1:
// × 1/0.6, the fitted RRT+ODT, clamp) and the exact sRGB curve, rounded to 8 bits, in
// double. The README's formula.
void aces_threejs(const float linear[3], std::uint8_t out[3]);

// PSNR in dB over the three channels of the pixels where `mask` is not magenta
// (#ff00ff); +inf for identical pixels. The images must have the mask's size.
double masked_psnr(const image::Image8& a, const image::Image8& b, const image::Image8& mask);

struct Result {
  std::string model;
  std::size_t pixels = 0;          // the mask's model pixels
  double vs_cycles = 0.0;          // softpbr vs cycles_256spp_aces.png, dB
  double vs_threejs = 0.0;         // softpbr vs threejs_aces.png
  double threejs_vs_cycles = 0.0;  // the peer against the path tracer (the README's figures)
  image::Image8 image;             // softpbr's frame through aces_threejs
};

// Renders `model` by the protocol with `renderer` (any threads: the same image) and
// measures it. `settings` may add to the protocol's (e.g. occlusion off); its size, MSAA,
// environment and tone mapping are the protocol's. Throws std::runtime_error naming a
// missing reference file.
Result measure(const std::filesystem::path& shared, const std::string& model, raster::Renderer& renderer,
               job::Settings settings = {});

}  // namespace softpbr::fidelity
