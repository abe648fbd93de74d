// KHR_materials_transmission and KHR_materials_volume (layered_shading.h's transmitted_light,
// pbr::render's transmission pass): the analytic limits bit for bit, Beer–Lambert against
// its closed form per channel, the pass' bits across lane widths, threads, tiles and sample
// storage, and the scene files' keys.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/golden/doctest_checks.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/layered_shading.h"
#include "softpbr/pbr/light.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
using pbr::Vec3L;

namespace {

bool same(const Vec3L<float>& a, const Vec3L<float>& b) {
  return std::memcmp(&a.x, &b.x, 4) == 0 && std::memcmp(&a.y, &b.y, 4) == 0 && std::memcmp(&a.z, &b.z, 4) == 0;
}

glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  return glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
}

// A unit cube of glass seen face on by an orthographic camera along −z, over the clear
// colour `behind`; no lights, no ambient, no environment: what the glass shows is the
// transmitted light alone (its reflection has nothing to reflect).
pbr::Scene glass_slab(const pbr::Material& glass, const glm::vec3& behind) {
  pbr::Scene s;
  s.camera.position = {0.0f, 0.0f, 5.0f};
  s.camera.target = {0.0f, 0.0f, 0.0f};
  s.camera.orthographic = true;
  s.camera.ymag = 1.0f;
  s.camera.near = 0.0f;
  s.ambient = glm::vec3(0.0f);
  s.background = glm::vec4(behind, 1.0f);
  s.objects.push_back({std::make_shared<const pbr::Mesh>(pbr::cube(1.0f)), glass, glm::mat4(1.0f)});
  return s;
}

pbr::Material clear_glass(float ior) {
  pbr::Material m;
  m.base_color = glm::vec3(1.0f);
  m.roughness = 0.0f;
  m.ior = ior;
  m.transmission.factor = 1.0f;
  return m;
}

// The centre pixel of a render of `s` at 64 × 64.
glm::vec4 centre(const pbr::Scene& s) {
  raster::Renderer renderer({.threads = 2});
  raster::Target target(64, 64);
  pbr::render(s, renderer, target);
  return target.color(32, 32);
}

}  // namespace

TEST_CASE("transmission: a factor of 0 shades the material bit for bit, with or without its uniforms") {
  pbr::EnvironmentLighting lighting;
  lighting.map = pbr::Environment::studio();
  const pbr::PreparedEnvironment env = pbr::prepare_environment(lighting);
  pbr::Light sun;
  sun.type = pbr::LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f));
  sun.intensity = 3.0f;
  const std::vector<pbr::PreparedLight> lights = {pbr::prepare_light(sun)};
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const pbr::TransmissionUniforms uniforms;  // no source: the environment alone is seen through
  int compared = 0;
  for (int i = 0; i < 200; ++i) {
    pbr::Material mat;
    mat.base_color = {u(rng), u(rng), u(rng)};
    mat.metallic = u(rng);
    mat.roughness = u(rng);
    const pbr::MaterialLanes<float> m0 = pbr::lanes<float>(pbr::prepare_material(mat));
    pbr::LayerLanes<float> layers;
    layers.dielectric = pbr::dielectric_lanes(pbr::f0_from_ior(1.4), Vec3L<float>(1.0f), 1.0f, mat.metallic);
    pbr::MaterialLanes<float> m = m0;
    m.f0 = pbr::layered_f0(layers.dielectric, m0.albedo, mat.metallic);
    const glm::vec3 n = random_unit(rng), v = random_unit(rng);
    const Vec3L<float> N(n.x, n.y, n.z), V(v.x, v.y, v.z), P(u(rng), u(rng), u(rng));
    for (const pbr::PreparedEnvironment* e : {static_cast<const pbr::PreparedEnvironment*>(nullptr), &env}) {
      const Vec3L<float> base = pbr::shade_layered(m, layers, lights, glm::vec3(0.1f), P, N, V, e, nullptr);
      pbr::LayerLanes<float> off = layers;
      off.transmission = true;
      off.transmission_lanes = {0.0f, u(rng), u(rng)};
      off.transmission_uniforms = &uniforms;
      CHECK(same(pbr::shade_layered(m, off, lights, glm::vec3(0.1f), P, N, V, e, nullptr), base));
      ++compared;
    }
  }
  CHECK(compared == 400);
  // And in a render: a material whose factor is 0 is not transmissive (no pass, the same bits).
  pbr::Material opaque = clear_glass(1.4f);
  opaque.transmission.factor = 0.0f;
  opaque.volume.thickness = 0.5f;
  CHECK_FALSE(opaque.transmissive());
  pbr::Material plain = opaque;
  plain.volume = pbr::Volume{};
  const glm::vec4 a = centre(glass_slab(opaque, {0.2f, 0.5f, 0.8f})), b = centre(glass_slab(plain, {0.2f, 0.5f, 0.8f}));
  CHECK(std::memcmp(&a, &b, sizeof a) == 0);
}

