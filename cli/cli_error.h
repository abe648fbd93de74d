// cli_error.h — how the softpbr command reports failure: one line on stderr and an exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace softpbr::cli {

// Exit codes (also in `softpbr --help` and docs/scene-format.md).
enum ExitCode : int {
  kExitOk = 0,
  kExitDifferent = 1,  // diff: the images differ beyond the tolerance
  kExitUsage = 2,      // bad command line; for diff, any error (as diff(1) and cmp(1))
  kExitInput = 3,      // a scene, model or image cannot be read or is invalid, or needs too much memory
  kExitOutput = 4,     // an output file cannot be written
  kExitInternal = 5,   // a bug: an unexpected exception
};

inline constexpr const char* kExitCodesHelp =
    "Exit codes:\n"
    "  0  success (diff: the images match within the tolerance)\n"
    "  1  diff: the images differ beyond the tolerance\n"
    "  2  bad command line (diff: any error)\n"
    "  3  invalid or unreadable input: scene file, model, image; or over a limit (memory, lights)\n"
    "  4  an output file cannot be written (nothing partial is left behind)\n"
    "  5  internal error (please report it)\n";

// A failure with its exit code; what() is the whole line to print.
class Error : public std::runtime_error {
 public:
  Error(int code, const std::string& line) : std::runtime_error(line), code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

}  // namespace softpbr::cli
