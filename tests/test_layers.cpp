// The material extensions' layers (layered_shading.h, lane_math.h, the sheen terms of
// brdf.h): lane math against dmath, the analytic limits bit for bit, the sheen's albedo
// table against its integral, energy in a white furnace, and the layers' monotonic rows.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "softpbr/golden/doctest_checks.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/layered_shading.h"
#include "softpbr/pbr/light.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace simd = softpbr::simd;
namespace raster = softpbr::raster;
using pbr::Vec3L;

namespace {

// Values spread over many octaves, for the lane math.
std::vector<float> test_values(float lo, float hi, int count) {
  std::vector<float> v;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(lo, hi);
  for (int i = 0; i < count; ++i) v.push_back(u(rng));
  return v;
}

template <int N, class Fn>
void check_lanes_match_scalar(const std::vector<float>& xs, Fn fn) {
  for (std::size_t i = 0; i + N <= xs.size(); i += N) {
    const auto lanes = fn(simd::Vec<N>::load(&xs[i]));
    for (int j = 0; j < N; ++j) {
      const float scalar = fn(xs[i + static_cast<std::size_t>(j)]);
      REQUIRE(std::memcmp(&scalar, &reinterpret_cast<const float*>(&lanes)[j], sizeof(float)) == 0);
    }
  }
}

// A uniform environment of radiance 1. The prepared environment points at the map, which
// lives on here (as Environment::studio()'s does).
pbr::PreparedEnvironment white_furnace() {
  static const std::shared_ptr<const pbr::Environment> map = [] {
    const int w = 64, h = 32;
    std::vector<float> white(static_cast<std::size_t>(w) * h * 4, 1.0f);
    return std::make_shared<const pbr::Environment>(softpbr::image::ImageViewF(w, h, white), "white");
  }();
  pbr::EnvironmentLighting l;
  l.map = map;
  return pbr::prepare_environment(l);
}

pbr::PreparedEnvironment studio_environment() {
  pbr::EnvironmentLighting l;
  l.map = pbr::Environment::studio();
  return pbr::prepare_environment(l);
}

std::vector<pbr::PreparedLight> test_lights() {
  std::vector<pbr::PreparedLight> lights;
  pbr::Light a;
  a.type = pbr::LightType::Directional;
  a.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f));
  a.intensity = 3.0f;
  lights.push_back(pbr::prepare_light(a));
  pbr::Light b;
  b.type = pbr::LightType::Point;
  b.position = {2.0f, 1.0f, 3.0f};
  b.intensity = 40.0f;
  lights.push_back(pbr::prepare_light(b));
  return lights;
}

// A unit vector from three normals, for random frames.
glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  return glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
}

pbr::MaterialLanes<float> material(float metallic, float roughness, const glm::vec3& base) {
  pbr::Material m;
  m.base_color = base;
  m.metallic = metallic;
  m.roughness = roughness;
  return pbr::lanes<float>(pbr::prepare_material(m));
}

// The default layers: F0(1.5) = 0.04, white specular colour, weight 1, no coat, no sheen.
pbr::LayerLanes<float> neutral_layers(float metallic) {
  pbr::LayerLanes<float> l;
  l.dielectric = pbr::dielectric_lanes(pbr::f0_from_ior(1.5), Vec3L<float>(1.0f), 1.0f, metallic);
  return l;
}

bool same(const Vec3L<float>& a, const Vec3L<float>& b) {
  return std::memcmp(&a.x, &b.x, 4) == 0 && std::memcmp(&a.y, &b.y, 4) == 0 && std::memcmp(&a.z, &b.z, 4) == 0;
}

}  // namespace

TEST_CASE("lane math: log2, exp2 and pow against dmath, and the same bits at every width") {
  double worst_log = 0.0, worst_exp = 0.0, worst_pow = 0.0;
  for (float x : test_values(1e-30f, 1.0f, 2000)) {
    worst_log = std::max(worst_log, std::abs(pbr::log2_lanes(x) - pbr::log2_lanes(static_cast<double>(x))));
  }
  for (float x : test_values(1.0f, 1e30f, 500))
    worst_log = std::max(worst_log, std::abs(pbr::log2_lanes(x) - pbr::log2_lanes(static_cast<double>(x))));
  for (float y : test_values(-120.0f, 120.0f, 2000)) {
    const double ref = pbr::exp2_lanes(static_cast<double>(y));
    worst_exp = std::max(worst_exp, std::abs(pbr::exp2_lanes(y) - ref) / ref);
  }
  const std::vector<float> bases = test_values(1e-4f, 1.0f, 400);
  for (float x : bases)
    for (float y : {0.17f, 0.5f, 2.0f, 14.0f, 250.0f}) {
      const double ref = pbr::pow_lanes(static_cast<double>(x), static_cast<double>(y));
      if (ref < 1e-30) continue;
      worst_pow = std::max(worst_pow, std::abs(pbr::pow_lanes(x, y) - ref) / ref);
    }
  MESSAGE("log2 abs error ", worst_log, ", exp2 rel ", worst_exp, ", pow rel (|y log2 x| ≤ 100) ", worst_pow);
  CHECK(worst_log < 1e-5);  // absolute, for |log2 x| up to 100: a few ulps of the result
  CHECK(worst_exp < 4e-7);
  CHECK(worst_pow < 5e-5);  // y log₂ x up to ~3000 bits of exponent: its rounding dominates
  // Exact points: powers of two, 0 and NaN.
  CHECK(pbr::log2_lanes(1.0f) == 0.0f);
  CHECK(pbr::log2_lanes(0.25f) == -2.0f);
  CHECK(pbr::exp2_lanes(-3.0f) == 0.125f);
  CHECK(pbr::exp2_lanes(0.0f) == 1.0f);
  CHECK(pbr::pow_lanes(0.0f, 2.0f) == 0.0f);
  CHECK(std::isfinite(pbr::exp2_lanes(std::nanf(""))));
  CHECK(std::isfinite(pbr::log2_lanes(std::nanf(""))));
  const std::vector<float> xs = test_values(1e-6f, 4.0f, 64);
  check_lanes_match_scalar<4>(xs, [](auto x) { return pbr::log2_lanes(x); });
  check_lanes_match_scalar<16>(xs, [](auto x) { return pbr::exp2_lanes(x * decltype(x)(-7.0f)); });
  check_lanes_match_scalar<8>(xs, [](auto x) { return pbr::pow_lanes(x * decltype(x)(0.25f), decltype(x)(3.7f)); });
}

