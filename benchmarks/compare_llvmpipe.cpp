// compare_llvmpipe — softpbr against Mesa's llvmpipe on the same scenes, in the same run.
//
//   compare_llvmpipe [--threads 1,2] [--seconds S] [--filter TEXT] [--images DIR] [--msaa 1|4|8] [--transient] [--tile-size N]
//
// For each thread count N a child process sets LP_NUM_THREADS=N before it creates its GL
// context (llvmpipe reads it once per process), then for every scene of scenes.h renders
// with softpbr (RendererOptions::threads = N) and with llvmpipe (OSMesa), alternating one
// frame of each until both have run for S seconds (default 1.5, at least 5 frames each),
// and prints one row:
//   softpbr ms   median wall time of pbr::render_rgba8(): clear + draws + end_frame, each
//                tile tone mapped and encoded to RGBA8 right after it is drawn
//   llvmpipe ms  median wall time of clear + draws + glFinish into the RGBA8 buffer (its
//                fragment shader tone maps)
//   ratio        softpbr / llvmpipe: below 1 means softpbr is faster
//   PSNR dB      between the two RGBA8 images (RGB channels); max diff: the largest
//                difference of one channel in 8-bit steps; differ: share of RGB channels
//                that differ at all; mean diff: the mean absolute difference over the RGB
//                channels, in 8-bit steps
// --msaa N renders both with N samples a pixel: softpbr into a multisampled Target (resolved
// and encoded per tile inside render_rgba8), llvmpipe into a multisampled framebuffer
// object resolved by glBlitFramebuffer before glFinish, both inside the timed region (llvmpipe
// with at most its GL_MAX_SAMPLES, 4 on Mesa 22: --msaa 8 compares softpbr 8x with its 4x).
// --transient makes softpbr's multisampled target transient (raster::SampleStorage: the
// samples live in tile blocks only and are not written back; llvmpipe keeps its FBO's).
// Scenes with an environment render without softpbr's screen-space occlusion (on by default
// in softpbr, absent from the GLSL): the same work on both sides.
// The scenes: scenes.h's all_scenes(), then gallery_shadows_1080p (one directional light
// with a 2048² shadow map, redrawn every frame on both sides inside the timed region: see
// llvmpipe.h) and gallery_noshadows_1080p (the same light without shadows).
// --images DIR writes both images of every scene as PNGs (NAME_softpbr.png,
// NAME_llvmpipe.png) to look at the differences.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "llvmpipe.h"
#include "scenes.h"
#include "softpbr/image/write.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/target.h"

