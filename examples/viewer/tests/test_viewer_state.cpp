// The viewer's state machine: what each key does, flying, mouse-look, lights.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "softpbr/pbr/material.h"
#include "viewer_state.h"

using namespace viewer;
namespace pbr = softpbr::pbr;

namespace {
Effect tap(ViewerState& s, Key k) {
  const Effect e = apply(s, KeyDown{k});
  apply(s, KeyUp{k});
  return e;
}
}  // namespace

TEST_CASE("number keys select presets 1 to 9 with the preset's roughness and metallic and 0 the gallery") {
  const auto presets = pbr::material_presets();
  const Key digits[] = {Key::Num1, Key::Num2, Key::Num3, Key::Num4, Key::Num5,
                        Key::Num6, Key::Num7, Key::Num8, Key::Num9};
  for (int i = 0; i < 9; ++i) {
    ViewerState s;
    CHECK(tap(s, digits[i]) == Effect::None);
    CHECK(s.material == i);
    CHECK(s.roughness() == presets[static_cast<std::size_t>(i)].material.roughness);
    CHECK(s.metallic == (presets[static_cast<std::size_t>(i)].material.metallic == 1.0f));
    tap(s, Key::Num0);
    CHECK(s.material == kGalleryMaterial);
  }
}

TEST_CASE("N steps through every preset in order and wraps around") {
  ViewerState s;
  const int count = static_cast<int>(pbr::material_presets().size());
  for (int i = 0; i < count; ++i) {
    tap(s, Key::N);
    CHECK(s.material == i);
    CHECK(s.roughness() == pbr::material_presets()[static_cast<std::size_t>(i)].material.roughness);
  }
  tap(s, Key::N);
  CHECK(s.material == 0);
}

TEST_CASE("M cycles the meshes and wraps and C Tab T toggle and P asks for a screenshot and Escape quits") {
  ViewerState s;
  s.mesh_count = 4;
  for (std::size_t expected : {1u, 2u, 3u, 0u, 1u}) {
    tap(s, Key::M);
    CHECK(s.mesh == expected);
  }
  struct Toggle {
    Key key;
    bool ViewerState::*field;
  };
  tap(s, Key::Num1);  // T acts in preset mode
  for (const Toggle t : {Toggle{Key::C, &ViewerState::lights_rotating}, Toggle{Key::Tab, &ViewerState::captured},
                         Toggle{Key::T, &ViewerState::metallic}}) {
    const bool before = s.*t.field;
    tap(s, t.key);
    CHECK(s.*t.field == !before);
    tap(s, t.key);
    CHECK(s.*t.field == before);
  }
  CHECK(tap(s, Key::P) == Effect::Screenshot);
  CHECK_FALSE(s.quit);
  CHECK(tap(s, Key::Escape) == Effect::Quit);
  CHECK(s.quit);
}

TEST_CASE("V toggles 4x MSAA on and off") {
  ViewerState s;
  CHECK(s.msaa == 1);
  tap(s, Key::V);
  CHECK(s.msaa == 4);
  tap(s, Key::V);
  CHECK(s.msaa == 1);
}

TEST_CASE("H turns the lights' shadows on, then the ground's too, then both off") {
  ViewerState s;
  CHECK_FALSE(s.shadows);
  CHECK_FALSE(s.ground);
  tap(s, Key::H);
  CHECK(s.shadows);
  CHECK_FALSE(s.ground);
  tap(s, Key::H);
  CHECK(s.shadows);
  CHECK(s.ground);
  tap(s, Key::H);
  CHECK_FALSE(s.shadows);
  CHECK_FALSE(s.ground);
}

TEST_CASE("a key held down is pressed once: repeated key-down events do not toggle again") {
  ViewerState s;
  apply(s, KeyDown{Key::C});
  apply(s, KeyDown{Key::C});
  apply(s, KeyDown{Key::C});
  CHECK(s.lights_rotating);
  apply(s, KeyUp{Key::C});
  apply(s, KeyDown{Key::C});
  CHECK_FALSE(s.lights_rotating);
}

