// Procedural meshes, smooth normals and bounds.
#include "softpbr/pbr/mesh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr {

namespace {
namespace dm = dmath;

glm::dvec3 normalized(const glm::dvec3& v) { return v / std::sqrt(glm::dot(v, v)); }

glm::vec3 to_float(const glm::dvec3& v) { return glm::vec3(v); }

// ---- Parameter checks ---------------------------------------------------------------------

[[noreturn]] void invalid(const char* shape, const std::string& what) {
  throw std::invalid_argument(std::string(shape) + ": " + what);
}

void check_positive(const char* shape, const char* name, float value) {
  if (!(value > 0.0f) || !std::isfinite(value)) {
    std::ostringstream os;
    os << name << " must be a positive finite number, got " << value;
    invalid(shape, os.str());
  }
}

void check_at_least(const char* shape, const char* name, int value, int minimum) {
  if (value < minimum)
    invalid(shape, std::string(name) + " must be at least " + std::to_string(minimum) + ", got " +
                       std::to_string(value));
}

void check_vertex_count(const char* shape, std::size_t count) {
  if (count > kMaxProceduralVertices)
    invalid(shape, "would need " + std::to_string(count) + " vertices, more than the limit of " +
                       std::to_string(kMaxProceduralVertices));
}

// A position's bits with −0 folded into +0, so positions that compare equal weld together.
struct PositionKey {
  std::array<std::uint32_t, 3> bits;
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  std::size_t operator()(const PositionKey& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (std::uint32_t b : k.bits) h = (h ^ b) * 0x100000001b3ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
PositionKey position_key(const glm::vec3& p) {
  return {{std::bit_cast<std::uint32_t>(p.x + 0.0f), std::bit_cast<std::uint32_t>(p.y + 0.0f),
           std::bit_cast<std::uint32_t>(p.z + 0.0f)}};
}

}  // namespace

// ---- Optional streams -----------------------------------------------------------------------

void validate_streams(const Mesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  auto check = [n](const char* name, std::size_t size) {
    if (size != 0 && size != n)
      throw std::invalid_argument(std::string("mesh: ") + name + " has " + std::to_string(size) +
                                  " entries, but the mesh has " + std::to_string(n) +
                                  " vertices (a stream is empty or has one entry per vertex)");
  };
  check("tangents", mesh.tangents.size());
  check("uv1", mesh.uv1.size());
  check("colors", mesh.colors.size());
}

// ---- UV sphere ------------------------------------------------------------------------------

Mesh uv_sphere(float radius, int segments, int rings) {
  if (!(radius > 0.0f) || segments < 3 || rings < 2)
    throw std::invalid_argument("uv_sphere: need radius > 0, segments >= 3, rings >= 2");
  Mesh mesh;
  mesh.vertices.reserve(static_cast<std::size_t>(segments + 1) * (rings + 1));
  for (int r = 0; r <= rings; ++r) {
    const double v = static_cast<double>(r) / rings;
    const double theta = v * dm::kPi;  // from the north pole (+y)
    const double st = dm::sin(theta), ct = dm::cos(theta);
    for (int s = 0; s <= segments; ++s) {
      const double u = static_cast<double>(s) / segments;
      const double phi = u * 2.0 * dm::kPi;
      const glm::vec3 n(static_cast<float>(st * dm::sin(phi)), static_cast<float>(ct),
                        static_cast<float>(st * dm::cos(phi)));
      mesh.vertices.push_back({n * radius, n, {static_cast<float>(u), static_cast<float>(v)}});
    }
  }
  const auto row = static_cast<std::uint32_t>(segments + 1);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const std::uint32_t i0 = static_cast<std::uint32_t>(r) * row + static_cast<std::uint32_t>(s);
      const std::uint32_t i1 = i0 + 1, i2 = i0 + row, i3 = i2 + 1;
      // Counter-clockwise seen from outside; the degenerate pole triangles are skipped.
      if (r != 0) mesh.indices.insert(mesh.indices.end(), {i0, i2, i1});
      if (r != rings - 1) mesh.indices.insert(mesh.indices.end(), {i1, i2, i3});
    }
  return mesh;
}

// ---- Icosphere ------------------------------------------------------------------------------

namespace {

// The unit icosphere before UVs: shared vertices, counter-clockwise triangles.
struct UnitIcosphere {
  std::vector<glm::dvec3> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// An icosahedron with vertices at the poles, two rings of five at latitude ±atan(1/2), the
// upper ring at longitudes 0°, 72°, … and the lower at 36°, 108°, …. The sines and cosines of
// multiples of 36° are closed forms in √5 with explicit signs, so the solid is exactly
// symmetric about x = 0 and stays so under subdivision: points on the seam plane have x == 0.
UnitIcosphere icosahedron() {
  const double r5 = std::sqrt(5.0);
  const double c36 = (1.0 + r5) / 4, c72 = (r5 - 1.0) / 4;
  const double s36 = std::sqrt(10.0 - 2.0 * r5) / 4, s72 = std::sqrt(10.0 + 2.0 * r5) / 4;
  // sin and cos of 36°·k for k = 0 … 9.
  const double sn[10] = {0.0, s36, s72, s72, s36, 0.0, -s36, -s72, -s72, -s36};
  const double cs[10] = {1.0, c36, c72, -c72, -c36, -1.0, -c36, -c72, c72, c36};
  const double y = 1.0 / r5, rho = 2.0 / r5;  // the rings: y = ±1/√5 at radius 2/√5

  UnitIcosphere s;
  s.points.push_back({0.0, 1.0, 0.0});  // 0: north pole
  for (int k = 0; k < 5; ++k) s.points.push_back(normalized({rho * sn[2 * k], y, rho * cs[2 * k]}));
  for (int k = 0; k < 5; ++k) s.points.push_back(normalized({rho * sn[2 * k + 1], -y, rho * cs[2 * k + 1]}));
  s.points.push_back({0.0, -1.0, 0.0});  // 11: south pole
  for (std::uint32_t k = 0; k < 5; ++k) {
    const std::uint32_t k1 = (k + 1) % 5;
    const std::uint32_t u0 = 1 + k, u1 = 1 + k1, l0 = 6 + k, l1 = 6 + k1;
    s.triangles.push_back({0, u0, u1});
    s.triangles.push_back({u0, l0, u1});
    s.triangles.push_back({u1, l0, l1});
    s.triangles.push_back({11, l1, l0});
  }
  return s;
}

// Splits every triangle into four at its edge midpoints, pushed onto the unit sphere.
void subdivide(UnitIcosphere& s) {
  std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
  auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
    const auto [it, inserted] = midpoints.try_emplace(key, static_cast<std::uint32_t>(s.points.size()));
    if (inserted) s.points.push_back(normalized(s.points[a] + s.points[b]));  // a + b == b + a
    return it->second;
  };
  std::vector<std::array<std::uint32_t, 3>> out;
  out.reserve(s.triangles.size() * 4);
  for (const auto& [a, b, c] : s.triangles) {
    const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    out.push_back({a, ab, ca});
    out.push_back({ab, b, bc});
    out.push_back({ca, bc, c});
    out.push_back({ab, bc, ca});
  }
  s.triangles = std::move(out);
}

// Turns the unit icosphere into a Mesh with equirectangular UVs. The seam is the half plane
// x = 0, z > 0 (u = 0 on the +x side, 1 on the −x side). Triangles crossing it are clipped
// into a piece on each side, so no triangle's UVs wrap around; the cut points are computed
// once per edge, so both triangles sharing a cut edge get the same bits. A pole has no
// longitude: each triangle gets its own pole vertex with u halfway between its other two.
class IcosphereBuilder {
 public:
  IcosphereBuilder(UnitIcosphere& s, float radius) : s_(s), radius_(radius) {}

