// softpbr.render / render_hdr: a scene to a numpy image, the GIL released while C++ runs.
//
// Settings are the scene's render block overridden by the keyword arguments, validated as the
// command validates its options; the memory estimate is checked before the target is
// allocated (pbr::image_memory, as `softpbr render`). Ctrl-C: the renderer polls
// RendererOptions::cancel between tiles; on the thread that called render() the poll takes
// the GIL at most every 10 ms and runs PyErr_CheckSignals(), so a KeyboardInterrupt (or what
// a SIGINT handler raises) stops the render and is raised by render() itself.
#include <unistd.h>

#include <algorithm>
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
#include "softpbr/loaders/format_bytes.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/renderer.h"

namespace softpbr::python {

namespace {

std::atomic<int> g_active_renders{0};  // renders inside C++ right now, in any thread

struct Overrides {
  std::optional<int> width, height;
  std::optional<unsigned> threads;
  std::optional<int> tile_size;
  std::optional<std::string> tonemap;
  std::optional<float> exposure, gamma;
  std::optional<int> msaa;
  long frame = 0;
};

template <class T>
T in_range(const char* name, T value, T lo, T hi) {
  if (value < lo || value > hi)
    value_error(std::string(name) + ": expected a value in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                std::to_string(value));
  return value;
}

pbr::RenderSettings settings_for(const PyScene& s, const Overrides& o) {
  pbr::RenderSettings r = s.file.render;
  if (o.width) r.width = *o.width;
  if (o.height) r.height = *o.height;
  in_range("width", r.width, 1, raster::kMaxTargetSize);
  in_range("height", r.height, 1, raster::kMaxTargetSize);
  if (o.threads) r.threads = *o.threads;
  in_range("threads", r.threads, 0u, 1024u);
  if (o.msaa) r.msaa = *o.msaa;
  if (!raster::valid_sample_count(r.msaa)) value_error("msaa: expected 1, 4 or 8, got " + std::to_string(r.msaa));
  if (o.tile_size) r.tile_size = *o.tile_size;
  if (!raster::valid_tile_size(r.tile_size))
    value_error("tile_size: expected an even size in [" + std::to_string(raster::kMinTileSize) + ", " +
                std::to_string(raster::kMaxTileSize) + "], got " + std::to_string(r.tile_size));
  if (o.tonemap) {
    const auto op = pbr::tone_map_from_name(*o.tonemap);
    if (!op) value_error("tonemap: expected one of none, reinhard, aces, neutral, got \"" + *o.tonemap + "\"");
    r.output.tone_map = *op;
  }
  if (o.exposure) r.output.exposure = *o.exposure;
  if (!(r.output.exposure >= -64.0f && r.output.exposure <= 64.0f))
    value_error("exposure: expected stops in [-64, 64], got " + std::to_string(r.output.exposure));
  if (o.gamma) r.output.gamma = *o.gamma;
  if (!(r.output.gamma == 0.0f || (r.output.gamma >= 0.1f && r.output.gamma <= 10.0f)))
    value_error("gamma: expected 0 (the sRGB curve) or a number in [0.1, 10], got " + std::to_string(r.output.gamma));
  // Memory, before anything is allocated: as the command, bounded by the machine's memory.
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  const std::uint64_t physical = pages > 0 && page > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) : 0;
  const std::uint64_t limit = physical ? std::min(pbr::kDefaultMemoryLimit, physical) : pbr::kDefaultMemoryLimit;
  const std::uint64_t needed = pbr::image_memory(r.width, r.height, r.msaa) + s.file.mesh_bytes + s.file.texture_bytes + s.file.environment_bytes;
  if (needed > limit)
    value_error("a " + std::to_string(r.width) + "x" + std::to_string(r.height) + " render of this scene needs an estimated " +
                pbr::format_bytes(needed) + ", over the limit of " + pbr::format_bytes(limit));
  return r;
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

py::array_t<std::uint8_t> render(const PyScene& s, const Overrides& o) {
  const pbr::RenderSettings r = settings_for(s, o);
  const pbr::Scene scene = pbr::animate(s.file, o.frame);  // a copy: Python may change `s` while C++ runs
  raster::Image8 image;
  run_released(r, [&](raster::Renderer& renderer) {
    // Only the image is returned: a multisampled target need keep no samples (each tile's
    // are resolved and encoded in render_rgba8's tile callback), 166 MB less at 1080p 4x.
    raster::Target target(r.width, r.height, r.msaa, &renderer.pool(), raster::SampleStorage::Transient);
    pbr::render_rgba8(scene, renderer, target, r.output, image);
  });
  return to_numpy(std::move(image));
}

py::array_t<float> render_hdr(const PyScene& s, const Overrides& o) {
  const pbr::RenderSettings r = settings_for(s, o);
  const pbr::Scene scene = pbr::animate(s.file, o.frame);
  auto target = std::make_unique<raster::Target>(r.width, r.height);  // one linear colour a pixel
  run_released(r, [&](raster::Renderer& renderer) {
    if (r.msaa == 1) {
      pbr::render(scene, renderer, *target);
    } else {
      // MSAA: the box filter's linear average, as .hdr and .exr output (pbr::write_exr),
      // made per tile from samples that are not kept (a transient target).
      raster::Target samples(r.width, r.height, r.msaa, &renderer.pool(), raster::SampleStorage::Transient);
      pbr::render_outputs(scene, renderer, samples, r.output, nullptr, target.get());
    }
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
  auto overrides = [](std::optional<int> width, std::optional<int> height, std::optional<unsigned> threads,
                      std::optional<int> tile_size, std::optional<std::string> tonemap, std::optional<float> exposure,
                      std::optional<float> gamma, std::optional<int> msaa, long frame) {
    return Overrides{width, height, threads, tile_size, std::move(tonemap), exposure, gamma, msaa, frame};
  };
  m.def(
      "render",
      [overrides](const PyScene& s, std::optional<int> width, std::optional<int> height, std::optional<unsigned> threads,
                  std::optional<int> tile_size, std::optional<std::string> tonemap, std::optional<float> exposure,
                  std::optional<float> gamma, std::optional<int> msaa, long frame) {
        return render(s, overrides(width, height, threads, tile_size, std::move(tonemap), exposure, gamma, msaa, frame));
      },
      py::arg("scene"), py::kw_only(), py::arg("width") = py::none(), py::arg("height") = py::none(),
      py::arg("threads") = py::none(), py::arg("tile_size") = py::none(), py::arg("tonemap") = py::none(),
      py::arg("exposure") = py::none(), py::arg("gamma") = py::none(), py::arg("msaa") = py::none(), py::arg("frame") = 0,
      "Renders a Scene to a (height, width, 4) uint8 numpy array (sRGB or gamma encoded, tone mapped).");
  m.def(
      "render_hdr",
      [overrides](const PyScene& s, std::optional<int> width, std::optional<int> height, std::optional<unsigned> threads,
                  std::optional<int> tile_size, std::optional<float> exposure, std::optional<int> msaa, long frame) {
        return render_hdr(s, overrides(width, height, threads, tile_size, std::nullopt, exposure, std::nullopt, msaa, frame));
      },
      py::arg("scene"), py::kw_only(), py::arg("width") = py::none(), py::arg("height") = py::none(),
      py::arg("threads") = py::none(), py::arg("tile_size") = py::none(), py::arg("exposure") = py::none(),
      py::arg("msaa") = py::none(), py::arg("frame") = 0,
      "Renders a Scene to a (height, width, 4) float32 numpy array: linear colour x 2^exposure (MSAA: the samples' "
      "linear average).");
  m.def("active_renders", [] { return g_active_renders.load(); },
        "How many renders are inside C++ right now, in all threads (they run without the GIL).");
}

}  // namespace softpbr::python
