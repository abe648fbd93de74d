// The viewer's state machine (see viewer_state.h).
#include "viewer_state.h"

#include <algorithm>

#include "softpbr/pbr/material.h"

namespace viewer {

namespace {
constexpr float kTwoPi = 6.283185307179586f;

int preset_count() { return static_cast<int>(softpbr::pbr::material_presets().size()); }

// +1, −1 or 0 for a pair of opposite movement directions.
float axis(const ViewerState& s, Key plus, Key plus_alt, Key minus, Key minus_alt) {
  const bool p = s.is_held(plus) || s.is_held(plus_alt);
  const bool m = s.is_held(minus) || s.is_held(minus_alt);
  return static_cast<float>(p) - static_cast<float>(m);
}

Effect press(ViewerState& s, Key key) {
  switch (key) {
    case Key::Tab: s.captured = !s.captured; break;
    case Key::Num0: select_material(s, kGalleryMaterial); break;
    case Key::Num1: case Key::Num2: case Key::Num3: case Key::Num4: case Key::Num5:
    case Key::Num6: case Key::Num7: case Key::Num8: case Key::Num9:
      select_material(s, static_cast<int>(key) - static_cast<int>(Key::Num1));
      break;
    case Key::N: select_material(s, (s.material + 1) % preset_count()); break;
    case Key::M: s.mesh = s.mesh_count > 0 ? (s.mesh + 1) % s.mesh_count : 0; break;
    case Key::C: s.lights_rotating = !s.lights_rotating; break;
    case Key::B: s.environment = s.environment_count > 0 ? (s.environment + 1) % s.environment_count : 0; break;
    case Key::R:
      if (s.material != kGalleryMaterial) s.roughness_steps = std::min(s.roughness_steps + 1, kRoughnessSteps);
      break;
    case Key::F:
      if (s.material != kGalleryMaterial) s.roughness_steps = std::max(s.roughness_steps - 1, 0);
      break;
    case Key::T:
      if (s.material != kGalleryMaterial) s.metallic = !s.metallic;
      break;
    case Key::V: s.msaa = s.msaa == 1 ? 4 : 1; break;
    case Key::H:  // off → the lights' shadows → and the ground's → off
      if (!s.shadows) s.shadows = true;
      else if (!s.ground) s.ground = true;
      else s.shadows = s.ground = false;
      break;
    case Key::P: return Effect::Screenshot;
    case Key::G: return Effect::NextVariant;
    case Key::Escape: s.quit = true; return Effect::Quit;
    default: break;  // movement keys act in advance()
  }
  return Effect::None;
}
}  // namespace

void select_material(ViewerState& s, int index) {
  if (index == kGalleryMaterial) {
    s.material = kGalleryMaterial;
    return;
  }
  if (index < 0 || index >= preset_count()) return;
  const softpbr::pbr::Material& m = softpbr::pbr::material_presets()[static_cast<std::size_t>(index)].material;
  s.material = index;
  // Presets' roughness values are multiples of 0.05; round to the nearest step anyway.
  s.roughness_steps = std::clamp(static_cast<int>(m.roughness * kRoughnessSteps + 0.5f), 0, kRoughnessSteps);
  s.metallic = m.metallic >= 0.5f;
}

Effect apply(ViewerState& s, const Event& event) {
  if (const auto* down = std::get_if<KeyDown>(&event)) {
    bool& held = s.held[static_cast<std::size_t>(down->key)];
    if (held) return Effect::None;  // already down: not a new press
    held = true;
    return press(s, down->key);
  }
  if (const auto* up = std::get_if<KeyUp>(&event)) {
    s.held[static_cast<std::size_t>(up->key)] = false;
    return Effect::None;
  }
  const auto& motion = std::get<MouseMotion>(event);
  // Mouse right turns right (yaw grows); mouse up (dy < 0) looks up (pitch grows).
  if (s.captured) s.camera.turn(motion.dx * kMouseRadiansPerPixel, -motion.dy * kMouseRadiansPerPixel);
  return Effect::None;
}

bool advance(ViewerState& s, float seconds) {
  if (s.lights_rotating) {
    s.light_angle += kLightRadiansPerSecond * seconds;
    if (s.light_angle >= kTwoPi) s.light_angle -= kTwoPi;
  }
  const float forward = axis(s, Key::W, Key::Up, Key::S, Key::Down);
  const float rightward = axis(s, Key::D, Key::Right, Key::A, Key::Left);
  const float upward = axis(s, Key::E, Key::E, Key::Q, Key::Q);
  if (forward == 0.0f && rightward == 0.0f && upward == 0.0f) return false;
  const float distance = kMoveSpeed * seconds;
  s.camera.move(forward * distance, rightward * distance, upward * distance);
  return true;
}

}  // namespace viewer