  Mesh build() {
    const std::size_t base_triangles = s_.triangles.size();
    for (std::size_t t = 0; t < base_triangles; ++t) {
      const std::array<std::uint32_t, 3> tri = s_.triangles[t];
      if (crosses_seam(tri)) {
        emit_clipped(tri, +1);
        emit_clipped(tri, -1);
      } else {
        const bool minus = s_.points[tri[0]].x < 0 || s_.points[tri[1]].x < 0 || s_.points[tri[2]].x < 0;
        emit_triangle(tri, minus);
      }
    }
    return std::move(mesh_);
  }

 private:
  bool on_seam(const glm::dvec3& p) const { return p.x == 0.0 && p.z > 0.0; }
  bool is_pole(const glm::dvec3& p) const { return p.x == 0.0 && p.z == 0.0; }

  // The point where edge (a, b) meets x = 0, on the sphere; computed from the +x endpoint.
  std::uint32_t cut_point(std::uint32_t a, std::uint32_t b) {
    if (s_.points[a].x < 0.0) std::swap(a, b);
    const std::uint64_t key = (std::uint64_t{a} << 32) | b;
    const auto [it, inserted] = cuts_.try_emplace(key, static_cast<std::uint32_t>(s_.points.size()));
    if (inserted) {
      const glm::dvec3 p = s_.points[a], q = s_.points[b];
      const double t = p.x / (p.x - q.x);
      glm::dvec3 m = p + t * (q - p);
      m.x = 0.0;
      s_.points.push_back(normalized(m));
    }
    return it->second;
  }

