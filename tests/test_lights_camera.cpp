// Punctual lights (KHR_lights_punctual falloff), cameras against glm, and the deterministic
// exp/log/pow/exp2 of dmath against libm.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <vector>

#include <doctest/doctest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/light.h"
#include "softpbr/dmath/dmath.h"

namespace pbr = softpbr::pbr;
namespace dm = softpbr::dmath;

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

pbr::Light point_light(glm::vec3 position, float intensity, float range = 0.0f) {
  pbr::Light l;
  l.type = pbr::LightType::Point;
  l.position = position;
  l.color = {1.0f, 0.5f, 0.25f};
  l.intensity = intensity;
  l.range = range;
  return l;
}

const glm::vec3 kDirections[] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0.48f, 0.6f, -0.64f}, {-0.36f, 0.48f, 0.8f}};

bool rel_close(double got, double want, double rel) { return std::fabs(got - want) <= rel * std::fabs(want); }

}  // namespace

// ---- Lights ---------------------------------------------------------------------------------

TEST_CASE("point light: inverse square falloff, radiance at distance 2 is 1/4 of distance 1") {
  const glm::vec3 at(0.5f, -1.0f, 2.0f);
  const pbr::PreparedLight p = pbr::prepare_light(point_light(at, 60.0f));
  for (const glm::vec3& dir : kDirections) {
    const glm::vec3 u = glm::normalize(dir);
    for (float d : {0.25f, 1.0f, 3.0f, 10.0f}) {
      const pbr::LightSample near = pbr::sample_light(p, at + d * u);
      const pbr::LightSample far = pbr::sample_light(p, at + 2.0f * d * u);
      CAPTURE(d);
      for (int c = 0; c < 3; ++c) {
        CHECK(rel_close(far.radiance[c], near.radiance[c] / 4.0, 1e-6));
        // Li = colour · intensity / d²
        CHECK(rel_close(near.radiance[c], p.light.color[c] * 60.0 / (double(d) * d), 1e-6));
      }
      // to_light is the unit vector towards the light.
      CHECK(glm::length(near.to_light) == doctest::Approx(1.0).epsilon(1e-6));
      CHECK(glm::dot(near.to_light, -u) == doctest::Approx(1.0).epsilon(1e-6));
    }
  }
}

TEST_CASE("point light range (KHR window): 0 at and beyond the range, unwindowed near the light") {
  const glm::vec3 at(1.0f, 2.0f, 3.0f);
  const float range = 10.0f;
  const pbr::PreparedLight windowed = pbr::prepare_light(point_light(at, 5.0f, range));
  const pbr::PreparedLight unlimited = pbr::prepare_light(point_light(at, 5.0f));
  // Exactly at the range (axis directions, where the float distance is exactly 10).
  for (const glm::vec3 u : {glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, 1)}) {
    CHECK(pbr::sample_light(windowed, at + range * u).radiance == glm::vec3(0.0f));
    CHECK(pbr::sample_light(windowed, at - range * u).radiance == glm::vec3(0.0f));
  }
  for (const glm::vec3& dir : kDirections) {
    const glm::vec3 u = glm::normalize(dir);
    for (float t : {1.0001f, 1.5f, 20.0f}) CHECK(pbr::sample_light(windowed, at + t * range * u).radiance == glm::vec3(0.0f));
    // Near the light the window is 1 − (d/R)⁴ ≈ 1: 1e-8 below at d = R/100.
    const glm::vec3 near = at + 0.01f * range * u;
    CHECK(rel_close(pbr::sample_light(windowed, near).radiance.r, pbr::sample_light(unlimited, near).radiance.r, 1e-6));
    // Everywhere: clamp(1 − (d/R)⁴, 0, 1) / d² in double, decreasing with distance.
    float previous = std::numeric_limits<float>::infinity();
    for (int i = 1; i <= 100; ++i) {
      const double d = range * i / 100.0;
      const glm::vec3 x = at + static_cast<float>(d) * u;
      const double dd = glm::length(glm::dvec3(x) - glm::dvec3(at));  // the float point's distance
      const double q = dd / range;
      const double want = 5.0 * std::clamp(1 - q * q * q * q, 0.0, 1.0) / (dd * dd);
      const float got = pbr::sample_light(windowed, x).radiance.r;
      CAPTURE(d);
      CHECK(std::fabs(got - want) <= 1e-5 * (5.0 / (dd * dd)));
      CHECK(got <= previous);
      previous = got;
    }
  }
}

