// Script parsing (see script.h).
#include "script.h"

#include <charconv>
#include <cstdint>
#include <string>

#include "softpbr/image/read_file.h"

namespace viewer {

namespace {
std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) words.push_back(line.substr(i, j - i));
    i = j;
  }
  return words;
}

// A word of the script as an error quotes it: in double quotes, at most 40 bytes (then
// "…"), control characters as '?': one short line, as the command's messages (a 15 MB
// line was echoed whole).
std::string shown_word(std::string_view word) {
  constexpr std::size_t kShown = 40;
  std::string out = "\"";
  for (const char c : word.substr(0, kShown)) out += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
  if (word.size() > kShown) out += "…";
  return out + "\"";
}

struct LineParser {
  const std::string& name;
  int line;
  std::vector<std::string_view> words;

  [[noreturn]] void fail(const std::string& what) const {
    throw ScriptError(name + ":" + std::to_string(line) + ": " + what);
  }
  void expect_args(std::size_t lo, std::size_t hi, const char* usage) const {
    const std::size_t n = words.size() - 1;
    if (n < lo || n > hi) fail(std::string("expected \"") + usage + "\"");
  }
  Key key(std::size_t i) const {
    const auto k = key_from_name(words[i]);
    if (!k) fail("unknown key " + shown_word(words[i]) + " (keys: w a s d q e up down left right tab 0-9 n m c r f t v p escape)");
    return *k;
  }
  // Whole pixels, as SDL reports mouse motion.
  float pixels(std::size_t i) const {
    const std::string text(words[i]);
    long v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || v < -kMaxMousePixels || v > kMaxMousePixels)
      fail(shown_word(text) + " is not a whole number of pixels in [-" + std::to_string(kMaxMousePixels) + ", " +
           std::to_string(kMaxMousePixels) + "]");
    return static_cast<float>(v);
  }
  long count(std::size_t i) const {
    const std::string text(words[i]);
    long v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || v < 1 || v > kMaxScriptFrames)
      fail("frame count " + shown_word(text) + " is not a whole number in [1, " + std::to_string(kMaxScriptFrames) + "]");
    return v;
  }
};
}  // namespace

std::vector<ScriptCommand> parse_script(std::string_view text, const std::string& name) {
  std::vector<ScriptCommand> commands;
  int line_number = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    LineParser p{name, line_number, split_words(line)};
    if (p.words.empty()) continue;
    const std::string_view verb = p.words[0];
    ScriptCommand c;
    c.line = line_number;
    if (verb == "press") {
      p.expect_args(1, 1, "press KEY");
      c.event = KeyDown{p.key(1)};
      commands.push_back(c);
      c.event = KeyUp{p.key(1)};
    } else if (verb == "down") {
      p.expect_args(1, 1, "down KEY");
      c.event = KeyDown{p.key(1)};
    } else if (verb == "up") {
      p.expect_args(1, 1, "up KEY");
      c.event = KeyUp{p.key(1)};
    } else if (verb == "mouse") {
      p.expect_args(2, 2, "mouse DX DY");
      c.event = MouseMotion{p.pixels(1), p.pixels(2)};
    } else if (verb == "frame") {
      p.expect_args(0, 1, "frame [N]");
      c.kind = ScriptCommand::Kind::Frames;
      c.frames = p.words.size() == 2 ? p.count(1) : 1;
    } else if (verb == "screenshot") {
      p.expect_args(1, 1, "screenshot FILE");
      c.kind = ScriptCommand::Kind::Screenshot;
      c.path = std::string(p.words[1]);
    } else if (verb == "drop") {
      p.expect_args(1, 1, "drop FILE");
      c.kind = ScriptCommand::Kind::Drop;
      c.path = std::string(p.words[1]);
    } else if (verb == "quit") {
      p.expect_args(0, 0, "quit");
      c.kind = ScriptCommand::Kind::Quit;
    } else {
      p.fail("unknown command " + shown_word(verb) + " (commands: press down up mouse frame screenshot drop quit)");
    }
    commands.push_back(c);
  }
  return commands;
}

std::vector<ScriptCommand> load_script(const std::filesystem::path& path) {
  constexpr std::uint64_t kMaxBytes = 16u << 20;  // a script is a few lines; refuse absurd files
  std::string text;
  // Never waits on a named pipe or a device (read_file.h).
  if (const softpbr::image::FileProblem p = softpbr::image::read_whole_file(path, kMaxBytes, text)) {
    if (p.too_large) throw ScriptError(path.string() + ": script is larger than 16 MiB");
    throw ScriptError(path.string() + ": cannot read the script (" + p.reason + ")");
  }
  return parse_script(text, path.string());
}

}  // namespace viewer