TEST_CASE("transmission: an IOR of 1 without a volume passes the background through, times 1 − the reflected part") {
  // Face on (n·v = 1): F0(1) = 0, F90 = 1, so the reflected part is the split sum's B at
  // (1, kMinRoughness); the glass shows (1 − B) · behind, and half of that at a factor of 0.5.
  const glm::vec3 behind(0.2f, 0.5f, 0.8f);
  float A = 0.0f, B = 0.0f;
  pbr::env_dfg(1.0f, pbr::kMinRoughness, A, B);
  REQUIRE(B < 0.05f);
  for (const float factor : {1.0f, 0.5f}) {
    CAPTURE(factor);
    pbr::Material glass = clear_glass(1.0f);
    glass.transmission.factor = factor;
    const glm::vec4 c = centre(glass_slab(glass, behind));
    for (int k = 0; k < 3; ++k) {
      CAPTURE(k);
      const double expected = static_cast<double>(behind[k]) * (1.0 - static_cast<double>(B)) * factor;
      CHECK(std::abs(c[k] - expected) <= 2e-6 * expected);
    }
  }
}

TEST_CASE("volume: Beer–Lambert per channel against colour^(d / distance), none at thickness 0 or distance ∞") {
  const glm::vec3 behind(0.6f, 0.7f, 0.9f);
  const glm::vec3 colour(0.5f, 0.25f, 0.8f);
  const float distance = 0.75f;
  pbr::Material clear = clear_glass(1.5f);
  clear.volume.thickness = 1.0f;
  const glm::vec4 through = centre(glass_slab(clear, behind));  // attenuation distance ∞
  REQUIRE(through.r > 0.1f);
  // Thickness 0 and distance ∞ attenuate nothing: the same bits as no volume at all.
  {
    pbr::Material thin = clear_glass(1.5f);
    thin.volume.attenuation_color = colour;
    thin.volume.attenuation_distance = distance;
    pbr::Material none = clear_glass(1.5f);
    const glm::vec4 a = centre(glass_slab(thin, behind)), b = centre(glass_slab(none, behind));
    CHECK(std::memcmp(&a, &b, sizeof a) == 0);
    pbr::Material infinite = clear;
    infinite.volume.attenuation_color = colour;  // distance stays ∞
    const glm::vec4 c = centre(glass_slab(infinite, behind));
    CHECK(std::memcmp(&c, &through, sizeof c) == 0);
  }
  // Face on the refracted ray goes straight through: it travels the thickness (× the
  // object's scale, 1 here), and each channel keeps colour^(thickness / distance).
  for (const float thickness : {0.1f, 0.5f, 1.0f, 2.0f, 4.0f}) {
    CAPTURE(thickness);
    pbr::Material glass = clear_glass(1.5f);
    glass.volume.thickness = thickness;
    glass.volume.attenuation_color = colour;
    glass.volume.attenuation_distance = distance;
    const glm::vec4 c = centre(glass_slab(glass, behind));
    for (int k = 0; k < 3; ++k) {
      CAPTURE(k);
      const double expected = std::pow(static_cast<double>(colour[k]), static_cast<double>(thickness) / distance);
      const double measured = static_cast<double>(c[k]) / static_cast<double>(through[k]);
      CHECK(std::abs(measured - expected) <= 1e-5 * expected + 1e-30);
    }
  }
  // The object's scale scales the thickness (glTF: the node's scale): a cube scaled 2 along
  // z with thickness 0.5 attenuates as thickness 1.
  pbr::Material glass = clear_glass(1.5f);
  glass.volume.thickness = 0.5f;
  glass.volume.attenuation_color = colour;
  glass.volume.attenuation_distance = distance;
  pbr::Scene scaled = glass_slab(glass, behind);
  scaled.objects[0].transform = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 1.0f, 2.0f));
  const glm::vec4 c = centre(scaled);
  for (int k = 0; k < 3; ++k) {
    CAPTURE(k);
    const double expected = std::pow(static_cast<double>(colour[k]), 1.0 / distance);
    CHECK(std::abs(static_cast<double>(c[k]) / through[k] - expected) <= 1e-5 * expected);
  }
}

