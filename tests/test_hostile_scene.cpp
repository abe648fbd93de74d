// Hostile scene files at the limits: nesting 10^6 levels deep is a one-line error
// naming the file and JSON pointer, in bounded time and memory (no recursion per level).
#include <doctest/doctest.h>

#include <string>

#include "softpbr/pbr/scene_file.h"

namespace pbr = softpbr::pbr;

namespace {

// The SceneFileError message of parsing `text` as "hostile.json", or "" if it loads.
std::string error_of(const std::string& text) {
  try {
    pbr::parse_scene_file(text, "hostile.json", SOFTPBR_SOURCE_DIR);
  } catch (const pbr::SceneFileError& e) {
    return e.what();
  }
  return "";
}

std::string repeat(const std::string& s, std::size_t n) {
  std::string out;
  out.reserve(s.size() * n);
  for (std::size_t i = 0; i < n; ++i) out += s;
  return out;
}

}  // namespace

TEST_CASE("scene files nested 10^6 levels deep are refused at the nesting limit, on one line") {
  constexpr std::size_t kDepth = 1'000'000;
  struct Case {
    const char* name;
    std::string text;
  };
  const Case cases[] = {
      {"arrays", "{\"objects\": " + repeat("[", kDepth) + repeat("]", kDepth) + "}"},
      {"objects", "{\"camera\": " + repeat("{\"a\": ", kDepth) + "1" + repeat("}", kDepth) + "}"},
      {"unclosed", repeat("[", kDepth)},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const std::string error = error_of(c.text);
    CHECK(error.rfind("hostile.json: ", 0) == 0);
    CHECK(error.find('\n') == std::string::npos);
    CHECK(error.size() < 400);  // the pointer of the 33rd level, not of the millionth
  }
}

// 10^6 lights in a scene file: tests/test_scene_file.cpp (refused by count before any light is
// read). Through the API: tests/test_hostile_limits.cpp.
