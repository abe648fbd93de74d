// glTF animations, skins and morph targets (docs/design.md, "Animation and deformation"):
// the samplers against their analytic values, small models built here (a .glb in memory)
// sampled, skinned and morphed against values computed independently, hostile files, and
// the Khronos samples of ../shared/gltf (skipped when absent) at chosen moments.
#include "softpbr/golden/doctest_checks.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "gltf/animation.h"
#include "gltf/deform.h"
#include "shared_assets.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/pool.h"
#include "softpbr/raster/raster.h"
#include "synthetic_rig.h"

namespace pbr = softpbr::pbr;
namespace gltf = softpbr::pbr::gltf;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Whether two vectors hold the same bytes (memcmp of an empty vector's null data is
// undefined: UBSan stops there).
template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}


// ---- A .glb made in memory ---------------------------------------------------------

struct Glb {
  json j = json::object();
  std::vector<std::uint8_t> bin;

  // An accessor over new bytes: `type` SCALAR/VEC3/VEC4/MAT4, float components.
  int floats(const std::vector<float>& v, const char* type, std::size_t comps) {
    return add(v.data(), v.size() * 4, type, TINYGLTF_FLOAT, v.size() / comps);
  }
  int u16(const std::vector<std::uint16_t>& v, const char* type, std::size_t comps) {
    return add(v.data(), v.size() * 2, type, TINYGLTF_U16, v.size() / comps);
  }
  static constexpr int TINYGLTF_FLOAT = 5126, TINYGLTF_U16 = 5123;

  int add(const void* data, std::size_t bytes, const char* type, int component, std::size_t count) {
    while (bin.size() % 4) bin.push_back(0);
    const std::size_t offset = bin.size();
    bin.resize(offset + bytes);
    std::memcpy(bin.data() + offset, data, bytes);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    j["accessors"].push_back({{"bufferView", j["bufferViews"].size() - 1},
                              {"componentType", component},
                              {"count", count},
                              {"type", type}});
    return static_cast<int>(j["accessors"].size() - 1);
  }

  std::vector<std::uint8_t> bytes() {
    j["asset"] = {{"version", "2.0"}};
    while (bin.size() % 4) bin.push_back(0);
    j["buffers"] = json::array({{{"byteLength", bin.size()}}});
    std::string text = j.dump();
    while (text.size() % 4) text.push_back(' ');
    std::vector<std::uint8_t> out;
    auto u32 = [&](std::uint32_t x) {
      for (int k = 0; k < 4; ++k) out.push_back(static_cast<std::uint8_t>(x >> (8 * k)));
    };
    u32(0x46546C67);  // "glTF"
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
    u32(static_cast<std::uint32_t>(text.size()));
    u32(0x4E4F534A);  // JSON
    out.insert(out.end(), text.begin(), text.end());
    u32(static_cast<std::uint32_t>(bin.size()));
    u32(0x004E4942);  // BIN
    out.insert(out.end(), bin.begin(), bin.end());
    return out;
  }
};

pbr::GltfScene load(Glb& g, const pbr::GltfOptions& options = {}) {
  const std::vector<std::uint8_t> b = g.bytes();
  return pbr::load_gltf(b, "test.glb", fs::current_path(), options);
}

