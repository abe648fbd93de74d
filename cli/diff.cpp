// `softpbr diff` (see diff.h): the comparison, statistics and diff images are
// softpbr::golden's (golden/include/softpbr/golden/compare.h).
#include "diff.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "cli_error.h"
#include "model_diff.h"
#include "softpbr/golden/compare.h"
#include "softpbr/golden/image.h"
#include "softpbr/image/load.h"
#include "softpbr/image/read_file.h"
#include "softpbr/image/write.h"

namespace softpbr::cli {

namespace golden = softpbr::golden;

CLI::App* add_diff_command(CLI::App& app, DiffArgs& a) {
  CLI::App* c = app.add_subcommand("diff", "Compare two images (.png, .hdr or .exr), or two models (.gltf, .glb, .obj, "
                                           "scene .json) rendered from the same views: exit 0 if they match within the "
                                           "tolerance, 1 if not, 2 on error");
  c->add_option("expected", a.expected, "The reference image or model")->required();
  c->add_option("actual", a.actual, "The image or model to check")->required();
  c->add_option("--max-diff", a.max_diff,
                "A pixel differs when one of its channels differs by more than this (8-bit codes for PNG, "
                "16-bit codes when either PNG is 16-bit, float values for .hdr and .exr)")
      ->capture_default_str();
  c->add_option("--max-pixels", a.max_pixels, "How many pixels may differ")
      ->check(CLI::NonNegativeNumber)  // "-1" would wrap to 2^64 - 1
      ->capture_default_str();
  c->add_option("--out", a.out,
                "Write a heat map of the difference (.png): black where equal, red to white. Models: a contact sheet, "
                "each view as expected | actual | heat map, the worst view first");
  c->add_flag("--side-by-side", a.side_by_side, "With --out: expected | actual | heat map");
  c->add_flag("-q,--quiet", a.quiet, "Print nothing; the exit code says it");
  // Models only.
  c->add_option("--views", a.views,
                "Models: N views, the automatic camera's front, a ring at pitch 15 and one from above (1..64)")
      ->capture_default_str();
  c->add_option("--yaw", a.yaws, "Models: the views' yaws in degrees, a list (0,90,180) instead of --views")->delimiter(',');
  c->add_option("--pitch", a.pitches, "Models: the views' pitches in degrees (-89..89), one for all or one a yaw")
      ->delimiter(',');
  c->add_option("--width", a.width, "Models: each view's width in pixels")->capture_default_str();
  c->add_option("--height", a.height, "Models: each view's height in pixels")->capture_default_str();
  c->add_option("--json", a.json, "Models: write the numbers as JSON to this file (- for standard output)");
  c->add_option("--threads", a.threads, "Models: worker threads, 0 = all cores (the images are the same for any)");
  c->add_option("--env", a.env, "Models: the environment, an .hdr/.exr, \"studio\" (the default) or \"none\"");
  c->add_option("--background", a.background, "Models: environment, blur (the default), transparent or R,G,B");
  a.max_memory_mib = 4096;
  c->add_option("--time", a.time, "glTF models: apply the animations at this moment, seconds (as render --time)");
  c->add_option("--animation", a.animation, "glTF models: only animation N or NAME (as render --animation)");
  c->add_option("--variant", a.variant, "glTF models: the material variant NAME or N (as render --variant)");
  c->add_option("--max-memory", a.max_memory_mib, "Models: refuse a model estimated to need more than this many MiB")
      ->capture_default_str();
  c->footer(kExitCodesHelp);
  return c;
}

namespace {
std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

// Why `path` cannot be read as an image, or "": checked without blocking (a named pipe
// with no writer is refused at once) and without reading it (read_file.h).
std::string input_problem(const std::string& path) {
  const image::FileProblem p = image::file_problem(path);
  if (!p) return {};
  return path + ": " + (p.folder ? "is a folder, not an image" : p.reason);
}

// A 16-bit PNG (IHDR bit depth 16): compared on its 16-bit samples.
bool is_16_bit_png(std::span<const std::uint8_t> h) {
  return h.size() >= 25 && h[1] == 'P' && h[2] == 'N' && h[3] == 'G' && h[12] == 'I' && h[13] == 'H' && h[14] == 'D' &&
         h[15] == 'R' && h[24] == 16;
}

// The 8-bit picture of 16-bit codes (image::load_png16), rounded: what a viewer shows.
raster::Image8 to_8_bits(const golden::ImageF& codes) {
  raster::Image8 out;
  out.width = codes.width;
  out.height = codes.height;
  out.rgba.resize(codes.rgba.size());
  for (std::size_t i = 0; i < codes.rgba.size(); ++i)
    out.rgba[i] = static_cast<std::uint8_t>((static_cast<std::uint32_t>(codes.rgba[i]) * 255u + 32767u) / 65535u);
  return out;
}

// `sixteen`: the images are 16-bit codes held in floats (image::load_png16): differences
// and --max-diff are in 16-bit codes, PSNR's peak is 65535, and the side-by-side image
// shows them at 8 bits with the heat map of the 16-bit difference.
template <class Image>
int compare_and_report(const DiffArgs& a, const Image& expected, const Image& actual, bool sixteen = false) {
  const golden::Comparison c = golden::compare(expected, actual, a.max_diff);
  const bool within = c.same_size() && c.pixels_above <= a.max_pixels;
  if (!a.out.empty()) {
    try {
      raster::Image8 picture;
      if constexpr (std::is_same_v<Image, golden::ImageF>) {
        if (sixteen && (a.side_by_side || !c.same_size())) {
          picture = golden::side_by_side(to_8_bits(expected), to_8_bits(actual));
          if (c.same_size()) {  // its third panel: the heat map of the 16-bit codes
            const raster::Image8 heat = golden::diff_image(expected, actual);
            const auto row = static_cast<std::size_t>(heat.width) * 4;
            for (int y = 0; y < heat.height; ++y)
              std::copy_n(heat.rgba.begin() + static_cast<std::ptrdiff_t>(y * row), row,
                          picture.rgba.begin() + static_cast<std::ptrdiff_t>(y * row * 3 + 2 * row));
          }
        }
      }
      if (picture.rgba.empty())
        picture = a.side_by_side || !c.same_size() ? golden::side_by_side(expected, actual) : golden::diff_image(expected, actual);
      image::write_file_atomic(a.out, image::encode_png(picture, a.out));
    } catch (const std::exception& e) {
      throw Error(kExitUsage, e.what());
    }
  }
  if (!a.quiet) {
    const char* samples = sixteen ? ", 16-bit samples" : "";
    if (!c.same_size())
      std::printf("%s vs %s: different sizes, %dx%d and %dx%d\n", a.expected.c_str(), a.actual.c_str(),
                  c.expected_width, c.expected_height, c.actual_width, c.actual_height);
    else if (c.identical)
      std::printf("%s vs %s: identical (%dx%d%s)\n", a.expected.c_str(), a.actual.c_str(), c.actual_width, c.actual_height,
                  samples);
    else
      std::printf("%s vs %s: %s: %llu of %llu pixels differ by more than %g%s (allowed: %llu), largest difference %g, "
                  "PSNR %.2f dB\n",
                  a.expected.c_str(), a.actual.c_str(), within ? "within tolerance" : "DIFFERENT",
                  static_cast<unsigned long long>(c.pixels_above), static_cast<unsigned long long>(c.pixels),
                  a.max_diff, sixteen ? " (16-bit codes)" : "", static_cast<unsigned long long>(a.max_pixels), c.max_diff(),
                  sixteen ? 20 * std::log10(65535 / c.rmse) : c.psnr);
  }
  return within ? kExitOk : kExitDifferent;
}
}  // namespace

int run_diff(const DiffArgs& a) {
  if (!(a.max_diff >= 0) || !std::isfinite(a.max_diff))
    throw Error(kExitUsage, "--max-diff: expected a finite number >= 0, got " + std::to_string(a.max_diff));
  if (is_model_path(a.expected) || is_model_path(a.actual)) return run_model_diff(a);
  if (!a.out.empty() && lower_extension(a.out) != ".png") throw Error(kExitUsage, a.out + ": --out writes a .png");
  for (const std::string* p : {&a.expected, &a.actual})
    if (const std::string problem = input_problem(*p); !problem.empty()) throw Error(kExitUsage, problem);
  if (!a.out.empty()) {
    // The heat map is a new file or replaces a regular one, never an input.
    if (const std::string problem = image::output_problem(a.out); !problem.empty())
      throw Error(kExitUsage, a.out + ": " + problem);
    struct stat out {}, in {};
    if (::stat(a.out.c_str(), &out) == 0)
      for (const std::string* p : {&a.expected, &a.actual})
        if (::stat(p->c_str(), &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino)
          throw Error(kExitUsage, a.out + ": cannot write: it is the input " + *p + " (--out never replaces an input)");
  }
  const std::string ea = lower_extension(a.expected), eb = lower_extension(a.actual);
  const bool float_a = ea == ".hdr" || ea == ".exr", float_b = eb == ".hdr" || eb == ".exr";
  if (float_a != float_b)
    throw Error(kExitUsage, a.expected + ", " + a.actual + ": cannot compare an 8-bit image with a float (.hdr/.exr) image");
  try {
    // Any image the command can render (up to 16384² float RGBA): the inputs are the
    // user's own files, so only the side limit applies, not the default decoded-bytes bound.
    image::Limits limits;
    limits.max_decoded_bytes = std::numeric_limits<std::uint64_t>::max();
    if (!float_a) {
      const std::vector<std::uint8_t> expected = image::read_file(a.expected, limits), actual = image::read_file(a.actual, limits);
      // A 16-bit PNG (golden images from other tools often are) is compared on its 16-bit
      // samples, exactly; an 8-bit one beside it is widened as PNG scales it (× 257).
      if (is_16_bit_png(expected) || is_16_bit_png(actual))
        return compare_and_report(a, image::load_png16(expected, a.expected, limits),
                                  image::load_png16(actual, a.actual, limits), /*sixteen=*/true);
      return compare_and_report(a, image::load_png(expected, a.expected, limits), image::load_png(actual, a.actual, limits));
    }
    auto load = [&](const std::string& path, const std::string& ext) {
      return ext == ".exr" ? image::load_exr(path, limits) : image::load_hdr(path, limits);
    };
    golden::ImageF expected = load(a.expected, ea), actual = load(a.actual, eb);
    // .exr against .hdr: compare what the .hdr could hold (RGBE keeps 8 mantissa bits, no alpha).
    if (ea != eb) {
      golden::ImageF& exr = ea == ".exr" ? expected : actual;
      exr = golden::hdr_round_trip(exr);
    }
    return compare_and_report(a, expected, actual);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(kExitUsage, e.what());  // the image library's messages start with the file's path
  }
}

}  // namespace softpbr::cli
