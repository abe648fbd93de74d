// `softpbr --version` (see version.h). SOFTPBR_VERSION and SOFTPBR_BUILD_TYPE come from
// cli/CMakeLists.txt (this file only), the compiler from its own macros.
#include "version.h"

#include <cstdio>

#include "cli_error.h"
#include "softpbr/simd/isa.h"
#include "softpbr/simd/simd.h"

#ifndef SOFTPBR_VERSION
#define SOFTPBR_VERSION "unknown"
#endif
#ifndef SOFTPBR_BUILD_TYPE
#define SOFTPBR_BUILD_TYPE "unknown"
#endif

namespace softpbr::cli {

namespace {

std::string compiler() {
#if defined(__clang__)
  std::string c = "Clang " __clang_version__;  // "14.0.6 " (a trailing space)
#elif defined(__GNUC__)
  std::string c = "GCC " __VERSION__;
#else
  std::string c = "unknown";
#endif
  while (!c.empty() && c.back() == ' ') c.pop_back();
  return c;
}

const char* architecture() {
#if defined(__x86_64__)
  return "x86-64";
#elif defined(__aarch64__)
  return "AArch64";
#else
  return "other";
#endif
}

int default_lanes(simd::Isa isa) {
  // As raster::Renderer picks them when RendererOptions::lanes is 0 (renderer.cpp).
  return isa == simd::Isa::Avx512 ? 16 : isa == simd::Isa::Avx2 ? 8 : simd::kNativeWidth;
}

}  // namespace

std::string version_text() {
  std::string build = SOFTPBR_BUILD_TYPE;
  if (build.empty()) build = "none";
#if defined(__OPTIMIZE__)
  build += " (optimized)";
#else
  build += " (not optimized)";
#endif
  std::string kernels = "baseline (" + std::to_string(simd::kNativeWidth) + " lanes)";
  // What raster::Renderer picks by default: the CPU's instruction set and its lane width.
  const simd::Isa cpu = simd::cpu_isa();
  std::string note = " (the image is the same for any width)";
#if SOFTPBR_SIMD_X86_TARGETS
  kernels += ", avx2 (8), avx512 (16)";
#else
  // Unoptimized builds compile no AVX2/AVX-512 copies: the widths run on the baseline
  // copy of every kernel (softpbr/simd/isa.h).
  if (cpu != simd::Isa::Baseline) note = ", run by the baseline kernels (this build has no " + std::string(simd::isa_name(cpu)) + " copies)";
#endif
  std::string text = "softpbr " SOFTPBR_VERSION "\n";
  text += "compiler   " + compiler() + ", " + architecture() + "\n";
  text += "build      " + build + ", -ffp-contract=off\n";
  text += "simd       lane widths 1, 4, 8, 16; kernels compiled for " + kernels + "\n";
  text += "this cpu   " + std::string(simd::isa_name(cpu)) + ": " + std::to_string(default_lanes(cpu)) +
          " lanes by default" + note + "\n";
  return text;
}

CLI::App* add_version_command(CLI::App& app) {
  app.set_version_flag("--version", [] {
    std::string t = version_text();
    if (!t.empty() && t.back() == '\n') t.pop_back();  // CLI11 adds the newline
    return t;
  }, "Print the version, compiler, build type and SIMD targets, and exit");
  CLI::App* c = app.add_subcommand("version", "Print the version, compiler, build type and SIMD targets (as --version)");
  return c;
}

int run_version() {
  std::fputs(version_text().c_str(), stdout);
  return std::fflush(stdout) == 0 && !std::ferror(stdout) ? kExitOk : kExitOutput;
}

}  // namespace softpbr::cli
