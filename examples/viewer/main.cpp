// viewer — the paper's interactive PBR viewer, drawn by softpbr on the CPU and shown in an
// SDL2 window (the window only displays the image: no GPU needed).
//
//   viewer [model.obj|model.gltf|model.glb ...] [--width W] [--height H] [--threads N] [--budget-ms MS]
//          [--software] [--script keys.txt] [--screenshot out.png] [--env map.hdr ...]
//
// OBJ and glTF files join the mesh cycle (M) after the sphere grid, spot, the teapot, a
// torus and a cube; so do files dropped on the window (SDL_DROPFILE), which are shown at
// once (a file that does not load is one line on stderr, and the viewer goes on). Controls:
// viewer_state.h. --script replays a script (script.h) with a fixed time step and full
// resolution, then quits; --screenshot writes what the window shows at the end (without
// --script: the first frame). Both use SDL's software renderer so the pixels are exact.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <SDL.h>

#include "resolution.h"
#include "script.h"
#include "sdl_input.h"
#include "sdl_window.h"
#include "softpbr/image/write.h"
#include "softpbr/raster/raster.h"
#include "viewer_scene.h"
#include "viewer_state.h"

namespace raster = softpbr::raster;
using Clock = std::chrono::steady_clock;

namespace {

struct Options {
  int width = 960, height = 540;
  unsigned threads = 0;
  double budget_ms = 40.0;
  bool software = false;
  std::string script, screenshot;
  std::vector<std::filesystem::path> objs;
  std::vector<std::filesystem::path> envs;  // --env, repeatable: maps B cycles through
};

// The viewer: state, meshes, the softpbr renderer and the window.
class Viewer {
 public:
  Viewer(const Options& o, std::vector<viewer::NamedMesh> meshes)
      : options_(o), meshes_(std::move(meshes)), renderer_({.threads = o.threads}),
        window_("softpbr viewer", o.width, o.height, o.script.empty() && o.screenshot.empty(),
                o.software || !o.script.empty() || !o.screenshot.empty()) {
    state_.mesh_count = meshes_.size();
    environments_ = viewer::load_environments(o.envs, &renderer_.pool());
    state_.environment_count = environments_.size();
    policy_.budget_ms = o.budget_ms;
    if (renderer_.threads() < renderer_.requested_threads())
      std::fprintf(stderr, "viewer: the system started %u of the %u threads asked for; rendering with %u\n",
                   renderer_.threads(), renderer_.requested_threads(), renderer_.threads());
  }

  // Renders the state at window size / divisor, shows it (not presented); returns ms.
  double draw(int divisor) {
    const auto start = Clock::now();
    const int w = viewer::scaled_size(window_.width(), divisor), h = viewer::scaled_size(window_.height(), divisor);
    window_.draw(viewer::render_view(state_, meshes_, renderer_, frame_, w, h, environments_));
    shown_divisor_ = divisor;
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  }

  // Renders the state at full resolution and writes what the window shows.
  void screenshot(const std::filesystem::path& path) {
    draw(1);
    const raster::Image8 image = window_.read_back();
    window_.present();
    softpbr::image::write_png(path, image);
    std::printf("viewer: wrote %s (%dx%d, %s, %s)\n", path.string().c_str(), image.width, image.height,
                meshes_[state_.mesh].name.c_str(), material_text().c_str());
  }