std::string load_error(Glb g, const pbr::GltfOptions& options = {}) {
  try {
    load(g, options);
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return "(loaded)";
}

// A quad of two triangles (4 vertices, normals +z) as mesh 0, with `extra` attributes.
const std::vector<float> kQuad = {-1, -1, 0.25f, 1, -1, 0.5f, 1, 1, 0.75f, -1, 1, 0.125f};
void add_quad(Glb& g, json attributes = json::object(), json targets = json()) {
  attributes["POSITION"] = g.floats(kQuad, "VEC3", 3);
  attributes["NORMAL"] = g.floats({0, 0, 1, 0, 0, 1, 0.6f, 0, 0.8f, 0, 0, 1}, "VEC3", 3);
  json prim = {{"attributes", attributes}, {"indices", g.u16({0, 1, 2, 0, 2, 3}, "SCALAR", 1)}};
  if (!targets.is_null()) prim["targets"] = targets;
  g.j["meshes"].push_back({{"primitives", json::array({prim})}});
}

// An animation of node 0's `path` by one sampler.
void animate(Glb& g, const char* path, const char* interpolation, const std::vector<float>& times,
             const std::vector<float>& values, const char* type, std::size_t comps) {
  const int in = g.floats(times, "SCALAR", 1), out = g.floats(values, type, comps);
  g.j["animations"].push_back(
      {{"samplers", json::array({{{"input", in}, {"output", out}, {"interpolation", interpolation}}})},
       {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", path}}}}})}});
}

glm::vec3 translation_of(const pbr::Object& o) { return glm::vec3(o.transform[3]); }

// The Hermite curve of glTF 2.0 Appendix C evaluated independently, as the cubic Bézier
// with control points p0, p0 + td·b0/3, p1 − td·a1/3, p1 (de Casteljau).
double bezier(double p0, double b0, double a1, double p1, double td, double u) {
  const double c0 = p0, c1 = p0 + td * b0 / 3.0, c2 = p1 - td * a1 / 3.0, c3 = p1;
  const double d0 = c0 + u * (c1 - c0), d1 = c1 + u * (c2 - c1), d2 = c2 + u * (c3 - c2);
  const double e0 = d0 + u * (d1 - d0), e1 = d1 + u * (d2 - d1);
  return e0 + u * (e1 - e0);
}

}  // namespace

// ---- Samplers --------------------------------------------------------------------------

TEST_CASE("animation samplers: STEP holds, LINEAR is the straight line, both clamp outside the keys") {
  gltf::Curve c;
  c.times = {0.5f, 1.0f, 2.0f};
  c.values = {1, 10, 100, 2, 20, 200, 4, 40, 400};
  c.width = 3;
  struct Row {
    double t;
    double step, linear;
  };
  for (const Row& r : {Row{-3.0, 1, 1}, Row{0.5, 1, 1}, Row{0.75, 1, 1.5}, Row{0.999, 1, 1.998}, Row{1.0, 2, 2},
                       Row{1.5, 2, 3}, Row{2.0, 4, 4}, Row{1e9, 4, 4}}) {
    CAPTURE(r.t);
    double v[3];
    c.interpolation = gltf::Interpolation::Step;
    gltf::sample(c, r.t, false, v);
    CHECK(v[0] == r.step);
    CHECK(v[2] == r.step * 100);
    c.interpolation = gltf::Interpolation::Linear;
    gltf::sample(c, r.t, false, v);
    CHECK(v[0] == doctest::Approx(r.linear).epsilon(1e-15));
    CHECK(v[1] == doctest::Approx(10 * r.linear).epsilon(1e-15));
  }
}

TEST_CASE("animation samplers: CUBICSPLINE matches the Hermite polynomial at the keys and between them") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> any(-3.0f, 3.0f);
  gltf::Curve c;
  c.interpolation = gltf::Interpolation::CubicSpline;
  c.times = {0.0f, 0.25f, 1.0f, 3.5f};
  c.width = 2;
  for (std::size_t i = 0; i < c.times.size() * 3 * c.width; ++i) c.values.push_back(any(rng));
  auto at = [&](std::size_t key, std::size_t group, std::size_t comp) {
    return static_cast<double>(c.values[(3 * key + group) * c.width + comp]);
  };
  for (std::size_t k = 0; k + 1 < c.times.size(); ++k)
    for (double u : {0.0, 0.1, 0.5, 0.77, 0.999}) {
      const double td = static_cast<double>(c.times[k + 1]) - c.times[k];
      const double t = c.times[k] + u * td;
      CAPTURE(t);
      double v[2];
      gltf::sample(c, t, false, v);
      for (std::size_t comp = 0; comp < 2; ++comp) {
        const double want = bezier(at(k, 1, comp), at(k, 2, comp), at(k + 1, 0, comp), at(k + 1, 1, comp), td, u);
        CHECK(v[comp] == doctest::Approx(want).epsilon(1e-12));
      }
    }
  // At a key exactly its value; before the first and after the last, clamped to them.
  double v[2];
  gltf::sample(c, 1.0, false, v);
  CHECK(v[0] == at(2, 1, 0));
  gltf::sample(c, -1.0, false, v);
  CHECK(v[1] == at(0, 1, 1));
  gltf::sample(c, 9.0, false, v);
  CHECK(v[0] == at(3, 1, 0));
}

TEST_CASE("animation samplers: a rotation between two keys is slerp in double, normalised") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> any(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    glm::dquat a = glm::normalize(glm::dquat(any(rng), any(rng), any(rng), any(rng)));
    glm::dquat b = glm::normalize(glm::dquat(any(rng), any(rng), any(rng), any(rng)));
    const double u = (any(rng) + 1.0) / 2.0;
    const glm::dquat q = gltf::slerp(a, b, u);
    // The oracle: the textbook formula with libm's acos and sin (a test may use libm).
    double d = glm::dot(a, b);
    glm::dquat bb = b;
    if (d < 0) d = -d, bb = -b;
    glm::dquat want;
    if (d > 0.9995) {
      want = glm::normalize(a + u * (bb - a));
    } else {
      const double th = std::acos(d);
      want = (std::sin((1 - u) * th) * a + std::sin(u * th) * bb) / std::sin(th);
    }
    CAPTURE(trial);
    CHECK(std::abs(glm::dot(q, q) - 1.0) < 1e-15);
    for (int k = 0; k < 4; ++k) CHECK(q[k] == doctest::Approx(want[k]).epsilon(1e-12));
  }
  // Through a loaded model: a node turned 0 → 90° about z, sampled at 1/3.
  Glb g;
  add_quad(g);
  g.j["nodes"] = json::array({{{"mesh", 0}}});
  const float s = std::sqrt(0.5f);
  animate(g, "rotation", "LINEAR", {0, 3}, {0, 0, 0, 1, 0, 0, s, s}, "VEC4", 4);
  const pbr::GltfScene m = load(g, {.time = 1.0});
  REQUIRE(m.objects.size() == 1);
  // 30°: the x axis goes to (cos 30°, sin 30°).
  CHECK(m.objects[0].transform[0][0] == doctest::Approx(std::cos(M_PI / 6)).epsilon(1e-6));
  CHECK(m.objects[0].transform[0][1] == doctest::Approx(std::sin(M_PI / 6)).epsilon(1e-6));
}

TEST_CASE("animations: a node's translation at a time, the node's own without one, a chosen animation alone") {
  Glb g;
  add_quad(g);
  g.j["nodes"] = json::array({{{"mesh", 0}, {"translation", {5, 0, 0}}}});
  animate(g, "translation", "LINEAR", {0, 2}, {0, 0, 0, 4, 8, 0}, "VEC3", 3);
  animate(g, "translation", "STEP", {0, 1}, {0, -1, 0, 0, -2, 0}, "VEC3", 3);
  g.j["animations"][1]["name"] = "hop";
  CHECK(translation_of(load(g).objects[0]) == glm::vec3(5, 0, 0));
  // Both, in order: the second (STEP) overrides the first on the same target.
  CHECK(translation_of(load(g, {.time = 0.5}).objects[0]) == glm::vec3(0, -1, 0));
  CHECK(translation_of(load(g, {.time = 0.5, .animation = "0"}).objects[0]) == glm::vec3(1, 2, 0));
  CHECK(translation_of(load(g, {.time = 1.5, .animation = "hop"}).objects[0]) == glm::vec3(0, -2, 0));
  CHECK(translation_of(load(g, {.time = 99, .animation = "0"}).objects[0]) == glm::vec3(4, 8, 0));
  const pbr::GltfScene m = load(g);
  REQUIRE(m.animations.size() == 2);
  CHECK(m.animations[0].duration == 2.0);
  CHECK(m.animations[1].name == "hop");
  CHECK(m.animations[1].channels == 1);
  CHECK(load_error(g, {.time = 0.5, .animation = "walk"}) == "test.glb: /animations: no animation is named \"walk\"");
  CHECK(load_error(g, {.time = 0.5, .animation = "2"}) == "test.glb: /animations: the file has 2 animations, no animation 2");
}

// ---- Skins -----------------------------------------------------------------------------

namespace {

// The quad skinned to two joints (nodes 1 and 2): vertices 0, 1 on joint 0, vertices 2, 3
// shared as given by `weights`; the mesh node (0) has a translation the skin ignores.
Glb skinned_quad(const std::vector<float>& weights, const json& joint1 = json::object(),
                 const std::vector<float>& ibm = {}) {
  Glb g;
  json attributes;
  attributes["JOINTS_0"] = g.u16({0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4", 4);
  attributes["WEIGHTS_0"] = g.floats(weights, "VEC4", 4);
  add_quad(g, attributes);
  json skin = {{"joints", {1, 2}}};
  if (!ibm.empty()) skin["inverseBindMatrices"] = g.floats(ibm, "MAT4", 16);
  g.j["skins"] = json::array({skin});
  g.j["nodes"] = json::array({{{"mesh", 0}, {"skin", 0}, {"translation", {7, 7, 7}}}, json::object(), joint1});
  g.j["scenes"] = json::array({{{"nodes", {0, 1, 2}}}});
  return g;
}

const std::vector<float> kOneJoint = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};

}  // namespace

TEST_CASE("skins: joints at rest give the unskinned mesh bit for bit, the skinned node's transform ignored") {
  Glb plain;
  add_quad(plain);
  plain.j["nodes"] = json::array({{{"mesh", 0}}});
  const pbr::GltfScene a = load(plain);
  // Joint 1 at rest: its world (a translation) cancelled by its inverse bind matrix.
  std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -2, 0, 0, 1};
  Glb skinned = skinned_quad({1, 0, 0, 0, 0.5f, 0.25f, 0.25f, 0, 1, 0, 0, 0, 0.25f, 0.75f, 0, 0},
                             {{"translation", {2, 0, 0}}}, ibm);
  const pbr::GltfScene b = load(skinned);
  REQUIRE(a.objects.size() == 1);
  REQUIRE(b.objects.size() == 1);
  CHECK(b.objects[0].transform == glm::mat4(1.0f));
  const pbr::Mesh& ma = *a.objects[0].mesh;
  const pbr::Mesh& mb = *b.objects[0].mesh;
  REQUIRE(ma.vertices.size() == mb.vertices.size());
  CHECK(same_bytes(ma.vertices, mb.vertices));
  CHECK(ma.indices == mb.indices);
  // And so the same image.
  auto render = [](const pbr::GltfScene& g) {
    pbr::Scene s;
    s.objects = g.objects;
    s.camera = pbr::framing_camera(pbr::world_bounds(s.objects), 1.0f, 0.3f, 0.2f);
    s.lights = pbr::default_light_rig(s.camera);
    raster::Renderer r({.threads = 2});
    raster::Target t(64, 64);
    pbr::render(s, r, t);
    return raster::hash_colors(t);
  };
  CHECK(render(a) == render(b));
}

TEST_CASE("skins: vertices move with their joints' matrices, weighted, normals by the inverse transpose") {
  // Joint 1 turned 90° about z and moved to (0, 0, 3); no inverse bind matrices.
  const float s = std::sqrt(0.5f);
  Glb g = skinned_quad({1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0.5f, 1.5f, 0, 0},
                       {{"translation", {0, 0, 3}}, {"rotation", {0, 0, s, s}}});
  const pbr::GltfScene m = load(g, {.time = 0.0});
  REQUIRE(m.objects.size() == 1);
  const pbr::Mesh& mesh = *m.objects[0].mesh;
  glm::dmat4 J1 = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 3)) *
                  glm::mat4_cast(glm::dquat(double(s), 0.0, 0.0, double(s)));
  // Vertex 0: joint 0 (identity): unchanged. Vertex 1: joint 1 alone.
  CHECK(mesh.vertices[0].position == glm::vec3(-1, -1, 0.25f));
  const glm::dvec4 p1 = J1 * glm::dvec4(1, -1, 0.5, 1);
  CHECK(mesh.vertices[1].position.x == doctest::Approx(p1.x).epsilon(1e-6));
  CHECK(mesh.vertices[1].position.y == doctest::Approx(p1.y).epsilon(1e-6));
  CHECK(mesh.vertices[1].position.z == doctest::Approx(p1.z).epsilon(1e-6));
  // Vertex 3: joint 1 weighing 0.5 and joint 0 1.5, normalised to 0.25 and 0.75.
  const glm::dvec4 p3 = 0.75 * glm::dvec4(-1, 1, 0.125, 1) + 0.25 * (J1 * glm::dvec4(-1, 1, 0.125, 1));
  CHECK(mesh.vertices[3].position.x == doctest::Approx(p3.x).epsilon(1e-6));
  CHECK(mesh.vertices[3].position.y == doctest::Approx(p3.y).epsilon(1e-6));
  CHECK(mesh.vertices[3].position.z == doctest::Approx(p3.z).epsilon(1e-6));
  // A rotation's normals turn with it: vertex 2's (0.6, 0, 0.8), on joint 1, becomes
  // (0, 0.6, 0.8); vertex 0's, on joint 0 (identity), stays.
  CHECK(mesh.vertices[0].normal == glm::vec3(0, 0, 1));
  CHECK(mesh.vertices[2].normal.x == doctest::Approx(0.0).epsilon(1e-6));
  CHECK(mesh.vertices[2].normal.y == doctest::Approx(0.6).epsilon(1e-6));
  CHECK(mesh.vertices[2].normal.z == doctest::Approx(0.8).epsilon(1e-6));
}

