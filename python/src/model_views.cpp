// softpbr.render_model_views: two models rendered from the same views, framed on the union
// of their bounds (softpbr/job/model_views.h, as `softpbr diff a.glb b.glb` renders them),
// for softpbr.testing.assert_model_matches. The GIL is released while C++ loads and renders.
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.h"
#include "softpbr/job/model_views.h"
#include "softpbr/raster/renderer.h"

namespace softpbr::python {

namespace {

py::dict render_model_views(const std::string& a, const std::string& b, int views, const std::vector<float>& yaws,
                            const std::vector<float>& pitches, int width, int height, std::optional<unsigned> threads,
                            std::optional<std::string> env) {
  require_readable(a);
  require_readable(b);
  job::Settings s;
  s.width = width;
  s.height = height;
  if (threads) s.threads = *threads;
  s.env = std::move(env);
  std::vector<job::View> list;
  try {
    job::validate(s);
    list = yaws.empty() && pitches.empty() ? job::default_views(views) : job::views_from_angles(yaws, pitches);
  } catch (const job::Error& e) {
    value_error(e.what());
  }
  std::vector<image::Image8> expected, actual;
  std::vector<std::pair<std::string, std::string>> summary_a, summary_b;
  std::string error;
  {
    py::gil_scoped_release unlocked;
    try {
      pbr::RenderSettings defaults;
      raster::Renderer renderer(raster::RendererOptions{threads ? *threads : defaults.threads, defaults.tile_size});
      const job::ViewedModel ma = job::load_viewed(a, s, renderer.pool());
      const job::ViewedModel mb = job::load_viewed(b, s, renderer.pool());
      const pbr::RenderSettings ra = job::resolve(ma.scene.render, s), rb = job::resolve(mb.scene.render, s);
      const job::MemoryLimit limit = job::memory_limit(job::requested_memory_limit(s));
      job::check_memory(job::estimate_memory(ma.scene, ra), ra, limit);
      job::check_memory(job::estimate_memory(mb.scene, rb), rb, limit);
      const pbr::Bounds both = ma.bounds.empty()   ? mb.bounds
                               : mb.bounds.empty() ? ma.bounds
                                                   : pbr::Bounds{glm::min(ma.bounds.min, mb.bounds.min),
                                                                 glm::max(ma.bounds.max, mb.bounds.max)};
      job::Frame frame;
      for (const job::View& v : list) {
        const pbr::Camera camera = job::view_camera(both, ra.width, ra.height, v, a + ", " + b);
        frame.render(job::scene_for_view(ma, camera), ra, renderer, {.rgba8 = true});
        expected.push_back(frame.take_rgba());
        frame.render(job::scene_for_view(mb, camera), rb, renderer, {.rgba8 = true});
        actual.push_back(frame.take_rgba());
      }
      summary_a = ma.summary;
      summary_b = mb.summary;
    } catch (const job::Error& e) {
      error = e.what();
    }
  }
  if (!error.empty()) value_error(error);
  py::list out_views, out_a, out_b;
  for (std::size_t i = 0; i < list.size(); ++i) {
    out_views.append(py::make_tuple(list[i].yaw, list[i].pitch));
    out_a.append(to_numpy(std::move(expected[i])));
    out_b.append(to_numpy(std::move(actual[i])));
  }
  py::dict d;
  d["views"] = out_views;
  d["expected"] = out_a;
  d["actual"] = out_b;
  d["expected_summary"] = summary_a;
  d["actual_summary"] = summary_b;
  return d;
}

}  // namespace

void bind_model_views(py::module_& m) {
  m.def("render_model_views", &render_model_views, py::arg("expected"), py::arg("actual"), py::kw_only(),
        py::arg("views") = 8, py::arg("yaws") = std::vector<float>{}, py::arg("pitches") = std::vector<float>{},
        py::arg("width") = 256, py::arg("height") = 256, py::arg("threads") = py::none(), py::arg("env") = py::none(),
        "Renders two models (.gltf, .glb, .obj or scene files) from the same views, framed on the union of their "
        "bounds, as `softpbr diff a b` does: a dict with views [(yaw, pitch)], expected and actual [uint8 (H, W, 4)], "
        "and each file's summary [(property, value)]. OSError if a file cannot be read, ValueError if it is invalid.");
}

}  // namespace softpbr::python
