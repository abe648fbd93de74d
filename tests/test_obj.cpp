// OBJ + MTL loading: the project's spot cow, small inline files for each feature, bad files
// that must fail with the file and line in the message, tinyobjloader's own edge cases and
// the other shared models (when ../shared exists).
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/geometric.hpp>

#include "softpbr/loaders/obj.h"

namespace pbr = softpbr::pbr;
namespace fs = std::filesystem;

namespace {

const fs::path kSourceDir = SOFTPBR_SOURCE_DIR;
const fs::path kShared = (kSourceDir / ".." / "shared" / "models").lexically_normal();

// A fresh directory under the system temp dir, removed with everything in it at the end.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("softpbr_test_obj_" + std::to_string(std::random_device{}()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return path / name;
  }
};

std::size_t triangles(const pbr::ObjModel& m) {
  std::size_t n = 0;
  for (const pbr::ObjShape& s : m.shapes) n += s.mesh.triangle_count();
  return n;
}

// What every loaded model must satisfy: indices in range, finite positions and UVs, unit
// normals, material indices in range.
void check_model(const pbr::ObjModel& m) {
  int bad = 0;
  for (const pbr::ObjShape& s : m.shapes) {
    bad += s.mesh.indices.size() % 3 != 0;
    bad += s.material < -1 || s.material >= static_cast<int>(m.materials.size());
    for (std::uint32_t i : s.mesh.indices) bad += i >= s.mesh.vertices.size();
    for (const pbr::MeshVertex& v : s.mesh.vertices) {
      bad += !std::isfinite(v.position.x) || !std::isfinite(v.position.y) || !std::isfinite(v.position.z);
      bad += !std::isfinite(v.uv.x) || !std::isfinite(v.uv.y);
      bad += !(std::fabs(glm::length(v.normal) - 1.0f) < 1e-5f);
    }
  }
  CHECK(bad == 0);
}

// The LoadError message, or "" if loading succeeded.
std::string load_error(const fs::path& path) {
  try {
    pbr::load_obj(path);
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return {};
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

bool any_contains(const std::vector<std::string>& list, const std::string& part) {
  return std::any_of(list.begin(), list.end(), [&](const std::string& s) { return contains(s, part); });
}

}  // namespace

TEST_CASE("obj: the spot cow from assets loads as one closed, outward-facing mesh") {
  const fs::path path = kSourceDir / "assets" / "models" / "spot" / "spot_triangulated.obj";
  const pbr::ObjModel model = pbr::load_obj(path);
  check_model(model);
  REQUIRE(model.shapes.size() == 1);
  CHECK(model.materials.empty());
  CHECK(model.warnings.empty());
  const pbr::Mesh& mesh = model.shapes[0].mesh;
  CHECK(model.shapes[0].material == -1);
  CHECK(mesh.triangle_count() == 5856);
  CHECK(mesh.vertices.size() >= 3225);  // split where UVs have seams
  // Positive enclosed volume: the triangles face outwards.
  double volume = 0.0;
  int disagree = 0;
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    const glm::dvec3 a(mesh.vertices[mesh.indices[t]].position), b(mesh.vertices[mesh.indices[t + 1]].position),
        c(mesh.vertices[mesh.indices[t + 2]].position);
    volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    for (int k = 0; k < 3; ++k)
      disagree += glm::dot(glm::cross(b - a, c - a), glm::dvec3(mesh.vertices[mesh.indices[t + k]].normal)) <= 0.0;
  }
  CHECK(volume > 0.0);
  CHECK(disagree < 20);
  // Closed: vertices split at UV seams keep their position's bits, so welded by position
  // every directed edge has exactly one reverse twin.
  std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, int> edges;
  auto at = [&](std::size_t i) {
    const glm::vec3 p = mesh.vertices[mesh.indices[i]].position;
    return std::array<float, 3>{p.x, p.y, p.z};
  };
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3)
    for (std::size_t k = 0; k < 3; ++k) ++edges[{at(t + k), at(t + (k + 1) % 3)}];
  int open = 0;
  for (const auto& [e, n] : edges) open += n != 1 || edges.count({e.second, e.first}) != 1;
  CHECK(open == 0);  // smooth normals may lean past a few triangles at sharp creases (ears, horns)
  const pbr::Bounds b = pbr::bounds(mesh);
  CHECK(!b.empty());
  // The file's UVs: four of its 3225 lie just outside [0, 1] (u down to −0.052, v up to
  // 1.0007, which the flip to v down makes −0.0007).
  for (const pbr::MeshVertex& v : mesh.vertices)
    CHECK((v.uv.x >= -0.06f && v.uv.x <= 1.0f && v.uv.y >= -0.001f && v.uv.y <= 1.0f));
}

