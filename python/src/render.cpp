// softpbr.render / render_hdr: a scene to a numpy image, the GIL released while C++ runs.
//
// The render job (softpbr::job, as `softpbr render` runs it): the scene's render block with
// the keyword arguments over it, checked with the job's messages (a ValueError), the memory
// estimate checked before the target is allocated, then a job::Frame. Ctrl-C: the renderer
// polls RendererOptions::cancel between tiles; on the thread that called render() the poll
// takes the GIL at most every 10 ms and runs PyErr_CheckSignals(), so a KeyboardInterrupt
// (or what a SIGINT handler raises) stops the render and is raised by render() itself.
#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include <pybind11/stl.h>

#include "bindings.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/job/render_job.h"
#include "softpbr/raster/renderer.h"

namespace softpbr::python {

namespace {

std::atomic<int> g_active_renders{0};  // renders inside C++ right now, in any thread

// The scene's settings with the keyword arguments over them, checked, and the memory the
// render needs within the limit (as the command's, bounded by the machine's memory).
pbr::RenderSettings settings_for(const PyScene& s, const job::Settings& o) {
  try {
    job::validate(o);  // the keywords' values (shadows, ground) before any work
    const pbr::RenderSettings r = job::resolve(s.file.render, o);
    job::check_memory(job::estimate_memory(s.file, r), r, job::memory_limit(job::requested_memory_limit(o)));
    return r;
  } catch (const job::Error& e) {
    value_error(e.what());
  }
}

bool is_finalizing() {
#if PY_VERSION_HEX >= 0x030D0000
  return Py_IsFinalizing() != 0;
#else
  return _Py_IsFinalizing() != 0;
#endif
}

// RendererOptions::cancel for a render called from Python (see the top of this file).
class Interrupt {
 public:
  bool poll() {
    if (stop_.load(std::memory_order_relaxed)) return true;
    if (std::this_thread::get_id() != caller_) return false;
    const auto now = std::chrono::steady_clock::now();
    if (now < next_) return false;
    next_ = now + std::chrono::milliseconds(10);
    // A thread that takes the GIL while the interpreter finalizes is ended by Python
    // (pthread_exit), which must not unwind through the renderer's pool. Python only
    // finalizes with this render running when a join() was interrupted (CPython < 3.13).
    if (is_finalizing()) return false;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) stop_.store(true, std::memory_order_relaxed);  // the exception stays set
    return stop_.load(std::memory_order_relaxed);
  }

 private:
  std::thread::id caller_ = std::this_thread::get_id();
  std::chrono::steady_clock::time_point next_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(10);
  std::atomic<bool> stop_{false};
};

// Runs `draw(renderer)` without the GIL; raises what interrupted it.
template <class Draw>
void run_released(const pbr::RenderSettings& r, Draw&& draw) {
  Interrupt interrupt;
  bool cancelled = false;
  {
    py::gil_scoped_release unlocked;
    struct Count {
      Count() { g_active_renders.fetch_add(1); }
      ~Count() { g_active_renders.fetch_sub(1); }
    } count;
    raster::Renderer renderer({.threads = r.threads, .tile_size = r.tile_size, .cancel = [&] { return interrupt.poll(); }});
    try {
      draw(renderer);
    } catch (const raster::Cancelled&) {
      cancelled = true;
    }
  }
  if (cancelled) {
    // Raise the KeyboardInterrupt (or the SIGINT handler's exception) that PyErr_CheckSignals
    // set, with a note saying where it stopped.
    PyObject *type = nullptr, *value = nullptr, *trace = nullptr;
    PyErr_Fetch(&type, &value, &trace);
    PyErr_NormalizeException(&type, &value, &trace);
    if (value && PyObject_HasAttrString(value, "add_note")) {
      PyObject* ok = PyObject_CallMethod(value, "add_note", "s", "softpbr: the render stopped early (interrupted between tiles)");
      if (ok) Py_DECREF(ok);
      else PyErr_Clear();
    }
    PyErr_Restore(type, value, trace);
    throw py::error_already_set();
  }
}

// The command's frame range (--frames: 0 .. job::kMaxFrame), named as the keyword.
void check_frame(long frame) {
  if (frame < 0 || frame > job::kMaxFrame)
    value_error("frame: expected a frame in [0, " + std::to_string(job::kMaxFrame) + "], got " + std::to_string(frame));
}

py::array_t<std::uint8_t> render(const PyScene& s, const job::Settings& o, long frame) {
  check_frame(frame);
  const pbr::RenderSettings r = settings_for(s, o);
  pbr::Scene scene = pbr::animate(s.file, frame);  // a copy: Python may change `s` while C++ runs
  job::apply_shadows(scene, o);
  job::Frame out;
  // Only the image is returned: a multisampled target need keep no samples (each tile's
  // are resolved and encoded as it is drawn), 166 MB less at 1080p 4x.
  run_released(r, [&](raster::Renderer& renderer) { out.render(scene, r, renderer, {.rgba8 = true}); });
  return to_numpy(out.take_rgba());
}

py::array_t<float> render_hdr(const PyScene& s, const job::Settings& o, long frame) {
  check_frame(frame);
  const pbr::RenderSettings r = settings_for(s, o);
  pbr::Scene scene = pbr::animate(s.file, frame);
  job::apply_shadows(scene, o);
  std::unique_ptr<raster::Target> target;
  run_released(r, [&](raster::Renderer& renderer) {
    // One linear colour a pixel (MSAA: the box filter's linear average, as .hdr and .exr
    // output), made per tile from samples that are not kept.
    job::Frame out;
    out.render(scene, r, renderer, {.linear = true});
    target = std::make_unique<raster::Target>(out.take_linear());
    // × 2^exposure on RGB, as .hdr and .exr output (pbr::write_exr).
    const auto scale = static_cast<float>(dmath::exp2(r.output.exposure));
    if (scale != 1.0f)
      for (glm::vec4& c : target->colors()) c = glm::vec4(c.r * scale, c.g * scale, c.b * scale, c.a);
  });
  // The array views the target's colour buffer: no copy (the depth buffer goes with it).
  raster::Target* owner = target.release();
  py::capsule free_when_done(owner, [](void* p) { delete static_cast<raster::Target*>(p); });
  const auto w = static_cast<py::ssize_t>(owner->width()), h = static_cast<py::ssize_t>(owner->height());
  const auto f = static_cast<py::ssize_t>(sizeof(float));
  return py::array_t<float>({h, w, py::ssize_t{4}}, {w * 4 * f, 4 * f, f},
                            reinterpret_cast<const float*>(std::as_const(*owner).colors().data()), free_when_done);
}

}  // namespace

