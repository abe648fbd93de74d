// Scene files: /environment, image-based lighting and the background (see scene_file/loader.h).
#include "loader.h"

#include "softpbr/pbr/environment.h"
#include "texture_cache.h"

namespace softpbr::pbr::scene_file {

void read_environment(const Reader& r, const Node& spec, const std::filesystem::path& base_dir, MemoryBudget& budget,
                      const SceneLoadOptions& options, SceneFile& out) {
  r.object(spec, {"file", "intensity", "rotation", "background", "blur", "multiscatter", "occlusion", "size", "samples"});
  EnvironmentLighting& e = out.scene.environment;
  EnvironmentOptions eo;
  if (auto s = r.member(spec, "size")) {
    eo.size = static_cast<int>(r.integer(*s, 0, 2048));
    check_at(r, *s, [&] { validate(eo); });
  }
  if (auto n = r.member(spec, "samples")) eo.samples = static_cast<int>(r.integer(*n, 8, 4096));
  if (auto f = r.member(spec, "file")) {
    const std::filesystem::path path = base_dir / r.string(*f);
    if (const std::string problem = detail::outside_roots(path, options.roots); !problem.empty())
      r.fail(*f, path.string() + ": " + problem);
    out.inputs.push_back(path.string());
    image::Limits limits;
    limits.max_decoded_bytes = std::max<std::uint64_t>(1, budget.left());
    try {
      e.map = load_environment(path, eo, options.pool, options.environment_cache, limits, &out.warnings);
    } catch (const std::exception& ex) {
      r.fail(*f, ex.what());
    }
  } else {
    if (auto s = r.member(spec, "size")) r.fail(*s, "size and samples apply to an environment file; the built-in studio has its own");
    if (auto s = r.member(spec, "samples")) r.fail(*s, "size and samples apply to an environment file; the built-in studio has its own");
    e.map = Environment::studio();
  }
  budget.charge(spec, e.map->bytes(), "the environment");
  out.environment_bytes = e.map->bytes();
  if (auto i = r.member(spec, "intensity")) e.intensity = r.number_f(*i, 0, 1e6);
  if (auto t = r.member(spec, "rotation")) e.rotation = r.number_f(*t, -1e6, 1e6);
  if (auto m = r.member(spec, "multiscatter")) e.multiscatter = r.boolean(*m);
  if (auto o = r.member(spec, "occlusion")) e.occlusion = r.boolean(*o);
  out.scene.background_mode = BackgroundMode::Environment;
  if (auto b = r.member(spec, "background")) {
    if (b->value.is_string()) {
      const std::string mode = r.choice(*b, {"environment", "blur", "transparent"});
      if (mode == "blur") out.scene.background_mode = BackgroundMode::Blur;
      if (mode == "transparent") {
        out.scene.background_mode = BackgroundMode::Color;
        out.scene.background = {0.0f, 0.0f, 0.0f, 0.0f};
      }
    } else if (b->value.is_array()) {
      out.scene.background_mode = BackgroundMode::Color;
      out.scene.background = glm::vec4(r.vec3(*b, 0, 1e30), 1.0f);
    } else {
      r.fail(*b, "expected \"environment\", \"blur\", \"transparent\" or a colour [r, g, b], got " +
                     json_reader::show(b->value));
    }
  }
  if (auto bl = r.member(spec, "blur")) out.scene.background_blur = r.number_f(*bl, 0, 1);
}

}  // namespace softpbr::pbr::scene_file