TEST_CASE("obj: quads and larger polygons are triangulated keeping their winding") {
  TempDir dir;
  // A unit quad, a convex pentagon and a concave (L-shaped) hexagon, all counter-clockwise
  // seen from +z.
  const fs::path path = dir.write("polygons.obj", R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
f 1 2 3 4
v 3 0 0
v 4 0 0
v 4.5 1 0
v 3.5 2 0
v 2.5 1 0
f 5 6 7 8 9
v 6 0 0
v 8 0 0
v 8 1 0
v 7 1 0
v 7 2 0
v 6 2 0
f 10 11 12 13 14 15
)");
  const pbr::ObjModel model = pbr::load_obj(path);
  check_model(model);
  REQUIRE(model.shapes.size() == 1);
  const pbr::Mesh& mesh = model.shapes[0].mesh;
  CHECK(mesh.triangle_count() == 2 + 3 + 4);
  double area = 0.0;
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    const glm::dvec3 a(mesh.vertices[mesh.indices[t]].position), b(mesh.vertices[mesh.indices[t + 1]].position),
        c(mesh.vertices[mesh.indices[t + 2]].position);
    const double z = glm::cross(b - a, c - a).z;
    CHECK(z > 0.0);
    area += z / 2;
  }
  CHECK(area == doctest::Approx(1.0 + 2.5 + 3.0));  // the triangles cover each polygon once
  for (const pbr::MeshVertex& v : mesh.vertices) CHECK(v.normal == glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST_CASE("obj: missing normals become smooth normals, given ones are normalised") {
  TempDir dir;
  // A cube from 8 shared positions without normals: angle-weighted normals lie along the
  // diagonals. One extra triangle has a (non-unit) normal of its own.
  const fs::path path = dir.write("cube.obj", R"(v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 5 6 7 8
f 2 1 4 3
f 6 2 3 7
f 1 5 8 4
f 8 7 3 4
f 1 2 6 5
o flagged
v 5 0 0
v 6 0 0
v 5 1 0
vn 0 0 2
f 9//1 10//1 11//1
)");
  const pbr::ObjModel model = pbr::load_obj(path);
  check_model(model);
  REQUIRE(model.shapes.size() == 2);
  CHECK(model.shapes[0].mesh.vertices.size() == 8);
  for (const pbr::MeshVertex& v : model.shapes[0].mesh.vertices)
    CHECK(glm::length(v.normal - v.position / std::sqrt(3.0f)) < 1e-6f);
  for (const pbr::MeshVertex& v : model.shapes[1].mesh.vertices) CHECK(v.normal == glm::vec3(0.0f, 0.0f, 1.0f));
  for (const pbr::MeshVertex& v : model.shapes[1].mesh.vertices) CHECK(v.uv == glm::vec2(0.0f));
}

TEST_CASE("obj: texture coordinates and normals are shared only where all indices agree") {
  TempDir dir;
  const fs::path path = dir.write("uv.obj", R"(v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
vt 0 0
vt 1 0
vt 0 1
vt 1 1
vt 0.5 0.5
f 1/1 2/2 3/3
f 2/2 4/4 3/5
)");
  const pbr::ObjModel model = pbr::load_obj(path);
  check_model(model);
  const pbr::Mesh& mesh = model.shapes.at(0).mesh;
  CHECK(mesh.vertices.size() == 5);  // position 3 appears with two different UVs
  // (u, 1 − v): OBJ's v grows up the image, softpbr's down.
  CHECK(mesh.vertices[mesh.indices[5]].uv == glm::vec2(0.5f, 0.5f));
  CHECK(mesh.vertices[mesh.indices[4]].uv == glm::vec2(1.0f, 0.0f));
  CHECK(mesh.vertices[mesh.indices[2]].uv == glm::vec2(0.0f, 0.0f));
  CHECK(mesh.vertices[mesh.indices[0]].uv == glm::vec2(0.0f, 1.0f));
}

TEST_CASE("obj: faces are split by material, one ObjShape per object and material") {
  TempDir dir;
  dir.write("two.mtl", "newmtl red\nKd 1 0 0\n\nnewmtl blue\nKd 0 0 1\n");
  const fs::path path = dir.write("split.obj", R"(mtllib two.mtl
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
o first
usemtl red
f 1 2 3
usemtl blue
f 2 4 3
usemtl red
f 1 2 4
o second
f 1 3 4
o third
usemtl nonexistent
f 1 2 3
)");
  const pbr::ObjModel model = pbr::load_obj(path);
  check_model(model);
  REQUIRE(model.materials.size() == 2);
  CHECK(model.materials[0].first == "red");
  CHECK(model.materials[1].first == "blue");
  CHECK(model.materials[0].second.base_color == glm::vec3(1, 0, 0));
  REQUIRE(model.shapes.size() == 4);
  // A material stays in force across `o` (as tinyobjloader and most readers do): "second"
  // is red, from the last usemtl before it.
  const std::vector<std::pair<std::string, int>> expected = {{"first", 0}, {"first", 1}, {"second", 0}, {"third", -1}};
  const std::vector<std::size_t> counts = {2, 1, 1, 1};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CAPTURE(i);
    CHECK(model.shapes[i].name == expected[i].first);
    CHECK(model.shapes[i].material == expected[i].second);
    CHECK(model.shapes[i].mesh.triangle_count() == counts[i]);
  }
  CHECK(any_contains(model.warnings, "nonexistent"));
  CHECK(any_contains(model.warnings, path.string()));
}

