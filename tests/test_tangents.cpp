// MikkTSpace tangents (generate_tangents) and the optional vertex streams: analytic tangents
// on a UV sphere, glTF's handedness on a plane and a cube, mirrored UVs splitting vertices,
// angle weighting, degenerate triangles, welding, determinism, and stream length checks.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/geometric.hpp>

#include "softpbr/loaders/obj.h"
#include "softpbr/pbr/mesh.h"

namespace pbr = softpbr::pbr;

namespace {

constexpr double kPi = 3.141592653589793;

double degrees_between(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * 180.0 / kPi;
}

glm::dvec3 xyz(const glm::vec4& t) { return {t.x, t.y, t.z}; }

// One tangent per vertex, finite, unit, perpendicular to a non-zero normal, w = ±1.
void check_frames(const pbr::Mesh& m) {
  REQUIRE(m.tangents.size() == m.vertices.size());
  int bad_finite = 0, bad_length = 0, bad_orthogonal = 0, bad_w = 0;
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const glm::vec4 t = m.tangents[i];
    const glm::dvec3 n(m.vertices[i].normal);
    const bool finite = std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z) && std::isfinite(t.w);
    bad_finite += !finite;
    bad_length += !(std::fabs(glm::length(xyz(t)) - 1.0) < 1e-6);
    if (glm::length(n) > 0.5) bad_orthogonal += !(std::fabs(glm::dot(xyz(t), glm::normalize(n))) < 1e-6);
    bad_w += !(t.w == 1.0f || t.w == -1.0f);
  }
  CHECK(bad_finite == 0);
  CHECK(bad_length == 0);
  CHECK(bad_orthogonal == 0);
  CHECK(bad_w == 0);
}

bool same_bits(const pbr::Mesh& a, const pbr::Mesh& b) {
  auto eq = [](const auto& x, const auto& y) {
    return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
  };
  return eq(a.vertices, b.vertices) && eq(a.indices, b.indices) && eq(a.tangents, b.tangents) && eq(a.uv1, b.uv1) &&
         eq(a.colors, b.colors);
}

// A strip in y = 0 facing +y along x ∈ [−1, 1], z ∈ [0, 1], `half` quads on each side of
// x = 0, wound as plane() (counter-clockwise from +y). u = |x|: the left half's UVs are a
// mirror image of the right half's, and the two vertices at x = 0 (u = 0) are shared.
pbr::Mesh mirrored_strip(int half) {
  pbr::Mesh m;
  const int columns = 2 * half + 1;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i < columns; ++i) {
      const float x = static_cast<float>(i - half) / static_cast<float>(half);
      m.vertices.push_back({{x, 0.0f, static_cast<float>(j)}, {0.0f, 1.0f, 0.0f}, {std::fabs(x), static_cast<float>(j)}});
    }
  const auto row = static_cast<std::uint32_t>(columns);
  for (std::uint32_t i = 0; i + 1 < row; ++i) {
    const std::uint32_t a = i, b = i + 1, c = i + row, d = c + 1;
    m.indices.insert(m.indices.end(), {a, c, d, a, d, b});
  }
  return m;
}

// The same triangles with three vertices of their own each.
pbr::Mesh triangle_soup(const pbr::Mesh& m) {
  pbr::Mesh soup;
  for (std::uint32_t i : m.indices) {
    soup.indices.push_back(static_cast<std::uint32_t>(soup.vertices.size()));
    soup.vertices.push_back(m.vertices[i]);
  }
  return soup;
}

