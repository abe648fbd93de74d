// Script parsing: every command, and one clear error line for every kind of bad line.
#include <doctest/doctest.h>

#include <string>

#include "script.h"

using namespace viewer;
using Kind = ScriptCommand::Kind;

TEST_CASE("a script parses into events and frames and screenshots and quit with line numbers") {
  const auto c = parse_script(
      "# comment\n"
      "press 2   # copper\n"
      "\n"
      "down w\r\n"
      "frame 12\n"
      "up w\n"
      "mouse 60 -30\n"
      "frame\n"
      "screenshot out/a.png\n"
      "quit",
      "s.txt");
  REQUIRE(c.size() == 9);
  CHECK(std::get<KeyDown>(c[0].event).key == Key::Num2);
  CHECK(std::get<KeyUp>(c[1].event).key == Key::Num2);
  CHECK(c[0].line == 2);
  CHECK(c[1].line == 2);
  CHECK(std::get<KeyDown>(c[2].event).key == Key::W);
  CHECK(c[2].line == 4);
  CHECK(c[3].kind == Kind::Frames);
  CHECK(c[3].frames == 12);
  CHECK(std::get<KeyUp>(c[4].event).key == Key::W);
  CHECK(std::get<MouseMotion>(c[5].event).dx == 60.0f);
  CHECK(std::get<MouseMotion>(c[5].event).dy == -30.0f);
  CHECK(c[6].kind == Kind::Frames);
  CHECK(c[6].frames == 1);
  CHECK(c[7].kind == Kind::Screenshot);
  CHECK(c[7].path == "out/a.png");
  CHECK(c[8].kind == Kind::Quit);
  CHECK(c[8].line == 10);
}

TEST_CASE("a bad line is one error naming the script and line and what was expected") {
  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"jump", "s.txt:1: unknown command \"jump\""},
      {"\n\npress x", "s.txt:3: unknown key \"x\""},
      {"press", "s.txt:1: expected \"press KEY\""},
      {"press w a", "s.txt:1: expected \"press KEY\""},
      {"down", "s.txt:1: expected \"down KEY\""},
      {"up W", "s.txt:1: unknown key \"W\""},
      {"mouse 1", "s.txt:1: expected \"mouse DX DY\""},
      {"mouse 1 nan", "s.txt:1: \"nan\" is not a whole number of pixels in [-100000, 100000]"},
      {"mouse 1.5 0", "s.txt:1: \"1.5\" is not a whole number of pixels"},
      {"mouse 0 100001", "s.txt:1: \"100001\" is not a whole number of pixels"},
      {"mouse 1x 0", "s.txt:1: \"1x\" is not a whole number of pixels"},
      {"frame 0", "s.txt:1: frame count \"0\" is not a whole number in [1, 1000000]"},
      {"frame -3", "s.txt:1: frame count \"-3\""},
      {"frame 1000001", "s.txt:1: frame count \"1000001\""},
      {"frame 2.5", "s.txt:1: frame count \"2.5\""},
      {"frame 1 2", "s.txt:1: expected \"frame [N]\""},
      {"screenshot", "s.txt:1: expected \"screenshot FILE\""},
      {"quit now", "s.txt:1: expected \"quit\""},
      {"drop", "s.txt:1: expected \"drop FILE\""},
      {"drop a.glb b.glb", "s.txt:1: expected \"drop FILE\""},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    try {
      parse_script(c.text, "s.txt");
      FAIL("expected a ScriptError");
    } catch (const ScriptError& e) {
      CHECK(std::string(e.what()).rfind(c.message, 0) == 0);
    }
  }
}

TEST_CASE("drop FILE is a dropped file with its path") {
  const auto c = parse_script("drop models/Duck.glb\npress m\n", "s.txt");
  REQUIRE(c.size() == 3);
  CHECK(c[0].kind == Kind::Drop);
  CHECK(c[0].path == "models/Duck.glb");
  CHECK(c[0].line == 1);
  CHECK(c[1].kind == Kind::Event);
}

TEST_CASE("a missing script file is an error naming the file") {
  try {
    load_script("/nonexistent/keys.txt");
    FAIL("expected a ScriptError");
  } catch (const ScriptError& e) {
    CHECK(std::string(e.what()).rfind("/nonexistent/keys.txt: ", 0) == 0);
  }
}

TEST_CASE("an error quotes at most 40 bytes of a script line, however long the line") {
  // A 15 MB word was echoed whole; each quoted word is cut at 40 bytes, control bytes as '?'.
  const std::string huge(15u << 20, 'x');
  const std::string shown = "\"" + std::string(40, 'x') + "…\"";
  const std::string cases[][2] = {
      {huge, "s.txt:1: unknown command " + shown + " (commands: "},
      {"press " + huge, "s.txt:1: unknown key " + shown + " (keys: "},
      {"mouse 0 " + huge, "s.txt:1: " + shown + " is not a whole number of pixels"},
      {"frame " + huge, "s.txt:1: frame count " + shown + " is not a whole number"},
      {"jump\x1b[2J", "s.txt:1: unknown command \"jump?[2J\""},
  };
  for (const auto& [text, message] : cases) {
    try {
      parse_script(text, "s.txt");
      FAIL("expected a ScriptError");
    } catch (const ScriptError& e) {
      const std::string what = e.what();
      CHECK(what.rfind(message, 0) == 0);
      CHECK(what.size() < 300);
    }
  }
}
