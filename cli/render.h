// render.h — `softpbr render SCENE -o OUT.png [...]`: a scene file to images, one frame or a
// sharded frame list; `softpbr render a.glb b.glb -o thumbs/{name}.png`: several inputs in
// one run, one renderer for all (see docs/scene-format.md for the scene and the command).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "softpbr/job/render_job.h"

namespace softpbr::cli {

struct RenderArgs {
  std::vector<std::string> scenes;  // one scene file or model, or several (a batch: docs/scene-format.md)
  std::vector<std::string> outputs;
  // The render's settings (softpbr::job): an option given overrides the scene's value.
  job::Settings settings;
  double max_memory_mib = 0;       // --max-memory, shown with its default
  std::vector<std::string> roots;  // --root: the folders a scene may read files from
  std::string env_cache;
  std::optional<std::string> frames, shard;
  std::string scenario, scenario_name;  // --scenario: a Render Fidelity scenario (scenario.h)
  bool force = false;
  bool quiet = false;
  bool turntable = false;  // --turntable: with --fps, the camera and lights turn too
};

CLI::App* add_render_command(CLI::App& app, RenderArgs& args);
int run_render(const RenderArgs& args);

}  // namespace softpbr::cli
