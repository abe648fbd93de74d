// Scene files: render settings and the turntable animation (see scene_file/loader.h).
#include "loader.h"

#include "softpbr/raster/renderer.h"
#include "softpbr/raster/target.h"

namespace softpbr::pbr::scene_file {

void read_render(const Reader& r, const Node& spec, SceneFile& out) {
  r.object(spec, {"width", "height", "tonemap", "exposure", "gamma", "background", "threads", "tile_size", "msaa", "resolve"});
  RenderSettings& s = out.render;
  if (auto w = r.member(spec, "width")) s.width = static_cast<int>(r.integer(*w, 1, raster::kMaxTargetSize));
  if (auto h = r.member(spec, "height")) s.height = static_cast<int>(r.integer(*h, 1, raster::kMaxTargetSize));
  if (auto t = r.member(spec, "tonemap"))
    s.output.tone_map = *tone_map_from_name(r.choice(*t, {"none", "reinhard", "aces", "neutral"}));
  if (auto e = r.member(spec, "exposure")) s.output.exposure = r.number_f(*e, -64, 64);
  if (auto g = r.member(spec, "gamma")) {
    if (g->value.is_string() && g->value.get<std::string>() == "srgb") s.output.gamma = 0.0f;
    else if (g->value.is_number()) s.output.gamma = r.number_f(*g, 0.1, 10);
    else r.fail(*g, "expected \"srgb\" or a number in [0.1, 10], got " + json_reader::show(g->value));
  }
  if (auto b = r.member(spec, "background")) {
    if (b->value.is_array() && b->value.size() == 4) {
      const std::vector<float> v = r.numbers(*b, 4, 0, 1e30);
      out.scene.background = {v[0], v[1], v[2], v[3]};
    } else {
      out.scene.background = glm::vec4(r.vec3(*b, 0, 1e30), 1.0f);
    }
  }
  if (auto t = r.member(spec, "threads")) s.threads = static_cast<unsigned>(r.integer(*t, 0, 1024));
  if (auto t = r.member(spec, "tile_size")) {
    s.tile_size = static_cast<int>(r.integer(*t, raster::kMinTileSize, raster::kMaxTileSize));
    if (!raster::valid_tile_size(s.tile_size)) r.fail(*t, "expected an even tile size, got " + std::to_string(s.tile_size));
  }
  if (auto m = r.member(spec, "msaa")) {
    s.msaa = static_cast<int>(r.integer(*m, 1, raster::kMaxSamples));
    if (!raster::valid_sample_count(s.msaa)) r.fail(*m, "expected 1, 4 or 8 samples, got " + std::to_string(s.msaa));
  }
  if (auto v = r.member(spec, "resolve")) s.output.resolve = *resolve_from_name(r.choice(*v, {"tonemapped", "linear"}));
}

void read_animation(const Reader& r, const Node& spec, Animation& a) {
  r.object(spec, {"camera_degrees_per_frame", "light_degrees_per_frame", "light_pivot"});
  if (auto c = r.member(spec, "camera_degrees_per_frame")) a.camera_degrees_per_frame = r.number(*c, -360, 360);
  if (auto l = r.member(spec, "light_degrees_per_frame")) a.light_degrees_per_frame = r.number(*l, -360, 360);
  if (auto p = r.member(spec, "light_pivot")) a.light_pivot = r.vec3(*p);
}

}  // namespace softpbr::pbr::scene_file
