// Where the shared assets are (../shared beside the source tree, or the folder
// SOFTPBR_SHARED names: a worktree's build), for the suites and benchmarks that use them
// and skip cleanly when they are absent.
#pragma once

#include <cstdlib>
#include <filesystem>

namespace shared_assets {

inline std::filesystem::path folder() {
  if (const char* s = std::getenv("SOFTPBR_SHARED")) return s;
  return std::filesystem::path(SOFTPBR_SOURCE_DIR).parent_path() / "shared";
}

}  // namespace shared_assets
