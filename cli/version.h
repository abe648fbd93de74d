// version.h — `softpbr --version` and `softpbr version`: the project version (CMake's
// project(VERSION)), the compiler, the build type and the SIMD targets this binary can
// dispatch its packet kernels to.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace softpbr::cli {

// The lines printed by --version (each ends with '\n'):
//   softpbr 0.1.0
//   compiler   GCC 12.2.0
//   build      Release (optimized)
//   simd       lane widths 1, 4, 8, 16; kernels compiled for baseline (4 lanes), avx2 (8), avx512 (16)
//   this cpu   avx512: 16 lanes by default (--threads and lanes never change the image)
std::string version_text();

CLI::App* add_version_command(CLI::App& app);
int run_version();

}  // namespace softpbr::cli