TEST_CASE("the sheen's terms: D_Charlie is normalised and the albedo table matches its integral") {
  // ∫ D (n·h) dω_h = 1 over the hemisphere, for several roughnesses (in double).
  for (double r : {0.1, 0.3, 0.6, 1.0}) {
    const double alpha = r * r;
    double sum = 0.0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      const double NoH = (i + 0.5) / n;
      sum += pbr::D_Charlie(1.0 - NoH * NoH, alpha) * NoH * (2.0 * pbr::kPiDouble / n);
    }
    CHECK(sum == doctest::Approx(1.0).epsilon(2e-3));
  }
  // The float lanes against the double oracle.
  for (float sin2h : {0.0f, 0.1f, 0.5f, 0.9f, 1.0f})
    for (float alpha : {0.002f, 0.05f, 0.5f, 1.0f}) {
      const double ref = pbr::D_Charlie(static_cast<double>(sin2h), static_cast<double>(alpha));
      CHECK(pbr::D_Charlie(sin2h, alpha) == doctest::Approx(ref).epsilon(1e-4).scale(1e-12));
    }
  // The table: every texel within [0, 1] (energy), and its bilinear lookup near the integral
  // with four times the samples.
  const auto& t = pbr::sheen_table();
  for (float e : t.texels_f()) {
    CHECK(e >= 0.0f);
    CHECK(e <= 1.0f);
  }
  for (double NoV : {0.1, 0.5, 0.9})
    for (double r : {0.3, 0.6, 1.0}) {
      const double ref = std::min(pbr::sheen_albedo_reference(NoV, r, 4 * pbr::kSheenSamples), 1.0);
      const float e = pbr::env_sheen_albedo(static_cast<float>(NoV), static_cast<float>(r));
      CHECK(e == doctest::Approx(ref).epsilon(0.05).scale(0.01));
    }
  // Grazing views see more sheen than normal ones (the fibres' back-scattering).
  CHECK(pbr::env_sheen_albedo(0.1f, 0.8f) > pbr::env_sheen_albedo(0.9f, 0.8f));
}

TEST_CASE("layers at their defaults shade bit for bit as the core material") {
  const pbr::PreparedEnvironment env = studio_environment();
  const std::vector<pbr::PreparedLight> lights = test_lights();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  CHECK(pbr::f0_from_ior(1.5) == pbr::kDielectricF0);
  int compared = 0;
  for (int i = 0; i < 300; ++i) {
    const float metallic = u(rng);
    const pbr::MaterialLanes<float> m = material(metallic, u(rng), {u(rng), u(rng), u(rng)});
    const glm::vec3 n = random_unit(rng), v = random_unit(rng);
    const Vec3L<float> N(n.x, n.y, n.z), V(v.x, v.y, v.z), P(u(rng), u(rng), u(rng));
    pbr::LayerLanes<float> layers = neutral_layers(metallic);
    pbr::MaterialLanes<float> ml = m;
    ml.f0 = pbr::layered_f0(layers.dielectric, m.albedo, metallic);
    REQUIRE(same(ml.f0, m.f0));
    for (const pbr::PreparedEnvironment* e : {static_cast<const pbr::PreparedEnvironment*>(nullptr), &env}) {
      const Vec3L<float> base = pbr::shade(m, lights, glm::vec3(0.1f), P, N, V, e);
      // Neutral layers; a coat of factor 0 and a black sheen, both switched on.
      CHECK(same(pbr::shade_layered(ml, layers, lights, glm::vec3(0.1f), P, N, V, e, nullptr), base));
      pbr::LayerLanes<float> off = layers;
      off.coat = true;
      off.coat_lanes = {0.0f, 0.3f, 0.09f, pbr::k_direct(0.3f), Vec3L<float>(0.0f, 1.0f, 0.0f)};
      off.sheen = true;
      off.sheen_lanes = {Vec3L<float>(0.0f), 0.5f};
      CHECK(same(pbr::shade_layered(ml, off, lights, glm::vec3(0.1f), P, N, V, e, nullptr), base));
      ++compared;
    }
  }
  CHECK(compared == 600);
}