TEST_CASE("hostile skins: joints and matrices that point nowhere, weights that sum to 0 or are negative") {
  CHECK(load_error((skinned_quad({1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0}))) ==
        "test.glb: /meshes/0/primitives/0/attributes/WEIGHTS_0: vertex 2's weights sum to 0 (every vertex of a skinned "
        "mesh needs a joint)");
  CHECK(load_error((skinned_quad({1, 0, 0, 0, 1, 0, 0, 0, -1, 2, 0, 0, 1, 0, 0, 0}))) ==
        "test.glb: /meshes/0/primitives/0/attributes/WEIGHTS_0: vertex 2 has a weight that is negative or not finite");
  // Joint index 1 of vertex 1 with only one joint in the skin.
  Glb g = skinned_quad({1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
  g.j["skins"][0]["joints"] = {1};
  CHECK(load_error(g) == "test.glb: /meshes/0/primitives/0/attributes/JOINTS_0: vertex 1 names joint 1 of a skin with 1 joints");
  Glb h = skinned_quad(kOneJoint);
  h.j["skins"][0]["inverseBindMatrices"] = h.floats(std::vector<float>(16, 1.0f), "MAT4", 16);
  CHECK(load_error(h) == "test.glb: /skins/0/inverseBindMatrices: has 1 matrices for 2 joints");
  Glb k = skinned_quad(kOneJoint);
  k.j["scenes"][0]["nodes"] = {0, 1};
  CHECK(load_error(k) == "test.glb: /skins/0/joints/1: node 2 is not in the scene");
}

// ---- Morph targets ---------------------------------------------------------------------

namespace {

const std::vector<float> kDelta0 = {0, 0, 1, 0, 0, 2, 0, 0, 3, 0.5f, 0, 0};
const std::vector<float> kDelta1 = {1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0};

Glb morphed_quad() {
  Glb g;
  const int d0 = g.floats(kDelta0, "VEC3", 3), d1 = g.floats(kDelta1, "VEC3", 3);
  add_quad(g, json::object(), json::array({{{"POSITION", d0}}, {{"POSITION", d1}}}));
  g.j["nodes"] = json::array({{{"mesh", 0}}});
  return g;
}

}  // namespace

TEST_CASE("hostile skins: joints and inverse bind matrices that point nowhere, 100 000 joints, a chain deeper than the limit") {
  Glb nowhere = skinned_quad(kOneJoint);
  nowhere.j["skins"][0]["joints"] = {1, 99};
  CHECK(load_error(nowhere) == "test.glb: /skins/0/joints/1: node 99 does not exist (3 nodes)");
  Glb no_matrices = skinned_quad(kOneJoint);
  no_matrices.j["skins"][0]["inverseBindMatrices"] = 99;
  CHECK(load_error(no_matrices).find("test.glb: /skins/0/inverseBindMatrices") == 0);
  // 100 000 joints, children of one root: loaded, the vertices on joint 65 535 moved by it.
  {
    Glb g;
    json attributes;
    attributes["JOINTS_0"] = g.u16({0, 0, 0, 0, 65535, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, "VEC4", 4);
    attributes["WEIGHTS_0"] = g.floats(kOneJoint, "VEC4", 4);
    add_quad(g, attributes);
    constexpr int kJoints = 100000;
    json nodes = json::array({{{"mesh", 0}, {"skin", 0}}, {{"children", json::array()}}});
    json joints = json::array();
    for (int j = 0; j < kJoints; ++j) {
      nodes[1]["children"].push_back(j + 2);
      joints.push_back(j + 2);
      nodes.push_back(j == 65535 ? json{{"translation", {0, 0, 4}}} : json::object());
    }
    g.j["nodes"] = nodes;
    g.j["skins"] = json::array({{{"joints", joints}}});
    g.j["scenes"] = json::array({{{"nodes", {0, 1}}}});
    const pbr::GltfScene s = load(g);
    REQUIRE(s.objects.size() == 1);
    CHECK(s.objects[0].mesh->vertices[0].position == glm::vec3(-1, -1, 0.25f));
    CHECK(s.objects[0].mesh->vertices[1].position == glm::vec3(1, -1, 4.5f));
    // The same joints as a chain: refused at the depth limit, not walked 100 000 deep.
    for (int j = 0; j < kJoints; ++j) g.j["nodes"][j + 1]["children"] = json::array({j + 2});
    g.j["nodes"][kJoints + 1].erase("children");
    CHECK(load_error(g) == "test.glb: /nodes/1026: the node hierarchy is deeper than 1024");
  }
}

TEST_CASE("hostile animations: 10^6 keys sampled quickly and within the memory limit, refused above it") {
  Glb g;
  add_quad(g);
  g.j["nodes"] = json::array({{{"mesh", 0}}});
  constexpr std::size_t kKeys = 1000000;
  std::vector<float> times(kKeys), values(3 * kKeys);
  for (std::size_t k = 0; k < kKeys; ++k) {
    times[k] = static_cast<float>(k) * 0.25f;
    values[3 * k] = static_cast<float>(k % 7);
  }
  animate(g, "translation", "LINEAR", times, values, "VEC3", 3);
  // Halfway between key 400 000 (100 000 s, x = 400 000 mod 7 = 6) and key 400 001 (x = 0).
  const pbr::GltfScene s = load(g, {.time = 100000.125});
  REQUIRE(s.objects.size() == 1);
  CHECK(translation_of(s.objects[0]).x == 3.0f);
  const std::string refused = load_error(g, {.memory_limit = std::uint64_t{8} << 20, .time = 1.0});
  CHECK(refused.find("test.glb: /animations: its samplers' keys need an estimated ") == 0);
  CHECK(refused.find("over the memory limit of 8.0 MiB") != std::string::npos);
}

TEST_CASE("morph targets: weights 0 give the base mesh bit for bit, weight 1 that target's positions") {
  Glb plain;
  add_quad(plain);
  plain.j["nodes"] = json::array({{{"mesh", 0}}});
  const pbr::GltfScene plain_scene = load(plain);
  const pbr::Mesh& base = *plain_scene.objects[0].mesh;
  Glb zero = morphed_quad();
  zero.j["meshes"][0]["weights"] = {0, 0};
  const pbr::GltfScene z = load(zero);
  CHECK(std::memcmp(z.objects[0].mesh->vertices.data(), base.vertices.data(), 4 * sizeof(pbr::MeshVertex)) == 0);
  Glb one = morphed_quad();
  one.j["meshes"][0]["weights"] = {1, 0};
  one.j["nodes"][0]["weights"] = {0, 1};  // the node's weights win over the mesh's
  const pbr::GltfScene o = load(one);
  for (std::size_t v = 0; v < 4; ++v)
    for (int c = 0; c < 3; ++c) CHECK(o.objects[0].mesh->vertices[v].position[c] == kQuad[3 * v + c] + kDelta1[3 * v + c]);
  // Animated weights: LINEAR from (0, 0) to (1, 0.5) over 2 s, at 1 s: (0.5, 0.25).
  Glb anim = morphed_quad();
  animate(anim, "weights", "LINEAR", {0, 2}, {0, 0, 1, 0.5f}, "SCALAR", 1);
  const pbr::GltfScene a = load(anim, {.time = 1.0});
  for (std::size_t v = 0; v < 4; ++v)
    for (int c = 0; c < 3; ++c)
      CHECK(a.objects[0].mesh->vertices[v].position[c] ==
            static_cast<float>(double(kQuad[3 * v + c]) + 0.5 * kDelta0[3 * v + c] + 0.25 * kDelta1[3 * v + c]));
  // Without a time the default weights (none: zeros) give the base mesh back.
  CHECK(std::memcmp(load(anim).objects[0].mesh->vertices.data(), base.vertices.data(), 4 * sizeof(pbr::MeshVertex)) == 0);
}

// ---- Deformation on the pool ---------------------------------------------------------

TEST_CASE("deformation: the same bits at 1, 2 and 8 threads, and each vertex the double-precision blend within float rounding") {
  for (const bool flat : {false, true}) {
    CAPTURE(flat);
    // 40 blocks of 4096 vertices, tangents, a vertex → accessor map that reverses.
    const std::unique_ptr<softpbr::testing::SyntheticRig> rig = softpbr::testing::synthetic_rig(40 * 4096 + 7, 37, true, true);
    rig->deformation.flat = flat;
    const pbr::Mesh one = gltf::deform(rig->base, rig->deformation, nullptr);
    for (unsigned threads : {2u, 8u}) {
      CAPTURE(threads);
      raster::ThreadPool pool(threads);
      pbr::Mesh out = rig->base;
      gltf::deform(rig->base, rig->deformation, out, &pool);
      CHECK(same_bytes(out.vertices, one.vertices));
      CHECK(same_bytes(out.tangents, one.tangents));
      // Deforming again into the deformed mesh gives the same (only base is read).
      gltf::deform(rig->base, rig->deformation, out, &pool);
      CHECK(same_bytes(out.vertices, one.vertices));
    }
    // The oracle: morphed and skinned in double from the same palette, Σ wⱼ·(Pⱼ·p).
    const gltf::SkinInfluences& k = rig->skin;
    const gltf::MorphTarget& target = rig->deformation.targets[0];
    int worst = 0;
    for (std::size_t i = 0; i < one.vertices.size(); i += 997) {
      const std::size_t s = rig->sources[i];
      glm::dvec3 p(rig->base.vertices[i].position), n(rig->base.vertices[i].normal);
      for (int c = 0; c < 3; ++c) p[c] += 0.5 * target.position[3 * s + static_cast<std::size_t>(c)];
      if (!flat)
        for (int c = 0; c < 3; ++c) n[c] += 0.5 * target.normal[3 * s + static_cast<std::size_t>(c)];
      else
        n = glm::dvec3(0.0);  // flat: made from the morphed triangle, not checked here
      glm::dvec3 q(0.0), m(0.0);
      for (std::size_t j = 0; j < 4; ++j) {
        const double w = k.weights[4 * s + j];
        const gltf::JointMatrix& P = rig->palette[k.joints[4 * s + j]];
        for (std::size_t r = 0; r < 3; ++r) {
          q[static_cast<int>(r)] += w * (P[4 * r] * p.x + P[4 * r + 1] * p.y + P[4 * r + 2] * p.z + P[4 * r + 3]);
          m[static_cast<int>(r)] += w * (P[12 + 3 * r] * n.x + P[12 + 3 * r + 1] * n.y + P[12 + 3 * r + 2] * n.z);
        }
      }
      for (int c = 0; c < 3; ++c) {
        const bool near_p = std::abs(one.vertices[i].position[c] - q[c]) <= 1e-5 * (1.0 + std::abs(q[c]));
        const bool near_n = flat || std::abs(one.vertices[i].normal[c] - m[c]) <= 1e-5 * (1.0 + std::abs(m[c]));
        if (!near_p || !near_n) ++worst;
      }
    }
    CHECK(worst == 0);
  }
}

TEST_CASE("hostile animations: NaN keys, decreasing times, wrong counts, missing samplers, each one line with its pointer") {
  {
    Glb g;
    add_quad(g);
    g.j["nodes"] = json::array({{{"mesh", 0}}});
    animate(g, "translation", "LINEAR", {0, 2, 1}, std::vector<float>(9, 0.0f), "VEC3", 3);
    CHECK(load_error(g, {.time = 1}) == "test.glb: /accessors/3: key times must increase strictly: key 2 (1.000000) follows 2.000000");
  }
  {
    Glb g;
    add_quad(g);
    g.j["nodes"] = json::array({{{"mesh", 0}}});
    animate(g, "translation", "LINEAR", {0, NAN}, std::vector<float>(6, 0.0f), "VEC3", 3);
    CHECK(load_error(g, {.time = 1}) == "test.glb: /accessors/3: key time 1 is not finite");
  }
  {
    Glb g;
    add_quad(g);
    g.j["nodes"] = json::array({{{"mesh", 0}}});
    animate(g, "translation", "CUBICSPLINE", {0, 1}, std::vector<float>(6, 0.0f), "VEC3", 3);
    CHECK(load_error(g, {.time = 1}) ==
          "test.glb: /animations/0/samplers/0/output: has 2 elements; 2 keys × 3 (CUBICSPLINE) need 6");
  }
  {
    Glb g;
    add_quad(g);
    g.j["nodes"] = json::array({{{"mesh", 0}}});
    animate(g, "scale", "LINEAR", {0, 1}, {1, 1, 1, NAN, 1, 1}, "VEC3", 3);
    CHECK(load_error(g, {.time = 1}) == "test.glb: /accessors/4: holds a value that is not finite");
  }
  {
    Glb g = morphed_quad();
    animate(g, "weights", "LINEAR", {0, 1}, {0, 1, 0}, "SCALAR", 1);
    CHECK(load_error(g, {.time = 1}) ==
          "test.glb: /animations/0/samplers/0/output: has 3 elements; 2 keys × 2 morph targets need 4");
  }
}

// ---- The Khronos samples -------------------------------------------------------------

namespace {

fs::path sample_file(const std::string& name) {
  const fs::path folder = shared_assets::folder() / "gltf" / name;
  for (const char* sub : {"glTF-Binary", "glTF"}) {
    if (!fs::is_directory(folder / sub)) continue;
    for (const auto& e : fs::directory_iterator(folder / sub))
      if (e.path().extension() == ".glb" || e.path().extension() == ".gltf") return e.path();
  }
  return {};
}

}  // namespace

TEST_CASE("InterpolationTest: each cube at known times against its sampler's analytic value") {
  const fs::path file = sample_file("InterpolationTest");
  if (file.empty()) {
    MESSAGE("skipped: InterpolationTest is absent");
    return;
  }
  // The objects in the scene's order: node 0 (Step Scale), 3 (Linear Scale), ..., 10
  // (Linear Translation); the keys are read from the file (python: see its accessors 56/57).
  auto at = [&](double t, const std::string& animation) {
    return pbr::load_gltf(file, {.time = t, .animation = animation});
  };
  auto find = [](const pbr::GltfScene& g, float x, float y) -> const pbr::Object* {
    // The cube whose rest position is (x, y) in the layout's 3 × 3 grid.
    for (const pbr::Object& o : g.objects)
      if (std::abs(o.transform[3][0] - x) < 0.5f && std::abs(o.transform[3][1] - y) < 2.5f) return &o;
    return nullptr;
  };
  // Linear Translation (node 10 at x ≈ −3.3): y from 6.621 at 0 to 10 at 0.41667.
  {
    const pbr::GltfScene g = at(0.2, "Linear Translation");
    const pbr::Object* o = find(g, -3.2975807f, 8.0f);
    REQUIRE(o != nullptr);
    const double u = 0.2 / 0.4166666567325592;
    CHECK(o->transform[3][1] == doctest::Approx(6.621014595031738 + u * (10.0 - 6.621014595031738)).epsilon(1e-6));
  }
  // Step Translation (node 8 at x = 0): 6.665 until 0.4583, then 10 until 0.8333.
  for (const auto& [t, y] : {std::pair{0.45, 6.665226459503174}, std::pair{0.46, 10.0}, std::pair{0.84, 6.0}}) {
    const pbr::GltfScene g = at(t, "Step Translation");
    const pbr::Object* o = find(g, 0.0f, 8.0f);
    REQUIRE(o != nullptr);
    CHECK(o->transform[3][1] == doctest::Approx(y).epsilon(1e-6));
  }
  // CubicSpline Translation (node 9 at x ≈ 3.3): zero tangents, so between keys 6.640 →
  // 10 the smoothstep 3u² − 2u³.
  {
    const double t = 0.1, u = t / 0.4166666567325592;
    const pbr::GltfScene g = at(t, "CubicSpline Translation");
    const pbr::Object* o = find(g, 3.3051798f, 8.0f);
    REQUIRE(o != nullptr);
    const double h = 3 * u * u - 2 * u * u * u;
    CHECK(o->transform[3][1] == doctest::Approx(6.640117168426514 + h * (10.0 - 6.640117168426514)).epsilon(1e-6));
  }
  // Linear Scale (node 3): 1 → 0.5 between keys 0.04167 and 0.41667.
  {
    const double t = 0.3, u = (t - 0.0416666679084301) / (0.4166666567325592 - 0.0416666679084301);
    const pbr::GltfScene g = at(t, "Linear Scale");
    const pbr::Object* o = find(g, -3.2963297f, 0.0f);
    REQUIRE(o != nullptr);
    CHECK(o->transform[0][0] == doctest::Approx(1.0 + u * (0.5 - 1.0)).epsilon(1e-6));
  }
  const pbr::GltfScene all = pbr::load_gltf(file);
  CHECK(all.animations.size() == 9);
}

namespace {

// "" when a and b place the same things with the same bits (objects' transforms, meshes'
// vertices and tangents, materials' base colours; cameras; lights), else the first difference.
std::string difference(const pbr::GltfScene& a, const pbr::GltfScene& b) {
  if (a.objects.size() != b.objects.size()) return "object counts";
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    const pbr::Object& x = a.objects[i];
    const pbr::Object& y = b.objects[i];
    const std::string at = "object " + std::to_string(i) + ": ";
    if (std::memcmp(&x.transform, &y.transform, sizeof(glm::mat4)) != 0) return at + "transform";
    if (x.mesh->vertices.size() != y.mesh->vertices.size() || x.mesh->tangents.size() != y.mesh->tangents.size())
      return at + "vertex counts";
    if (!same_bytes(x.mesh->vertices, y.mesh->vertices)) return at + "vertices";
    if (!same_bytes(x.mesh->tangents, y.mesh->tangents)) return at + "tangents";
    if (x.mesh->indices != y.mesh->indices) return at + "indices";
    if (x.material.base_color != y.material.base_color) return at + "material";
  }
  if (a.cameras.size() != b.cameras.size() || a.lights.size() != b.lights.size()) return "camera or light counts";
  for (std::size_t i = 0; i < a.cameras.size(); ++i)
    if (a.cameras[i].camera.position != b.cameras[i].camera.position || a.cameras[i].camera.target != b.cameras[i].camera.target ||
        a.cameras[i].camera.up != b.cameras[i].camera.up)
      return "camera " + std::to_string(i);
  for (std::size_t i = 0; i < a.lights.size(); ++i)
    if (a.lights[i].position != b.lights[i].position || a.lights[i].direction != b.lights[i].direction)
      return "light " + std::to_string(i);
  return "";
}

}  // namespace

TEST_CASE("a poseable scene posed at another moment equals the model loaded at that moment, bit for bit") {
  struct Case {
    std::string sample;
    std::optional<double> time;
    std::string animation;
  };
  const std::vector<Case> cases = {{"Fox", 1.3, ""},          {"Fox", 0.45, "Run"},      {"Fox", std::nullopt, ""},
                                   {"AnimatedMorphCube", 0.7, ""}, {"InterpolationTest", 1.25, ""},
                                   {"RiggedFigure", 0.9, "0"},   {"SimpleSkin", 2.5, ""}};
  std::map<std::string, pbr::GltfScene> posed;
  raster::ThreadPool pool(2);
  for (const Case& c : cases) {
    const fs::path file = sample_file(c.sample);
    if (file.empty()) {
      MESSAGE("skipped: " << c.sample << " is absent");
      continue;
    }
    CAPTURE(c.sample);
    CAPTURE(c.animation);
    CAPTURE(c.time.value_or(-1.0));
    // Loaded once (at 0.2 s), then posed again for each case.
    auto it = posed.find(c.sample);
    if (it == posed.end()) it = posed.emplace(c.sample, pbr::load_gltf(file, {.time = 0.2, .poseable = true})).first;
    pbr::GltfScene& scene = it->second;
    REQUIRE(scene.poser != nullptr);
    scene.pose(c.time, c.animation, &pool);
    const pbr::GltfScene loaded = pbr::load_gltf(file, {.time = c.time, .animation = c.animation});
    CHECK(difference(scene, loaded) == "");
    // The moment matters (a check that can fail): the loaded pose at 0.2 s differs.
    if (c.time && c.sample != "SimpleSkin")
      CHECK(difference(scene, pbr::load_gltf(file, {.time = 0.2, .animation = c.animation})) != "");
  }
  // A morphed quad made here (no shared files needed): weights animated, posed back and forth.
  Glb anim = morphed_quad();
  animate(anim, "weights", "LINEAR", {0, 2}, {0, 0, 1, 0.5f}, "SCALAR", 1);
  pbr::GltfScene scene = load(anim, {.poseable = true});
  for (const double t : {1.0, 0.0, 1.5, 1.0}) {
    CAPTURE(t);
    scene.pose(t);
    CHECK(difference(scene, load(anim, {.time = t})) == "");
  }
  // What the pose reads is checked as loading checks it; a scene not loaded poseable says so.
  std::string error;
  try {
    scene.pose(1.0, "nope");
  } catch (const pbr::LoadError& e) {
    error = e.what();
  }
  CHECK(error == "test.glb: /animations: no animation is named \"nope\"");
  pbr::GltfScene fixed = load(anim);
  CHECK(fixed.poser == nullptr);
  CHECK_THROWS_AS(fixed.pose(1.0), std::logic_error);
}

TEST_CASE("scenes: the file's default scene, another by index or by name, an unknown one an error listing them") {
  Glb g;
  add_quad(g);
  g.j["nodes"] = json::array({{{"mesh", 0}}, {{"mesh", 0}, {"translation", {5, 0, 0}}}});
  g.j["scenes"] = json::array({{{"name", "left"}, {"nodes", {0}}}, {{"name", "right"}, {"nodes", {1}}}});
  g.j["scene"] = 1;
  auto x_of = [&g](const std::string& name) {
    const pbr::GltfScene s = load(g, {.scene_name = name});
    return s.objects.size() == 1 ? translation_of(s.objects[0]).x : -1.0f;
  };
  CHECK(x_of("") == 5.0f);  // the file's "scene"
  CHECK(x_of("left") == 0.0f);
  CHECK(x_of("0") == 0.0f);
  CHECK(x_of("right") == 5.0f);
  CHECK(load_error(g, {.scene_name = "nope"}) == "test.glb: /scenes: no scene \"nope\" (the scenes: 0 \"left\", 1 \"right\")");
  CHECK(load_error(g, {.scene_name = "7"}) == "test.glb: /scenes: no scene 7 (the scenes: 0 \"left\", 1 \"right\")");
  // A scene named like an index is found by its name first.
  g.j["scenes"][1]["name"] = "0";
  CHECK(x_of("0") == 5.0f);
  // The Khronos sample: scene 1 (the default) a square, scene 0 a triangle.
  const fs::path file = sample_file("MultipleScenes");
  if (file.empty()) {
    MESSAGE("skipped: MultipleScenes is absent");
    return;
  }
  CHECK(pbr::load_gltf(file).triangles == 2);
  CHECK(pbr::load_gltf(file, {.scene_name = "0"}).triangles == 1);
  CHECK(pbr::load_gltf(file, {.scene_name = "1"}).triangles == 2);
}

TEST_CASE("EXT_mesh_gpu_instancing: one object a instance at world × T·R·S, counted before it is built, bad attributes refused") {
  auto instanced = [](std::size_t count, bool with_scale) {
    Glb g;
    add_quad(g);
    std::vector<float> t, s;
    for (std::size_t i = 0; i < count; ++i) {
      t.insert(t.end(), {static_cast<float>(i), 0.0f, 0.0f});
      s.insert(s.end(), {1.0f, 2.0f, 1.0f});
    }
    json attributes = {{"TRANSLATION", g.floats(t, "VEC3", 3)}};
    if (with_scale) attributes["SCALE"] = g.floats(s, "VEC3", 3);
    g.j["nodes"] = json::array({{{"mesh", 0}, {"translation", {0, 0, 10}},
                                 {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}}}}});
    g.j["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
    g.j["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
    return g;
  };
  Glb three = instanced(3, true);
  const pbr::GltfScene s = load(three);
  REQUIRE(s.objects.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) {
    CAPTURE(i);
    CHECK(translation_of(s.objects[i]) == glm::vec3(static_cast<float>(i), 0.0f, 10.0f));
    CHECK(s.objects[i].transform[1][1] == 2.0f);
    CHECK(s.objects[i].mesh == s.objects[0].mesh);  // one mesh, shared
  }
  CHECK(s.warnings.empty());
  // Counted before anything is built: 100 000 instances against a 16 MiB limit.
  const std::string big = load_error(instanced(100000, false), {.memory_limit = std::uint64_t{16} << 20});
  CHECK(big.find("test.glb: /nodes: its nodes place 100000 mesh instances") == 0);
  CHECK(big.find("(counted before any mesh is built)") != std::string::npos);
  // Attributes of different counts; a NaN; no attribute at all.
  Glb uneven = instanced(3, true);
  uneven.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"] = uneven.floats({1, 1, 1}, "VEC3", 3);
  CHECK(load_error(uneven) == "test.glb: /nodes/0/extensions/EXT_mesh_gpu_instancing/attributes/SCALE: has 1 instances; the other attributes have 3");
  Glb nan = instanced(3, false);
  nan.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] =
      nan.floats({0, 0, 0, std::nanf(""), 0, 0}, "VEC3", 3);
  CHECK(load_error(nan) == "test.glb: /accessors/4: holds a value that is not finite");
  Glb none = instanced(3, false);
  none.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = json::object();
  CHECK(load_error(none) ==
        "test.glb: /nodes/0/extensions/EXT_mesh_gpu_instancing/attributes: must be an object naming TRANSLATION, ROTATION or SCALE accessors");
  // The Khronos sample: 125 instances of one cube, each turned and scaled.
  const fs::path file = sample_file("SimpleInstancing");
  if (file.empty()) {
    MESSAGE("skipped: SimpleInstancing is absent");
    return;
  }
  const pbr::GltfScene cubes = pbr::load_gltf(file);
  CHECK(cubes.objects.size() == 125);
  CHECK(cubes.warnings.empty());
}

TEST_CASE("animated samples render with the same bits twice and with 1 and 8 threads") {
  // Not structured bindings: clang 14 cannot capture them in CAPTURE's lambda.
  for (const auto& sample : {std::pair{std::string("Fox"), 1.0}, std::pair{std::string("AnimatedMorphCube"), 0.5},
                             std::pair{std::string("RiggedFigure"), 0.4}}) {
    const std::string& name = sample.first;
    const double t = sample.second;
    const fs::path file = sample_file(name);
    if (file.empty()) {
      MESSAGE("skipped: " << name << " is absent");
      continue;
    }
    CAPTURE(name);
    std::uint64_t first = 0;
    for (unsigned threads : {1u, 8u, 8u}) {
      raster::Renderer renderer({.threads = threads, .tile_size = threads == 1 ? 64 : 16});
      const pbr::GltfScene g = pbr::load_gltf(file, {.pool = &renderer.pool(), .time = t});
      pbr::Scene s;
      s.objects = g.objects;
      s.camera = pbr::framing_camera(pbr::world_bounds(s.objects), 1.0f);
      s.lights = pbr::default_light_rig(s.camera);
      raster::Target target(96, 96);
      pbr::render(s, renderer, target);
      const std::uint64_t h = raster::hash_colors(target);
      if (threads == 1) first = h;
      CHECK(h == first);
    }
    // And the moment matters: another time gives another image.
    raster::Renderer renderer({.threads = 2});
    const pbr::GltfScene g = pbr::load_gltf(file, {.pool = &renderer.pool(), .time = t + 0.3});
    pbr::Scene s;
    s.objects = g.objects;
    s.camera = pbr::framing_camera(pbr::world_bounds(pbr::load_gltf(file, {.time = t}).objects), 1.0f);
    s.lights = pbr::default_light_rig(s.camera);
    raster::Target target(96, 96);
    pbr::render(s, renderer, target);
    CHECK(raster::hash_colors(target) != first);
  }
}

TEST_CASE("golden animated glTF renders: Fox walking at 1 s, SimpleSkin at 1 s, AnimatedMorphCube at 1.5 s") {
  // Compared by eye with the Khronos screenshots before committing (see the commit).
  struct Case {
    const char* name;
    double time;
    const char* animation;
  };
  for (const Case& c : {Case{"Fox", 1.0, "Walk"}, Case{"SimpleSkin", 1.0, ""}, Case{"AnimatedMorphCube", 1.5, ""}}) {
    const fs::path file = sample_file(c.name);
    if (file.empty()) {
      MESSAGE("skipped: " << c.name << " is absent");
      continue;
    }
    CAPTURE(c.name);
    raster::Renderer renderer({.threads = 0});
    const pbr::GltfScene g = pbr::load_gltf(file, {.pool = &renderer.pool(), .time = c.time, .animation = c.animation});
    pbr::Scene s;
    s.objects = g.objects;
    s.camera = pbr::framing_camera(pbr::world_bounds(s.objects), 320.0f / 240.0f, 0.5f, 0.25f);
    s.lights = pbr::default_light_rig(s.camera);
    s.ambient = glm::vec3(pbr::kDefaultAmbient);
    s.background = {0.05f, 0.05f, 0.06f, 1.0f};
    raster::Target t(320, 240);
    pbr::render(s, renderer, t);
    CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, pbr::OutputSettings{}), std::string("goldens/gltf_anim_") + c.name);
  }
}

