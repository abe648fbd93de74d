// A file name in a suite's scratch folder under the build tree (made if missing), for the
// suites that link no golden helpers (golden_helpers.h's scratch() gives a fresh folder per case).
#pragma once

#include <filesystem>
#include <string>

namespace test_files {

inline std::filesystem::path scratch_file(const std::string& suite, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(SOFTPBR_BINARY_DIR) / suite;
  std::filesystem::create_directories(dir);
  return dir / name;
}

}  // namespace test_files