TEST_CASE("layers in a white furnace stay within the energy that arrives") {
  // A uniform environment of radiance 1 and no lights: what a white, rough dielectric with a
  // full sheen and a full coat reflects toward v stays ≤ 1, and each layer changes it.
  const pbr::PreparedEnvironment env = white_furnace();
  const Vec3L<float> N(0.0f, 0.0f, 1.0f), P(0.0f);
  for (float NoV : {0.05f, 0.3f, 0.7f, 1.0f}) {
    const Vec3L<float> V(std::sqrt(1.0f - NoV * NoV), 0.0f, NoV);
    for (float rough : {0.1f, 0.5f, 1.0f}) {
      const pbr::MaterialLanes<float> m = material(0.0f, rough, glm::vec3(1.0f));
      pbr::LayerLanes<float> layers = neutral_layers(0.0f);
      pbr::MaterialLanes<float> ml = m;
      const Vec3L<float> base = pbr::shade_layered(ml, layers, {}, glm::vec3(0.0f), P, N, V, &env, nullptr);
      layers.sheen = true;
      layers.sheen_lanes = {Vec3L<float>(1.0f), rough};
      const Vec3L<float> sheen = pbr::shade_layered(ml, layers, {}, glm::vec3(0.0f), P, N, V, &env, nullptr);
      layers.coat = true;
      layers.coat_lanes = {1.0f, 0.045f, 0.045f * 0.045f, pbr::k_direct(0.045f), N};
      const Vec3L<float> coat = pbr::shade_layered(ml, layers, {}, glm::vec3(0.0f), P, N, V, &env, nullptr);
      CAPTURE(NoV);
      CAPTURE(rough);
      CHECK(base.x <= 1.01f);
      CHECK(sheen.x <= 1.01f);
      CHECK(coat.x <= 1.01f);
      // A smooth sheen seen head-on reflects nothing (its fibres scatter at grazing angles).
      if (pbr::env_sheen_albedo(NoV, rough) > 1e-3f) CHECK(sheen.x != base.x);
      CHECK(coat.x != sheen.x);
      // Energy is redistributed, not lost: each layer keeps at least 90% of the white total.
      CHECK(sheen.x >= 0.9f * base.x);
      CHECK(coat.x >= 0.9f * base.x);
    }
  }
}

TEST_CASE("specular factor and IOR rows change monotonically, as KHR_materials_specular says") {
  const pbr::PreparedEnvironment env = studio_environment();
  const std::vector<pbr::PreparedLight> lights = test_lights();
  const Vec3L<float> N(0.0f, 1.0f, 0.0f), P(0.0f);
  const glm::vec3 l = -lights[0].unit_direction;
  // The mirror of the directional light: the specular highlight.
  const glm::vec3 v = glm::reflect(-l, glm::vec3(0.0f, 1.0f, 0.0f));
  const Vec3L<float> V(v.x, v.y, v.z);
  const pbr::MaterialLanes<float> m = material(0.0f, 0.3f, glm::vec3(0.2f, 0.4f, 0.8f));
  // The specular factor 0 … 1: the highlight grows and the diffuse body (blue) loses less
  // as it does… the total at the highlight grows.
  float previous = -1.0f;
  for (float w : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
    pbr::LayerLanes<float> layers;
    layers.dielectric = pbr::dielectric_lanes(pbr::kDielectricF0, Vec3L<float>(1.0f), w, 0.0f);
    pbr::MaterialLanes<float> ml = m;
    ml.f0 = pbr::layered_f0(layers.dielectric, m.albedo, 0.0f);
    const Vec3L<float> c = pbr::shade_layered(ml, layers, lights, glm::vec3(0.0f), P, N, V, nullptr, nullptr);
    CHECK(c.x > previous);  // red: almost only the (white) highlight
    previous = c.x;
  }
  // IOR 1 → no reflection at all of a dielectric (F0 = 0); then rising F0 with the IOR.
  CHECK(pbr::f0_from_ior(1.0) == 0.0f);
  CHECK(pbr::f0_from_ior(0.0) == 1.0f);
  previous = -1.0f;
  for (double ior : {1.0, 1.2, 1.5, 2.0, 3.0}) {
    pbr::LayerLanes<float> layers;
    layers.dielectric = pbr::dielectric_lanes(pbr::f0_from_ior(ior), Vec3L<float>(1.0f), 1.0f, 0.0f);
    pbr::MaterialLanes<float> ml = m;
    ml.f0 = pbr::layered_f0(layers.dielectric, m.albedo, 0.0f);
    const Vec3L<float> c = pbr::shade_layered(ml, layers, lights, glm::vec3(0.0f), P, N, V, &env, nullptr);
    CHECK(c.x > previous);
    previous = c.x;
  }
  // A metal ignores both (F0 = base colour, F90 = 1).
  const pbr::MaterialLanes<float> metal = material(1.0f, 0.3f, glm::vec3(0.9f, 0.6f, 0.3f));
  pbr::LayerLanes<float> a, b;
  a.dielectric = pbr::dielectric_lanes(pbr::f0_from_ior(1.2), Vec3L<float>(0.3f), 0.2f, 1.0f);
  b.dielectric = pbr::dielectric_lanes(pbr::f0_from_ior(2.5), Vec3L<float>(1.0f), 1.0f, 1.0f);
  pbr::MaterialLanes<float> ma = metal, mb = metal;
  ma.f0 = pbr::layered_f0(a.dielectric, metal.albedo, 1.0f);
  mb.f0 = pbr::layered_f0(b.dielectric, metal.albedo, 1.0f);
  CHECK(same(pbr::shade_layered(ma, a, lights, glm::vec3(0.0f), P, N, V, &env, nullptr),
             pbr::shade_layered(mb, b, lights, glm::vec3(0.0f), P, N, V, &env, nullptr)));
}

