// Matching images and renders against golden files: compare, explain, write the images to
// look at on failure, rewrite the golden in update mode.
#include "softpbr/golden/golden.h"

#include <cctype>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string_view>

#include "softpbr/image/read_file.h"
#include "softpbr/image/write.h"

namespace softpbr::golden {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

fs::path resolve(const fs::path& golden, const Options& o) {
  return golden.is_absolute() || o.golden_dir.empty() ? golden : o.golden_dir / golden;
}

// options.output_dir / <the golden's folder relative to golden_dir> / <the golden's stem>:
// failure images are named by appending ".actual.png" and so on.
fs::path output_base(const fs::path& golden, const fs::path& resolved, const Options& o) {
  const fs::path out = o.output_dir.empty() ? fs::path("golden-output") : o.output_dir;
  fs::path folder;
  if (golden.is_relative()) {
    folder = golden.parent_path();
  } else if (!o.golden_dir.empty()) {
    const fs::path rel = resolved.lexically_relative(o.golden_dir);
    if (!rel.empty() && *rel.begin() != "..") folder = rel.parent_path();
  }
  return (out / folder / resolved.stem()).lexically_normal();
}

fs::path with_suffix(const fs::path& base, std::string_view suffix) { return fs::path(base.string() + std::string(suffix)); }

// Runs one write, recording the path or why it failed; never throws.
void try_write(MatchResult& r, const fs::path& path, const std::function<void(const fs::path&)>& write) {
  try {
    if (path.has_parent_path()) fs::create_directories(path.parent_path());
    write(path);
    r.written.push_back(path);
  } catch (const std::exception& e) {
    r.message += "\n  (could not write " + path.string() + ": " + e.what() + ")";
  }
}

void write_text(const fs::path& path, const std::string& text) {
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(text.data());
  image::write_file_atomic(path, std::span<const std::uint8_t>(bytes, text.size()));
}

void add_paths_and_hint(MatchResult& r, const Options& o) {
  if (!r.written.empty()) {
    r.message += "\n  wrote:";
    for (const fs::path& p : r.written) r.message += "\n    " + p.string();
  }
  r.message += "\n  If the change is intended, look at the images, then accept it with: " + o.update_command;
}

std::string tolerance_text(const Tolerance& t) {
  std::ostringstream s;
  if (t.max_diff == 0 && t.max_pixels == 0) return "exact";
  s << "at most " << t.max_pixels << " pixels differing by more than " << t.max_diff;
  return s.str();
}

// The shared logic of match_golden for 8-bit (.png) and float (.hdr) goldens. `actual` is
// already what the golden file can hold.
template <class Image>
MatchResult match_image(const Image& actual, const fs::path& golden, const Tolerance& tolerance, const Options& o,
                        const std::function<Image(const fs::path&)>& load,
                        const std::function<void(const fs::path&, const Image&)>& write, std::string_view ext) {
  MatchResult r;
  r.golden = resolve(golden, o);
  const fs::path base = output_base(golden, r.golden, o);
  auto write_golden = [&](const std::string& what) {
    try {
      if (r.golden.has_parent_path()) fs::create_directories(r.golden.parent_path());
      write(r.golden, actual);
      r.passed = r.updated = true;
      r.message = what + " " + r.golden.string();
    } catch (const std::exception& e) {
      r.message = "golden " + r.golden.string() + ": cannot write it: " + e.what();
    }
  };
  auto write_actual = [&] { try_write(r, with_suffix(base, std::string(".actual") + std::string(ext)), [&](const fs::path& p) { write(p, actual); }); };

  std::error_code ec;
  if (!fs::exists(r.golden, ec)) {
    if (o.update) {
      write_golden("created golden");
      return r;
    }
    r.message = "golden " + r.golden.string() + " is missing";
    write_actual();
    add_paths_and_hint(r, o);
    return r;
  }
  Image expected;
  try {
    expected = load(r.golden);
  } catch (const std::exception& e) {
    if (o.update) {
      write_golden(std::string("rewrote unreadable golden (") + e.what() + ")");
      return r;
    }
    r.message = std::string("cannot read golden: ") + e.what();
    write_actual();
    add_paths_and_hint(r, o);
    return r;
  }
  r.comparison = compare(expected, actual, tolerance.max_diff);
  const bool within = r.comparison.same_size() && r.comparison.pixels_above <= tolerance.max_pixels;
  if (within) {
    r.passed = true;
    r.message = "golden " + r.golden.string() + " matches (" + tolerance_text(tolerance) + "): " + r.comparison.describe();
    return r;
  }
  if (o.update) {
    write_golden("updated golden (was: " + r.comparison.describe() + ")");
    return r;
  }
  r.message = "golden " + r.golden.string() + " differs (tolerance: " + tolerance_text(tolerance) + "): " +
              r.comparison.describe();
  write_actual();
  if (r.comparison.same_size())
    try_write(r, with_suffix(base, ".diff.png"), [&](const fs::path& p) { write_png(p, diff_image(expected, actual)); });
  try_write(r, with_suffix(base, ".side-by-side.png"),
            [&](const fs::path& p) { write_png(p, side_by_side(expected, actual)); });
  add_paths_and_hint(r, o);
  return r;
}

MatchResult unsupported(const fs::path& golden, const Options& o, const std::string& why) {
  MatchResult r;
  r.golden = resolve(golden, o);
  r.message = "golden " + r.golden.string() + ": " + why;
  return r;
}

// The first whitespace-separated word of a .hash file, or "" when it cannot be read (read
// without blocking: a named pipe or a device is not a .hash file; one is 17 bytes).
std::string read_hash(const fs::path& path) {
  std::string text;
  if (image::read_whole_file(path, 4096, text)) return "";
  std::istringstream in(text);
  std::string word;
  in >> word;
  return word;
}

bool is_hash(const std::string& s) {
  if (s.size() != 16) return false;
  for (char c : s)
    if (!std::isxdigit(static_cast<unsigned char>(c)) || std::isupper(static_cast<unsigned char>(c))) return false;
  return true;
}

}  // namespace