TEST_CASE("spot light: full inside the inner cone, 0 outside the outer cone, monotonic between") {
  struct Cone {
    float inner, outer;
  };
  for (const Cone cone : {Cone{0.3f, 0.6f}, Cone{0.0f, 0.7853982f}, Cone{0.5f, 0.5f}, Cone{1.2f, 1.5707964f}}) {
    pbr::Light l = point_light({0, 1, 0}, 8.0f);
    l.type = pbr::LightType::Spot;
    l.direction = {0, -2, 0};  // not unit: prepare_light normalises
    l.inner_cone = cone.inner;
    l.outer_cone = cone.outer;
    const pbr::PreparedLight spot = pbr::prepare_light(l);
    const pbr::PreparedLight point = pbr::prepare_light(point_light({0, 1, 0}, 8.0f));
    CAPTURE(cone.inner);
    CAPTURE(cone.outer);
    const double cos_o = std::cos(double(cone.outer)), cos_i = std::cos(double(cone.inner));
    double previous = 1.0;  // the cone factor Li(spot) / Li(point), non-increasing in θ
    for (int i = 0; i <= 400; ++i) {
      const double theta = (kPi / 2) * i / 400;  // angle from the spot axis
      for (double phi : {0.0, 2.0}) {
        const glm::vec3 x(static_cast<float>(2 * std::sin(theta) * std::cos(phi)), static_cast<float>(1 - 2 * std::cos(theta)),
                          static_cast<float>(2 * std::sin(theta) * std::sin(phi)));
        const float got = pbr::sample_light(spot, x).radiance.g;
        const float full = pbr::sample_light(point, x).radiance.g;
        CAPTURE(theta);
        // Full inside the inner cone, zero outside the outer. KHR caps the scale at 1/0.001,
        // so a hard-edged cone (inner == outer) fades over a cosine gap of 0.001 just inside.
        const double gap = std::max(0.001, cos_i - cos_o);
        if (std::cos(theta) > cos_o + gap + 1e-6) CHECK(got == full);
        if (theta > cone.outer + 1e-4) CHECK(got == 0.0f);
        if (phi == 0.0) {
          const double factor = double(got) / full;
          CHECK(factor <= previous + 1e-6);
          previous = factor;
        }
        // KHR: saturate((cos θ − cos outer) / (cos inner − cos outer))².
        const double t = std::clamp((std::cos(theta) - cos_o) / gap, 0.0, 1.0);
        CHECK(std::fabs(got - full * t * t) <= 2e-3 * full);
      }
    }
  }
}

TEST_CASE("directional light: the same radiance and direction everywhere") {
  pbr::Light l;
  l.type = pbr::LightType::Directional;
  l.direction = {1, -2, 2};
  l.color = {0.9f, 0.8f, 0.7f};
  l.intensity = 3.0f;
  const pbr::PreparedLight p = pbr::prepare_light(l);
  const glm::vec3 expected_to_light = -glm::normalize(l.direction);
  for (const glm::vec3 x : {glm::vec3(0), glm::vec3(1e6f, -1e6f, 3), glm::vec3(-0.5f, 2, 7), glm::vec3(0, 0, -1e-30f)}) {
    const pbr::LightSample s = pbr::sample_light(p, x);
    CHECK(s.radiance == l.color * 3.0f);
    for (int c = 0; c < 3; ++c) CHECK(s.to_light[c] == doctest::Approx(expected_to_light[c]).epsilon(1e-6));
  }
}