TEST_CASE("the layered shader gives the same bits at every lane width") {
  const pbr::PreparedEnvironment env = studio_environment();
  const std::vector<pbr::PreparedLight> lights = test_lights();
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  constexpr int N = 8;
  float nx[N], ny[N], nz[N], rough[N];
  for (int i = 0; i < N; ++i) {
    const glm::vec3 n = random_unit(rng);
    nx[i] = n.x, ny[i] = std::abs(n.y), nz[i] = n.z;
    rough[i] = u(rng);
  }
  using L = simd::Vec<N>;
  const auto shade = [&](auto n_x, auto n_y, auto n_z, auto r) {
    using F = decltype(r);
    pbr::MaterialLanes<F> m;
    m.albedo = Vec3L<F>(F(0.5f), F(0.3f), F(0.2f));
    m.one_minus_metallic = F(0.7f);
    m.roughness = simd::clamp(r, F(pbr::kMinRoughness), F(1.0f));
    m.alpha = m.roughness * m.roughness;
    m.k = pbr::k_direct(m.roughness);
    m.ao = F(1.0f);
    m.emissive = Vec3L<F>(F(0.0f));
    pbr::LayerLanes<F> layers;
    layers.dielectric = pbr::dielectric_lanes(0.06f, Vec3L<F>(F(1.0f), F(0.8f), F(0.9f)), F(0.7f), F(0.3f));
    m.f0 = pbr::layered_f0(layers.dielectric, m.albedo, F(0.3f));
    layers.coat = true;
    layers.coat_lanes = {F(0.8f), m.roughness, m.alpha, m.k, Vec3L<F>(F(0.0f), F(1.0f), F(0.0f))};
    layers.sheen = true;
    layers.sheen_lanes = {Vec3L<F>(F(0.9f), F(0.5f), F(0.4f)), r};
    const Vec3L<F> n(n_x, n_y, n_z), v(F(0.0f), F(0.6f), F(0.8f)), p(F(0.1f), F(0.0f), F(0.2f));
    return pbr::shade_layered(m, layers, lights, glm::vec3(0.0f), p, n, v, &env, nullptr);
  };
  const Vec3L<L> wide = shade(L::load(nx), L::load(ny), L::load(nz), L::load(rough));
  for (int i = 0; i < N; ++i) {
    const Vec3L<float> one = shade(nx[i], ny[i], nz[i], rough[i]);
    CHECK(std::memcmp(&one.x, &reinterpret_cast<const float*>(&wide.x)[i], 4) == 0);
    CHECK(std::memcmp(&one.y, &reinterpret_cast<const float*>(&wide.y)[i], 4) == 0);
    CHECK(std::memcmp(&one.z, &reinterpret_cast<const float*>(&wide.z)[i], 4) == 0);
  }
}

namespace {

// Renders examples/scenes/<name>.json at 400×320, checks it against goldens/<golden>, and
// the same bits at every lane width, with 1 or 2 threads and other tile sizes.
void check_scene_golden(const std::string& name, const std::string& golden) {
  const pbr::SceneFile file =
      pbr::load_scene_file(std::filesystem::path(SOFTPBR_SOURCE_DIR) / "examples" / "scenes" / (name + ".json"));
  const auto render = [&](const raster::RendererOptions& options) {
    raster::Renderer renderer(options);
    raster::Target target(400, 320);
    pbr::render(file.scene, renderer, target);
    return target;
  };
  const raster::Target t = render({.threads = 0});
  CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, file.render.output), "goldens/" + golden);
  for (int lanes : {1, 4, 8, 16}) {
    CAPTURE(lanes);
    const raster::Target o = render({.threads = lanes == 8 ? 1u : 2u, .tile_size = 16 * (lanes % 3 + 1), .lanes = lanes,
                                     .dispatch = lanes != 16});
    CHECK(raster::hash_colors(o) == raster::hash_colors(t));
  }
}

// The error of a scene file whose one object has this material (JSON), or "(no error)".
std::string material_error(const std::string& material) {
  const std::string text = R"({"objects": [{"mesh": {"type": "cube"}, "material": )" + material + "}]}";
  try {
    pbr::parse_scene_file(text, "s.json", ".");
  } catch (const pbr::SceneFileError& e) {
    return std::string(e.what());
  }
  return std::string("(no error)");
}

}  // namespace

TEST_CASE("golden: examples/scenes/layers.json (coat, sheen, specular, IOR rows) at every width and thread count") {
  // Looked at before committing: the coat's reflections grow left to right over the matte red,
  // the velvet whitens at its rim as the sheen roughens, the grey spheres' highlight and the
  // black spheres' reflection grow with the specular factor and with the IOR (1.0: none).
  check_scene_golden("layers", "layers");
}