namespace {

// Glass in front of coloured opaque spheres, lit and in the studio, with a blended sphere in
// front: every stage of the pass (the flush, the copy's mip chain, refraction off screen,
// attenuation, the order transmissive → blended).
pbr::Scene glass_scene() {
  pbr::Scene s;
  s.camera.position = {0.3f, 0.4f, 4.0f};
  s.camera.target = {0.0f, 0.0f, 0.0f};
  s.environment.map = pbr::Environment::studio();
  s.background_mode = pbr::BackgroundMode::Environment;
  pbr::Light sun;
  sun.type = pbr::LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.6f));
  sun.intensity = 2.0f;
  s.lights.push_back(sun);
  const auto sphere = std::make_shared<const pbr::Mesh>(pbr::uv_sphere(0.5f, 32, 16));
  const auto box = std::make_shared<const pbr::Mesh>(pbr::cube(1.0f));
  for (int i = 0; i < 3; ++i) {
    pbr::Material m;
    m.base_color = {i == 0 ? 0.8f : 0.1f, i == 1 ? 0.8f : 0.1f, i == 2 ? 0.8f : 0.1f};
    m.roughness = 0.4f;
    s.objects.push_back({sphere, m, glm::translate(glm::mat4(1.0f), glm::vec3(-1.2f + 1.2f * i, 0.0f, -1.5f))});
  }
  for (int i = 0; i < 3; ++i) {
    pbr::Material g;
    g.base_color = glm::vec3(1.0f);
    g.roughness = 0.3f * static_cast<float>(i);
    g.ior = 1.5f;
    g.transmission.factor = 1.0f;
    g.volume.thickness = 0.8f;
    g.volume.attenuation_color = {0.9f, 0.6f, 0.3f};
    g.volume.attenuation_distance = 1.5f;
    const glm::mat4 t = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(-1.1f + 1.1f * i, 0.1f, 0.3f)), 0.5f,
                                    glm::vec3(0.3f, 1.0f, 0.2f));
    s.objects.push_back({box, g, glm::scale(t, glm::vec3(0.8f))});
  }
  pbr::Material veil;
  veil.base_color = {0.9f, 0.9f, 0.2f};
  veil.alpha = 0.4f;
  veil.alpha_mode = pbr::AlphaMode::Blend;
  s.objects.push_back({sphere, veil, glm::translate(glm::mat4(1.0f), glm::vec3(0.4f, -0.3f, 1.2f))});
  return s;
}

}  // namespace

