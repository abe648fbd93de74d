// `softpbr diff A.glb B.glb` (see model_diff.h): each model loaded once, both framed on the
// union of their bounds, every view rendered on one renderer and compared with
// softpbr::golden, the worst view first on the contact sheet.
#include "model_diff.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "cli_error.h"
#include "softpbr/golden/compare.h"
#include "softpbr/image/read_file.h"
#include "softpbr/image/write.h"
#include "softpbr/job/model_views.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/raster/pool.h"

namespace softpbr::cli {

namespace fs = std::filesystem;
namespace golden = softpbr::golden;

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

// The comparison of one view.
struct ViewResult {
  int index = 0;
  job::View view;
  golden::Comparison c;
  raster::Image8 expected, actual;  // kept for the contact sheet
};

// Worst first: the most differing pixels, then the largest difference, then the lowest
// PSNR; ties in view order.
bool worse(const ViewResult& x, const ViewResult& y) {
  if (x.c.pixels_above != y.c.pixels_above) return x.c.pixels_above > y.c.pixels_above;
  if (x.c.max_diff() != y.c.max_diff()) return x.c.max_diff() > y.c.max_diff();
  if (x.c.rmse != y.c.rmse) return x.c.rmse > y.c.rmse;
  return x.index < y.index;
}

// The rows of the two summaries whose values differ, in A's order then B's rows A lacks.
struct Change {
  std::string property, expected, actual;
};
std::vector<Change> changes(const job::ViewedModel& a, const job::ViewedModel& b) {
  std::map<std::string, std::string> of_a(a.summary.begin(), a.summary.end()), of_b(b.summary.begin(), b.summary.end());
  std::vector<Change> out;
  const std::string none = "(none)";
  for (const auto& [key, value] : a.summary) {
    const auto it = of_b.find(key);
    if (it == of_b.end() || it->second != value) out.push_back({key, value, it == of_b.end() ? none : it->second});
  }
  for (const auto& [key, value] : b.summary)
    if (!of_a.count(key)) out.push_back({key, none, value});
  return out;
}

std::string psnr_text(const golden::Comparison& c) {
  if (!std::isfinite(c.psnr)) return "inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", c.psnr);
  return buf;
}

// The contact sheet: each view a row, expected | actual | heat map, the worst first. Rows
// that would make the sheet taller than an image may be are left out (said on stdout).
raster::Image8 contact_sheet(const std::vector<const ViewResult*>& order, int width, int height, std::size_t& rows) {
  rows = std::min<std::size_t>(order.size(), static_cast<std::size_t>(raster::kMaxTargetSize / height));
  raster::Image8 sheet;
  sheet.width = 3 * width;
  sheet.height = static_cast<int>(rows) * height;
  sheet.rgba.resize(static_cast<std::size_t>(sheet.width) * static_cast<std::size_t>(sheet.height) * 4);
  for (std::size_t r = 0; r < rows; ++r) {
    const raster::Image8 row = golden::side_by_side(order[r]->expected, order[r]->actual);
    std::copy(row.rgba.begin(), row.rgba.end(), sheet.rgba.begin() + static_cast<std::ptrdiff_t>(r * row.rgba.size()));
  }
  return sheet;
}

job::ViewedModel load_compared(const std::string& path, const job::Settings& s, raster::ThreadPool& pool) {
  try {
    return job::load_viewed(path, s, pool);
  } catch (const job::Error& e) {
    throw Error(kExitUsage, job::option_text(e));
  } catch (const pbr::LoadError& e) {
    throw Error(kExitUsage, e.what());
  } catch (const pbr::SceneFileError& e) {
    throw Error(kExitUsage, e.what());
  }
}

}  // namespace

bool is_model_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".gltf" || ext == ".glb" || ext == ".obj" || ext == ".json";
}

