// viewer/script.h — scripted input for the headless test mode (viewer --script keys.txt).
//
// One command per line; '#' starts a comment; blank lines are ignored:
//   press KEY          key down then key up, with no frame between (a tap)
//   down KEY           key down (held: movement keys fly the camera in each frame)
//   up KEY             key up
//   mouse DX DY        relative mouse motion in whole pixels (turns the camera while captured)
//   frame [N]          advance N frames (default 1) of kScriptFrameSeconds each
//   screenshot FILE    write what the window shows, at full resolution, as a PNG
//   drop FILE          a file dropped on the window (SDL_DROPFILE): an .obj, .gltf or .glb
//                      joins the mesh list and is shown
//   quit               end the session (so does "press escape")
// KEY is a name from key_from_name(): w a s d q e up down left right tab 0-9 n m c r f t p
// escape. A bad line is a ScriptError "keys.txt:3: unknown key "x"".
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "input.h"

namespace viewer {

class ScriptError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Upper bound on one "frame N": 10⁶ frames of 1/30 s are over 9 hours of simulated time.
inline constexpr long kMaxScriptFrames = 1000000;
// Largest mouse motion in one event, in pixels: far beyond any screen.
inline constexpr long kMaxMousePixels = 100000;

struct ScriptCommand {
  enum class Kind { Event, Frames, Screenshot, Drop, Quit };
  Kind kind = Kind::Event;
  int line = 0;             // 1-based line in the script
  Event event{};            // Kind::Event
  long frames = 0;          // Kind::Frames
  std::string path;         // Kind::Screenshot, Kind::Drop
};

// Parses a script's text; `name` is used in error messages. "press" becomes two Event
// commands (down, up).
std::vector<ScriptCommand> parse_script(std::string_view text, const std::string& name);

// Reads and parses a script file (at most 16 MiB). Throws ScriptError naming the file.
std::vector<ScriptCommand> load_script(const std::filesystem::path& path);

}  // namespace viewer