TEST_CASE("transmission pass: the same bits at every lane width, thread count, tile size and sample storage") {
  const pbr::Scene s = glass_scene();
  for (const int samples : {1, 4}) {
    CAPTURE(samples);
    const auto render = [&](const raster::RendererOptions& options, raster::SampleStorage storage) {
      raster::Renderer renderer(options);
      raster::Target target(160, 120, samples, &renderer.pool(), storage);
      raster::Image8 image;
      pbr::render_outputs(s, renderer, target, pbr::OutputSettings{}, &image, nullptr);
      return std::vector<std::uint8_t>(image.rgba.begin(), image.rgba.end());
    };
    const std::vector<std::uint8_t> reference = render({.threads = 1, .lanes = 1}, raster::SampleStorage::Kept);
    // The glass shows the spheres behind it, tinted: not the clear colour, not all one value.
    std::size_t distinct = 0;
    for (std::size_t i = 4; i < reference.size(); i += 4) distinct += reference[i] != reference[i - 4];
    CHECK(distinct > 1000);
    for (const int lanes : {4, 8, 16}) {
      for (const unsigned threads : {1u, 8u}) {
        CAPTURE(lanes);
        CAPTURE(threads);
        const int tile = lanes == 8 ? 16 : 64;
        CHECK(render({.threads = threads, .tile_size = tile, .lanes = lanes, .dispatch = lanes != 16},
                     raster::SampleStorage::Kept) == reference);
        if (samples > 1)
          CHECK(render({.threads = threads, .tile_size = tile, .lanes = lanes}, raster::SampleStorage::Transient) ==
                reference);
      }
    }
    // Over the geometry budget (several passes before and after the copy): the same bits.
    CHECK(render({.threads = 2, .lanes = 8, .geometry_budget = 4096}, raster::SampleStorage::Kept) == reference);
  }
}

TEST_CASE("transmission: rougher glass blurs what is behind it more") {
  // A sharp black/white edge behind the glass (a black opaque quad over a white clear
  // colour): the rougher the glass, the wider the ramp across the edge.
  std::vector<double> widths;
  for (const float roughness : {0.0f, 0.3f, 0.6f, 1.0f}) {
    pbr::Material glass = clear_glass(1.5f);
    glass.roughness = roughness;
    pbr::Scene s = glass_slab(glass, glm::vec3(1.0f));
    s.objects[0].transform = glm::scale(glm::mat4(1.0f), glm::vec3(1.9f, 1.9f, 0.1f));
    pbr::Material black;
    black.base_color = glm::vec3(0.0f);
    black.emissive = glm::vec3(0.0f);
    black.metallic = 0.0f;
    black.roughness = 1.0f;
    // Left half of the view, behind the glass.
    s.objects.push_back({std::make_shared<const pbr::Mesh>(pbr::cube(1.0f)), black,
                         glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f, 0.0f, -1.0f)),
                                    glm::vec3(1.0f, 3.0f, 0.1f))});
    raster::Renderer renderer({.threads = 2});
    raster::Target target(64, 64);
    pbr::render(s, renderer, target);
    // Pixels of the middle row strictly between black and white.
    int between = 0;
    for (int x = 0; x < 64; ++x) {
      const float r = target.color(x, 32).r;
      between += r > 0.02f && r < 0.8f;
    }
    widths.push_back(between);
  }
  CAPTURE(widths[0]);
  CAPTURE(widths[3]);
  for (std::size_t i = 1; i < widths.size(); ++i) CHECK(widths[i] >= widths[i - 1]);
  CHECK(widths[3] > widths[0] + 4);
}

namespace {
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

TEST_CASE("scene files: the transmission's and the volume's keys are checked like every other key") {
  const auto error = material_error;
  CHECK(error(R"({"transmission": {"factor": 1}, "volume": {"thickness": 0.5, "attenuation_distance": 2,
                  "attenuation_color": [0.9, 0.5, 0.2]}})") == "(no error)");
  CHECK(error(R"({"transmission": {"factor": 1.5}})").find("/objects/0/material/transmission/factor") !=
        std::string::npos);
  CHECK(error(R"({"transmission": 1})").find("/objects/0/material/transmission") != std::string::npos);
  CHECK(error(R"({"volume": {"thickness": -1}})").find("/objects/0/material/volume/thickness") != std::string::npos);
  CHECK(error(R"({"volume": {"attenuation_distance": 0}})").find("/objects/0/material/volume/attenuation_distance") !=
        std::string::npos);
  CHECK(error(R"({"volume": {"attenuation_color": [2, 0, 0]}})").find("/objects/0/material/volume/attenuation_color") !=
        std::string::npos);
  CHECK(error(R"({"volume": {"depth": 1}})").find("/objects/0/material/volume") != std::string::npos);
}