  void run_script(const std::vector<viewer::ScriptCommand>& commands) {
    using Kind = viewer::ScriptCommand::Kind;
    for (const viewer::ScriptCommand& c : commands) {
      SDL_PumpEvents();  // keep the window alive; real input is dropped in script mode
      switch (c.kind) {
        case Kind::Event: {
          // Through SDL's queue and the interactive event handling, as if typed. Whatever
          // else is queued (real input, window events) is dropped first and nothing is
          // pumped in between, so the session does not depend on the keyboard or mouse.
          SDL_PumpEvents();
          SDL_FlushEvents(SDL_FIRSTEVENT, SDL_LASTEVENT);
          SDL_Event e = viewer::to_sdl_event(c.event, window_.id());
          if (SDL_PushEvent(&e) != 1 || SDL_PeepEvents(&e, 1, SDL_GETEVENT, SDL_FIRSTEVENT, SDL_LASTEVENT) != 1)
            throw std::runtime_error(std::string("cannot queue an event: ") + SDL_GetError());
          bool turned = false;
          handle(e, turned);
          if (screenshot_requested_) {
            screenshot_requested_ = false;
            screenshot(next_screenshot_name());
          }
          break;
        }
        case Kind::Frames:
          for (long i = 0; i < c.frames; ++i) viewer::advance(state_, viewer::kScriptFrameSeconds);
          update_title(draw(1));
          window_.present();
          break;
        case Kind::Screenshot: screenshot(c.path); break;
        case Kind::Drop: {
          // An SDL_DROPFILE event through SDL's queue, as a file dropped on the window.
          SDL_PumpEvents();
          SDL_FlushEvents(SDL_FIRSTEVENT, SDL_LASTEVENT);
          SDL_Event e{};
          e.type = SDL_DROPFILE;
          e.drop.file = SDL_strdup(c.path.c_str());  // freed by handle(), as SDL's own
          e.drop.windowID = window_.id();
          if (e.drop.file == nullptr || SDL_PushEvent(&e) != 1 ||
              SDL_PeepEvents(&e, 1, SDL_GETEVENT, SDL_FIRSTEVENT, SDL_LASTEVENT) != 1)
            throw std::runtime_error(std::string("cannot queue a dropped file: ") + SDL_GetError());
          bool turned = false;
          handle(e, turned);
          break;
        }
        case Kind::Quit: state_.quit = true; break;
      }
      if (state_.quit) return;
    }
  }

  void run_interactive() {
    bool dirty = true;
    auto last = Clock::now();
    while (!state_.quit) {
      bool turned = false;
      SDL_Event e;
      // Sleep in the event queue while nothing changes.
      if (!dirty && !state_.lights_rotating && !movement_held() && shown_divisor_ == 1) {
        if (SDL_WaitEventTimeout(&e, 250)) dirty |= handle(e, turned);
        last = Clock::now();
      }
      while (SDL_PollEvent(&e)) dirty |= handle(e, turned);
      if (screenshot_requested_) {
        screenshot_requested_ = false;
        try {
          screenshot(next_screenshot_name());
        } catch (const std::exception& ex) {  // e.g. a read-only folder: say so, go on
          std::fprintf(stderr, "viewer: %s\n", ex.what());
        }
      }
      if (state_.quit) break;
      const auto now = Clock::now();
      // Clamp the time step so a stall (a slow full-resolution frame) is not a big jump.
      const float dt = std::min(std::chrono::duration<float>(now - last).count(), 0.1f);
      last = now;
      const bool moving = viewer::advance(state_, dt) || turned || state_.lights_rotating;
      if (!dirty && !moving && shown_divisor_ == 1) {
        SDL_Delay(5);  // keys held that cancel out: nothing to draw, do not spin
        continue;
      }
      const int divisor = moving ? policy_.divisor : 1;
      const double ms = draw(divisor);
      window_.present();
      policy_.next(ms, moving);
      update_title(ms);
      dirty = false;
    }
  }

 private:
  bool movement_held() const {
    using viewer::Key;
    for (Key k : {Key::W, Key::A, Key::S, Key::D, Key::Q, Key::E, Key::Up, Key::Down, Key::Left, Key::Right})
      if (state_.is_held(k)) return true;
    return false;
  }