TEST_CASE("prepare_light rejects invalid values, naming the field") {
  struct Bad {
    const char* field;
    std::function<void(pbr::Light&)> spoil;
  };
  auto spot = [](pbr::Light& l) { l.type = pbr::LightType::Spot; };
  const Bad cases[] = {
      {"position", [](pbr::Light& l) { l.position.y = kNaN; }},
      {"direction", [](pbr::Light& l) { l.direction.x = kInf; }},
      {"direction", [](pbr::Light& l) {
         l.type = pbr::LightType::Directional;
         l.direction = {0, 0, 0};
       }},
      {"direction", [&](pbr::Light& l) {
         spot(l);
         l.direction = {0, 0, 0};
       }},
      {"color", [](pbr::Light& l) { l.color = {1, -0.5f, 1}; }},
      {"color", [](pbr::Light& l) { l.color.b = kNaN; }},
      {"intensity", [](pbr::Light& l) { l.intensity = -1; }},
      {"intensity", [](pbr::Light& l) { l.intensity = kInf; }},
      {"range", [](pbr::Light& l) { l.range = -2; }},
      {"range", [](pbr::Light& l) { l.range = kNaN; }},
      {"outer_cone", [&](pbr::Light& l) {
         spot(l);
         l.outer_cone = 2.0f;
       }},
      {"outer_cone", [&](pbr::Light& l) {
         spot(l);
         l.outer_cone = 0.0f;
       }},
      {"outer_cone", [&](pbr::Light& l) {
         spot(l);
         l.inner_cone = -0.1f;
       }},
      {"inner_cone", [&](pbr::Light& l) {
         spot(l);
         l.inner_cone = 0.5f;
         l.outer_cone = 0.4f;
       }},
  };
  for (const Bad& b : cases) {
    pbr::Light l;
    b.spoil(l);
    CAPTURE(b.field);
    CHECK_THROWS_WITH_AS(pbr::prepare_light(l), doctest::Contains(b.field), std::invalid_argument);
  }
  for (pbr::LightType t : {pbr::LightType::Point, pbr::LightType::Directional, pbr::LightType::Spot}) {
    pbr::Light l;
    l.type = t;
    CHECK_NOTHROW(pbr::prepare_light(l));
  }
}

// ---- Cameras --------------------------------------------------------------------------------

TEST_CASE("perspective() equals glm::perspective within 1e-6 relative, look_at() equals glm::lookAt") {
  struct P {
    float fovy, aspect, near, far;
  };
  for (const P p : {P{0.7853982f, 16.0f / 9.0f, 0.1f, 100.0f}, P{1.2f, 1.0f, 0.01f, 1000.0f}, P{0.1f, 0.5f, 1.0f, 2.0f},
                    P{3.0f, 2.35f, 0.5f, 1e5f}}) {
    const glm::mat4 got = pbr::perspective(p.fovy, p.aspect, p.near, p.far);
    const glm::mat4 want = glm::perspective(p.fovy, p.aspect, p.near, p.far);
    CAPTURE(p.fovy);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        CAPTURE(c);
        CAPTURE(r);
        if (want[c][r] == 0.0f)
          CHECK(got[c][r] == 0.0f);
        else
          CHECK(std::fabs(got[c][r] - want[c][r]) <= 1e-6 * std::fabs(want[c][r]));
      }
  }
  struct L {
    glm::vec3 eye, target, up;
  };
  for (const L l : {L{{0, 0, 9}, {0, 0, 0}, {0, 1, 0}}, L{{3, 0.35f, 1}, {-0.5f, 0, 0}, {0, 1, 0}},
                    L{{-2, 5, -3}, {1, -1, 2}, {0.2f, 1, 0.1f}}, L{{0, 10, 0}, {0, 0, 0}, {0, 0, -1}}})
    CHECK(pbr::look_at(l.eye, l.target, l.up) == glm::lookAt(l.eye, l.target, l.up));
  // The camera's matrices are these.
  pbr::Camera cam;
  CHECK(cam.view() == glm::lookAt(cam.position, cam.target, cam.up));
  CHECK(cam.projection(1.5f) == pbr::perspective(cam.fovy, 1.5f, cam.near, cam.far));
}

