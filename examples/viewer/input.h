// viewer/input.h — the viewer's input, without SDL: the keys it knows and the events that
// change its state. The SDL shell (main.cpp) translates SDL events into these; scripts
// (script.h) name keys with key_from_name().
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <variant>

namespace viewer {

enum class Key {
  W, A, S, D, Q, E,          // fly: forward, left, back, right, down, up
  Up, Down, Left, Right,     // arrows: forward, back, left, right
  Tab,                       // capture / release the mouse
  Num0, Num1, Num2, Num3, Num4, Num5, Num6, Num7, Num8, Num9,  // 0 gallery, 1–9 presets
  N,                         // next material preset (all presets, in order)
  M,                         // next mesh
  C,                         // start / stop the rotating lights
  R, F,                      // roughness up / down
  T,                         // toggle metallic
  P,                         // screenshot
  B,                         // next environment (off, the built-in studio, each --env map)
  V,                         // toggle 4× MSAA
  H,                         // the lights' shadows, then the ground's, then neither
  G,                         // next material variant of a glTF model (KHR_materials_variants)
  Escape,                    // quit
};

// How many keys there are: Escape is the last.
inline constexpr std::size_t kKeyCount = static_cast<std::size_t>(Key::Escape) + 1;

// Lower-case script names: "w", "up", "tab", "0"… "9", "escape".
std::optional<Key> key_from_name(std::string_view name);
std::string_view key_name(Key key);

struct KeyDown {
  Key key;
};
struct KeyUp {
  Key key;
};
// Relative mouse motion in window pixels (x right, y down); turns the camera only while
// the mouse is captured.
struct MouseMotion {
  float dx = 0.0f;
  float dy = 0.0f;
};

using Event = std::variant<KeyDown, KeyUp, MouseMotion>;

}  // namespace viewer