TEST_CASE("scene files: the layers' keys are checked like every other key") {
  const auto error = material_error;
  CHECK(error(R"({"clearcoat": {"factor": 1, "roughness": 0.2}, "sheen": {"color": [1, 0, 0]}, "ior": 1.4,
                  "specular": {"factor": 0.5, "color": [2, 1, 1]}})") == "(no error)");
  CHECK(error(R"({"ior": 0.5})").find("/objects/0/material/ior") != std::string::npos);
  CHECK(error(R"({"clearcoat": {"factor": 2}})").find("/objects/0/material/clearcoat/factor") != std::string::npos);
  CHECK(error(R"({"sheen": {"colour": [1, 1, 1]}})").find("/objects/0/material/sheen") != std::string::npos);
  CHECK(error(R"({"specular": {"factor": -1}})").find("/objects/0/material/specular/factor") != std::string::npos);
}

// --- Anisotropy (KHR_materials_anisotropy) and the thin film (KHR_materials_iridescence). ---

TEST_CASE("lane math: cos against dmath, and the same bits at every width") {
  const std::vector<float> xs = test_values(-100.0f, 100.0f, 4096);
  double worst = 0.0;
  for (float x : xs) worst = std::max(worst, std::abs(static_cast<double>(pbr::cos_lanes(x)) - pbr::cos_lanes(double{x})));
  CAPTURE(worst);
  CHECK(worst < 2e-6);  // the reduction of |x| ≤ 100 and one float rounding of r
  CHECK(pbr::cos_lanes(0.0f) == 1.0f);
  CHECK(pbr::cos_lanes(3.14159265f) == doctest::Approx(-1.0).epsilon(1e-6));
  check_lanes_match_scalar<4>(xs, [](auto x) { return pbr::cos_lanes(x); });
  check_lanes_match_scalar<8>(xs, [](auto x) { return pbr::cos_lanes(x); });
  check_lanes_match_scalar<16>(xs, [](auto x) { return pbr::cos_lanes(x); });
}

namespace {
// D_GGX_anisotropic_t at a unit half vector h = (t·h, b·h, n·h) of the frame (t, b, n).
double D_aniso(double th, double bh, double nh, double at, double ab) {
  return pbr::D_GGX_anisotropic_t(th, bh, nh, 1.0, at, ab);
}
}  // namespace

TEST_CASE("anisotropic GGX: normalised, GGX at strength 0, its visibility Smith's height-correlated one") {
  // ∫ D (n·h) dω_h = 1 over the hemisphere, by the midpoint rule in (θ, φ).
  for (const std::pair<double, double>& alphas : std::vector<std::pair<double, double>>{{0.3, 0.3}, {0.6, 0.2}, {1.0, 0.25}, {0.5, 0.45}}) {
    const double at = alphas.first, ab = alphas.second;  // not bindings: CAPTURE's lambda (clang 14)
    CAPTURE(at);
    CAPTURE(ab);
    const int nt = 2000, np = 400;
    double sum = 0.0;
    for (int i = 0; i < nt; ++i) {
      const double theta = (i + 0.5) * (softpbr::dmath::kPi / 2) / nt;
      const double st = softpbr::dmath::sin(theta), ct = softpbr::dmath::cos(theta);
      for (int j = 0; j < np; ++j) {
        const double phi = (j + 0.5) * 2 * softpbr::dmath::kPi / np;
        sum += D_aniso(st * softpbr::dmath::cos(phi), st * softpbr::dmath::sin(phi), ct, at, ab) * ct * st;
      }
    }
    CHECK(sum * (softpbr::dmath::kPi / 2 / nt) * (2 * softpbr::dmath::kPi / np) == doctest::Approx(1.0).epsilon(2e-3));
  }
  // α_t = α_b = α: D_GGX, at any h.
  std::mt19937 rng(3);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 hf = random_unit(rng);
    const double len = std::sqrt(double{hf.x} * hf.x + double{hf.y} * hf.y + double{hf.z} * hf.z);
    const double hx = hf.x / len, hy = hf.y / len, nh = std::abs(hf.z) / len, alpha = 0.05 + 0.9 * (i / 200.0);
    CHECK(D_aniso(hx, hy, nh, alpha, alpha) == doctest::Approx(pbr::D_GGX(nh, alpha)).epsilon(1e-9));
    // The lane form in float against the double oracle.
    const float f = pbr::D_GGX_anisotropic_t(hf.x, hf.y, std::abs(hf.z), 1.0f, static_cast<float>(alpha),
                                             static_cast<float>(alpha * 0.5));
    CHECK(f == doctest::Approx(D_aniso(hf.x, hf.y, std::abs(hf.z), alpha, alpha * 0.5)).epsilon(1e-4));
  }
  // The visibility at α_t = α_b: 1/2 / (n·l √(α² + (1 − α²)(n·v)²) + n·v √(α² + (1 − α²)(n·l)²)).
  for (double alpha : {0.1, 0.4, 0.9}) {
    for (double nv : {0.1, 0.5, 1.0}) {
      for (double nl : {0.2, 0.7}) {
        // t·v² + b·v² = 1 − n·v² (unit vectors).
        const double tv = std::sqrt(1 - nv * nv), tl = 0.6 * std::sqrt(1 - nl * nl), bl = 0.8 * std::sqrt(1 - nl * nl);
        const double a2 = alpha * alpha;
        const double expected =
            0.5 / (nl * std::sqrt(a2 + (1 - a2) * nv * nv) + nv * std::sqrt(a2 + (1 - a2) * nl * nl));
        CHECK(pbr::V_GGX_anisotropic(nl, nv, tv, 0.0, tl, bl, alpha, alpha) ==
              doctest::Approx(std::min(expected, 1.0)).epsilon(1e-12));
      }
    }
  }
}