TEST_CASE("fly camera: front = (sin yaw cos pitch, sin pitch, -cos yaw cos pitch), pitch clamped to +-89 degrees") {
  struct F {
    float yaw, pitch;
  };
  for (const F f : {F{0, 0}, F{1.5707964f, 0}, F{-1.5707964f, 0}, F{3.1415927f, 0}, F{0.3f, 0.4f}, F{-2.0f, -1.0f}}) {
    pbr::FlyCamera c;
    c.yaw = f.yaw;
    c.pitch = f.pitch;
    const glm::dvec3 want(std::sin(double(f.yaw)) * std::cos(double(f.pitch)), std::sin(double(f.pitch)),
                          -std::cos(double(f.yaw)) * std::cos(double(f.pitch)));
    const glm::vec3 front = c.front();
    CAPTURE(f.yaw);
    CAPTURE(f.pitch);
    for (int k = 0; k < 3; ++k) CHECK(std::fabs(front[k] - want[k]) <= 1e-7);
    // right = front × world up, normalised; the camera looks along front.
    const glm::vec3 right = c.right();
    CHECK(glm::length(right) == doctest::Approx(1.0).epsilon(1e-6));
    CHECK(std::fabs(glm::dot(right, front)) < 1e-6);
    CHECK(std::fabs(right.y) < 1e-6);
    const pbr::Camera cam = c.camera();
    CHECK(cam.position == c.position);
    CHECK(cam.target == c.position + front);
  }
  pbr::FlyCamera c;
  CHECK(c.front() == glm::vec3(0, 0, -1));
  c.yaw = static_cast<float>(kPi / 2);
  CHECK(c.front().x == 1.0f);
  CHECK(std::fabs(c.front().z) < 1e-7f);
  const float max_pitch = static_cast<float>(89.0 * kPi / 180.0);
  c.turn(0.0f, 10.0f);
  CHECK(c.pitch == doctest::Approx(max_pitch).epsilon(1e-7));
  CHECK(c.front().y == doctest::Approx(std::sin(89.0 * kPi / 180.0)).epsilon(1e-6));
  c.turn(0.25f, -100.0f);
  CHECK(c.pitch == doctest::Approx(-max_pitch).epsilon(1e-7));
  CHECK(c.yaw == doctest::Approx(kPi / 2 + 0.25).epsilon(1e-6));
  c.turn(0.0f, 0.5f);  // inside the range: no clamp
  CHECK(c.pitch == doctest::Approx(-max_pitch + 0.5f).epsilon(1e-6));
  // Moving forward by 2 at yaw π/2, pitch 0 goes +x.
  pbr::FlyCamera m;
  m.yaw = static_cast<float>(kPi / 2);
  m.move(2.0f, 0.0f, 0.5f);
  CHECK(m.position.x == doctest::Approx(2.0));
  CHECK(m.position.y == doctest::Approx(0.5));
  CHECK(m.position.z == doctest::Approx(3.0));
}

TEST_CASE("orbit camera: yaw 0 pitch 0 sits at target + (0, 0, distance), always at that distance, looking at it") {
  pbr::OrbitCamera o;
  o.target = {1.0f, -2.0f, 0.5f};
  o.distance = 4.0f;
  CHECK(o.position() == o.target + glm::vec3(0, 0, 4));
  for (float yaw : {0.0f, 0.7f, 3.0f, -1.2f})
    for (float pitch : {0.0f, 0.5f, -1.0f, 1.5f}) {
      o.yaw = yaw;
      o.pitch = pitch;
      const glm::dvec3 want = glm::dvec3(o.target) + 4.0 * glm::dvec3(std::sin(double(yaw)) * std::cos(double(pitch)),
                                                                     std::sin(double(pitch)),
                                                                     std::cos(double(yaw)) * std::cos(double(pitch)));
      const glm::vec3 p = o.position();
      for (int k = 0; k < 3; ++k) CHECK(std::fabs(p[k] - want[k]) <= 2e-6);
      CHECK(glm::distance(p, o.target) == doctest::Approx(4.0).epsilon(1e-6));
      CHECK(o.camera().target == o.target);
      CHECK_NOTHROW(pbr::validate(o.camera()));
    }
}

