// Render Fidelity scenarios (see scenario.h).
#include "scenario.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cli_error.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/image/read_file.h"

namespace softpbr::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A scenario file is a few kilobytes; the project's config.json with every scenario ~30 KB.
constexpr std::uint64_t kMaxScenarioBytes = 4u << 20;

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw Error(kExitInput, file_ + ": " + (where.empty() ? "/" : where) + ": " + what);
  }
  const json& member(const json& o, const std::string& where, const char* key) const {
    if (!o.is_object()) fail(where, "expected an object");
    const auto it = o.find(key);
    if (it == o.end()) fail(where, std::string("missing key \"") + key + "\"");
    return *it;
  }
  double number(const json& o, const std::string& where, const char* key, double lo, double hi) const {
    const json& v = member(o, where, key);
    const std::string at = where + "/" + key;
    if (!v.is_number()) fail(at, "expected a number");
    const double x = v.get<double>();
    if (!(x >= lo && x <= hi)) fail(at, "expected a number in [" + show(lo) + ", " + show(hi) + "], got " + show(x));
    return x;
  }
  std::string text(const json& o, const std::string& where, const char* key) const {
    const json& v = member(o, where, key);
    if (!v.is_string()) fail(where + "/" + key, "expected a string");
    return v.get<std::string>();
  }
  static std::string show(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
  }

 private:
  std::string file_;
};

}  // namespace

Scenario read_scenario(const std::string& path, const std::string& name) {
  std::string bytes;
  if (const image::FileProblem p = image::read_whole_file(path, kMaxScenarioBytes, bytes))
    throw Error(kExitInput, path + ": " + (p.folder ? std::string("is a folder, not a scenario") : p.reason));
  json root = json::parse(bytes.begin(), bytes.end(), nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded()) throw Error(kExitInput, path + ": not valid JSON");
  const Reader r(path);
  const json* scenario = &root;
  std::string where;
  if (root.is_object() && root.contains("scenarios")) {
    const json& list = root["scenarios"];
    if (!list.is_array() || list.empty()) r.fail("/scenarios", "expected a non-empty array");
    std::size_t pick = list.size();
    for (std::size_t i = 0; i < list.size(); ++i)
      if (name.empty() ? list.size() == 1 : (list[i].is_object() && list[i].value("name", "") == name)) pick = i;
    if (pick == list.size())
      r.fail("/scenarios", name.empty() ? std::to_string(list.size()) + " scenarios: name one with --scenario-name"
                                        : "no scenario named \"" + name + "\"");
    scenario = &list[pick];
    where = "/scenarios/" + std::to_string(pick);
  } else if (!name.empty() && (!root.is_object() || root.value("name", "") != name)) {
    r.fail("/name", "not \"" + name + "\"");
  }
  const json& s = *scenario;
  Scenario out;
  const fs::path base = fs::path(path).parent_path();
  auto resolve = [&](const std::string& p) { return fs::path(p).is_absolute() || base.empty() ? p : (base / p).string(); };
  out.model = resolve(r.text(s, where, "model"));
  if (s.is_object() && s.contains("name")) out.name = r.text(s, where, "name");
  if (s.is_object() && s.contains("lighting")) out.lighting = resolve(r.text(s, where, "lighting"));
  const json& dims = r.member(s, where, "dimensions");
  out.width = static_cast<long>(r.number(dims, where + "/dimensions", "width", 1, raster::kMaxTargetSize));
  out.height = static_cast<long>(r.number(dims, where + "/dimensions", "height", 1, raster::kMaxTargetSize));
  constexpr double kBig = 1e30;
  const json& target = r.member(s, where, "target");
  out.target = {r.number(target, where + "/target", "x", -kBig, kBig), r.number(target, where + "/target", "y", -kBig, kBig),
                r.number(target, where + "/target", "z", -kBig, kBig)};
  const json& orbit = r.member(s, where, "orbit");
  out.theta = r.number(orbit, where + "/orbit", "theta", -360, 360);
  out.phi = r.number(orbit, where + "/orbit", "phi", 0, 180);
  out.radius = r.number(orbit, where + "/orbit", "radius", 1e-6, kBig);
  out.vertical_fov = r.number(s, where, "verticalFoV", 1, 179);
  if (s.contains("renderSkybox")) {
    if (!s["renderSkybox"].is_boolean()) r.fail(where + "/renderSkybox", "expected true or false");
    out.render_skybox = s["renderSkybox"].get<bool>();
  }
  return out;
}

void apply_scenario(const Scenario& s, job::Settings& settings) {
  if (!settings.width) settings.width = s.width;
  if (!settings.height) settings.height = s.height;
  if (!settings.env) settings.env = s.lighting.empty() ? std::string("studio") : s.lighting;
  // Without the skybox the renderers of the comparison show the model alone: transparent.
  if (!settings.background) settings.background = s.render_skybox ? "environment" : "transparent";
}

pbr::Camera scenario_camera(const Scenario& s, const pbr::Bounds& bounds) {
  const double theta = dmath::radians(s.theta), phi = dmath::radians(s.phi);
  const glm::dvec3 dir(dmath::sin(phi) * dmath::sin(theta), dmath::cos(phi), dmath::sin(phi) * dmath::cos(theta));
  pbr::Camera c;
  c.target = glm::vec3(s.target);
  c.position = glm::vec3(s.target + dir * s.radius);
  // Straight above or below: "up" is the direction θ faces at the horizon.
  const double horizontal = dmath::sin(phi);
  c.up = horizontal > 1e-6 ? glm::vec3(0.0f, 1.0f, 0.0f)
                           : glm::vec3(glm::dvec3(-dmath::sin(theta), 0.0, -dmath::cos(theta)) * (s.phi < 90 ? 1.0 : -1.0));
  c.fovy = static_cast<float>(dmath::radians(s.vertical_fov));
  // Near and far hold the whole model: from the camera to the far side of its bounding
  // sphere; near at most 1/10000 of far (depth precision), never behind the camera.
  double r = 1.0, d = s.radius;
  if (!bounds.empty()) {
    const glm::dvec3 centre = (glm::dvec3(bounds.min) + glm::dvec3(bounds.max)) * 0.5;
    const glm::dvec3 extent = glm::dvec3(bounds.max) - glm::dvec3(bounds.min);
    r = std::sqrt(glm::dot(extent, extent)) / 2.0;
    d = glm::length(glm::dvec3(c.position) - centre);
  }
  const double far = d + 1.5 * r + s.radius * 1e-3;
  c.far = static_cast<float>(far);
  c.near = static_cast<float>(std::max(d - 1.5 * r, far / 1e4));
  return c;
}

}  // namespace softpbr::cli