TEST_CASE("anisotropy: a stronger lobe is lower at the mirror and wider along its direction") {
  // α = 0.3² along b; along t α_t = mix(α, 1, s²): the peak falls, and the lobe 0.4 rad off
  // the mirror along t grows against the same angle across it (the highlight stretches).
  const double alpha = 0.09;
  double peak = 1e30, stretch = 0.0;
  for (double s : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    const double at = alpha + (1 - alpha) * s * s;
    const double p = D_aniso(0.0, 0.0, 1.0, at, alpha);
    const double along = D_aniso(std::sin(0.4), 0.0, std::cos(0.4), at, alpha);
    const double across = D_aniso(0.0, std::sin(0.4), std::cos(0.4), at, alpha);
    CAPTURE(s);
    if (s > 0) {
      CHECK(p < peak);
      CHECK(along / across > stretch);
    } else {
      CHECK(along == doctest::Approx(across).epsilon(1e-12));
    }
    peak = p, stretch = along / across;
  }
}

TEST_CASE("the thin film: float against double, the extension's formulas, colours that change with thickness") {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  double worst = 0.0;
  for (int i = 0; i < 500; ++i) {
    const float cos1 = 0.02f + 0.98f * u(rng), ior = 1.0f + u(rng), d = 1200.0f * u(rng);
    const glm::vec3 f0(u(rng), u(rng), u(rng));
    const Vec3L<float> f = pbr::F_iridescence(pbr::thin_film(cos1, ior, d), Vec3L<float>(f0.x, f0.y, f0.z));
    const Vec3L<double> g =
        pbr::F_iridescence(pbr::thin_film<double>(cos1, ior, d), Vec3L<double>(f0.x, f0.y, f0.z));
    worst = std::max({worst, std::abs(f.x - g.x), std::abs(f.y - g.y), std::abs(f.z - g.z)});
    CHECK(f.x >= 0.0f);
    CHECK(f.y >= 0.0f);
    CHECK(f.z >= 0.0f);
    CHECK(std::max({f.x, f.y, f.z}) < 1.5f);
  }
  CAPTURE(worst);
  CHECK(worst < 1e-4);
  // Against the extension's formulas written out plainly in double with libm (evalIridescence
  // and evalSensitivity with their cosines of m · phase + m · shift and their exponentials,
  // the phase shifts as vectors): F_iridescence's sign and double-angle shortcuts change
  // nothing beyond dmath's last bits.
  const auto reference = [](double cos1, double eta2, double d, const glm::dvec3& f0) {
    const double pi = softpbr::dmath::kPi;
    const auto schlick = [](double r0, double c) { return r0 + (1 - r0) * std::pow(1 - c, 5); };
    const double x = std::clamp(d / 0.03, 0.0, 1.0);
    const double eta = 1 + (eta2 - 1) * (x * x * (3 - 2 * x));
    const double cos2 = std::sqrt(1 - (1 / eta) * (1 / eta) * (1 - cos1 * cos1));
    const double R0 = std::pow((eta - 1) / (eta + 1), 2);
    const double R12 = schlick(R0, cos1), T121 = 1 - R12;
    const double phi21 = pi;  // the film's index ≥ the outside's: φ12 = 0
    const double opd = 2 * eta * d * cos2;
    glm::dvec3 out;
    double phi[3], R23[3];
    for (int c = 0; c < 3; ++c) {
      const double s = std::sqrt(std::clamp(f0[c], 0.0, 0.9999));
      const double n3 = (1 + s) / (1 - s);
      R23[c] = schlick(std::pow((n3 - eta) / (n3 + eta), 2), cos2);
      phi[c] = phi21 + (n3 < eta ? pi : 0.0);
    }
    const auto sensitivity = [&](double o, const double* shift) {
      const double phase = 2 * pi * o * 1e-9;
      const double val[3] = {5.4856e-13, 4.4201e-13, 5.2481e-13}, pos[3] = {1.6810e+06, 1.7953e+06, 2.2084e+06},
                   var[3] = {4.3278e+09, 9.3046e+09, 6.6121e+09};
      double xyz[3];
      for (int c = 0; c < 3; ++c)
        xyz[c] = val[c] * std::sqrt(2 * pi * var[c]) * std::cos(pos[c] * phase + shift[c]) * std::exp(-phase * phase * var[c]);
      xyz[0] += 9.7470e-14 * std::sqrt(2 * pi * 4.5282e+09) * std::cos(2.2399e+06 * phase + shift[0]) *
                std::exp(-4.5282e+09 * phase * phase);
      for (double& v : xyz) v /= 1.0685e-7;
      return glm::dvec3(3.2404542 * xyz[0] - 1.5371385 * xyz[1] - 0.4985314 * xyz[2],
                        -0.9692660 * xyz[0] + 1.8760108 * xyz[1] + 0.0415560 * xyz[2],
                        0.0556434 * xyz[0] - 0.2040259 * xyz[1] + 1.0572252 * xyz[2]);
    };
    glm::dvec3 I, Cm;
    for (int c = 0; c < 3; ++c) {
      const double R123 = std::clamp(R12 * R23[c], 1e-5, 0.9999);
      const double Rs = T121 * T121 * R23[c] / (1 - R123);
      I[c] = R12 + Rs;
      Cm[c] = Rs - T121;
    }
    for (int m = 1; m <= 2; ++m) {
      const double shift[3] = {m * phi[0], m * phi[1], m * phi[2]};
      const glm::dvec3 S = 2.0 * sensitivity(m * opd, shift);
      for (int c = 0; c < 3; ++c) {
        Cm[c] *= std::sqrt(std::clamp(R12 * R23[c], 1e-5, 0.9999));
        I[c] += Cm[c] * S[c];
      }
    }
    for (int c = 0; c < 3; ++c) out[c] = std::max(I[c], 0.0);
    return out;
  };
  double worst_reference = 0.0;
  for (int i = 0; i < 300; ++i) {
    const double cos1 = 0.02 + 0.98 * u(rng), eta2 = 1.0 + u(rng), d = 1200.0 * u(rng);
    const glm::dvec3 f0(u(rng), u(rng), u(rng));
    const Vec3L<double> g = pbr::F_iridescence(pbr::thin_film<double>(cos1, eta2, d), Vec3L<double>(f0.x, f0.y, f0.z));
    const glm::dvec3 r = reference(cos1, eta2, d, f0);
    worst_reference = std::max({worst_reference, std::abs(g.x - r.x), std::abs(g.y - r.y), std::abs(g.z - r.z)});
  }
  CAPTURE(worst_reference);
  CHECK(worst_reference < 1e-6);  // dmath's cos and exp against libm's: 3.4·10⁻⁸ seen
  // Thickness changes the colour (the hue of a 300 nm film is not that of a 500 nm one) and
  // thick films average out toward the film-free reflectance.
  const auto film = [](double d) {
    return pbr::F_iridescence(pbr::thin_film<double>(0.9, 1.33, d), Vec3L<double>(0.04));
  };
  const Vec3L<double> a = film(300), b = film(500);
  CHECK(std::abs((a.x - a.z) - (b.x - b.z)) > 0.01);
}