TEST_CASE("R and F move roughness in steps of 0.05 between 0 and 1 only in preset mode") {
  ViewerState s;
  tap(s, Key::R);
  tap(s, Key::T);
  CHECK(s.roughness_steps == 6);  // gallery mode: unchanged
  CHECK(s.metallic);
  tap(s, Key::Num1);  // gold, roughness 0.3
  for (int i = 0; i < 30; ++i) tap(s, Key::R);
  CHECK(s.roughness() == 1.0f);
  tap(s, Key::F);
  CHECK(s.roughness() == 0.95f);
  for (int i = 0; i < 30; ++i) tap(s, Key::F);
  CHECK(s.roughness() == 0.0f);
  // Every step is the float nearest the decimal k/20 (no drift from repeated ± 0.05).
  for (int k = 0; k <= kRoughnessSteps; ++k) {
    CHECK(s.roughness() == static_cast<float>(k / 20.0));
    tap(s, Key::R);
  }
}

TEST_CASE("each movement key flies kMoveSpeed units per second along its camera axis") {
  struct Case {
    Key key;
    glm::vec3 direction;  // for the starting camera, which looks down −z
  };
  const Case cases[] = {
      {Key::W, {0, 0, -1}}, {Key::Up, {0, 0, -1}},   {Key::S, {0, 0, 1}},     {Key::Down, {0, 0, 1}},
      {Key::A, {-1, 0, 0}}, {Key::Left, {-1, 0, 0}}, {Key::D, {1, 0, 0}},     {Key::Right, {1, 0, 0}},
      {Key::E, {0, 1, 0}},  {Key::Q, {0, -1, 0}},
  };
  for (const Case& c : cases) {
    CAPTURE(key_name(c.key));
    ViewerState s;
    const glm::vec3 start = s.camera.position;
    apply(s, KeyDown{c.key});
    CHECK(advance(s, 0.5f));
    const glm::vec3 moved = s.camera.position - start;
    for (int i = 0; i < 3; ++i) CHECK(moved[i] == doctest::Approx(c.direction[i] * kMoveSpeed * 0.5f).epsilon(1e-6));
    apply(s, KeyUp{c.key});
    const glm::vec3 before = s.camera.position;
    CHECK_FALSE(advance(s, 0.5f));
    CHECK(s.camera.position == before);
  }
}

TEST_CASE("opposite movement keys cancel") {
  ViewerState s;
  apply(s, KeyDown{Key::W});
  apply(s, KeyDown{Key::Down});
  const glm::vec3 before = s.camera.position;
  CHECK_FALSE(advance(s, 1.0f));
  CHECK(s.camera.position == before);
}

TEST_CASE("the mouse turns the camera only while captured and pitch stays within 89 degrees") {
  ViewerState s;
  apply(s, MouseMotion{100.0f, -50.0f});
  CHECK(s.camera.yaw == 0.0f);
  CHECK(s.camera.pitch == 0.0f);
  tap(s, Key::Tab);
  apply(s, MouseMotion{100.0f, -50.0f});
  CHECK(s.camera.yaw == doctest::Approx(100.0 * kMouseRadiansPerPixel));
  CHECK(s.camera.pitch == doctest::Approx(50.0 * kMouseRadiansPerPixel));  // mouse up looks up
  CHECK(s.camera.front().x > 0.0f);  // turned right
  CHECK(s.camera.front().y > 0.0f);
  apply(s, MouseMotion{0.0f, -1e5f});
  CHECK(s.camera.pitch == doctest::Approx(89.0 * 0.017453292519943295));
}

TEST_CASE("rotating lights turn at kLightRadiansPerSecond and the angle stays below 2pi") {
  ViewerState s;
  advance(s, 1.0f);
  CHECK(s.light_angle == 0.0f);
  tap(s, Key::C);
  advance(s, 1.0f);
  CHECK(s.light_angle == doctest::Approx(kLightRadiansPerSecond));
  for (int i = 0; i < 10000; ++i) {
    advance(s, kScriptFrameSeconds);
    REQUIRE(s.light_angle >= 0.0f);
    REQUIRE(s.light_angle < 6.2831855f);
  }
  // 10000 frames of 1/30 s plus the first second, modulo a turn.
  const double expected = std::fmod(kLightRadiansPerSecond * (1.0 + 10000.0 / 30.0), 2.0 * 3.141592653589793);
  CHECK(s.light_angle == doctest::Approx(expected).epsilon(1e-3));
}

TEST_CASE("every key has a script name that maps back to it") {
  for (std::size_t k = 0; k < kKeyCount; ++k) {
    const Key key = static_cast<Key>(k);
    const auto back = key_from_name(key_name(key));
    REQUIRE(back.has_value());
    CHECK(*back == key);
  }
  CHECK_FALSE(key_from_name("W").has_value());  // names are lower case
  CHECK_FALSE(key_from_name("").has_value());
}