TEST_CASE("validate(camera) throws for a camera that cannot make an image, naming the field") {
  struct Bad {
    const char* field;
    std::function<void(pbr::Camera&)> spoil;
  };
  const Bad cases[] = {
      {"target", [](pbr::Camera& c) { c.target = c.position; }},
      {"up", [](pbr::Camera& c) { c.up = {0, 0, 1}; }},  // parallel to the view direction (0, 0, −1)
      {"up", [](pbr::Camera& c) { c.up = {0, 0, -5}; }},
      {"up", [](pbr::Camera& c) { c.up = {0, 0, 0}; }},
      {"fovy", [](pbr::Camera& c) { c.fovy = 0.0f; }},
      {"fovy", [](pbr::Camera& c) { c.fovy = 3.2f; }},
      {"fovy", [](pbr::Camera& c) { c.fovy = kNaN; }},
      {"near", [](pbr::Camera& c) { c.near = 0.0f; }},
      {"near", [](pbr::Camera& c) { c.near = -1.0f; }},
      {"near", [](pbr::Camera& c) { c.near = kNaN; }},
      {"far", [](pbr::Camera& c) { c.far = c.near; }},
      {"far", [](pbr::Camera& c) { c.far = 0.05f; }},
      {"far", [](pbr::Camera& c) { c.far = kInf; }},
      {"position", [](pbr::Camera& c) { c.position.x = kNaN; }},
      {"target", [](pbr::Camera& c) { c.target.z = kInf; }},
      {"up", [](pbr::Camera& c) { c.up.y = kNaN; }},
      // Finite, but too far apart or too long for the float view matrix.
      {"position", [](pbr::Camera& c) { c.position.z = 1e30f; }},
      {"position", [](pbr::Camera& c) { c.target.x = -3e19f; }},
      {"up", [](pbr::Camera& c) { c.up = {0.0f, 1e30f, 0.0f}; }},
  };
  // Far, but within range: a camera 1e18 away from its target is valid.
  pbr::Camera far_away;
  far_away.position.z = 1e18f;
  CHECK_NOTHROW(pbr::validate(far_away));
  CHECK_NOTHROW(pbr::validate(pbr::Camera{}));
  for (const Bad& b : cases) {
    pbr::Camera c;
    b.spoil(c);
    CAPTURE(b.field);
    CHECK_THROWS_WITH_AS(pbr::validate(c), doctest::Contains(b.field), std::invalid_argument);
  }
}

// ---- dmath: exp, log, pow, exp2 -------------------------------------------------------------

namespace {

// |got − want| within `rel` relative, or within one subnormal step where want is subnormal
// (a subnormal has fewer significant bits: its own rounding is 2⁻¹⁰⁷⁴ absolute).
bool dm_close(double got, double want, double rel) {
  if (std::isinf(want) || want == 0.0) return got == want;
  if (std::fabs(want) < DBL_MIN) return std::fabs(got - want) <= std::numeric_limits<double>::denorm_min();
  return std::fabs(got - want) <= rel * std::fabs(want);
}

struct Worst {
  double rel = 0, at = 0;
  void add(double got, double want, double x) {
    if (std::fabs(want) < DBL_MIN || std::isinf(want)) return;
    const double e = std::fabs(got - want) / std::fabs(want);
    if (e > rel) {
      rel = e;
      at = x;
    }
  }
};

}  // namespace

TEST_CASE("dmath exp, exp2 and log agree with libm within 1e-14 relative, subnormal and huge values included") {
  constexpr int kN = 200000;
  Worst we, we2, wl;
  int bad = 0;
  for (int i = 0; i <= kN; ++i) {
    // exp over its whole finite range, results from subnormal to near DBL_MAX.
    const double x = -745.0 + (709.78 + 745.0) * i / kN;
    if (!dm_close(dm::exp(x), std::exp(x), 1e-14) && bad++ < 5) FAIL_CHECK("exp(" << x << ")");
    we.add(dm::exp(x), std::exp(x), x);
    // exp2 from the smallest subnormal to the largest finite power.
    const double y = -1074.5 + (1023.99 + 1074.5) * i / kN;
    if (!dm_close(dm::exp2(y), std::exp2(y), 1e-14) && bad++ < 5) FAIL_CHECK("exp2(" << y << ")");
    we2.add(dm::exp2(y), std::exp2(y), y);
    // log from the smallest subnormal to DBL_MAX (log-spaced), and densely around 1.
    for (const double z : {std::exp2(y), 0.5 + 1.5 * i / kN}) {
      if (!dm_close(dm::log(z), std::log(z), 1e-14) && bad++ < 5) FAIL_CHECK("log(" << z << ")");
      wl.add(dm::log(z), std::log(z), z);
    }
  }
  CHECK(bad == 0);
  // Integer powers of two are exact, and e^1 is e.
  for (int n = -1074; n <= 1023; ++n) CHECK(dm::exp2(n) == std::ldexp(1.0, n));
  CHECK(dm::exp(1.0) == doctest::Approx(2.718281828459045).epsilon(1e-15));
  CHECK(dm::log(1.0) == 0.0);
  CHECK(dm::log(DBL_MAX) == doctest::Approx(709.782712893384).epsilon(1e-15));
  CHECK(dm::log(std::numeric_limits<double>::denorm_min()) == doctest::Approx(-744.4400719213812).epsilon(1e-15));
  MESSAGE("worst relative error vs libm: exp " << we.rel << " (x = " << we.at << "), exp2 " << we2.rel << " (x = "
                                               << we2.at << "), log " << wl.rel << " (x = " << wl.at << ")");
}