TEST_CASE("anisotropy and the thin film in a white furnace, and at their zero strength") {
  const pbr::PreparedEnvironment env = white_furnace();
  const Vec3L<float> N(0.0f, 0.0f, 1.0f), P(0.0f);
  for (float NoV : {0.05f, 0.3f, 0.7f, 1.0f}) {
    const Vec3L<float> V(std::sqrt(1.0f - NoV * NoV), 0.0f, NoV);
    for (float rough : {0.1f, 0.5f, 1.0f}) {
      for (float metallic : {0.0f, 1.0f}) {
        const pbr::MaterialLanes<float> m = material(metallic, rough, glm::vec3(1.0f));
        pbr::LayerLanes<float> layers = neutral_layers(metallic);
        pbr::MaterialLanes<float> ml = m;
        const Vec3L<float> base = pbr::shade_layered(ml, layers, {}, glm::vec3(0.0f), P, N, V, &env, nullptr);
        layers.anisotropy = true;
        layers.anisotropy_lanes = {1.0f, Vec3L<float>(1.0f, 0.0f, 0.0f), Vec3L<float>(0.0f, 1.0f, 0.0f)};
        const Vec3L<float> aniso = pbr::shade_layered(ml, layers, {}, glm::vec3(0.0f), P, N, V, &env, nullptr);
        layers.anisotropy = false;
        layers.film = true;
        layers.film_lanes = {1.0f, 400.0f, 1.3f};
        layers.dielectric_color = Vec3L<float>(0.04f);
        const Vec3L<float> film = pbr::shade_layered(ml, layers, {}, glm::vec3(0.0f), P, N, V, &env, nullptr);
        CAPTURE(NoV);
        CAPTURE(rough);
        CAPTURE(metallic);
        for (float c : {aniso.x, aniso.y, aniso.z, film.x, film.y, film.z}) CHECK(c <= 1.05f);
        // A uniform environment looks the same from every direction: the bent lookup changes
        // nothing there (the lobe's direction does not matter, only its width).
        CHECK(aniso.x == doctest::Approx(base.x).epsilon(1e-5));
      }
    }
  }
  // A film of thickness 0 is no film: the same bits as without it (the factor becomes 0, and
  // every mix by it keeps its first term exactly).
  {
    const pbr::PreparedEnvironment studio = studio_environment();
    const std::vector<pbr::PreparedLight> lights = test_lights();
    const pbr::MaterialLanes<float> m = material(0.4f, 0.3f, glm::vec3(0.8f, 0.5f, 0.3f));
    pbr::LayerLanes<float> layers = neutral_layers(0.4f);
    pbr::MaterialLanes<float> ml = m;
    const Vec3L<float> V(0.3f, 0.2f, 0.9327379f), Nn(0.1f, 0.0f, 0.99498744f);
    const Vec3L<float> without = pbr::shade_layered(ml, layers, lights, glm::vec3(0.0f), P, Nn, V, &studio, nullptr);
    layers.film = true;
    layers.film_lanes = {1.0f, 0.0f, 1.5f};
    layers.dielectric_color = Vec3L<float>(0.04f);
    CHECK(same(pbr::shade_layered(ml, layers, lights, glm::vec3(0.0f), P, Nn, V, &studio, nullptr), without));
    layers.film_lanes.thickness = 300.0f;
    CHECK_FALSE(same(pbr::shade_layered(ml, layers, lights, glm::vec3(0.0f), P, Nn, V, &studio, nullptr), without));
  }
  // Strength 0 and factor 0 are no layer at all: the material draws with the core shaders.
  pbr::Material m;
  m.anisotropy.rotation = 1.0f;
  m.iridescence.ior = 1.8f;
  m.iridescence.thickness_max = 700.0f;
  CHECK_FALSE(m.layered());
  m.anisotropy.strength = 0.5f;
  CHECK(m.layered());
  m.anisotropy.strength = 0.0f;
  m.iridescence.factor = 0.1f;
  CHECK(m.layered());
}