TEST_CASE("obj: MTL values map onto metal/roughness materials, Ns when Pr is absent") {
  TempDir dir;
  dir.write("pbr.mtl", R"(# PBR extension keys and the Blinn-Phong fallback
newmtl gold
Kd 1 0.71 0.29
Pr 0.3
Pm 1
Ke 1 2 3
newmtl mirror
Ns 10
Pr 0
newmtl phong
Kd 0.5 0.25 0.125
Ns 98
newmtl matte
Ns 0
newmtl plain
Kd 0.2 0.2 0.2
newmtl too_bright
Kd 2 0.5 0.5
Pr 1.5
)");
  const fs::path path = dir.write("pbr.obj", "mtllib pbr.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl gold\nf 1 2 3\n");
  const pbr::ObjModel model = pbr::load_obj(path);
  check_model(model);
  std::map<std::string, pbr::Material> m(model.materials.begin(), model.materials.end());
  REQUIRE(m.size() == 6);
  CHECK(m["gold"].base_color == glm::vec3(1.0f, 0.71f, 0.29f));
  CHECK(m["gold"].roughness == doctest::Approx(0.3f));
  CHECK(m["gold"].metallic == 1.0f);
  CHECK(m["gold"].emissive == glm::vec3(1, 2, 3));
  CHECK(m["mirror"].roughness == 0.0f);  // an explicit Pr 0 wins over Ns
  CHECK(m["phong"].roughness == doctest::Approx(std::sqrt(std::sqrt(2.0 / 100.0))));
  CHECK(m["phong"].base_color == glm::vec3(0.5f, 0.25f, 0.125f));
  CHECK(m["phong"].metallic == 0.0f);
  CHECK(m["matte"].roughness == 1.0f);
  CHECK(m["plain"].roughness == pbr::Material{}.roughness);  // neither Pr nor Ns
  CHECK(m["too_bright"].base_color == glm::vec3(1.0f, 0.5f, 0.5f));
  CHECK(m["too_bright"].roughness == 1.0f);
  CHECK(any_contains(model.warnings, "Kd clamped"));
  CHECK(any_contains(model.warnings, "Pr clamped"));
  CHECK(model.shapes.at(0).material == 0);
}

