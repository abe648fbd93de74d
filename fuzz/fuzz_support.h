// fuzz_support.h — what the file-reading fuzz targets share: a private temporary folder
// for the input files (the loaders take paths), and how a finding stops the run.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace softpbr::fuzz {

// A finding: say what, then abort so libFuzzer saves the input.
[[noreturn]] inline void finding(const char* target, const char* what) {
  std::fprintf(stderr, "%s: %s\n", target, what);
  std::abort();
}

// softpbr-fuzz-<name>-<pid> under the system's temporary folder, made on first use and
// removed when the fuzzer exits. One per process: each target calls it with one name.
inline const std::filesystem::path& private_folder(const char* name) {
  struct Folder {
    std::filesystem::path path;
    explicit Folder(const char* name)
        : path(std::filesystem::temp_directory_path() /
               ("softpbr-fuzz-" + std::string(name) + "-" + std::to_string(::getpid()))) {
      std::filesystem::create_directories(path);
    }
    ~Folder() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Folder folder(name);
  return folder.path;
}

}  // namespace softpbr::fuzz