TEST_CASE("anisotropy and the thin film give the same bits at every lane width") {
  const pbr::PreparedEnvironment env = studio_environment();
  const std::vector<pbr::PreparedLight> lights = test_lights();
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  constexpr int N = 16;
  float nx[N], ny[N], nz[N], rough[N], thick[N];
  for (int i = 0; i < N; ++i) {
    const glm::vec3 n = random_unit(rng);
    nx[i] = n.x, ny[i] = std::abs(n.y), nz[i] = n.z;
    rough[i] = u(rng);
    thick[i] = 1000.0f * u(rng);
  }
  const auto shade = [&](auto n_x, auto n_y, auto n_z, auto r, auto d) {
    using F = decltype(r);
    pbr::MaterialLanes<F> m;
    m.albedo = Vec3L<F>(F(0.9f), F(0.6f), F(0.4f));
    m.one_minus_metallic = F(0.4f);
    m.roughness = simd::clamp(r, F(pbr::kMinRoughness), F(1.0f));
    m.alpha = m.roughness * m.roughness;
    m.k = pbr::k_direct(m.roughness);
    m.ao = F(1.0f);
    m.emissive = Vec3L<F>(F(0.0f));
    pbr::LayerLanes<F> layers;
    layers.dielectric = pbr::dielectric_lanes(0.04f, Vec3L<F>(F(1.0f)), F(1.0f), F(0.6f));
    m.f0 = pbr::layered_f0(layers.dielectric, m.albedo, F(0.6f));
    const Vec3L<F> n(n_x, n_y, n_z), v(F(0.0f), F(0.6f), F(0.8f)), p(F(0.1f), F(0.0f), F(0.2f));
    layers.anisotropy = true;
    layers.anisotropy_lanes.strength = r;
    layers.anisotropy_lanes.t = pbr::normalize_or(Vec3L<F>(F(1.0f), F(0.0f), F(0.0f)) - n * n_x, n);
    layers.anisotropy_lanes.b = Vec3L<F>(n.y * layers.anisotropy_lanes.t.z - n.z * layers.anisotropy_lanes.t.y,
                                         n.z * layers.anisotropy_lanes.t.x - n.x * layers.anisotropy_lanes.t.z,
                                         n.x * layers.anisotropy_lanes.t.y - n.y * layers.anisotropy_lanes.t.x);
    layers.film = true;
    layers.film_lanes = {F(0.8f), d, 1.5f};
    layers.dielectric_color = Vec3L<F>(F(0.04f));
    return pbr::shade_layered(m, layers, lights, glm::vec3(0.0f), p, n, v, &env, nullptr);
  };
  const auto check_width = [&](auto tag) {
    using L = decltype(tag);
    constexpr int W = sizeof(L) / sizeof(float);
    for (int first = 0; first < N; first += W) {
      const Vec3L<L> wide =
          shade(L::load(nx + first), L::load(ny + first), L::load(nz + first), L::load(rough + first), L::load(thick + first));
      for (int i = 0; i < W; ++i) {
        const Vec3L<float> one = shade(nx[first + i], ny[first + i], nz[first + i], rough[first + i], thick[first + i]);
        CHECK(std::memcmp(&one.x, &reinterpret_cast<const float*>(&wide.x)[i], 4) == 0);
        CHECK(std::memcmp(&one.y, &reinterpret_cast<const float*>(&wide.y)[i], 4) == 0);
        CHECK(std::memcmp(&one.z, &reinterpret_cast<const float*>(&wide.z)[i], 4) == 0);
      }
    }
  };
  check_width(simd::Vec<4>{});
  check_width(simd::Vec<8>{});
  check_width(simd::Vec<16>{});
}

TEST_CASE("golden: examples/scenes/layers_anisotropy_iridescence.json at every width and thread count") {
  // Looked at before committing: the silver row's highlight stretches as the strength grows,
  // the copper row's streak turns with the rotation, the black row's thin-film colours grow
  // with the factor, the chrome row's colours change with the film's thickness.
  check_scene_golden("layers_anisotropy_iridescence", "layers_anisotropy_iridescence");
}

TEST_CASE("scene files: the anisotropy's and the film's keys are checked like every other key") {
  const auto error = material_error;
  CHECK(error(R"({"anisotropy": {"strength": 0.5, "rotation": 1.2},
                  "iridescence": {"factor": 1, "ior": 1.3, "thickness_min": 100, "thickness_max": 400}})") ==
        "(no error)");
  CHECK(error(R"({"anisotropy": {"strength": 1.5}})").find("/objects/0/material/anisotropy/strength") !=
        std::string::npos);
  CHECK(error(R"({"anisotropy": {"direction": 1}})").find("/objects/0/material/anisotropy") != std::string::npos);
  CHECK(error(R"({"iridescence": {"ior": 0.5}})").find("/objects/0/material/iridescence/ior") != std::string::npos);
  CHECK(error(R"({"iridescence": {"thickness_max": -1}})").find("/objects/0/material/iridescence/thickness_max") !=
        std::string::npos);
}
