// The material extensions' layers (layered_shading.h, lane_math.h, the sheen terms of
// brdf.h): lane math against dmath, the analytic limits bit for bit, the sheen's albedo
// table against its integral, energy in a white furnace, and the layers' monotonic rows.
#include <doctest/doctest.h>

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
  const int w = 64, h = 32;
  std::vector<float> white(static_cast<std::size_t>(w) * h * 4, 1.0f);
  pbr::EnvironmentLighting l;
  l.map = std::make_shared<const pbr::Environment>(softpbr::image::ImageViewF(w, h, white), "white");
  const pbr::PreparedEnvironment env = pbr::prepare_environment(l);
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

TEST_CASE("golden: examples/scenes/layers.json (coat, sheen, specular, IOR rows) at every width and thread count") {
  // Looked at before committing: the coat's reflections grow left to right over the matte red,
  // the velvet whitens at its rim as the sheen roughens, the grey spheres' highlight and the
  // black spheres' reflection grow with the specular factor and with the IOR (1.0: none).
  const pbr::SceneFile file =
      pbr::load_scene_file(std::filesystem::path(SOFTPBR_SOURCE_DIR) / "examples" / "scenes" / "layers.json");
  const auto render = [&](const raster::RendererOptions& options) {
    raster::Renderer renderer(options);
    raster::Target target(400, 320);
    pbr::render(file.scene, renderer, target);
    return target;
  };
  const raster::Target t = render({.threads = 0});
  CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, file.render.output), "goldens/layers");
  for (int lanes : {1, 4, 8, 16}) {
    CAPTURE(lanes);
    const raster::Target o = render({.threads = lanes == 8 ? 1u : 2u, .tile_size = 16 * (lanes % 3 + 1), .lanes = lanes,
                                     .dispatch = lanes != 16});
    CHECK(raster::hash_colors(o) == raster::hash_colors(t));
  }
}

TEST_CASE("scene files: the layers' keys are checked like every other key") {
  const auto error = [](const std::string& material) {
    const std::string text = R"({"objects": [{"mesh": {"type": "cube"}, "material": )" + material + "}]}";
    try {
      pbr::parse_scene_file(text, "s.json", ".");
    } catch (const pbr::SceneFileError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  CHECK(error(R"({"clearcoat": {"factor": 1, "roughness": 0.2}, "sheen": {"color": [1, 0, 0]}, "ior": 1.4,
                  "specular": {"factor": 0.5, "color": [2, 1, 1]}})") == "(no error)");
  CHECK(error(R"({"ior": 0.5})").find("/objects/0/material/ior") != std::string::npos);
  CHECK(error(R"({"clearcoat": {"factor": 2}})").find("/objects/0/material/clearcoat/factor") != std::string::npos);
  CHECK(error(R"({"sheen": {"colour": [1, 1, 1]}})").find("/objects/0/material/sheen") != std::string::npos);
  CHECK(error(R"({"specular": {"factor": -1}})").find("/objects/0/material/specular/factor") != std::string::npos);
}