  bool crosses_seam(const std::array<std::uint32_t, 3>& tri) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      const double xa = s_.points[a].x, xb = s_.points[b].x;
      if ((xa > 0 && xb < 0) || (xa < 0 && xb > 0))
        if (s_.points[cut_point(a, b)].z > 0.0) return true;
    }
    return false;
  }

  // Sutherland–Hodgman clip of the triangle to x ≥ 0 (side +1) or x ≤ 0 (side −1), fanned.
  void emit_clipped(const std::array<std::uint32_t, 3>& tri, int side) {
    std::array<std::uint32_t, 4> poly{};
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      const double xa = side * s_.points[a].x, xb = side * s_.points[b].x;
      if (xa >= 0.0) poly[n++] = a;
      if ((xa > 0 && xb < 0) || (xa < 0 && xb > 0)) poly[n++] = cut_point(a, b);
    }
    for (int k = 1; k + 1 < n; ++k) emit_triangle({poly[0], poly[k], poly[k + 1]}, side < 0);
  }

  void emit_triangle(const std::array<std::uint32_t, 3>& tri, bool minus_side) {
    std::array<glm::dvec2, 3> uv;
    for (int k = 0; k < 3; ++k) uv[k] = uv_of(s_.points[tri[k]], minus_side);
    for (int k = 0; k < 3; ++k)
      if (is_pole(s_.points[tri[k]])) uv[k].x = 0.5 * (uv[(k + 1) % 3].x + uv[(k + 2) % 3].x);
    for (int k = 0; k < 3; ++k) mesh_.indices.push_back(vertex(tri[k], uv[k]));
  }

  glm::dvec2 uv_of(const glm::dvec3& p, bool minus_side) const {
    const double v = dm::atan2(std::sqrt(p.x * p.x + p.z * p.z), p.y) / dm::kPi;
    if (on_seam(p)) return {minus_side ? 1.0 : 0.0, v};
    double phi = dm::atan2(p.x, p.z);
    if (phi < 0.0) phi += 2.0 * dm::kPi;
    return {phi / (2.0 * dm::kPi), v};
  }

  // One vertex per (point, u): the seam and pole copies differ only in u.
  std::uint32_t vertex(std::uint32_t point, const glm::dvec2& uv) {
    const auto [it, inserted] =
        vertices_.try_emplace({point, std::bit_cast<std::uint64_t>(uv.x)}, static_cast<std::uint32_t>(mesh_.vertices.size()));
    if (inserted) {
      const glm::dvec3& p = s_.points[point];
      mesh_.vertices.push_back({to_float(p * static_cast<double>(radius_)), to_float(p),
                                {static_cast<float>(uv.x), static_cast<float>(uv.y)}});
    }
    return it->second;
  }

  struct VertexKey {
    std::uint32_t point;
    std::uint64_t u_bits;
    bool operator==(const VertexKey&) const = default;
  };
  struct VertexKeyHash {
    std::size_t operator()(const VertexKey& k) const {
      return static_cast<std::size_t>((k.u_bits ^ (std::uint64_t{k.point} * 0x9e3779b97f4a7c15ull)) * 0xff51afd7ed558ccdull);
    }
  };

  UnitIcosphere& s_;
  float radius_;
  Mesh mesh_;
  std::unordered_map<std::uint64_t, std::uint32_t> cuts_;
  std::unordered_map<VertexKey, std::uint32_t, VertexKeyHash> vertices_;
};

}  // namespace

