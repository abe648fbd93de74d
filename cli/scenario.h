// scenario.h — `softpbr render --scenario scenario.json -o out.png`: a scenario of the Khronos
// glTF Render Fidelity project (a model, an HDR environment, an orbit camera around a
// target, a vertical field of view, the image size, whether the environment is drawn), so
// that softpbr can take part in its comparisons (docs/scene-format.md, "Render Fidelity
// scenarios").
#pragma once

#include <string>

#include <glm/vec3.hpp>

#include "softpbr/job/render_job.h"
#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/mesh.h"

namespace softpbr::cli {

struct Scenario {
  std::string name;
  std::string model;     // resolved against the scenario file's folder
  std::string lighting;  // the environment (.hdr, .exr), resolved likewise; "" for the studio
  long width = 768, height = 768;
  glm::dvec3 target{0.0};
  double theta = 0, phi = 90, radius = 1;  // degrees, degrees, model units
  double vertical_fov = 45;                // degrees
  bool render_skybox = false;
};

// Reads `path`: one scenario object, or a file with "scenarios" (the project's config.json),
// of which `name` picks one (needed when there are several). Throws Error (exit 3) naming
// the file and the JSON path of the first bad value.
Scenario read_scenario(const std::string& path, const std::string& name);

// The scenario's size, environment and background as the render's settings; a setting
// already given on the command line stays.
void apply_scenario(const Scenario& s, job::Settings& settings);

// The orbit camera: at target + radius · (sin φ sin θ, cos φ, sin φ cos θ) (θ about the
// vertical axis from +z, φ from the vertical, as model-viewer's camera-orbit), looking at
// the target, with the vertical field of view; near and far from the model's bounds.
pbr::Camera scenario_camera(const Scenario& s, const pbr::Bounds& bounds);

}  // namespace softpbr::cli