Options options_from_environment(Options defaults) {
  if (const char* dir = std::getenv("SOFTPBR_GOLDEN_DIR"); dir && *dir) defaults.golden_dir = dir;
  if (const char* out = std::getenv("SOFTPBR_GOLDEN_OUTPUT"); out && *out) defaults.output_dir = out;
  if (const char* update = std::getenv("SOFTPBR_UPDATE_GOLDENS")) defaults.update = std::string_view(update) == "1";
  return defaults;
}

MatchResult match_golden(const Image8& actual, const fs::path& golden, const Tolerance& tolerance, const Options& options) {
  const std::string ext = lower_extension(golden);
  if (ext == ".hdr")
    return unsupported(golden, options, "an 8-bit image cannot be checked against a float .hdr golden (use a .png golden)");
  if (ext != ".png") return unsupported(golden, options, "unsupported golden format '" + ext + "' (use .png or .hdr)");
  return match_image<Image8>(
      actual, golden, tolerance, options, [](const fs::path& p) { return load_png(p); },
      [](const fs::path& p, const Image8& im) { write_png(p, im); }, ".png");
}

MatchResult match_golden(const ImageF& actual, const fs::path& golden, const Tolerance& tolerance, const Options& options) {
  const std::string ext = lower_extension(golden);
  if (ext == ".png") return match_golden(to_srgb8(actual), golden, tolerance, options);
  if (ext != ".hdr") return unsupported(golden, options, "unsupported golden format '" + ext + "' (use .png or .hdr)");
  return match_image<ImageF>(
      hdr_round_trip(actual), golden, tolerance, options, [](const fs::path& p) { return load_hdr(p); },
      [](const fs::path& p, const ImageF& im) { write_hdr(p, im); }, ".hdr");
}