std::string thrown_message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST_CASE("tangents: a UV sphere's tangents follow dp/du with the handedness of its unmirrored map") {
  pbr::Mesh m = pbr::uv_sphere(1.0f, 128, 64);
  const std::size_t vertex_count = m.vertices.size();
  pbr::generate_tangents(m);
  check_frames(m);
  CHECK(m.vertices.size() == vertex_count);  // no mirrored faces: nothing is split
  double worst_inside = 0.0, worst_seam = 0.0;
  int bad_w = 0, checked = 0;
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const pbr::MeshVertex& v = m.vertices[i];
    // uv_sphere: p = (sin θ sin φ, cos θ, sin θ cos φ) with φ = 2π u, θ = π v.
    const double phi = 2.0 * kPi * v.uv.x, theta = kPi * v.uv.y;
    if (theta < kPi / 18 || theta > kPi - kPi / 18) continue;  // 10° from a pole
    const glm::dvec3 dp_du(std::cos(phi), 0.0, -std::sin(phi));  // ∂p/∂φ / sin θ
    const glm::dvec3 dp_dv(std::cos(theta) * std::sin(phi), -std::sin(theta), std::cos(theta) * std::cos(phi));
    const glm::dvec3 n(v.normal);
    // glTF: the bitangent points up the image, along −∂p/∂v (v = 0 is the image's top).
    const float w = glm::dot(glm::cross(n, dp_du), -dp_dv) > 0.0 ? 1.0f : -1.0f;
    bad_w += m.tangents[i].w != w || w != 1.0f;
    const double err = degrees_between(xyz(m.tangents[i]), dp_du);
    const bool seam = v.uv.x == 0.0f || v.uv.x == 1.0f;
    (seam ? worst_seam : worst_inside) = std::max(seam ? worst_seam : worst_inside, err);
    ++checked;
  }
  INFO("worst angle to dp/du: " << worst_inside << "° inside, " << worst_seam << "° on the seam");
  CHECK(checked > 100 * 50);
  CHECK(bad_w == 0);
  // Inside, the faces around a vertex are symmetric about its meridian: their chords' tilts
  // cancel in the angle-weighted sum.
  CHECK(worst_inside < 0.001);
  // The seam's u = 0 and u = 1 vertices differ in uv, so (as in MikkTSpace) they are not
  // welded and each sees only the faces on its side: their chords run half a segment
  // (360°/128/2 = 1.40625°) off ∂p/∂u, tilted out of the tangent plane by that times cos θ.
  CHECK(worst_seam < 1.40625);
  CHECK(worst_seam > 1.0);
}

TEST_CASE("tangents: plane() gets tangent +x and w = +1, its bitangent pointing up the glTF image") {
  // Convention verified: glTF's. UV (0, 0) is the image's top left, so v grows down the
  // image, and a normal texture's +Y is up the image: the bitangent w·cross(n, t) must point
  // along −∂p/∂v. plane(): n = +y, u along +x (t = +x), v along +z. cross(+y, +x) = −z =
  // −∂p/∂v, so w = +1; the plane seen from +y shows the image unmirrored (x right, z down).
  pbr::Mesh m = pbr::plane(2.0f, 3.0f, 4);
  pbr::generate_tangents(m);
  check_frames(m);
  REQUIRE(m.vertices.size() == 25);
  int bad_tangent = 0, bad_w = 0, bad_bitangent = 0;
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const glm::vec4 t = m.tangents[i];
    bad_tangent += !(glm::length(xyz(t) - glm::dvec3(1.0, 0.0, 0.0)) < 1e-6);
    bad_w += t.w != 1.0f;
    const glm::dvec3 b = static_cast<double>(t.w) * glm::cross(glm::dvec3(m.vertices[i].normal), xyz(t));
    bad_bitangent += !(glm::length(b - glm::dvec3(0.0, 0.0, -1.0)) < 1e-6);
  }
  CHECK(bad_tangent == 0);
  CHECK(bad_w == 0);
  CHECK(bad_bitangent == 0);
}

TEST_CASE("tangents: cube() faces, upright images seen from outside, get w = +1 and bitangents up") {
  // cube(): each side face shows the texture upright (v = 0 at the top, +y), the top face
  // with its top towards −z and the bottom face towards +z (mesh.h, mesh.cpp).
  pbr::Mesh m = pbr::cube(2.0f);
  pbr::generate_tangents(m);
  check_frames(m);
  CHECK(m.vertices.size() == 24);  // faces do not share vertices: nothing to split
  int bad_w = 0, bad_up = 0;
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const glm::dvec3 n(m.vertices[i].normal), t = xyz(m.tangents[i]);
    bad_w += m.tangents[i].w != 1.0f;
    const glm::dvec3 b = static_cast<double>(m.tangents[i].w) * glm::cross(n, t);
    const glm::dvec3 up = n.y > 0.5 ? glm::dvec3(0, 0, -1) : n.y < -0.5 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    bad_up += !(glm::length(b - up) < 1e-6);
  }
  CHECK(bad_w == 0);
  CHECK(bad_up == 0);
}