TEST_CASE("transmission: bad values in a Material are refused by render, naming the field") {
  for (const int which : {0, 1, 2, 3}) {
    CAPTURE(which);
    pbr::Material glass = clear_glass(1.5f);
    if (which == 0) glass.transmission.factor = std::nanf("");
    if (which == 1) glass.volume.thickness = std::numeric_limits<float>::infinity();
    if (which == 2) glass.volume.attenuation_distance = 0.0f;
    if (which == 3) glass.volume.attenuation_color = {std::nanf(""), 1.0f, 1.0f};
    const char* field = which == 0 ? "transmission.factor"
                        : which == 1 ? "volume.thickness"
                        : which == 2 ? "volume.attenuation_distance"
                                     : "volume.attenuation_color";
    raster::Renderer renderer({.threads = 1});
    raster::Target target(16, 16);
    std::string what = "(no error)";
    try {
      pbr::render(glass_slab(glass, glm::vec3(0.5f)), renderer, target);
    } catch (const std::invalid_argument& e) {
      what = e.what();
    }
    CHECK(what.find(field) != std::string::npos);
  }
}

TEST_CASE("golden: examples/scenes/glass.json (roughness and attenuation rows) at every width and thread count") {
  // Looked at before committing (docs/design.md, "Shading"): the top row's clear boxes show
  // the spheres behind them shifted by refraction, blurred more to the right as the
  // roughness grows; the bottom row's boxes tint them blue, darker to the right as the
  // attenuation distance shrinks.
  const pbr::SceneFile file =
      pbr::load_scene_file(std::filesystem::path(SOFTPBR_SOURCE_DIR) / "examples" / "scenes" / "glass.json");
  const auto render = [&](const raster::RendererOptions& options) {
    raster::Renderer renderer(options);
    raster::Target target(400, 320);
    pbr::render(file.scene, renderer, target);
    return target;
  };
  const raster::Target t = render({.threads = 0});
  CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, file.render.output), "goldens/glass");
  for (int lanes : {1, 4, 8, 16}) {
    CAPTURE(lanes);
    const raster::Target o = render({.threads = lanes == 8 ? 1u : 2u, .tile_size = 16 * (lanes % 3 + 1), .lanes = lanes,
                                     .dispatch = lanes != 16});
    CHECK(raster::hash_colors(o) == raster::hash_colors(t));
  }
}

TEST_CASE("dispersion: green keeps the undispersed bits, red and blue move, and 0 or a thin wall disperse nothing") {
  pbr::Scene plain = glass_scene();
  pbr::Scene dispersed = plain;
  pbr::Scene zero = plain;
  pbr::Scene thin = plain;
  for (std::size_t i = 0; i < plain.objects.size(); ++i) {
    if (!plain.objects[i].material.transmissive()) continue;
    dispersed.objects[i].material.dispersion = 2.0f;
    dispersed.objects[i].material.ior = 1.8f;
    plain.objects[i].material.ior = 1.8f;
    zero.objects[i].material.ior = 1.8f;
    zero.objects[i].material.dispersion = 0.0f;
    thin.objects[i].material.volume.thickness = 0.0f;
    thin.objects[i].material.dispersion = 2.0f;
  }
  pbr::Scene thin_plain = thin;
  for (pbr::Object& o : thin_plain.objects) o.material.dispersion = 0.0f;
  const auto render = [](const pbr::Scene& s) {
    raster::Renderer renderer({.threads = 2});
    raster::Target target(160, 120);
    pbr::render(s, renderer, target);
    return target;
  };
  const raster::Target a = render(plain), b = render(dispersed);
  CHECK(raster::hash_colors(render(zero)) == raster::hash_colors(a));
  CHECK(raster::hash_colors(render(thin)) == raster::hash_colors(render(thin_plain)));
  int green_differs = 0, red_differs = 0, blue_differs = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      const glm::vec4 p = a.color(x, y), q = b.color(x, y);
      green_differs += std::memcmp(&p.g, &q.g, 4) != 0;
      red_differs += p.r != q.r;
      blue_differs += p.b != q.b;
    }
  CHECK(green_differs == 0);
  CHECK(red_differs > 100);
  CHECK(blue_differs > 100);
}