MatchResult match_golden(const raster::Target& actual, const fs::path& golden, const Tolerance& tolerance,
                         const Options& options) {
  return match_golden(to_image(actual), golden, tolerance, options);
}

MatchResult match_render(const raster::Target& target, const Image8& image, const fs::path& golden_stem,
                         const Options& options) {
  MatchResult r;
  const fs::path stem_resolved = resolve(golden_stem, options);
  const fs::path hash_path = with_suffix(stem_resolved, ".hash");
  const fs::path png_path = with_suffix(stem_resolved, ".png");
  const fs::path base = output_base(golden_stem, with_suffix(stem_resolved, ".png"), options);
  r.golden = hash_path;

  const std::string got = hash_hex(raster::hash_colors(target));
  std::error_code ec;
  const bool hash_exists = fs::exists(hash_path, ec);
  const std::string expected_hash = hash_exists ? read_hash(hash_path) : "";
  const bool hash_ok = expected_hash == got;

  Image8 golden_image;
  std::string png_problem;
  bool png_loaded = false;
  if (!fs::exists(png_path, ec)) {
    png_problem = png_path.string() + " is missing";
  } else {
    try {
      golden_image = load_png(png_path);
      png_loaded = true;
    } catch (const std::exception& e) {
      png_problem = std::string("cannot read golden: ") + e.what();
    }
  }
  if (png_loaded) r.comparison = compare(golden_image, image);
  const bool png_ok = png_loaded && r.comparison.identical;

  if (hash_ok && png_ok) {
    r.passed = true;
    r.message = "render " + golden_stem.string() + " matches its golden: hash " + got + ", image identical";
    return r;
  }
  if (options.update) {
    r.passed = r.updated = true;
    r.message = "updated render golden " + stem_resolved.string() + ":";
    try {
      if (hash_path.has_parent_path()) fs::create_directories(hash_path.parent_path());
      if (!hash_ok) {
        write_text(hash_path, got + "\n");
        r.message += " hash " + (expected_hash.empty() ? std::string("(none)") : expected_hash) + " -> " + got + ";";
      }
      if (!png_ok) {
        write_png(png_path, image);
        r.message += " image " + (png_loaded ? r.comparison.describe() : png_problem) + " -> rewritten";
      }
    } catch (const std::exception& e) {
      r.passed = r.updated = false;
      r.message = "render golden " + stem_resolved.string() + ": cannot update it: " + e.what();
    }
    return r;
  }

  std::ostringstream m;
  m << "render " << golden_stem.string() << " differs from its golden:";
  if (!hash_ok) {
    m << "\n  colour buffer hash " << got << ", expected ";
    if (!hash_exists) m << "(missing " << hash_path.string() << ")";
    else if (!is_hash(expected_hash)) m << "(not 16 lowercase hex digits in " << hash_path.string() << ")";
    else m << expected_hash << " (" << hash_path.string() << ")";
  }
  if (!png_loaded) m << "\n  image: " << png_problem;
  else if (!png_ok) m << "\n  image: " << r.comparison.describe();
  else m << "\n  image: identical 8-bit image; the float colour buffer differs in bits too small to show";
  r.message = m.str();
  try_write(r, with_suffix(base, ".actual.png"), [&](const fs::path& p) { write_png(p, image); });
  try_write(r, with_suffix(base, ".actual.hash"), [&](const fs::path& p) { write_text(p, got + "\n"); });
  if (png_loaded && r.comparison.same_size())
    try_write(r, with_suffix(base, ".diff.png"), [&](const fs::path& p) { write_png(p, diff_image(golden_image, image)); });
  if (png_loaded)
    try_write(r, with_suffix(base, ".side-by-side.png"),
              [&](const fs::path& p) { write_png(p, side_by_side(golden_image, image)); });
  add_paths_and_hint(r, options);
  return r;
}

}  // namespace softpbr::golden