Mesh icosphere(float radius, int subdivisions) {
  // 8 levels: 1.3 M triangles, already far finer than a pixel for any sphere on screen.
  constexpr int kMaxSubdivisions = 8;
  check_positive("icosphere", "radius", radius);
  check_at_least("icosphere", "subdivisions", subdivisions, 0);
  if (subdivisions > kMaxSubdivisions)
    invalid("icosphere", "subdivisions must be at most " + std::to_string(kMaxSubdivisions) + ", got " +
                             std::to_string(subdivisions));
  UnitIcosphere s = icosahedron();
  for (int i = 0; i < subdivisions; ++i) subdivide(s);
  return IcosphereBuilder(s, radius).build();
}

// ---- Cube -----------------------------------------------------------------------------------

Mesh cube(float size) {
  check_positive("cube", "size", size);
  const float h = size * 0.5f;
  // Each face: outward normal n, and `right` × `up` = n so the corners below run
  // counter-clockwise seen from outside. Side faces have up = +y; the top's up is −z and the
  // bottom's +z, so every face's image is upright seen from outside with +y up.
  struct Face {
    glm::vec3 n, right, up;
  };
  const Face faces[6] = {
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
  };
  // Corner k at n·h + (s·right + t·up)·h, with uv (0.5 + 0.5 s, 0.5 − 0.5 t): v = 0 at the top.
  const float st[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  Mesh mesh;
  mesh.vertices.reserve(24);
  mesh.indices.reserve(36);
  for (const Face& f : faces) {
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (const auto& [s, t] : st)
      mesh.vertices.push_back({(f.n + s * f.right + t * f.up) * h, f.n, {0.5f + 0.5f * s, 0.5f - 0.5f * t}});
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  return mesh;
}

// ---- Plane ----------------------------------------------------------------------------------

Mesh plane(float width, float depth, int subdivisions) {
  check_positive("plane", "width", width);
  check_positive("plane", "depth", depth);
  check_at_least("plane", "subdivisions", subdivisions, 1);
  const auto n = static_cast<std::size_t>(subdivisions);
  check_vertex_count("plane", (n + 1) * (n + 1));
  Mesh mesh;
  mesh.vertices.reserve((n + 1) * (n + 1));
  mesh.indices.reserve(n * n * 6);
  for (std::size_t j = 0; j <= n; ++j) {
    const double v = static_cast<double>(j) / static_cast<double>(n);
    for (std::size_t i = 0; i <= n; ++i) {
      const double u = static_cast<double>(i) / static_cast<double>(n);
      mesh.vertices.push_back({{static_cast<float>((u - 0.5) * width), 0.0f, static_cast<float>((v - 0.5) * depth)},
                               {0.0f, 1.0f, 0.0f},
                               {static_cast<float>(u), static_cast<float>(v)}});
    }
  }
  const auto row = static_cast<std::uint32_t>(n + 1);
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      // (i, j) → (i, j+1) → (i+1, j+1) runs counter-clockwise seen from +y (x right, z down).
      const std::uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, c, d, a, d, b});
    }
  return mesh;
}

// ---- Torus ----------------------------------------------------------------------------------

Mesh torus(float major, float minor, int segments, int sides) {
  check_positive("torus", "major radius", major);
  check_positive("torus", "minor radius", minor);
  if (!(minor < major)) {
    std::ostringstream os;
    os << "minor radius " << minor << " must be less than major radius " << major
       << " (a horn or spindle torus intersects itself)";
    invalid("torus", os.str());
  }
  check_at_least("torus", "segments", segments, 3);
  check_at_least("torus", "sides", sides, 3);
  const auto ns = static_cast<std::size_t>(segments), nt = static_cast<std::size_t>(sides);
  check_vertex_count("torus", (ns + 1) * (nt + 1));

  // Angles from index tables that wrap, so the seam columns repeat the first ones bit for bit.
  auto sincos_table = [](std::size_t count) {
    std::vector<std::array<double, 2>> t(count);
    for (std::size_t i = 0; i < count; ++i) {
      const double a = 2.0 * dm::kPi * static_cast<double>(i) / static_cast<double>(count);
      t[i] = {dm::sin(a), dm::cos(a)};
    }
    return t;
  };
  const auto ring = sincos_table(ns), tube = sincos_table(nt);
  const double R = major, r = minor;
  Mesh mesh;
  mesh.vertices.reserve((ns + 1) * (nt + 1));
  mesh.indices.reserve(ns * nt * 6);
  for (std::size_t i = 0; i <= ns; ++i) {
    const auto [sp, cp] = ring[i % ns];
    const glm::dvec3 d(sp, 0.0, cp);  // from the axis towards the tube centre
    for (std::size_t j = 0; j <= nt; ++j) {
      const auto [st, ct] = tube[j % nt];
      const glm::dvec3 n = ct * d + glm::dvec3(0.0, st, 0.0);
      const glm::dvec3 p = R * d + r * n;
      mesh.vertices.push_back({to_float(p), to_float(n),
                               {static_cast<float>(static_cast<double>(i) / static_cast<double>(ns)),
                                static_cast<float>(static_cast<double>(j) / static_cast<double>(nt))}});
    }
  }
  const auto row = static_cast<std::uint32_t>(nt + 1);
  for (std::uint32_t i = 0; i < ns; ++i)
    for (std::uint32_t j = 0; j < nt; ++j) {
      // u grows to the right and v upwards seen from outside at the outer equator.
      const std::uint32_t a = i * row + j, b = a + row, c = b + 1, d = a + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    }
  return mesh;
}

