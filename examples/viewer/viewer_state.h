// viewer/viewer_state.h — what the viewer shows (camera, material, mesh, lights) and how
// input changes it. No SDL here: the SDL shell and the script player feed the same events
// to apply() and call advance() once per frame, so a scripted session reaches exactly the
// state an interactive one would.
//
// Controls (as the paper's program; docs/viewer.md):
//   W A S D / arrows  fly forward, left, back, right      Q / E   down / up
//   Tab               capture / release the mouse; while captured, the mouse turns the camera
//   1 … 9             material preset 1 … 9 (gold, copper, silver, …)   N  next preset (all)
//   0                 the paper's gallery: one preset per row, roughness rising across
//   M                 next mesh (sphere grid, spot, teapot, torus, cube, OBJ files given)
//   C                 start / stop the rotating lights
//   R / F             roughness up / down by 0.05    T  toggle metallic (preset mode only)
//   B                 next environment: off (the paper's lights), the built-in studio, each --env map
//   V                 toggle 4× MSAA (antialiased edges, docs/design.md "MSAA")
//   H                 the lights' shadows, then also the ground's, then neither (docs/design.md "Shadows")
//   P                 screenshot                      Escape  quit
#pragma once

#include <array>
#include <cstddef>

#include "input.h"
#include "softpbr/pbr/camera.h"

namespace viewer {

// LearnOpenGL's Camera class (the paper's fly camera): SPEED 2.5 units/s and
// SENSITIVITY 0.1° per pixel of mouse motion.
inline constexpr float kMoveSpeed = 2.5f;
inline constexpr float kMouseRadiansPerPixel = 0.1f * 0.017453292519943295f;
// Rotating lights turn about the y axis at 0.5 rad/s: a full turn in about 12.6 s.
inline constexpr float kLightRadiansPerSecond = 0.5f;
// Roughness is kept as a whole number of steps of 1/20 (0.05) so that R and F never
// accumulate rounding error: roughness() = steps / 20 is the float nearest the decimal.
inline constexpr int kRoughnessSteps = 20;
// Script mode advances every frame by this fixed time step (seconds).
inline constexpr float kScriptFrameSeconds = 1.0f / 30.0f;

inline constexpr int kGalleryMaterial = -1;  // ViewerState::material: the paper's rows

struct ViewerState {
  // The gallery's camera: at (0, 0, 9) looking down −z at the grid, 45° vertical fov.
  softpbr::pbr::FlyCamera camera{{0.0f, 0.0f, 9.0f}, 0.0f, 0.0f, 0.7853981633974483f, 0.1f, 100.0f};
  int material = kGalleryMaterial;  // or an index into pbr::material_presets()
  int roughness_steps = 6;          // preset mode: roughness = steps / 20
  bool metallic = true;             // preset mode
  std::size_t mesh = 0;             // index into the mesh list
  std::size_t mesh_count = 1;       // how many meshes the list has (M cycles through them)
  std::size_t environment = 0;        // 0: none; else an index into the environment list
  std::size_t environment_count = 1;  // how many entries the list has (B cycles through them)
  bool lights_rotating = false;
  float light_angle = 0.0f;  // radians in [0, 2π): the lights' turn about the y axis
  bool captured = false;     // mouse captured: motion turns the camera
  int msaa = 1;              // samples a pixel: 1 or 4 (V toggles)
  bool shadows = false;      // the lights cast shadows (H; job::Settings::shadows)
  bool ground = false;       // a shadow catcher under the objects (H after shadows; job::Settings::ground)
  bool quit = false;
  std::array<bool, kKeyCount> held{};  // keys currently down

  float roughness() const { return static_cast<float>(roughness_steps) / static_cast<float>(kRoughnessSteps); }
  bool is_held(Key k) const { return held[static_cast<std::size_t>(k)]; }
};

// What an event asks of the shell besides the state change.
// NextVariant: show the current glTF model's next material variant (the shell reloads it:
// viewer_scene.h's next_variant).
enum class Effect { None, Screenshot, Quit, NextVariant };

// Applies one input event. Key repeats are not events: the shell drops them.
Effect apply(ViewerState& state, const Event& event);

// Selects material preset `index` (roughness and metallic from the preset), or the
// gallery for kGalleryMaterial. Out-of-range indices are ignored.
void select_material(ViewerState& state, int index);

// Advances one frame of `seconds`: held movement keys fly the camera kMoveSpeed · seconds
// along its axes, rotating lights turn. Returns true when the camera moved.
bool advance(ViewerState& state, float seconds);

}  // namespace viewer