namespace bench = softpbr::bench;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {

struct Options {
  std::vector<unsigned> threads{1, 2};
  double seconds = 1.5;
  std::string filter;
  std::string images;
  int msaa = 1;
  bool transient = false;
  int tile_size = 64;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

template <class F>
double time_ms(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// PSNR over the RGB channels of two RGBA8 images of the same size (infinite when equal),
// the largest difference of one channel, and the share of channels that differ.
struct Difference {
  double psnr;
  int max;
  double differing;  // fraction of RGB channels
  double mean;       // mean |difference| over the RGB channels, in 8-bit steps
};
Difference compare(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
  double sum = 0.0, abs_sum = 0.0;
  std::size_t n = 0, differing = 0;
  int max = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (i % 4 == 3) continue;
    const int d = static_cast<int>(a[i]) - static_cast<int>(b[i]);
    sum += static_cast<double>(d) * d;
    abs_sum += std::abs(d);
    max = std::max(max, std::abs(d));
    differing += d != 0;
    ++n;
  }
  const double psnr = sum == 0.0 ? INFINITY : 10.0 * std::log10(255.0 * 255.0 / (sum / static_cast<double>(n)));
  return {psnr, max, static_cast<double>(differing) / static_cast<double>(n), abs_sum / static_cast<double>(n)};
}

void run_child(const Options& o, unsigned threads) {
  const std::string lp = std::to_string(threads);
  setenv("LP_NUM_THREADS", lp.c_str(), 1);  // before the first GL context of this process
  bool said = false;
  // scenes.h's scenes, then the shadowed gallery and the same without its shadows (issue 51).
  std::vector<bench::BenchScene> scenes = bench::all_scenes(bench::default_shared_models());
  for (bench::BenchScene& s : bench::shadow_gallery_scenes(1920, 1080)) scenes.push_back(std::move(s));
  for (bench::BenchScene& s : scenes) {
    if (!o.filter.empty() && s.name.find(o.filter) == std::string::npos) continue;
    // The same work on both sides: the GLSL has no screen-space occlusion, so softpbr renders
    // without it too (bench_scenes' gallery_ibl_noocclusion against gallery_ibl is its cost).
    s.scene.environment.occlusion = false;
    raster::Renderer renderer({.threads = threads, .tile_size = o.tile_size});
    raster::Target target(s.width, s.height, o.msaa, nullptr,
                          o.transient ? raster::SampleStorage::Transient : raster::SampleStorage::Kept);
    // llvmpipe's GL_MAX_SAMPLES may be below --msaa (4 on Mesa 22): it then runs with 4.
    int gl_samples = o.msaa;
    std::unique_ptr<bench::LlvmpipeRenderer> gl_owner;
    try {
      gl_owner = std::make_unique<bench::LlvmpipeRenderer>(s.width, s.height, gl_samples);
    } catch (const std::runtime_error&) {
      if (gl_samples <= 4) throw;
      gl_samples = 4;
      gl_owner = std::make_unique<bench::LlvmpipeRenderer>(s.width, s.height, gl_samples);
    }
    bench::LlvmpipeRenderer& gl = *gl_owner;
    if (!said) {
      const std::string aniso = gl.anisotropy_extension();
      std::printf("# %s, softpbr %dx MSAA, llvmpipe %dx, LP_NUM_THREADS=%u; anisotropic filtering: %s (max %.0f)\n",
                  gl.renderer_name().c_str(), o.msaa, gl_samples, threads, aniso.empty() ? "none reported" : aniso.c_str(),
                  static_cast<double>(gl.max_anisotropy()));
      said = true;
    }
    gl.load(s.scene, s.output);
    raster::Image8 image;
    pbr::render_rgba8(s.scene, renderer, target, s.output, image);  // warm-up (and llvmpipe's shader compile)
    gl.render();
    std::vector<double> soft, lp_ms;
    double soft_total = 0, lp_total = 0;
    while (soft.size() < 5 || lp_ms.size() < 5 || soft_total < o.seconds * 1e3 || lp_total < o.seconds * 1e3) {
      if (soft_total < o.seconds * 1e3 || soft.size() < 5) {
        soft.push_back(time_ms([&] { pbr::render_rgba8(s.scene, renderer, target, s.output, image); }));
        soft_total += soft.back();
      }
      if (lp_total < o.seconds * 1e3 || lp_ms.size() < 5) {
        lp_ms.push_back(time_ms([&] { gl.render(); }));
        lp_total += lp_ms.back();
      }
    }
    const double soft_ms = median(soft), llvm_ms = median(lp_ms);
    const Difference d = compare(image.rgba, gl.pixels());
    std::printf("%-22s %7u %10.2f %11.2f %7.3f %8.1f %8d %9.5f %7.3f%% %9zu\n", s.name.c_str(), threads, soft_ms,
                llvm_ms, soft_ms / llvm_ms, d.psnr, d.max, d.mean, 100.0 * d.differing, s.triangles);
    std::fflush(stdout);
    if (!o.images.empty()) {
      std::filesystem::create_directories(o.images);
      const std::filesystem::path dir(o.images);
      softpbr::image::write_png(dir / (s.name + "_softpbr.png"), image);
      raster::Image8 other{s.width, s.height, gl.pixels()};
      softpbr::image::write_png(dir / (s.name + "_llvmpipe.png"), other);
    }
  }
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--threads" && has_value) {
      o.threads.clear();
      std::string list = argv[++i];
      for (std::size_t p = 0; p < list.size();) {
        const std::size_t comma = std::min(list.find(',', p), list.size());
        const int n = std::atoi(list.substr(p, comma - p).c_str());
        if (n < 1 || n > 256) return false;
        o.threads.push_back(static_cast<unsigned>(n));
        p = comma + 1;
      }
    } else if (a == "--seconds" && has_value) {
      o.seconds = std::atof(argv[++i]);
      if (!(o.seconds > 0.0)) return false;
    } else if (a == "--filter" && has_value) {
      o.filter = argv[++i];
    } else if (a == "--msaa" && has_value) {
      o.msaa = std::atoi(argv[++i]);
      if (!raster::valid_sample_count(o.msaa)) return false;
    } else if (a == "--transient") {
      o.transient = true;
    } else if (a == "--tile-size" && has_value) {
      o.tile_size = std::atoi(argv[++i]);
      if (!raster::valid_tile_size(o.tile_size)) return false;
    } else if (a == "--images" && has_value) {
      o.images = argv[++i];
    } else {
      return false;
    }
  }
  return !o.threads.empty();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr, "usage: %s [--threads 1,2] [--seconds S] [--filter TEXT] [--images DIR] [--msaa 1|4|8] [--transient] [--tile-size N]\n", argv[0]);
    return 2;
  }
  std::printf("softpbr vs llvmpipe: median ms per frame to an RGBA8 image; ratio = softpbr / llvmpipe\n");
  std::printf("%-22s %7s %10s %11s %7s %8s %8s %9s %8s %9s\n", "scene", "threads", "softpbr ms", "llvmpipe ms",
              "ratio", "PSNR dB", "max diff", "mean diff", "differ", "triangles");
  std::fflush(stdout);
  int status = 0;
  for (const unsigned t : o.threads) {
    const pid_t pid = fork();
    if (pid < 0) {
      std::perror("fork");
      return 1;
    }
    if (pid == 0) {
      try {
        run_child(o, t);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "compare_llvmpipe: %s\n", e.what());
        std::fflush(stdout);
        _exit(1);
      }
      std::fflush(stdout);
      _exit(0);
    }
    int child = 0;
    waitpid(pid, &child, 0);
    if (!WIFEXITED(child) || WEXITSTATUS(child) != 0) status = 1;
  }
  return status;
}