TEST_CASE("tangents: mirrored UVs give opposite w and split the vertices the two halves share") {
  pbr::Mesh m = mirrored_strip(2);
  const pbr::Mesh before = m;
  // Streams to be carried into the copies: a different value per vertex.
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    m.uv1.push_back({static_cast<float>(i), 0.5f});
    m.colors.push_back({0.1f * static_cast<float>(i), 0.0f, 1.0f, 1.0f});
  }
  const std::vector<glm::vec2> uv1_before = m.uv1;
  const std::vector<glm::vec4> colors_before = m.colors;
  pbr::generate_tangents(m);
  check_frames(m);
  CHECK(m.vertices.size() == before.vertices.size() + 2);  // the two vertices at x = 0
  REQUIRE(m.indices.size() == before.indices.size());
  REQUIRE(m.uv1.size() == m.vertices.size());
  REQUIRE(m.colors.size() == m.vertices.size());
  // The first vertices are untouched; every corner still sees the vertex it had (position,
  // normal, uv and the other streams), through its new index.
  CHECK(std::memcmp(m.vertices.data(), before.vertices.data(), before.vertices.size() * sizeof(pbr::MeshVertex)) == 0);
  int moved = 0, rewritten = 0, bad_side = 0;
  for (std::size_t c = 0; c < m.indices.size(); ++c) {
    const std::uint32_t was = before.indices[c], now = m.indices[c];
    rewritten += was != now;
    moved += std::memcmp(&m.vertices[now], &before.vertices[was], sizeof(pbr::MeshVertex)) != 0 ||
             m.uv1[now] != uv1_before[was] || m.colors[now] != colors_before[was];
    // Triangle t lies left of x = 0 for the first 2·half quads' triangles.
    const bool left = c / 3 < 4;
    const glm::vec4 t = m.tangents[now];
    // Right: u along +x, unmirrored as plane(): (+1, 0, 0, +1). Left: u along −x, mirrored:
    // the bitangent still points along −∂p/∂v = −z, so w·cross(+y, −x) = w·(+z) = −z, w = −1.
    const glm::vec4 expected = left ? glm::vec4(-1, 0, 0, -1) : glm::vec4(1, 0, 0, 1);
    bad_side += !(glm::length(xyz(t) - xyz(expected)) < 1e-6 && t.w == expected.w);
  }
  CHECK(moved == 0);
  CHECK(rewritten > 0);
  CHECK(bad_side == 0);
}

TEST_CASE("tangents: a corner's tangent is the angle-weighted sum of its faces' projected tangents") {
  // Two faces around O (normal +y) with the same UV orientation and different tangents:
  // face 1 (90° at O) has tangent +x, face 2 (45° at O) (1, 0, −1)/√2, from UVs that do not
  // come from one affine map.
  pbr::Mesh m;
  const glm::vec3 up(0, 1, 0);
  m.vertices = {{{0, 0, 0}, up, {0, 0}}, {{1, 0, 0}, up, {1, 0}}, {{0, 0, -1}, up, {0, 1}}, {{-1, 0, -1}, up, {-1, 2}}};
  m.indices = {0, 1, 2, 0, 2, 3};
  pbr::generate_tangents(m);
  check_frames(m);
  CHECK(m.vertices.size() == 4);
  const glm::dvec3 t1(1, 0, 0), t2 = glm::normalize(glm::dvec3(1, 0, -1));
  const glm::dvec3 weighted = glm::normalize(kPi / 2 * t1 + kPi / 4 * t2), plain = glm::normalize(t1 + t2);
  REQUIRE(degrees_between(weighted, plain) > 5.0);  // the weighting is visible
  CHECK(degrees_between(xyz(m.tangents[0]), weighted) < 1e-4);
  CHECK(degrees_between(xyz(m.tangents[1]), t1) < 1e-4);  // only face 1
  CHECK(degrees_between(xyz(m.tangents[3]), t2) < 1e-4);  // only face 2
  // v grows towards −z here, so up the image (−∂p/∂v) is +z: w·cross(+y, ≈+x) = +z, w = −1.
  for (const glm::vec4& t : m.tangents) CHECK(t.w == -1.0f);
}