void bind_render(py::module_& m) {
  // The keyword arguments as the job's settings (a None leaves the scene's value).
  auto settings = [](std::optional<int> width, std::optional<int> height, std::optional<unsigned> threads,
                     std::optional<int> tile_size, std::optional<std::string> tonemap, std::optional<float> exposure,
                     std::optional<float> gamma, std::optional<int> msaa, std::optional<bool> shadows,
                     std::optional<std::string> ground) {
    job::Settings o;
    o.width = width;
    o.height = height;
    o.threads = threads;
    o.tile_size = tile_size;
    o.tonemap = std::move(tonemap);
    o.exposure = exposure;
    o.gamma = gamma;
    o.msaa = msaa;
    if (shadows) o.shadows = *shadows ? "on" : "off";
    o.ground = std::move(ground);
    return o;
  };
  m.def(
      "render",
      [settings](const PyScene& s, std::optional<int> width, std::optional<int> height, std::optional<unsigned> threads,
                 std::optional<int> tile_size, std::optional<std::string> tonemap, std::optional<float> exposure,
                 std::optional<float> gamma, std::optional<int> msaa, long frame, std::optional<bool> shadows,
                 std::optional<std::string> ground) {
        return render(
            s, settings(width, height, threads, tile_size, std::move(tonemap), exposure, gamma, msaa, shadows, std::move(ground)),
            frame);
      },
      py::arg("scene"), py::kw_only(), py::arg("width") = py::none(), py::arg("height") = py::none(),
      py::arg("threads") = py::none(), py::arg("tile_size") = py::none(), py::arg("tonemap") = py::none(),
      py::arg("exposure") = py::none(), py::arg("gamma") = py::none(), py::arg("msaa") = py::none(), py::arg("frame") = 0,
      py::arg("shadows") = py::none(), py::arg("ground") = py::none(),
      "Renders a Scene to a (height, width, 4) uint8 numpy array (sRGB or gamma encoded, tone mapped). shadows: True "
      "(every light casts shadows), False (none does) or None (as the scene says); ground: \"shadow\" (a shadow "
      "catcher under the objects), \"none\" or None (as the scene says).");
  m.def(
      "render_hdr",
      [settings](const PyScene& s, std::optional<int> width, std::optional<int> height, std::optional<unsigned> threads,
                 std::optional<int> tile_size, std::optional<float> exposure, std::optional<int> msaa, long frame,
                 std::optional<bool> shadows, std::optional<std::string> ground) {
        return render_hdr(s,
                          settings(width, height, threads, tile_size, std::nullopt, exposure, std::nullopt, msaa, shadows,
                                   std::move(ground)),
                          frame);
      },
      py::arg("scene"), py::kw_only(), py::arg("width") = py::none(), py::arg("height") = py::none(),
      py::arg("threads") = py::none(), py::arg("tile_size") = py::none(), py::arg("exposure") = py::none(),
      py::arg("msaa") = py::none(), py::arg("frame") = 0, py::arg("shadows") = py::none(), py::arg("ground") = py::none(),
      "Renders a Scene to a (height, width, 4) float32 numpy array: linear colour x 2^exposure (MSAA: the samples' "
      "linear average).");
  m.def("active_renders", [] { return g_active_renders.load(); },
        "How many renders are inside C++ right now, in all threads (they run without the GIL).");
}

}  // namespace softpbr::python
