// diff.h — `softpbr diff A B`: compare two images (PNG or .hdr) on top of softpbr::golden,
// with a tolerance; exit 0 within it, 1 outside, 2 on any error (as diff(1)).
#pragma once

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

namespace softpbr::cli {

struct DiffArgs {
  std::string expected, actual;
  double max_diff = 0;          // a pixel differs when a channel differs by more (8-bit codes or float values)
  std::uint64_t max_pixels = 0; // how many pixels may differ
  std::string out;              // heat map (or side by side with --side-by-side), .png
  bool side_by_side = false;
  bool quiet = false;
};

CLI::App* add_diff_command(CLI::App& app, DiffArgs& args);
int run_diff(const DiffArgs& args);

}  // namespace softpbr::cli