TEST_CASE("tangents: degenerate triangles, stray vertices and bad normals give finite unit tangents") {
  pbr::Mesh m;
  const glm::vec3 up(0, 1, 0);
  const float nan = std::nanf("");
  // A, B, C: the good face (A, C, B), mapping u along +z. D lies on the line of A's and B's
  // uv, so (A, B, D) has zero UV area; E on the line AB, so (A, B, E) has zero area.
  m.vertices = {
      {{0, 0, 0}, up, {0, 0}},          // 0 A
      {{1, 0, 0}, up, {0, 1}},          // 1 B
      {{0, 0, 1}, up, {1, 0}},          // 2 C
      {{0.5f, 0, -1}, up, {0, 0.5f}},   // 3 D
      {{2, 0, 0}, up, {0, 2}},          // 4 E
      {{5, 0, 5}, up, {0.3f, 0.3f}},    // 5 used by no triangle
      {{0, 2, 0}, {0, 0, 0}, {0, 0}},   // 6 zero normal, in a face with a NaN uv
      {{1, 2, 0}, up, {0, 0}},          // 7
      {{0, 2, 1}, up, {nan, 0}},        // 8
      {{0, 0, 2}, up, {1, 0}},          // 9 X1: (C, X2, X1) has C's uv thrice, zero UV area,
      {{-1, 0, 1}, up, {1, 0}},         // 10 X2: and shares no edge with the good face
  };
  m.indices = {0, 2, 1, 0, 1, 3, 0, 1, 4, 0, 0, 0, 6, 8, 7, 2, 10, 9};
  pbr::generate_tangents(m);
  check_frames(m);  // finite, unit, ⊥ normal, w = ±1 everywhere
  // No corner disagrees with its vertex: the zero-area face's corners take A's and B's
  // result, and at C the lone zero-UV face's group (nothing to add) takes the good face's.
  CHECK(m.vertices.size() == 11);
  // The zero-UV face (A, B, D) joins A's and B's group: it adds nothing and takes its
  // tangent. The good face maps u along +z, mirrored (w = −1) seen from +y.
  for (std::uint32_t i : {0u, 1u, 2u}) {
    CAPTURE(i);
    CHECK(degrees_between(xyz(m.tangents[i]), glm::dvec3(0, 0, 1)) < 1e-4);
    CHECK(m.tangents[i].w == -1.0f);
  }
  // D, E and the unused vertex have no face with a tangent: the perpendicular fallback,
  // (1, 0, 0) for a normal along +y, with the orientation of D's face, adopted from the good
  // face (w = −1), and w = +1 where none is known; the zero normal gets (1, 0, 0) too.
  CHECK(m.tangents[3] == glm::vec4(1, 0, 0, -1));
  for (std::uint32_t i : {4u, 5u, 6u, 9u, 10u}) {
    CAPTURE(i);
    CHECK(m.tangents[i] == glm::vec4(1, 0, 0, 1));
  }
}

TEST_CASE("tangents: the fallback for a face without UV derivatives is perpendicular to any normal") {
  // One zero-UV triangle per normal direction, each alone: its vertices take the fallback.
  const glm::vec3 normals[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0.6f, 0.0f, -0.8f}, {0.48f, 0.6f, 0.64f}};
  for (const glm::vec3 n : normals) {
    CAPTURE(n.x);
    CAPTURE(n.y);
    CAPTURE(n.z);
    pbr::Mesh m;
    m.vertices = {{{0, 0, 0}, n, {0.5f, 0.5f}}, {{1, 0, 0}, n, {0.5f, 0.5f}}, {{0, 1, 0}, n, {0.5f, 0.5f}}};
    m.indices = {0, 1, 2};
    pbr::generate_tangents(m);
    check_frames(m);
  }
}

TEST_CASE("tangents: identical vertices are welded, so a triangle soup gets the indexed mesh's tangents") {
  const pbr::Mesh shapes[] = {pbr::uv_sphere(1.0f, 16, 8), pbr::torus(1.0f, 0.3f, 12, 8), mirrored_strip(3)};
  for (const pbr::Mesh& shape : shapes) {
    pbr::Mesh indexed = shape, soup = triangle_soup(shape);
    pbr::generate_tangents(indexed);
    pbr::generate_tangents(soup);
    REQUIRE(soup.indices.size() == indexed.indices.size());
    int differ = 0;
    for (std::size_t c = 0; c < soup.indices.size(); ++c)
      differ += std::memcmp(&soup.tangents[soup.indices[c]], &indexed.tangents[indexed.indices[c]], sizeof(glm::vec4)) != 0;
    CHECK(differ == 0);
    CHECK(soup.vertices.size() == shape.indices.size());  // a soup's corners never need a split
  }
}