  // Applies an SDL event; returns true when the picture must be redrawn.
  bool handle(const SDL_Event& e, bool& turned) {
    switch (e.type) {
      case SDL_QUIT: state_.quit = true; return false;
      case SDL_KEYDOWN:
      case SDL_KEYUP: {
        const auto key = viewer::key_from_sdl(e.key.keysym.sym);
        if (!key || e.key.repeat) return false;
        if (e.type == SDL_KEYUP) {
          viewer::apply(state_, viewer::KeyUp{*key});
          return false;
        }
        const viewer::Effect effect = viewer::apply(state_, viewer::KeyDown{*key});
        // Scripts capture in the state only: a real grab would add real mouse motion.
        if (options_.script.empty()) SDL_SetRelativeMouseMode(state_.captured ? SDL_TRUE : SDL_FALSE);
        if (effect == viewer::Effect::Screenshot) screenshot_requested_ = true;
        if (effect == viewer::Effect::NextVariant) show_next_variant();
        return true;
      }
      case SDL_MOUSEMOTION:
        if (!state_.captured) return false;
        viewer::apply(state_, viewer::MouseMotion{static_cast<float>(e.motion.xrel), static_cast<float>(e.motion.yrel)});
        turned = true;
        return true;
      case SDL_DROPFILE: {
        // SDL allocated the name; it is ours to free.
        const std::string file = e.drop.file ? e.drop.file : "";
        SDL_free(e.drop.file);
        return open_dropped(file);
      }
      case SDL_WINDOWEVENT:
        if (e.window.event == SDL_WINDOWEVENT_FOCUS_LOST)  // no key stays held behind our back
          for (std::size_t k = 0; k < viewer::kKeyCount; ++k) state_.held[k] = false;
        return e.window.event == SDL_WINDOWEVENT_SIZE_CHANGED || e.window.event == SDL_WINDOWEVENT_EXPOSED;
      default: return false;
    }
  }

  // The title's material: a glTF model is drawn with its own.
  std::string material_text() const {
    const viewer::NamedMesh& entry = meshes_[state_.mesh];
    if (entry.model.empty()) return viewer::material_label(state_);
    const std::string variant = viewer::variant_label(entry);
    return variant.empty() ? std::string("own materials") : "own materials, " + variant;
  }

  // G: the shown glTF model's next material variant. One that does not load again is one
  // line on stderr, and the view stays as it was.
  void show_next_variant() {
    viewer::NamedMesh& entry = meshes_[state_.mesh];
    try {
      std::vector<std::string> warnings;
      if (!viewer::next_variant(entry, warnings, &renderer_.pool())) return;
      const std::string label = viewer::variant_label(entry);
      std::printf("viewer: %s: %s\n", entry.name.c_str(), label.empty() ? "default materials" : label.c_str());
      std::fflush(stdout);
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr, "viewer: %s: out of memory\n", entry.file.string().c_str());
    } catch (const std::exception& ex) {
      std::fprintf(stderr, "viewer: %s\n", ex.what());
    }
  }

  // A dropped file joins the mesh list and is shown; one that does not load is one line on
  // stderr, and the view stays as it was.
  bool open_dropped(const std::string& file) {
    try {
      std::vector<std::string> warnings;
      viewer::NamedMesh entry = viewer::load_model(file, warnings, &renderer_.pool());
      for (const std::string& w : warnings) std::fprintf(stderr, "viewer: warning: %s\n", w.c_str());
      meshes_.push_back(std::move(entry));
      state_.mesh_count = meshes_.size();
      state_.mesh = meshes_.size() - 1;
      std::printf("viewer: opened %s (mesh %zu of %zu)\n", file.c_str(), state_.mesh + 1, meshes_.size());
      std::fflush(stdout);
      return true;
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr, "viewer: %s: out of memory\n", file.c_str());
    } catch (const std::exception& ex) {
      std::fprintf(stderr, "viewer: %s\n", ex.what());
    }
    return false;
  }

  std::filesystem::path next_screenshot_name() const {
    for (int i = 1;; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "viewer-%04d.png", i);
      if (!std::filesystem::exists(name)) return name;
    }
  }

  void update_title(double ms) {
    char title[256];
    std::snprintf(title, sizeof title, "softpbr viewer | %.1f ms (%.1f FPS) | %s | %s | %dx%d%s%s | %u threads%s%s", ms,
                  ms > 0.0 ? 1000.0 / ms : 0.0, material_text().c_str(),
                  meshes_[state_.mesh].name.c_str(), frame_.rgba().width, frame_.rgba().height,
                  state_.msaa > 1 ? " 4x MSAA" : "", shown_divisor_ > 1 ? " (moving)" : "", renderer_.threads(),
                  state_.lights_rotating ? " | lights rotating" : "", state_.ground ? " | shadows + ground" : state_.shadows ? " | shadows" : "");
    window_.set_title(title);
  }

  Options options_;
  std::vector<viewer::NamedMesh> meshes_;
  viewer::Environments environments_;
  viewer::ViewerState state_;
  viewer::ResolutionPolicy policy_;
  raster::Renderer renderer_;
  softpbr::job::Frame frame_;  // the render job's: its target kept while the size and MSAA stay
  viewer::SdlWindow window_;
  int shown_divisor_ = 0;
  bool screenshot_requested_ = false;  // P was pressed: write one after the events
};