TEST_CASE("dmath pow: x^(1/2.4) and x^2.2 on [0, 1] within 1e-14 of libm, elsewhere within its documented |y ln x| bound") {
  Worst w;
  for (int i = 1; i <= 200000; ++i) {
    const double x = i / 200000.0;
    for (double y : {1 / 2.4, 2.4, 1 / 2.2, 2.2}) {
      CHECK_MESSAGE(dm_close(dm::pow(x, y), std::pow(x, y), 1e-14), "pow(" << x << ", " << y << ")");
      w.add(dm::pow(x, y), std::pow(x, y), x);
    }
  }
  MESSAGE("pow on (0, 1], exponents 1/2.4, 2.4, 1/2.2, 2.2: worst relative error " << w.rel << " at x = " << w.at);
  // Wide range: relative error about |y ln x| · 1e-16 (dmath.h); allow (|y ln x| + 4) · 2⁻⁵².
  for (double x : {1e-300, 1e-30, 0.001, 0.37, 1.0, 1.5, 10.0, 1e10, 1e300})
    for (double y : {-3.5, -1.0, 0.25, 0.5, 1.0, 2.2, 7.0, 100.0}) {
      const double want = std::pow(x, y);
      if (!(want > DBL_MIN) || std::isinf(want)) continue;
      CAPTURE(x);
      CAPTURE(y);
      CHECK(std::fabs(dm::pow(x, y) - want) <= (std::fabs(y * std::log(x)) + 4) * DBL_EPSILON * want);
    }
}

TEST_CASE("dmath special values: exp(-1000) = 0, exp(1000) = inf, log(0) = -inf, log(-1) = NaN, pow(0, 2) = 0, pow(x, 0) = 1") {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(dm::exp(-1000.0) == 0.0);
  CHECK(dm::exp(1000.0) == inf);
  CHECK(dm::exp(-inf) == 0.0);
  CHECK(dm::exp(inf) == inf);
  CHECK(std::isnan(dm::exp(nan)));
  CHECK(dm::exp(0.0) == 1.0);
  CHECK(dm::exp2(-1100.0) == 0.0);
  CHECK(dm::exp2(1024.0) == inf);
  CHECK(dm::exp2(0.0) == 1.0);
  CHECK(std::isnan(dm::exp2(nan)));
  CHECK(dm::log(0.0) == -inf);
  CHECK(dm::log(-0.0) == -inf);
  CHECK(std::isnan(dm::log(-1.0)));
  CHECK(std::isnan(dm::log(nan)));
  CHECK(dm::log(inf) == inf);
  CHECK(dm::pow(0.0, 2.0) == 0.0);
  CHECK(dm::pow(0.0, 0.5) == 0.0);
  CHECK(dm::pow(0.0, -1.0) == inf);
  for (double x : {0.0, 1e-300, 0.5, 1.0, 3.0, 1e300, inf}) CHECK(dm::pow(x, 0.0) == 1.0);
  CHECK(dm::pow(1.0, 123.456) == 1.0);
  CHECK(std::isnan(dm::pow(-2.0, 0.5)));
}