TEST_CASE("scene files: a glTF mesh's time and animation keys pose the model as --time and --animation do") {
  Glb g;
  add_quad(g);
  g.j["nodes"] = json::array({{{"mesh", 0}}});
  animate(g, "translation", "LINEAR", {0, 2}, {0, 0, 0, 4, 0, 0}, "VEC3", 3);
  g.j["animations"][0]["name"] = "slide";
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "gltf_animation";
  fs::create_directories(dir);
  {
    const std::vector<std::uint8_t> bytes = g.bytes();
    std::ofstream(dir / "slide.glb", std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                            static_cast<std::streamsize>(bytes.size()));
  }
  auto first_x = [&](const std::string& keys) {
    const std::string text = R"({"objects": [{"mesh": {"file": "slide.glb")" + keys + "}}]}";
    const pbr::SceneFile f = pbr::parse_scene_file(text, "t.json", dir);
    REQUIRE(!f.scene.objects.empty());
    return f.scene.objects[0].mesh->vertices[0].position.x;  // node transforms are baked in
  };
  CHECK(first_x("") == -1.0f);
  CHECK(first_x(R"(, "time": 1)") == 1.0f);
  CHECK(first_x(R"(, "time": 1, "animation": "slide")") == 1.0f);
  CHECK(first_x(R"(, "time": 1.5, "animation": 0)") == 2.0f);
  CHECK_THROWS_WITH_AS(first_x(R"(, "time": 1, "animation": "run")"),
                       doctest::Contains("/objects/0/mesh/file: "), pbr::SceneFileError);
}