constexpr const char* kUsage =
    "usage: viewer [model.obj|.gltf|.glb ...] [--width W] [--height H] [--threads N] [--budget-ms MS]\n"
    "              [--software] [--script keys.txt] [--screenshot out.png] [--env map.hdr ...]\n"
    "keys: WASD/arrows fly, Q/E down/up, Tab capture mouse, 1-9 presets, N next preset, 0 gallery,\n"
    "      M next mesh or model (also files dropped on the window), C rotate lights, R/F roughness up/down, T metallic, V 4x MSAA, H shadows (then + ground), P screenshot, Esc quit\n";

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto text = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    auto number = [&](long lo, long hi) -> long {
      const std::string v = text();
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || n < lo || n > hi)
        throw std::invalid_argument(arg + " expects a whole number in [" + std::to_string(lo) + ", " +
                                    std::to_string(hi) + "], not \"" + v + "\"");
      return n;
    };
    // 4096² pixels keep the float target (20 bytes a pixel) near 320 MiB.
    if (arg == "--width") o.width = static_cast<int>(number(16, 4096));
    else if (arg == "--height") o.height = static_cast<int>(number(16, 4096));
    else if (arg == "--threads") o.threads = static_cast<unsigned>(number(0, 256));
    else if (arg == "--budget-ms") o.budget_ms = static_cast<double>(number(1, 10000));
    else if (arg == "--software") o.software = true;
    else if (arg == "--script") o.script = text();
    else if (arg == "--screenshot") o.screenshot = text();
    else if (arg == "--env") o.envs.emplace_back(text());
    else if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (!arg.empty() && arg[0] == '-') throw std::invalid_argument("unknown option " + arg);
    else o.objs.emplace_back(arg);
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  std::vector<viewer::ScriptCommand> script;
  try {
    options = parse(argc, argv);
    if (!options.script.empty()) script = viewer::load_script(options.script);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viewer: %s\n%s", e.what(), kUsage);
    return 2;
  }
  try {
    // The files load before any window opens (a bad one is an error line, no window);
    // glTF images decode on a pool of the render's thread count.
    std::vector<viewer::NamedMesh> meshes;
    {
      raster::ThreadPool pool(options.threads);
      std::vector<std::string> warnings;
      meshes = viewer::load_meshes(SOFTPBR_ASSETS_DIR, options.objs, warnings, &pool);
      for (const std::string& w : warnings) std::fprintf(stderr, "viewer: warning: %s\n", w.c_str());
    }
    Viewer v(options, std::move(meshes));
    if (!options.script.empty()) v.run_script(script);
    else if (options.screenshot.empty()) v.run_interactive();
    if (!options.screenshot.empty()) v.screenshot(options.screenshot);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viewer: %s\n", e.what());
    return 1;
  }
  return 0;
}