TEST_CASE("obj: roughness from the Phong exponent follows √(√(2 / (Ns + 2))) within [0, 1]") {
  const std::vector<std::pair<float, double>> table = {
      {0.0f, 1.0}, {-5.0f, 1.0}, {2.0f, std::sqrt(std::sqrt(0.5))}, {98.0f, std::sqrt(std::sqrt(0.02))},
      {1000.0f, std::sqrt(std::sqrt(2.0 / 1002.0))}, {INFINITY, 0.0}, {NAN, 1.0}};
  for (const auto& entry : table) {
    const auto& [ns, r] = entry;
    CAPTURE(entry.first);  // not `ns`: Clang 14 cannot capture a structured binding
    CHECK(pbr::roughness_from_phong_exponent(ns) == doctest::Approx(r).epsilon(1e-6));
  }
  float last = 2.0f;
  for (float ns = 0.0f; ns <= 4096.0f; ns += 7.0f) {
    const float r = pbr::roughness_from_phong_exponent(ns);
    CHECK(r < last);  // sharper highlights, smoother surface
    CHECK(r >= 0.0f);
    CHECK(r <= 1.0f);
    last = r;
  }
}

TEST_CASE("obj: a missing MTL file is a warning, the faces load without material") {
  TempDir dir;
  const fs::path path = dir.write("nomtl.obj", "mtllib absent.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n");
  const pbr::ObjModel model = pbr::load_obj(path);
  check_model(model);
  CHECK(model.shapes.at(0).material == -1);
  CHECK(any_contains(model.warnings, "absent.mtl"));
}

TEST_CASE("obj: bad files throw LoadError naming the file and the line") {
  TempDir dir;
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  struct Case {
    const char* name;
    std::string text;  // not written when empty
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"missing.obj", "", "no such file"},
      {"binary.obj", std::string("v 0 0 0\n\x7f\x45\x4c\x46\x02\x01\x00\x00junk", 20), ":2: binary data"},
      {"word.obj", "v 1 2 banana\n", ":1: vertex coordinate 'banana' is not a number"},
      {"nan.obj", tri + "v nan 0 0\n", ":4: vertex coordinate 'nan' is not a finite number"},
      {"inf.obj", "v 0 -inf 0\n", ":1: vertex coordinate '-inf' is not a finite number"},
      // tinyobjloader converts a skin-weight joint to int: inf was undefined (fuzz_obj).
      {"vw_inf.obj", tri + "vw 1 1e999 0.5\n", ":4: skin weight value '1e999' is out of range"},
      {"vw_huge.obj", tri + "vw 1 3e9 0.5\n", ":4: skin weight joint '3e9' is not a joint index (a whole number in [0, 2^31))"},
      {"vw_half.obj", tri + "vw 1 0.5 0.5\n", ":4: skin weight joint '0.5' is not a joint index (a whole number in [0, 2^31))"},
      {"msvc.obj", "v 1.#IND 0 0\n", ":1: vertex coordinate '1.#IND' is not a number"},
      {"huge.obj", "v 1e39 0 0\n", ":1: vertex coordinate '1e39' is beyond the float range"},
      {"short.obj", "# two numbers only\nv 1 2\n", ":2: 'v' needs 3 numbers, found 2"},
      {"nan_normal.obj", tri + "vn 0 nan 1\n", ":4: normal coordinate"},
      {"nan_uv.obj", tri + "vt inf 0\n", ":4: texture coordinate"},
      {"range.obj", tri + "f 1 2 4\n", ":4: position index 4 is out of range (3 positions in the file)"},
      {"zero.obj", tri + "f 0 1 2\n", ":4: position index 0 is invalid"},
      {"relative.obj", "f -4 -3 -2\n" + tri, ":1: position index -4 is out of range (0 positions defined before"},
      {"uv_range.obj", tri + "vt 0 0\nf 1/1 2/2 3/1\n", ":5: texture index 2 is out of range"},
      {"not_int.obj", tri + "f 1 2 x\n", ":4: face vertex 'x': position index 'x' is not an integer"},
      {"slashes.obj", tri + "f 1/1/1/1 2 3\n", ":4: face vertex '1/1/1/1' has more than three"},
      {"zero_line.obj", tri + "l 0 1\n", ":4:"},  // tinyobjloader's own error, its line
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const fs::path path = c.text.empty() ? dir.path / c.name : dir.write(c.name, c.text);
    const std::string message = load_error(path);
    CAPTURE(message);
    CHECK(message.rfind(path.string(), 0) == 0);  // starts with the file
    CHECK(contains(message, c.expected));
  }
  CHECK(contains(load_error(dir.path), "is a folder"));
}

