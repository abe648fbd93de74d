// The fidelity protocol (see fidelity.h and ../shared/fidelity/README.md).
#include "fidelity.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/image/load.h"

namespace softpbr::fidelity {

namespace fs = std::filesystem;

const std::vector<std::string>& models() {
  static const std::vector<std::string> m = {"WaterBottle", "MetalRoughSpheresNoTextures", "NormalTangentMirrorTest",
                                             "AlphaBlendModeTest"};
  return m;
}

fs::path find_shared(const fs::path& source_dir) {
  const char* named = std::getenv("SOFTPBR_SHARED");  // a worktree's build: ../shared is elsewhere
  const fs::path shared = named != nullptr ? fs::path(named) : source_dir.parent_path() / "shared";
  std::error_code ec;
  if (fs::is_directory(shared / "fidelity", ec) && fs::is_directory(shared / "gltf", ec) &&
      fs::is_regular_file(shared / "envmaps" / "studio_small_03_1k.hdr", ec))
    return shared;
  return {};
}

void aces_threejs(const float linear[3], std::uint8_t out[3]) {
  const double k = 1.0 / 0.6;
  const double c[3] = {linear[0] * k, linear[1] * k, linear[2] * k};
  static constexpr double in[3][3] = {{0.59719, 0.35458, 0.04823}, {0.07600, 0.90834, 0.01566}, {0.02840, 0.13383, 0.83777}};
  static constexpr double outm[3][3] = {
      {1.60475, -0.53108, -0.07367}, {-0.10208, 1.10813, -0.00605}, {-0.00327, -0.07276, 1.07602}};
  double v[3];
  for (int i = 0; i < 3; ++i) {
    const double x = in[i][0] * c[0] + in[i][1] * c[1] + in[i][2] * c[2];
    v[i] = (x * (x + 0.0245786) - 0.000090537) / (x * (0.983729 * x + 0.4329510) + 0.238081);
  }
  for (int i = 0; i < 3; ++i) {
    double x = outm[i][0] * v[0] + outm[i][1] * v[1] + outm[i][2] * v[2];
    x = std::clamp(x, 0.0, 1.0);
    x = x <= 0.0031308 ? 12.92 * x : 1.055 * dmath::pow(x, 1.0 / 2.4) - 0.055;
    out[i] = static_cast<std::uint8_t>(std::clamp(std::floor(x * 255.0 + 0.5), 0.0, 255.0));
  }
}

double masked_psnr(const image::Image8& a, const image::Image8& b, const image::Image8& mask) {
  if (a.width != mask.width || a.height != mask.height || b.width != mask.width || b.height != mask.height)
    throw std::invalid_argument("masked_psnr: the images differ in size");
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(mask.width) * static_cast<std::size_t>(mask.height); ++p) {
    const std::uint8_t* m = &mask.rgba[4 * p];
    if (m[0] == 255 && m[1] == 0 && m[2] == 255) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = static_cast<double>(a.rgba[4 * p + c]) - static_cast<double>(b.rgba[4 * p + c]);
      sum += d * d;
    }
    n += 3;
  }
  if (n == 0) throw std::invalid_argument("masked_psnr: the mask has no model pixel");
  if (sum == 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 / (sum / static_cast<double>(n)));
}

namespace {

fs::path model_file(const fs::path& folder) {
  for (const char* sub : {"glTF-Binary", "glTF"}) {
    std::error_code ec;
    if (!fs::is_directory(folder / sub, ec)) continue;
    for (const auto& e : fs::directory_iterator(folder / sub)) {
      const std::string ext = e.path().extension().string();
      if (ext == ".glb" || ext == ".gltf") return e.path();
    }
  }
  throw std::runtime_error(folder.string() + ": no .glb or .gltf model");
}

image::Image8 load(const fs::path& p) {
  std::error_code ec;
  if (!fs::is_regular_file(p, ec)) throw std::runtime_error(p.string() + ": missing reference file");
  return image::load_png(p);
}

glm::vec3 vec3_of(const nlohmann::json& j) {
  return {j.at(0).get<float>(), j.at(1).get<float>(), j.at(2).get<float>()};
}

}  // namespace

Result measure(const fs::path& shared, const std::string& model, raster::Renderer& renderer, job::Settings settings) {
  const fs::path refs = shared / "fidelity" / model;
  std::ifstream in(refs / "camera.json");
  if (!in) throw std::runtime_error((refs / "camera.json").string() + ": missing reference file");
  const nlohmann::json cam = nlohmann::json::parse(in);

  settings.width = cam.at("width").get<long>();
  settings.height = cam.at("height").get<long>();
  settings.msaa = 4;
  settings.tonemap = "none";
  settings.exposure = 0.0f;
  settings.env = (shared / "envmaps" / "studio_small_03_1k.hdr").string();
  settings.env_intensity = 1.0f;
  settings.env_rotation = -90.0f;
  settings.background = "environment";
  job::validate(settings);
  pbr::LoadedScene loaded = job::load(model_file(shared / "gltf" / model).string(), settings, renderer.pool());
  pbr::Camera& c = loaded.scene.camera;
  c = pbr::Camera{};
  c.position = vec3_of(cam.at("eye"));
  c.target = vec3_of(cam.at("target"));
  c.up = vec3_of(cam.at("up"));
  c.fovy = static_cast<float>(dmath::radians(cam.at("fov_vertical_deg").get<double>()));
  c.near = cam.at("near").get<float>();
  c.far = cam.at("far").get<float>();
  const pbr::RenderSettings rs = job::resolve(loaded.render, settings);

  job::Frame frame;
  frame.render(loaded.scene, rs, renderer, {.rgba8 = false, .linear = true});
  const raster::Target& linear = frame.linear();

  Result r;
  r.model = model;
  r.image = image::Image8(linear.width(), linear.height(),
                          image::PixelVector<std::uint8_t>(static_cast<std::size_t>(linear.width()) *
                                                           static_cast<std::size_t>(linear.height()) * 4));
  const std::span<const glm::vec4> colors = linear.colors();
  for (std::size_t p = 0; p < colors.size(); ++p) {
    const float rgb[3] = {colors[p].x, colors[p].y, colors[p].z};
    aces_threejs(rgb, &r.image.rgba[4 * p]);
    r.image.rgba[4 * p + 3] = 255;
  }
  const image::Image8 mask = load(refs / "mask.png");
  const image::Image8 cycles = load(refs / "cycles_256spp_aces.png");
  const image::Image8 three = load(refs / "threejs_aces.png");
  for (std::size_t p = 0; p < static_cast<std::size_t>(mask.width) * static_cast<std::size_t>(mask.height); ++p)
    if (!(mask.rgba[4 * p] == 255 && mask.rgba[4 * p + 1] == 0 && mask.rgba[4 * p + 2] == 255)) ++r.pixels;
  r.vs_cycles = masked_psnr(r.image, cycles, mask);
  r.vs_threejs = masked_psnr(r.image, three, mask);
  r.threejs_vs_cycles = masked_psnr(three, cycles, mask);
  return r;
}

}  // namespace softpbr::fidelity