TEST_CASE("tangents: bit-identical when run twice, and a second run changes nothing") {
  auto mirrored_sphere = [] {
    pbr::Mesh m = pbr::uv_sphere(1.0f, 24, 12);
    for (pbr::MeshVertex& v : m.vertices) v.uv.x = std::fabs(2.0f * v.uv.x - 1.0f);  // mirrored about u = 0.5
    return m;
  };
  const pbr::Mesh shapes[] = {pbr::icosphere(1.0f, 3), pbr::torus(1.0f, 0.4f, 24, 12), mirrored_sphere(),
                              mirrored_strip(4)};
  for (const pbr::Mesh& shape : shapes) {
    pbr::Mesh a = shape, b = shape;
    pbr::generate_tangents(a);
    pbr::generate_tangents(b);
    CHECK(same_bits(a, b));
    check_frames(a);
    pbr::Mesh again = a;
    pbr::generate_tangents(again);
    CHECK(same_bits(again, a));
  }
  pbr::Mesh m = mirrored_sphere();
  const std::size_t count = m.vertices.size();
  pbr::generate_tangents(m);
  CHECK(m.vertices.size() > count);  // the mirror line's vertices are split
}

TEST_CASE("tangents: bad indices and stream lengths are rejected and leave the mesh unchanged") {
  pbr::Mesh good = pbr::plane(1.0f, 1.0f);
  struct Case {
    const char* name;
    std::function<void(pbr::Mesh&)> spoil;
    const char* says;
  };
  const Case cases[] = {
      {"index out of range", [](pbr::Mesh& m) { m.indices[4] = 4; }, "index 4 is 4"},
      {"indices not a multiple of 3", [](pbr::Mesh& m) { m.indices.push_back(0); }, "multiple of 3"},
      {"short tangents", [](pbr::Mesh& m) { m.tangents.assign(3, glm::vec4(1, 0, 0, 1)); }, "tangents has 3 entries"},
      {"long uv1", [](pbr::Mesh& m) { m.uv1.assign(5, glm::vec2(0)); }, "uv1 has 5 entries"},
      {"short colors", [](pbr::Mesh& m) { m.colors.assign(1, glm::vec4(1)); }, "colors has 1 entries"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    pbr::Mesh m = good;
    c.spoil(m);
    const pbr::Mesh spoilt = m;
    const std::string what = thrown_message([&] { pbr::generate_tangents(m); });
    CHECK(what.find(c.says) != std::string::npos);
    CHECK(same_bits(m, spoilt));
  }
}

TEST_CASE("streams: validate_streams and merge_shapes accept empty or per-vertex streams only") {
  pbr::Mesh m = pbr::cube(1.0f);
  CHECK_NOTHROW(pbr::validate_streams(m));
  m.uv1.assign(24, glm::vec2(0.25f));
  m.colors.assign(24, glm::vec4(1.0f));
  CHECK_NOTHROW(pbr::validate_streams(m));
  m.colors.pop_back();
  CHECK(thrown_message([&] { pbr::validate_streams(m); }).find("colors has 23 entries, but the mesh has 24") !=
        std::string::npos);

  pbr::ObjModel model;
  model.shapes.push_back({"bad", m, -1});
  CHECK(thrown_message([&] { pbr::merge_shapes(model); }).find("colors has 23 entries") != std::string::npos);

  // A stream every shape has is concatenated; one only some shapes have is dropped.
  m.colors.push_back(glm::vec4(1.0f));
  pbr::Mesh other = pbr::plane(1.0f, 1.0f);
  other.colors.assign(4, glm::vec4(0.5f));
  model.shapes = {{"cube", m, -1}, {"plane", other, -1}};
  const pbr::Mesh merged = pbr::merge_shapes(model);
  CHECK(merged.vertices.size() == 28);
  CHECK(merged.colors.size() == 28);
  CHECK(merged.colors[25] == glm::vec4(0.5f));
  CHECK(merged.uv1.empty());
  CHECK(merged.tangents.empty());
  CHECK_NOTHROW(pbr::validate_streams(merged));
}