TEST_CASE("obj: a normal index out of range only drops that normal, with a warning") {
  TempDir dir;
  const fs::path path = dir.write("badnormal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//7\n");
  const pbr::ObjModel model = pbr::load_obj(path);
  check_model(model);
  for (const pbr::MeshVertex& v : model.shapes.at(0).mesh.vertices) CHECK(v.normal == glm::vec3(0, 0, 1));
  CHECK(any_contains(model.warnings, path.string() + ":5: normal index 7 is out of range"));
}

TEST_CASE("obj: lines, points, unknown keywords and degenerate faces are skipped with warnings") {
  TempDir dir;
  const fs::path path = dir.write("mixed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\ncstype bspline\nf 1 2\nf 1 2 3\n");
  const pbr::ObjModel model = pbr::load_obj(path);
  check_model(model);
  CHECK(triangles(model) == 1);
  CHECK(any_contains(model.warnings, "1 line(s) and 1 point(s) ignored"));
  CHECK(any_contains(model.warnings, ":6: 1 line(s) with unsupported keywords ignored (the first is 'cstype')"));
  CHECK(any_contains(model.warnings, "Degenerated face"));
  const pbr::ObjModel empty = pbr::load_obj(dir.write("empty.obj", ""));
  CHECK(empty.shapes.empty());
}

