// softpbr::golden matching: golden files checked exactly or within a tolerance, failure
// images written where the message says, update mode, renders (.hash + .png), the
// environment, and the doctest macros.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include <doctest/doctest.h>

#include "golden_helpers.h"
#include "softpbr/golden/doctest_checks.h"
#include "softpbr/golden/golden.h"
#include "softpbr/image/write.h"
#include "softpbr/raster/target.h"

namespace golden = softpbr::golden;
namespace raster = softpbr::raster;
using namespace golden_test;

namespace {

golden::Options options_in(const fs::path& dir, bool update = false) {
  return golden::Options{dir / "goldens", dir / "out", update, "UPDATE-COMMAND"};
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Changes `n` pixels of `im` (from the first) by `by` codes in the green channel (up, or
// down where up would pass 255).
raster::Image8 changed(raster::Image8 im, int n, int by) {
  for (int p = 0; p < n; ++p) {
    const int g = im.rgba[4 * p + 1];
    im.rgba[4 * p + 1] = static_cast<std::uint8_t>(g + by <= 255 ? g + by : g - by);
  }
  return im;
}

raster::Target target_of(const golden::ImageF& f) {
  raster::Target t(f.width, f.height);
  for (std::size_t i = 0; i < t.colors().size(); ++i)
    t.colors()[i] = {f.rgba[4 * i], f.rgba[4 * i + 1], f.rgba[4 * i + 2], f.rgba[4 * i + 3]};
  return t;
}

}  // namespace

TEST_CASE("match_golden: the same image passes, any changed pixel fails and writes actual, diff and side by side") {
  const fs::path dir = scratch("match_exact");
  const golden::Options o = options_in(dir);
  const raster::Image8 im = pattern8(16, 8);
  fs::create_directories(dir / "goldens" / "sub");
  softpbr::image::write_png(dir / "goldens" / "sub" / "pic.png", im);

  const golden::MatchResult ok = golden::match_golden(im, "sub/pic.png", {}, o);
  CHECK(ok.passed);
  CHECK_FALSE(ok.updated);
  CHECK(ok.comparison.identical);
  CHECK(ok.written.empty());
  CHECK_FALSE(fs::exists(dir / "out"));

  const raster::Image8 off = changed(im, 1, 1);
  const golden::MatchResult bad = golden::match_golden(off, "sub/pic.png", {}, o);
  CHECK_FALSE(bad.passed);
  CHECK(bad.golden == dir / "goldens" / "sub" / "pic.png");
  CHECK(bad.comparison.pixels_above == 1);
  const fs::path out = dir / "out" / "sub";
  REQUIRE(bad.written == std::vector<fs::path>{out / "pic.actual.png", out / "pic.diff.png", out / "pic.side-by-side.png"});
  for (const fs::path& p : bad.written) CHECK(contains(bad.message, p.string()));
  CHECK(contains(bad.message, "UPDATE-COMMAND"));
  CHECK(contains(bad.message, "1 of 128 pixels"));
  CHECK(golden::load_png(out / "pic.actual.png").rgba == off.rgba);
  CHECK(golden::load_png(out / "pic.diff.png").rgba == golden::diff_image(im, off).rgba);
  CHECK(golden::load_png(out / "pic.side-by-side.png").rgba == golden::side_by_side(im, off).rgba);
  CHECK(golden::load_png(dir / "goldens" / "sub" / "pic.png").rgba == im.rgba);  // the golden is untouched
}

TEST_CASE("match_golden: a tolerance passes when at most max_pixels pixels differ by more than max_diff") {
  const fs::path dir = scratch("match_tolerance");
  const golden::Options o = options_in(dir);
  const raster::Image8 im = pattern8(10, 10);
  fs::create_directories(dir / "goldens");
  softpbr::image::write_png(dir / "goldens" / "t.png", im);
  struct Case {
    int pixels, by;
    golden::Tolerance tolerance;
    bool passes;
  };
  const Case cases[] = {{0, 0, {}, true},         {1, 1, {}, false},        {1, 1, {1, 0}, true},
                        {1, 2, {1, 0}, false},    {5, 2, {1, 5}, true},     {6, 2, {1, 5}, false},
                        {100, 3, {2, 99}, false}, {100, 3, {3, 0}, true},   {100, 3, {0, 100}, true}};
  for (const Case& c : cases) {
    CAPTURE(c.pixels);
    CAPTURE(c.by);
    CAPTURE(c.tolerance.max_diff);
    CAPTURE(c.tolerance.max_pixels);
    const golden::MatchResult r = golden::match_golden(changed(im, c.pixels, c.by), "t.png", c.tolerance, o);
    CHECK(r.passed == c.passes);
    CHECK(r.written.empty() == c.passes);
  }
}

TEST_CASE("match_golden: a missing golden fails with the actual image written, update mode creates it, then it passes") {
  const fs::path dir = scratch("match_missing");
  const raster::Image8 im = pattern8(5, 4);
  const golden::MatchResult missing = golden::match_golden(im, "new/one.png", {}, options_in(dir));
  CHECK_FALSE(missing.passed);
  CHECK(contains(missing.message, "missing"));
  CHECK(missing.written == std::vector<fs::path>{dir / "out" / "new" / "one.actual.png"});
  CHECK_FALSE(fs::exists(dir / "goldens" / "new" / "one.png"));

  const golden::MatchResult created = golden::match_golden(im, "new/one.png", {}, options_in(dir, true));
  CHECK(created.passed);
  CHECK(created.updated);
  CHECK(golden::load_png(dir / "goldens" / "new" / "one.png").rgba == im.rgba);
  CHECK(golden::match_golden(im, "new/one.png", {}, options_in(dir)).passed);
}

TEST_CASE("match_golden update mode rewrites a golden outside the tolerance and leaves one inside it untouched") {
  const fs::path dir = scratch("match_update");
  const raster::Image8 im = pattern8(6, 6);
  fs::create_directories(dir / "goldens");
  softpbr::image::write_png(dir / "goldens" / "u.png", im);
  const std::vector<char> before = file_bytes(dir / "goldens" / "u.png");

  const golden::MatchResult inside = golden::match_golden(changed(im, 2, 1), "u.png", {1, 0}, options_in(dir, true));
  CHECK(inside.passed);
  CHECK_FALSE(inside.updated);
  CHECK(file_bytes(dir / "goldens" / "u.png") == before);

  const raster::Image8 off = changed(im, 2, 9);
  const golden::MatchResult outside = golden::match_golden(off, "u.png", {1, 0}, options_in(dir, true));
  CHECK(outside.passed);
  CHECK(outside.updated);
  CHECK(golden::load_png(dir / "goldens" / "u.png").rgba == off.rgba);
  CHECK(outside.written.empty());
}

TEST_CASE("match_golden never throws for bad goldens: unreadable, wrong format, 8-bit against .hdr, wrong size") {
  const fs::path dir = scratch("match_bad");
  const golden::Options o = options_in(dir);
  fs::create_directories(dir / "goldens");
  write_bytes(dir / "goldens" / "garbage.png", "not a png");
  softpbr::image::write_png(dir / "goldens" / "small.png", pattern8(3, 3));
  struct Case {
    std::string golden, says;
  };
  const Case cases[] = {{"garbage.png", "cannot read golden"},
                        {"pic.jpg", "unsupported golden format '.jpg'"},
                        {"pic.hdr", "cannot be checked against a float .hdr golden"},
                        {"small.png", "expected 3x3, actual 4x4"}};
  for (const Case& c : cases) {
    CAPTURE(c.golden);
    golden::MatchResult r;
    CHECK_NOTHROW(r = golden::match_golden(pattern8(4, 4), c.golden, {}, o));
    CHECK_FALSE(r.passed);
    CHECK(contains(r.message, c.says));
  }
  // Different sizes: the side by side is written, no diff.
  const golden::MatchResult r = golden::match_golden(pattern8(4, 4), "small.png", {}, o);
  CHECK(r.written == std::vector<fs::path>{dir / "out" / "small.actual.png", dir / "out" / "small.side-by-side.png"});
}

TEST_CASE("match_golden with floats: .hdr goldens hold the render's RGBE values, .png goldens its sRGB codes") {
  const fs::path dir = scratch("match_float");
  const golden::Options o = options_in(dir);
  const golden::ImageF f = patternF(12, 7);
  const raster::Target t = target_of(f);
  CHECK(golden::match_golden(t, "r.hdr", {}, options_in(dir, true)).updated);
  CHECK(golden::match_golden(t, "r.png", {}, options_in(dir, true)).updated);
  CHECK(golden::match_golden(t, "r.hdr", {}, o).passed);
  CHECK(golden::match_golden(f, "r.hdr", {}, o).passed);
  CHECK(golden::match_golden(t, "r.png", {}, o).passed);
  CHECK(golden::load_png(dir / "goldens" / "r.png").rgba == raster::resolve_srgb8(t).rgba);

  golden::ImageF g = f;
  g.rgba[4 * 5 + 0] *= 1.5f;  // pixel 5, red: far beyond RGBE's 8-bit mantissa
  const golden::MatchResult r = golden::match_golden(g, "r.hdr", {}, o);
  CHECK_FALSE(r.passed);
  CHECK(r.comparison.pixels_above == 1);
  CHECK(r.comparison.peak == 1);
  CHECK(r.written.front() == dir / "out" / "r.actual.hdr");
  CHECK(golden::load_hdr(dir / "out" / "r.actual.hdr").rgba == golden::hdr_round_trip(g).rgba);
  // Within a float tolerance of the change it passes.
  CHECK(golden::match_golden(g, "r.hdr", {r.comparison.max_diff(), 0}, o).passed);
}

TEST_CASE("match_render: the colour hash and the PNG must both match, a float bit too small to show still fails") {
  const fs::path dir = scratch("match_render");
  const golden::Options o = options_in(dir);
  raster::Target t = target_of(patternF(9, 5));
  const raster::Image8 shown = raster::resolve_srgb8(t);

  const golden::MatchResult first = golden::match_render(t, shown, "scene", o);
  CHECK_FALSE(first.passed);
  CHECK(contains(first.message, "missing"));
  CHECK(golden::match_render(t, shown, "scene", options_in(dir, true)).updated);
  CHECK(file_bytes(dir / "goldens" / "scene.hash").size() == 17);  // 16 hex digits and a newline
  const golden::MatchResult ok = golden::match_render(t, shown, "scene", o);
  CHECK(ok.passed);
  CHECK(ok.golden == dir / "goldens" / "scene.hash");

  // One ulp in one pixel: the same 8-bit image, another hash.
  raster::Target nudged = t;
  nudged.color(3, 2).r = std::nextafter(nudged.color(3, 2).r, 10.0f);
  REQUIRE(raster::resolve_srgb8(nudged).rgba == shown.rgba);
  const golden::MatchResult tiny = golden::match_render(nudged, shown, "scene", o);
  CHECK_FALSE(tiny.passed);
  CHECK(contains(tiny.message, golden::hash_hex(raster::hash_colors(nudged))));
  CHECK(contains(tiny.message, golden::hash_hex(raster::hash_colors(t))));
  CHECK(contains(tiny.message, "too small to show"));
  const fs::path out = dir / "out";
  CHECK(tiny.written == std::vector<fs::path>{out / "scene.actual.png", out / "scene.actual.hash", out / "scene.diff.png",
                                              out / "scene.side-by-side.png"});
  CHECK(file_bytes(out / "scene.actual.hash").size() == 17);

  // A visible change fails on both; update mode rewrites both.
  nudged.color(0, 0) = {1, 1, 1, 1};
  const raster::Image8 shown2 = raster::resolve_srgb8(nudged);
  const golden::MatchResult visible = golden::match_render(nudged, shown2, "scene", o);
  CHECK_FALSE(visible.passed);
  CHECK(visible.comparison.pixels_above == 1);
  CHECK(golden::match_render(nudged, shown2, "scene", options_in(dir, true)).updated);
  CHECK(golden::match_render(nudged, shown2, "scene", o).passed);
  CHECK_FALSE(golden::match_render(t, shown, "scene", o).passed);

  // A malformed .hash file is reported as such.
  write_bytes(dir / "goldens" / "scene.hash", "XYZ\n");
  CHECK(contains(golden::match_render(nudged, shown2, "scene", o).message, "not 16 lowercase hex digits"));
}

TEST_CASE("options_from_environment: SOFTPBR_GOLDEN_DIR, SOFTPBR_GOLDEN_OUTPUT and SOFTPBR_UPDATE_GOLDENS=1 override the defaults") {
  const char* names[] = {"SOFTPBR_GOLDEN_DIR", "SOFTPBR_GOLDEN_OUTPUT", "SOFTPBR_UPDATE_GOLDENS"};
  std::string saved[3];
  bool had[3];
  for (int i = 0; i < 3; ++i) {
    const char* v = std::getenv(names[i]);
    had[i] = v != nullptr;
    saved[i] = v ? v : "";
    unsetenv(names[i]);
  }
  const golden::Options defaults{"gd", "od", false, "cmd"};
  struct Case {
    const char *dir, *out, *update;
    fs::path want_dir, want_out;
    bool want_update;
  };
  const Case cases[] = {{nullptr, nullptr, nullptr, "gd", "od", false}, {"/x", nullptr, "1", "/x", "od", true},
                        {nullptr, "/o", "0", "gd", "/o", false},        {"", "", "yes", "gd", "od", false},
                        {"a", "b", "1", "a", "b", true}};
  for (const Case& c : cases) {
    CAPTURE(c.want_dir);
    const char* values[] = {c.dir, c.out, c.update};
    for (int i = 0; i < 3; ++i) {
      if (values[i]) setenv(names[i], values[i], 1);
      else unsetenv(names[i]);
    }
    const golden::Options got = golden::options_from_environment(defaults);
    CHECK(got.golden_dir == c.want_dir);
    CHECK(got.output_dir == c.want_out);
    CHECK(got.update == c.want_update);
    CHECK(got.update_command == "cmd");
  }
  for (int i = 0; i < 3; ++i) {
    if (had[i]) setenv(names[i], saved[i].c_str(), 1);
    else unsetenv(names[i]);
  }
}

TEST_CASE("golden doctest macros resolve against SOFTPBR_GOLDEN_DIR: a committed golden matches itself, exactly and within a tolerance") {
  // tests/CMakeLists.txt sets SOFTPBR_GOLDEN_DIR to tests/.
  const raster::Image8 gallery = golden::load_png(fs::path(SOFTPBR_GOLDEN_DIR) / "goldens" / "grazing_light.png");
  CHECK_IMAGE_MATCHES(gallery, "goldens/grazing_light.png");
  REQUIRE_IMAGE_MATCHES(gallery, "goldens/grazing_light.png");
  CHECK_IMAGE_MATCHES_WITHIN(changed(gallery, 3, 1), "goldens/grazing_light.png", golden::Tolerance{1, 0});
  REQUIRE_IMAGE_MATCHES_WITHIN(changed(gallery, 3, 2), "goldens/grazing_light.png", golden::Tolerance{2, 0});
  // The same change outside the tolerance fails (checked through match_golden, so this
  // test does not fail; update mode is off whatever the environment says).
  golden::Options o = SOFTPBR_GOLDEN_OPTIONS();
  o.update = false;
  o.output_dir = scratch("match_macros");
  CHECK_FALSE(golden::match_golden(changed(gallery, 3, 2), "goldens/grazing_light.png", {1, 2}, o).passed);
  CHECK(golden::match_golden(changed(gallery, 3, 2), "goldens/grazing_light.png", {1, 3}, o).passed);
}

TEST_CASE("match_golden and match_render fail at once on goldens that are named pipes, never wait on them") {
  // A blocked read ends the test binary after 60 s instead of hanging the suite.
  ::signal(SIGALRM, [](int) { ::_exit(3); });
  ::alarm(60);
  const fs::path dir = scratch("match_fifo");
  const golden::Options o = options_in(dir);
  fs::create_directories(dir / "goldens");
  for (const char* name : {"pipe.png", "pipe.hash"}) {
    fs::remove(dir / "goldens" / name);
    REQUIRE(::mkfifo((dir / "goldens" / name).c_str(), 0644) == 0);
  }
  const golden::MatchResult image = golden::match_golden(pattern8(4, 4), "pipe.png", {}, o);
  CHECK_FALSE(image.passed);
  CHECK(contains(image.message, "is a named pipe (FIFO), not a regular file"));
  raster::Target t = target_of(patternF(9, 5));
  const golden::MatchResult render = golden::match_render(t, raster::resolve_srgb8(t), "pipe", o);
  CHECK_FALSE(render.passed);
  CHECK(contains(render.message, "is a named pipe (FIFO), not a regular file"));
  ::alarm(0);
}