int run_model_diff(const DiffArgs& a) {
  // 1. The command line, before any work.
  for (const std::string* p : {&a.expected, &a.actual})
    if (!is_model_path(*p))
      throw Error(kExitUsage, *p + ": cannot compare an image with a model (.gltf, .glb, .obj or a scene .json)");
  if (a.side_by_side) throw Error(kExitUsage, "--side-by-side: images only (the contact sheet of models is side by side)");
  job::Settings s;
  s.width = a.width;
  s.height = a.height;
  s.threads = a.threads;
  s.env = a.env;
  s.background = a.background;
  s.max_memory_mib = a.max_memory_mib;
  s.time = a.time;
  s.animation = a.animation;
  s.variant = a.variant;
  std::vector<job::View> views;
  try {
    job::validate(s);
    views = a.yaws.empty() && a.pitches.empty() ? job::default_views(a.views) : job::views_from_angles(a.yaws, a.pitches);
  } catch (const job::Error& e) {
    throw Error(kExitUsage, job::option_text(e));
  }
  if (!a.out.empty()) {
    if (lower_extension(a.out) != ".png") throw Error(kExitUsage, a.out + ": --out writes a .png");
    if (const std::string problem = image::output_problem(a.out); !problem.empty())
      throw Error(kExitUsage, a.out + ": " + problem);
  }
  if (!a.json.empty() && a.json != "-")
    if (const std::string problem = image::output_problem(a.json); !problem.empty())
      throw Error(kExitUsage, a.json + ": " + problem);
  for (const std::string* p : {&a.expected, &a.actual})
    if (const image::FileProblem problem = image::file_problem(*p))
      throw Error(kExitUsage, *p + ": " + (problem.folder ? std::string("is a folder, not a model") : problem.reason));

  // 2. Both models, one pool and one renderer for both; the memory each needs at this size.
  pbr::RenderSettings defaults;
  raster::Renderer renderer(raster::RendererOptions{a.threads ? static_cast<unsigned>(*a.threads) : defaults.threads,
                                                    defaults.tile_size});
  raster::ThreadPool& pool = renderer.pool();
  const job::ViewedModel ma = load_compared(a.expected, s, pool);
  const job::ViewedModel mb = load_compared(a.actual, s, pool);
  // Every input is an input: neither output may replace one of the files read.
  std::set<std::pair<dev_t, ino_t>> inputs;
  for (const job::ViewedModel* m : {&ma, &mb})
    for (const std::string& f : m->scene.inputs) {
      struct stat st {};
      if (::stat(f.c_str(), &st) == 0) inputs.emplace(st.st_dev, st.st_ino);
    }
  for (const std::string* p : {&a.expected, &a.actual}) {
    struct stat st {};
    if (::stat(p->c_str(), &st) == 0) inputs.emplace(st.st_dev, st.st_ino);
  }
  for (const std::string* o : {&a.out, &a.json}) {
    struct stat st {};
    if (!o->empty() && *o != "-" && ::stat(o->c_str(), &st) == 0 && inputs.count({st.st_dev, st.st_ino}))
      throw Error(kExitUsage, *o + ": cannot write: it is an input of this command (an output never replaces an input)");
  }
  pbr::RenderSettings ra, rb;
  try {
    ra = job::resolve(ma.scene.render, s);
    rb = job::resolve(mb.scene.render, s);
    const job::MemoryLimit limit = job::memory_limit(job::requested_memory_limit(s));
    job::check_memory(job::estimate_memory(ma.scene, ra), ra, limit);
    job::check_memory(job::estimate_memory(mb.scene, rb), rb, limit);
  } catch (const job::Error& e) {
    throw Error(kExitUsage, a.expected + ", " + a.actual + ": " + job::option_text(e));
  }
  // The contact sheet needs every view's two images until the worst is known.
  const std::uint64_t kept = a.out.empty() ? 0 : views.size() * 2 * static_cast<std::uint64_t>(ra.width) * ra.height * 4;
  if (kept > job::requested_memory_limit(s))
    throw Error(kExitUsage, a.out + ": a contact sheet of " + std::to_string(views.size()) + " views at " +
                                std::to_string(ra.width) + "x" + std::to_string(ra.height) + " needs more than --max-memory");
  const pbr::Bounds both = ma.bounds.empty() ? mb.bounds : mb.bounds.empty() ? ma.bounds : pbr::Bounds{glm::min(ma.bounds.min, mb.bounds.min), glm::max(ma.bounds.max, mb.bounds.max)};

  // 3. Every view of both, compared.
  std::vector<ViewResult> results;
  job::Frame frame;
  for (std::size_t i = 0; i < views.size(); ++i) {
    ViewResult r;
    r.index = static_cast<int>(i);
    r.view = views[i];
    pbr::Camera camera;
    try {
      camera = job::view_camera(both, ra.width, ra.height, views[i], a.expected + ", " + a.actual);
    } catch (const job::Error& e) {
      throw Error(kExitUsage, job::option_text(e));
    }
    try {
      frame.render(job::scene_for_view(ma, camera), ra, renderer, {.rgba8 = true});
      r.expected = frame.take_rgba();
      frame.render(job::scene_for_view(mb, camera), rb, renderer, {.rgba8 = true});
      r.actual = frame.take_rgba();
    } catch (const std::invalid_argument& e) {
      throw Error(kExitUsage, a.expected + ", " + a.actual + ": " + e.what());
    }
    r.c = golden::compare(r.expected, r.actual, a.max_diff);
    if (a.out.empty()) r.expected = r.actual = {};
    results.push_back(std::move(r));
  }
  std::vector<const ViewResult*> order;
  for (const ViewResult& r : results) order.push_back(&r);
  std::stable_sort(order.begin(), order.end(), [](const ViewResult* x, const ViewResult* y) { return worse(*x, *y); });
  std::size_t differing = 0, identical = 0;
  bool within = true;
  for (const ViewResult& r : results) {
    identical += r.c.identical;
    differing += r.c.pixels_above > 0;
    within = within && r.c.pixels_above <= a.max_pixels;
  }
  const std::vector<Change> changed = changes(ma, mb);

  // 4. The outputs, each written whole or not at all.
  std::size_t sheet_rows = 0;
  try {
    if (!a.out.empty())
      image::write_file_atomic(a.out, image::encode_png(contact_sheet(order, ra.width, ra.height, sheet_rows), a.out));
    if (!a.json.empty()) {
      nlohmann::json j;
      j["expected"] = a.expected;
      j["actual"] = a.actual;
      j["width"] = ra.width;
      j["height"] = ra.height;
      j["max_diff"] = a.max_diff;
      j["max_pixels"] = a.max_pixels;
      j["identical"] = identical == results.size();
      j["within_tolerance"] = within;
      j["worst_view"] = order.front()->index;
      j["views"] = nlohmann::json::array();
      for (const ViewResult& r : results)
        j["views"].push_back({{"index", r.index},
                              {"yaw", r.view.yaw},
                              {"pitch", r.view.pitch},
                              {"identical", r.c.identical},
                              {"psnr", std::isfinite(r.c.psnr) ? nlohmann::json(r.c.psnr) : nlohmann::json(nullptr)},
                              {"max_diff", r.c.max_diff()},
                              {"pixels_differing", r.c.pixels_above},
                              {"share_differing", r.c.fraction_above}});
      j["changes"] = nlohmann::json::array();
      for (const Change& c : changed) j["changes"].push_back({{"property", c.property}, {"expected", c.expected}, {"actual", c.actual}});
      // Invalid UTF-8 in a name from the file is replaced, never a throw.
      const std::string text = j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
      if (a.json == "-") std::fwrite(text.data(), 1, text.size(), stdout);
      else image::write_file_atomic(a.json, std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
    }
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(kExitUsage, e.what());
  }

  // 5. The report: what changed in the files, each view, the verdict.
  if (!a.quiet && a.json != "-") {
    if (!changed.empty()) {
      std::size_t w = 8;
      for (const Change& c : changed) w = std::max(w, c.property.size());
      std::printf("What changed in the files (%zu propert%s):\n", changed.size(), changed.size() == 1 ? "y" : "ies");
      for (const Change& c : changed) {
        std::printf("  %-*s  %s\n", static_cast<int>(w), printable_line(c.property).c_str(), printable_line(c.expected).c_str());
        std::printf("  %-*s  %s\n", static_cast<int>(w), "", printable_line(c.actual).c_str());
      }
    }
    std::printf("%-5s %8s %6s %9s %9s %12s %9s\n", "view", "yaw", "pitch", "PSNR dB", "max diff", "pixels", "share");
    for (const ViewResult& r : results)
      std::printf("%-5d %8.2f %6.2f %9s %9g %12llu %8.3f%%\n", r.index, static_cast<double>(r.view.yaw),
                  static_cast<double>(r.view.pitch), psnr_text(r.c).c_str(), r.c.max_diff(),
                  static_cast<unsigned long long>(r.c.pixels_above), 100.0 * r.c.fraction_above);
    if (!a.out.empty()) {
      std::printf("%s: %zu views, worst first:", a.out.c_str(), sheet_rows);
      for (std::size_t k = 0; k < sheet_rows; ++k) std::printf(" %d", order[k]->index);
      std::printf(sheet_rows < order.size() ? " (the rest left out: the sheet is at its height limit)\n" : "\n");
    }
    const ViewResult& worst = *order.front();
    if (identical == results.size())
      std::printf("%s vs %s: identical (%zu views at %dx%d)\n", a.expected.c_str(), a.actual.c_str(), results.size(),
                  ra.width, ra.height);
    else
      std::printf("%s vs %s: %s: %zu of %zu views differ (worst: view %d, yaw %g, pitch %g: %llu pixels, %.3f%%, "
                  "largest difference %g, PSNR %s dB)\n",
                  a.expected.c_str(), a.actual.c_str(), within ? "within tolerance" : "DIFFERENT", differing, results.size(),
                  worst.index, static_cast<double>(worst.view.yaw), static_cast<double>(worst.view.pitch),
                  static_cast<unsigned long long>(worst.c.pixels_above), 100.0 * worst.c.fraction_above, worst.c.max_diff(),
                  psnr_text(worst.c).c_str());
  }
  return within ? kExitOk : kExitDifferent;
}

}  // namespace softpbr::cli
