// `softpbr thumbnail` (see thumbnail.h).
#include "thumbnail.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>
#include <optional>

#include "cli_error.h"
#include "softpbr/image/read_file.h"
#include "softpbr/image/write.h"
#include "softpbr/job/model_views.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/scene_file.h"

namespace softpbr::cli {

namespace fs = std::filesystem;

// The specification's largest size (xx-large, 1024); a file manager asks for 128 to 1024.
constexpr long kMaxThumbnailSize = 1024;

CLI::App* add_thumbnail_command(CLI::App& app, ThumbnailArgs& a) {
  CLI::App* c = app.add_subcommand(
      "thumbnail", "A desktop thumbnail of a glTF (.gltf, .glb) or OBJ model: a SIZE x SIZE PNG, transparent background "
                   "(share/thumbnailers/softpbr.thumbnailer runs it as: softpbr thumbnail -s %s %i %o)");
  c->add_option("-s,--size", a.size, "The thumbnail's width and height in pixels (1..1024)")->capture_default_str();
  c->add_option("input", a.input, "The model (its kind from its extension, else from its first bytes)")->required();
  c->add_option("output", a.output, "The PNG to write (replaced whole, or left as it was on any failure)")->required();
  c->add_option("--timeout", a.timeout, "Give up after this many seconds (exit 3), 0 for never")->capture_default_str();
  c->add_option("--max-memory", a.max_memory_mib,
                "Refuse a model estimated to need more than this many MiB; the process's data limit is this plus 512 MiB")
      ->capture_default_str();
  c->add_option("--threads", a.threads, "Worker threads, 0 = all cores (the image is the same for any)")->capture_default_str();
  c->footer(kExitCodesHelp);
  return c;
}

namespace {

// What the timer's signal handler may touch: plain buffers filled before it is armed.
char g_timeout_line[2300];
std::size_t g_timeout_length = 0;
char g_link[4200], g_link_dir[4200];

extern "C" void on_timeout(int) {
  // Only async-signal-safe calls: the output is an unnamed temporary until renamed, so
  // nothing partial is left behind.
  (void)!::write(STDERR_FILENO, g_timeout_line, g_timeout_length);
  if (g_link[0]) ::unlink(g_link);
  if (g_link_dir[0]) ::rmdir(g_link_dir);
  ::_exit(kExitInput);
}

void arm_timeout(const std::string& input, double seconds) {
  char shown[32];
  std::snprintf(shown, sizeof shown, "%g", seconds);
  const std::string line =
      printable_line(input + ": gave up after --timeout " + shown + " s (the model takes too long to load or render)") + "\n";
  g_timeout_length = std::min(line.size(), sizeof g_timeout_line);
  std::memcpy(g_timeout_line, line.data(), g_timeout_length);
  struct sigaction sa {};
  sa.sa_handler = on_timeout;
  ::sigemptyset(&sa.sa_mask);
  ::sigaction(SIGALRM, &sa, nullptr);
  itimerval t{};
  t.it_value.tv_sec = static_cast<time_t>(seconds);
  t.it_value.tv_usec = static_cast<suseconds_t>((seconds - std::floor(seconds)) * 1e6);
  if (t.it_value.tv_sec == 0 && t.it_value.tv_usec == 0) t.it_value.tv_usec = 1;
  ::setitimer(ITIMER_REAL, &t, nullptr);
}

// The process's data segment and private writable mappings (RLIMIT_DATA) held to `bytes`:
// an allocation past it fails (std::bad_alloc, exit 3) instead of the machine swapping.
// Not under AddressSanitizer, whose shadow memory and allocator count against RLIMIT_DATA
// (its processes abort at the first allocation past it): there the render's own estimate
// (--max-memory) is the only bound.
void limit_memory(std::uint64_t bytes) {
#if defined(__SANITIZE_ADDRESS__)
  (void)bytes;
  return;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  (void)bytes;
  return;
#endif
#endif
  rlimit r{};
  if (::getrlimit(RLIMIT_DATA, &r) != 0) return;
  if (r.rlim_cur == RLIM_INFINITY || r.rlim_cur > bytes) {
    r.rlim_cur = static_cast<rlim_t>(bytes);
    ::setrlimit(RLIMIT_DATA, &r);
  }
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

// The kind of a file without a model's extension (a download saved as "model", a file
// manager's copy): ".glb" for the binary container's magic, ".gltf" for JSON, else ".obj".
std::string sniff_extension(const std::string& path) {
  char head[64] = {};
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return ".obj";
  const ssize_t n = ::read(fd, head, sizeof head);
  ::close(fd);
  if (n >= 4 && std::memcmp(head, "glTF", 4) == 0) return ".glb";
  for (ssize_t i = 0; i < n; ++i) {
    if (std::isspace(static_cast<unsigned char>(head[i]))) continue;
    return head[i] == '{' ? ".gltf" : ".obj";
  }
  return ".obj";
}

// A symbolic link named model.EXT to `path` in a folder of its own, removed on exit.
struct NamedLink {
  std::string path;
  NamedLink(const std::string& target, const std::string& ext) {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/softpbr-thumbnail-XXXXXX";
    if (pattern.size() + 16 >= sizeof g_link) throw Error(kExitInput, target + ": TMPDIR is too long a path");
    if (!::mkdtemp(pattern.data())) throw Error(kExitInput, target + ": cannot make a temporary folder: " + std::strerror(errno));
    std::strcpy(g_link_dir, pattern.c_str());
    path = pattern + "/model" + ext;
    std::error_code ec;
    const fs::path absolute = fs::absolute(target, ec);
    if (ec || ::symlink(absolute.c_str(), path.c_str()) != 0) {
      ::rmdir(g_link_dir);
      g_link_dir[0] = 0;
      throw Error(kExitInput, target + ": cannot link it under a model's name in " + pattern);
    }
    std::strcpy(g_link, path.c_str());
  }
  ~NamedLink() {
    ::unlink(g_link);
    ::rmdir(g_link_dir);
    g_link[0] = g_link_dir[0] = 0;
  }
};

}  // namespace

int run_thumbnail(const ThumbnailArgs& a) {
  if (a.size < 1 || a.size > kMaxThumbnailSize)
    throw Error(kExitUsage, "--size: expected 1 to " + std::to_string(kMaxThumbnailSize) + " pixels, got " + std::to_string(a.size));
  if (!(a.timeout >= 0 && a.timeout <= 86400))
    throw Error(kExitUsage, "--timeout: expected 0 to 86400 seconds, got " + std::to_string(a.timeout));
  job::Settings s;
  s.width = s.height = a.size;
  s.threads = a.threads;
  s.background = "transparent";
  s.missing_images = "warn";  // a download without its textures still gets a thumbnail
  s.max_memory_mib = a.max_memory_mib;
  try {
    job::validate(s);
  } catch (const job::Error& e) {
    throw Error(kExitUsage, job::option_text(e));
  }
  if (const std::string problem = image::output_problem(a.output); !problem.empty())
    throw Error(kExitOutput, a.output + ": " + problem);
  // Refused at once, never opened for reading: a pipe, a device, a folder.
  if (const image::FileProblem p = image::file_problem(a.input))
    throw Error(kExitInput, a.input + ": " + (p.folder ? std::string("is a folder, not a model") : p.reason));
  if (a.timeout > 0) arm_timeout(a.input, a.timeout);
  limit_memory(static_cast<std::uint64_t>(a.max_memory_mib * 1048576.0) + (std::uint64_t{512} << 20));

  std::string ext = lower_extension(a.input);
  std::optional<NamedLink> link;
  if (ext != ".gltf" && ext != ".glb" && ext != ".obj") link.emplace(a.input, sniff_extension(a.input));
  const std::string& path = link ? link->path : a.input;
  // Messages name the file the file manager gave, not the link.
  auto named = [&](std::string what) {
    if (link && what.compare(0, path.size(), path) == 0) what = a.input + what.substr(path.size());
    return what;
  };
  job::Frame frame;
  try {
    pbr::RenderSettings defaults;
    raster::Renderer renderer(raster::RendererOptions{a.threads ? static_cast<unsigned>(a.threads) : defaults.threads,
                                                      defaults.tile_size});
    const job::ViewedModel model = job::load_viewed(path, s, renderer.pool());
    const pbr::RenderSettings r = job::resolve(model.scene.render, s);
    try {
      job::check_memory(job::estimate_memory(model.scene, r), r, job::memory_limit(job::requested_memory_limit(s)));
    } catch (const job::Error& e) {
      throw Error(kExitInput, a.input + ": " + e.detail() + " (--max-memory)");
    }
    const pbr::Camera camera = job::view_camera(model.bounds, r.width, r.height, job::View{}, a.input);
    frame.render(job::scene_for_view(model, camera), r, renderer, {.rgba8 = true});
  } catch (const job::Error& e) {
    throw Error(e.kind() == job::Error::Kind::Setting ? kExitUsage : kExitInput, named(job::option_text(e)));
  } catch (const pbr::LoadError& e) {
    throw Error(kExitInput, named(e.what()));
  } catch (const pbr::SceneFileError& e) {
    throw Error(kExitInput, named(e.what()));
  } catch (const std::bad_alloc&) {
    throw Error(kExitInput, a.input + ": out of memory (over --max-memory)");
  } catch (const std::invalid_argument& e) {
    throw Error(kExitInput, a.input + ": " + e.what());
  }
  try {
    image::write_file_atomic(a.output, image::encode_png(frame.rgba(), a.output));
  } catch (const std::bad_alloc&) {
    throw Error(kExitInput, a.input + ": out of memory (over --max-memory)");
  } catch (const std::exception& e) {
    throw Error(kExitOutput, e.what());  // the writer's messages start with the output's path
  }
  return kExitOk;
}

}  // namespace softpbr::cli