// ---- Smooth normals -------------------------------------------------------------------------

void compute_smooth_normals(Mesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  for (std::size_t i = 0; i < mesh.indices.size(); ++i)
    if (mesh.indices[i] >= n)
      throw std::invalid_argument("compute_smooth_normals: index " + std::to_string(i) + " is " +
                                  std::to_string(mesh.indices[i]) + ", but the mesh has only " +
                                  std::to_string(n) + " vertices");

  // Weld: every vertex accumulates into the first vertex with the same position.
  std::vector<std::uint32_t> rep(n);
  {
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> first;
    first.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
      rep[i] = first.try_emplace(position_key(mesh.vertices[i].position), static_cast<std::uint32_t>(i))
                   .first->second;
  }

  std::vector<glm::dvec3> sum(n, glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t idx[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
    const glm::dvec3 p[3] = {glm::dvec3(mesh.vertices[idx[0]].position), glm::dvec3(mesh.vertices[idx[1]].position),
                             glm::dvec3(mesh.vertices[idx[2]].position)};
    const glm::dvec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double len2 = glm::dot(c, c);
    if (!(len2 > 0.0) || !std::isfinite(len2)) continue;  // zero-area (or non-finite): no direction
    const glm::dvec3 face_n = c / std::sqrt(len2);
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
      // A positive area means both edges are non-zero, so the angle is well defined.
      sum[rep[idx[k]]] += dm::angle_between(e1, e2) * face_n;
    }
  }

  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 s = sum[rep[i]];
    const double len2 = glm::dot(s, s);
    glm::vec3& normal = mesh.vertices[i].normal;
    if (len2 > 0.0 && std::isfinite(len2)) {
      normal = to_float(s / std::sqrt(len2));
    } else {
      const glm::dvec3 old(normal);
      const double old2 = glm::dot(old, old);
      normal = old2 > 0.0 && std::isfinite(old2) ? to_float(old / std::sqrt(old2)) : glm::vec3(0.0f, 1.0f, 0.0f);
    }
  }
}

// ---- Bounds ---------------------------------------------------------------------------------

Bounds bounds(const Mesh& mesh) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  Bounds b{glm::vec3(inf), glm::vec3(-inf)};
  for (const MeshVertex& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) {
      b.min[k] = std::min(b.min[k], v.position[k]);
      b.max[k] = std::max(b.max[k], v.position[k]);
    }
  }
  return b;
}

Bounds merge(const Bounds& a, const Bounds& b) {
  Bounds m;
  for (int k = 0; k < 3; ++k) {
    m.min[k] = std::min(a.min[k], b.min[k]);
    m.max[k] = std::max(a.max[k], b.max[k]);
  }
  return m;
}

glm::mat4 fit_transform(const Bounds& b, float size) {
  const glm::vec3 extent = b.extent();
  const float largest = std::max({extent.x, extent.y, extent.z});
  if (!(largest > 0.0f)) return glm::mat4(1.0f);  // empty (−∞) or a single point (0)
  const float s = size / largest;
  return glm::scale(glm::mat4(1.0f), glm::vec3(s)) * glm::translate(glm::mat4(1.0f), -b.centre());
}

}  // namespace softpbr::pbr