TEST_CASE("obj: every tinyobjloader edge case loads cleanly or fails with a clear message") {
  const fs::path folder = kShared / "edge-cases";
  if (!fs::is_directory(folder)) {
    MESSAGE("skipped: " << folder.string() << " is absent");
    return;
  }
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(folder))
    if (e.path().extension() == ".obj") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  CHECK(files.size() >= 40);
  // Files that must fail: non-finite coordinates, index 0, indices before the first vertex.
  const std::vector<std::string> must_fail = {"test-nan.obj", "issue-140-zero-face-idx.obj",
                                              "invalid-relative-vertex-index.obj", "invalid-relative-texture-index.obj"};
  std::string loaded, failed;
  std::size_t texture_failures = 0;
  for (const fs::path& path : files) {
    const std::string name = path.filename().string();
    CAPTURE(name);
    const bool should_fail = std::find(must_fail.begin(), must_fail.end(), name) != must_fail.end();
    try {
      // Geometry and material values first: the images these MTL files name are not in
      // tinyobjloader's repository.
      const pbr::ObjModel model = pbr::load_obj(path, {.textures = false});
      check_model(model);
      CHECK(!should_fail);
      loaded += "\n  " + name + ": " + std::to_string(model.shapes.size()) + " shape(s), " +
                std::to_string(triangles(model)) + " triangle(s), " + std::to_string(model.materials.size()) +
                " material(s), " + std::to_string(model.warnings.size()) + " warning(s)";
    } catch (const pbr::LoadError& e) {
      const std::string message = e.what();
      CHECK(contains(message, name));
      CHECK(should_fail);
      failed += "\n  " + message;
      continue;
    }
    // With textures: it loads, or a map fails naming its MTL file and line (a missing image,
    // or -o/-s with fewer than three numbers, which takes the file name for a number).
    try {
      check_model(pbr::load_obj(path));
    } catch (const pbr::LoadError& e) {
      const std::string message = e.what();
      CAPTURE(message);
      CHECK(contains(message, ".mtl:"));
      CHECK((contains(message, ": no such file") || contains(message, ": no image file name after the options")));
      ++texture_failures;
    }
  }
  CHECK(texture_failures >= 5);
  MESSAGE(files.size() << " edge cases: " << std::count(loaded.begin(), loaded.end(), '\n') << " load, "
                       << std::count(failed.begin(), failed.end(), '\n') << " fail (details with -s)");
  INFO("edge cases that load:" << loaded);
  INFO("edge cases that fail:" << failed);
  CHECK(true);  // reports the INFO lines above under -s

  // A few expected values from tinyobjloader's tests (tests/tester.cc).
  const pbr::ObjModel ext = pbr::load_obj(folder / "pbr-mat-ext.obj", {.textures = false});
  REQUIRE(ext.materials.size() == 1);
  CHECK(ext.materials[0].second.roughness == doctest::Approx(0.2f));
  CHECK(ext.materials[0].second.metallic == doctest::Approx(0.3f));
  CHECK(ext.materials[0].second.emissive == glm::vec3(0.1f));
  CHECK(triangles(pbr::load_obj(folder / "issue-295-trianguation-failure.obj")) == 28);
  CHECK(triangles(pbr::load_obj(folder / "invalid-face-definition.obj")) == 0);
  const pbr::ObjModel squares = pbr::load_obj(folder / "smoothing-group-two-squares.obj");
  CHECK(triangles(squares) == 3);
  CHECK(any_contains(squares.warnings, "normal index 1 is out of range"));
  CHECK(pbr::load_obj(folder / "cornell_box_multimaterial.obj").shapes.size() >
        pbr::load_obj(folder / "cornell_box.obj").shapes.size());
}

TEST_CASE("obj: the other shared models load with the triangle counts of SOURCES.md") {
  // The Stanford bunny and armadillo are left out to keep the suite fast.
  const std::vector<std::pair<const char*, std::size_t>> models = {
      {"bob/bob_tri.obj", 10688},
      {"blub/blub_triangulated.obj", 14208},
      {"teapot/teapot.obj", 15704},
      {"cornell-box/CornellBox-Original.obj", 36},
      {"cornell-box/CornellBox-Sphere.obj", 2188},
  };
  for (const auto& entry : models) {
    const auto& [file, expected] = entry;
    const fs::path path = kShared / file;
    CAPTURE(entry.first);  // not `file`: Clang 14 cannot capture a structured binding
    if (!fs::exists(path)) {
      MESSAGE("skipped: " << path.string() << " is absent");
      continue;
    }
    const pbr::ObjModel model = pbr::load_obj(path);
    check_model(model);
    CHECK(triangles(model) == expected);
  }
  const fs::path cornell = kShared / "cornell-box" / "CornellBox-Original.obj";
  if (fs::exists(cornell)) {
    const pbr::ObjModel model = pbr::load_obj(cornell);
    std::map<std::string, pbr::Material> m(model.materials.begin(), model.materials.end());
    REQUIRE(m.count("light") == 1);
    CHECK(m["light"].emissive == glm::vec3(17, 12, 4));  // the only emitter, via Ke
  }
}
