// diff.h — `softpbr diff A B`: compare two images (PNG or .hdr) on top of softpbr::golden,
// with a tolerance; exit 0 within it, 1 outside, 2 on any error (as diff(1)). Two models
// (.gltf, .glb, .obj or scene files) are rendered from several views and compared view by
// view (model_diff.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace softpbr::cli {

struct DiffArgs {
  std::string expected, actual;
  double max_diff = 0;          // a pixel differs when a channel differs by more (8-bit codes or float values)
  std::uint64_t max_pixels = 0; // how many pixels may differ
  std::string out;              // heat map (or side by side with --side-by-side), .png
  bool side_by_side = false;
  bool quiet = false;
  // Models (model_diff.h): the views, their image size and the render's settings.
  int views = 8;                      // --views N: the default views (job::default_views)
  std::vector<float> yaws, pitches;   // --yaw/--pitch lists instead
  long width = 512, height = 512;
  std::string json;                   // --json FILE ("-": standard output)
  std::optional<long> threads;
  std::optional<std::string> env, background;
  double max_memory_mib = 0;
  // glTF models: the moment and animation (as `render --time/--animation`), the material
  // variant (`render --variant`), the same for both models.
  std::optional<double> time;
  std::optional<std::string> animation, variant;
};

CLI::App* add_diff_command(CLI::App& app, DiffArgs& args);
int run_diff(const DiffArgs& args);

}  // namespace softpbr::cli
