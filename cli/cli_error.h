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

// `what` as one bounded line for stderr: control characters (a newline or NUL from a name
// in the input) become '?', trailing newlines go, and over kMaxLine bytes it is cut.
inline std::string printable_line(const std::string& what) {
  constexpr std::size_t kMaxLine = 2000;
  std::string line = what.substr(0, kMaxLine);
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r' || line.back() == ' ')) line.pop_back();
  for (char& c : line)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  if (what.size() > kMaxLine) line += "...";
  return line;
}

// A failure with its exit code; what() is the whole line to print.
class Error : public std::runtime_error {
 public:
  Error(int code, const std::string& line) : std::runtime_error(line), code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

}  // namespace softpbr::cli
