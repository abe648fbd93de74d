// MikkTSpace tangents (mesh.h, generate_tangents), written from the algorithm's description
// (Mikkelsen 2008, "Simulation of Wrinkled Surfaces Revisited"): weld identical vertices,
// form per-vertex groups of edge-connected triangles with the same UV orientation, sum each
// group's angle-weighted tangents projected into the normal's plane.
//
// Deviations, none visible in glTF's vec4 tangent: the reference also averages |∂p/∂u| and
// the bitangent per group, which a glTF tangent does not hold; and its default angular
// threshold of 180° splits a group further only between corners whose tangents are exactly
// opposite, which is left out (such corners are summed together: the larger angle wins, or
// equal ones cancel into the fallback).
// Quads are not taken: meshes here are triangles.
//
// Every value is computed in double from the float inputs with basic operations (and
// dmath::angle_between) in a fixed order; hash maps are only looked up, never iterated, so
// the result has the same bits everywhere.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/pbr/mesh.h"

namespace softpbr::pbr {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// ---- Welding ------------------------------------------------------------------------------

// Position, normal and uv bits with −0 folded into +0: MikkTSpace treats vertices whose
// attributes compare equal as one, so duplicated vertices do not cut a fan in two.
struct WeldKey {
  std::array<std::uint32_t, 8> bits;
  bool operator==(const WeldKey&) const = default;
};
struct WeldKeyHash {
  std::size_t operator()(const WeldKey& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (std::uint32_t b : k.bits) h = (h ^ b) * 0x100000001b3ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
WeldKey weld_key(const MeshVertex& v) {
  const float f[8] = {v.position.x, v.position.y, v.position.z, v.normal.x,
                      v.normal.y,   v.normal.z,   v.uv.x,       v.uv.y};
  WeldKey k;
  for (int i = 0; i < 8; ++i) k.bits[i] = std::bit_cast<std::uint32_t>(f[i] + 0.0f);
  return k;
}

// For every vertex, the first vertex with the same attributes (itself if none before it).
std::vector<std::uint32_t> weld(const std::vector<MeshVertex>& vertices) {
  std::vector<std::uint32_t> rep(vertices.size());
  std::unordered_map<WeldKey, std::uint32_t, WeldKeyHash> first;
  first.reserve(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i)
    rep[i] = first.try_emplace(weld_key(vertices[i]), static_cast<std::uint32_t>(i)).first->second;
  return rep;
}

// ---- Per-triangle tangent -----------------------------------------------------------------

glm::dvec3 project(const glm::dvec3& v, const glm::dvec3& n) { return v - n * glm::dot(n, v); }

// v / |v|, or zero when |v| is zero or not finite.
glm::dvec3 unit_or_zero(const glm::dvec3& v) {
  const double len2 = glm::dot(v, v);
  return len2 > 0.0 && std::isfinite(len2) ? v / std::sqrt(len2) : glm::dvec3(0.0);
}

bool is_zero(const glm::dvec3& v) { return v.x == 0.0 && v.y == 0.0 && v.z == 0.0; }

struct Face {
  std::array<std::uint32_t, 3> welded;     // welded vertex of each corner
  std::array<std::uint32_t, 3> neighbour;  // across edge k (corner k → k+1), kNone if open
  glm::dvec3 tangent{0.0};                 // unit ∂p/∂u; zero when the UV area is zero
  int orientation = 0;                     // sign of the (u, −v) area; 0 = not yet known
  bool degenerate = false;                 // zero or non-finite area: in no group
};

// A triangle's tangent from its UV derivatives: with d1 = p1 − p0, d2 = p2 − p0 and the UV
// differences (s1, t1), (s2, t2), ∂p/∂u = (t2·d1 − t1·d2) / (s1·t2 − s2·t1) (solve
// d = s·∂p/∂u + t·∂p/∂v for both edges). v enters negated — MikkTSpace on (u, −v) — so
// that ∂p/∂(−v), the bitangent, points up a glTF image (mesh.h). The sign of the UV area
// is the face's orientation; the tangent keeps only its direction, as MikkTSpace weights
// directions by angle and averages the magnitude |∂p/∂u| separately (not part of a glTF
// tangent, so not computed here).
Face make_face(const std::array<MeshVertex, 3>& v) {
  Face f;
  const glm::dvec3 p0(v[0].position), d1 = glm::dvec3(v[1].position) - p0, d2 = glm::dvec3(v[2].position) - p0;
  const glm::dvec3 c = glm::cross(d1, d2);  // twice the area, along the face normal
  const double c2 = glm::dot(c, c);
  f.degenerate = !(c2 > 0.0) || !std::isfinite(c2);
  if (f.degenerate) return f;
  const double s1 = double(v[1].uv.x) - double(v[0].uv.x), t1 = double(v[0].uv.y) - double(v[1].uv.y);
  const double s2 = double(v[2].uv.x) - double(v[0].uv.x), t2 = double(v[0].uv.y) - double(v[2].uv.y);
  const double uv_area = s1 * t2 - s2 * t1;
  if (uv_area == 0.0 || !std::isfinite(uv_area)) return f;  // no UV derivatives: joins any group
  f.orientation = uv_area > 0.0 ? 1 : -1;
  f.tangent = unit_or_zero(static_cast<double>(f.orientation) * (t2 * d1 - t1 * d2));
  return f;
}

// The corner's angle within the normal's plane (MikkTSpace measures it between the edges
// projected into that plane); 0 when an edge runs along the normal and has no direction
// there.
double corner_angle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& n) {
  const glm::dvec3 e1 = project(a - p, n), e2 = project(b - p, n);
  if (is_zero(e1) || is_zero(e2)) return 0.0;
  return dmath::angle_between(e1, e2);
}

// A unit vector perpendicular to the unit vector n, continuous except across n.z = 0's sign:
// the first basis vector of Duff et al. 2017, "Building an Orthonormal Basis, Revisited",
// Listing 3 (basic operations and copysign only). (1, 0, 0) for n = (0, ±1, 0).
glm::dvec3 any_perpendicular(const glm::dvec3& n) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  // + 0.0 folds the −0s the products make for n along an axis: the same bits as +0's.
  return {1.0 + sign * n.x * n.x * a, sign * n.x * n.y * a + 0.0, -sign * n.x + 0.0};
}

// ---- Edge pairing -------------------------------------------------------------------------

// Sets each face's neighbour across each edge: the triangle with the same edge (welded)
// running the other way, as in a consistently wound mesh. Edges are sorted (a total order,
// so no tie depends on the sort), and on an edge with more than two triangles each one is
// paired with the earliest one still unpaired.
void pair_edges(std::vector<Face>& faces) {
  struct HalfEdge {
    std::uint32_t lo, hi, face, k;
    bool forward;  // runs lo → hi
  };
  std::vector<HalfEdge> edges;
  edges.reserve(faces.size() * 3);
  for (std::uint32_t t = 0; t < faces.size(); ++t) {
    if (faces[t].degenerate) continue;
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t a = faces[t].welded[k], b = faces[t].welded[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), t, k, a < b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    if (x.lo != y.lo) return x.lo < y.lo;
    if (x.hi != y.hi) return x.hi < y.hi;
    if (x.face != y.face) return x.face < y.face;
    return x.k < y.k;
  });
  std::vector<std::size_t> waiting[2];  // unpaired half-edges of the current edge, by direction
  std::size_t next[2] = {0, 0};
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (i == 0 || edges[i].lo != edges[i - 1].lo || edges[i].hi != edges[i - 1].hi) {
      for (int d = 0; d < 2; ++d) waiting[d].clear(), next[d] = 0;
    }
    const HalfEdge& e = edges[i];
    const int dir = e.forward ? 1 : 0, other = 1 - dir;
    if (next[other] < waiting[other].size()) {
      const HalfEdge& m = edges[waiting[other][next[other]++]];
      faces[e.face].neighbour[e.k] = m.face;
      faces[m.face].neighbour[m.k] = e.face;
    } else {
      waiting[dir].push_back(i);
    }
  }
}

// ---- Groups -------------------------------------------------------------------------------

struct Group {
  std::uint32_t welded;
  int orientation;
};

// Assigns every corner of every non-degenerate face to a group (group_of, per corner 3t + k).
// A group starts at an unassigned corner and grows across the two edges of the face that meet
// at its vertex, into neighbours with the group's orientation. A face with zero UV area takes
// the orientation of the first group that reaches it (MikkTSpace's one order dependency;
// here the fixed order of faces and corners). Groups start from oriented faces first, so a
// zero-UV face joins its oriented neighbours where it can; its corners no group reached
// start groups of their own afterwards, with its orientation or, never reached, +1.
std::vector<Group> build_groups(std::vector<Face>& faces, std::vector<std::uint32_t>& group_of) {
  std::vector<Group> groups;
  std::vector<std::uint32_t> stack;  // corners 3t + k
  auto grow = [&](std::uint32_t g) {
    while (!stack.empty()) {
      const std::uint32_t c = stack.back();
      stack.pop_back();
      const Face& f = faces[c / 3];
      const std::uint32_t k = c % 3, w = f.welded[k];
      for (const std::uint32_t u : {f.neighbour[k], f.neighbour[(k + 2) % 3]}) {
        if (u == kNone) continue;
        Face& nf = faces[u];
        const std::uint32_t j = nf.welded[0] == w ? 0 : nf.welded[1] == w ? 1 : 2;  // shares w
        if (group_of[3 * u + j] != kNone) continue;
        if (nf.orientation == 0) nf.orientation = groups[g].orientation;
        if (nf.orientation != groups[g].orientation) continue;
        group_of[3 * u + j] = g;
        stack.push_back(3 * u + j);
      }
    }
  };
  std::vector<bool> oriented_by_uv(faces.size());
  for (std::size_t t = 0; t < faces.size(); ++t) oriented_by_uv[t] = faces[t].orientation != 0;
  for (int pass = 0; pass < 2; ++pass)
    for (std::uint32_t t = 0; t < faces.size(); ++t) {
      if (faces[t].degenerate || (pass == 0 && !oriented_by_uv[t])) continue;
      for (std::uint32_t k = 0; k < 3; ++k) {
        if (group_of[3 * t + k] != kNone) continue;
        if (faces[t].orientation == 0) faces[t].orientation = 1;
        const auto g = static_cast<std::uint32_t>(groups.size());
        groups.push_back({faces[t].welded[k], faces[t].orientation});
        group_of[3 * t + k] = g;
        stack.push_back(3 * t + k);
        grow(g);
      }
    }
  return groups;
}

bool same_bits(const glm::vec4& a, const glm::vec4& b) {
  for (int i = 0; i < 4; ++i)
    if (std::bit_cast<std::uint32_t>(a[i]) != std::bit_cast<std::uint32_t>(b[i])) return false;
  return true;
}

}  // namespace

void generate_tangents(Mesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  if (mesh.indices.size() % 3 != 0)
    throw std::invalid_argument("generate_tangents: " + std::to_string(mesh.indices.size()) +
                                " indices is not a whole number of triangles (a multiple of 3)");
  for (std::size_t i = 0; i < mesh.indices.size(); ++i)
    if (mesh.indices[i] >= n)
      throw std::invalid_argument("generate_tangents: index " + std::to_string(i) + " is " +
                                  std::to_string(mesh.indices[i]) + ", but the mesh has only " +
                                  std::to_string(n) + " vertices");
  validate_streams(mesh);
  // Vertices and corners are numbered in 32 bits, kNone excluded.
  if (n >= kNone || mesh.indices.size() >= kNone)
    throw std::length_error("generate_tangents: more than 2^32 - 2 vertices or indices");

  const std::vector<std::uint32_t> rep = weld(mesh.vertices);
  // The unit normal of each welded vertex; zero if the normal is zero or not finite (then
  // nothing is projected and the fallback tangent is (1, 0, 0)).
  std::vector<glm::dvec3> normal(n, glm::dvec3(0.0));
  for (std::size_t i = 0; i < n; ++i)
    if (rep[i] == i) normal[i] = unit_or_zero(glm::dvec3(mesh.vertices[i].normal));

  const std::size_t triangles = mesh.indices.size() / 3;
  std::vector<Face> faces(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    std::array<MeshVertex, 3> v;
    for (int k = 0; k < 3; ++k) v[k] = mesh.vertices[mesh.indices[3 * t + k]];
    faces[t] = make_face(v);
    for (int k = 0; k < 3; ++k) {
      faces[t].welded[k] = rep[mesh.indices[3 * t + k]];
      faces[t].neighbour[k] = kNone;
    }
  }
  pair_edges(faces);
  std::vector<std::uint32_t> group_of(mesh.indices.size(), kNone);
  const std::vector<Group> groups = build_groups(faces, group_of);

  // Each group's sum of angle-weighted unit tangents projected into the normal's plane, in
  // corner order (not the order the groups grew in), so the sum's rounding is fixed.
  std::vector<glm::dvec3> sum(groups.size(), glm::dvec3(0.0));
  for (std::size_t c = 0; c < group_of.size(); ++c) {
    const Face& f = faces[c / 3];
    if (group_of[c] == kNone || is_zero(f.tangent)) continue;
    const std::size_t k = c % 3;
    const glm::dvec3& nv = normal[f.welded[k]];
    const glm::dvec3 t = unit_or_zero(project(f.tangent, nv));
    if (is_zero(t)) continue;  // the face's tangent runs along the normal
    auto pos = [&](std::size_t kk) { return glm::dvec3(mesh.vertices[mesh.indices[c - k + kk]].position); };
    sum[group_of[c]] += corner_angle(pos(k), pos((k + 1) % 3), pos((k + 2) % 3), nv) * t;
  }

  // Results. A group with nothing to sum (zero-UV faces only, or cancelling tangents) takes
  // the result of the first group at its welded vertex that has one; failing that the
  // perpendicular fallback with its orientation.
  auto fallback = [&](std::uint32_t w, int orientation) {
    const glm::dvec3& nv = normal[w];
    const glm::dvec3 t = is_zero(nv) ? glm::dvec3(1.0, 0.0, 0.0) : any_perpendicular(nv);
    return glm::vec4(glm::vec3(t), static_cast<float>(orientation));
  };
  std::vector<glm::vec4> result(groups.size());
  std::vector<bool> summed(groups.size());
  std::vector<std::uint32_t> first_summed(n, kNone), first_group(n, kNone);
  for (std::uint32_t g = 0; g < groups.size(); ++g) {
    const glm::dvec3 t = unit_or_zero(sum[g]);
    summed[g] = !is_zero(t);
    if (summed[g]) result[g] = glm::vec4(glm::vec3(t), static_cast<float>(groups[g].orientation));
    const std::uint32_t w = groups[g].welded;
    if (first_group[w] == kNone) first_group[w] = g;
    if (summed[g] && first_summed[w] == kNone) first_summed[w] = g;
  }
  for (std::uint32_t g = 0; g < groups.size(); ++g) {
    if (summed[g]) continue;
    const std::uint32_t from = first_summed[groups[g].welded];
    result[g] = from != kNone ? result[from] : fallback(groups[g].welded, groups[g].orientation);
  }

  // Vertices: each corner's result goes to its vertex; the first result keeps the vertex,
  // each different one gets a copy (chained through copy_next) that the corner is
  // re-indexed to. Corners of degenerate faces take their welded vertex's first group's
  // result (borrowed from the first with a sum if it had none), as MikkTSpace copies a
  // degenerate corner's tangent space from one of the vertex's faces.
  std::vector<glm::vec4> tangents(n);
  std::vector<bool> assigned(n, false);
  std::vector<std::uint32_t> copy_next(n, kNone), copy_of;  // copy_of: source of each new vertex
  std::vector<std::uint32_t> indices = mesh.indices;
  for (std::size_t c = 0; c < indices.size(); ++c) {
    const std::uint32_t vi = indices[c], w = rep[vi];
    glm::vec4 r;
    if (group_of[c] != kNone) {
      r = result[group_of[c]];
    } else {  // a degenerate face's corner
      r = first_group[w] != kNone ? result[first_group[w]] : fallback(w, 1);
    }
    std::uint32_t s = vi;
    while (assigned[s] && !same_bits(tangents[s], r) && copy_next[s] != kNone) s = copy_next[s];
    if (!assigned[s]) {
      tangents[s] = r;
      assigned[s] = true;
    } else if (!same_bits(tangents[s], r)) {
      if (tangents.size() >= kNone)
        throw std::length_error("generate_tangents: splitting vertices would need more than 2^32 - 1");
      const auto copy = static_cast<std::uint32_t>(tangents.size());
      copy_next[s] = copy;
      copy_next.push_back(kNone);
      tangents.push_back(r);
      assigned.push_back(true);
      copy_of.push_back(vi);
      s = copy;
    }
    indices[c] = s;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!assigned[i]) tangents[i] = fallback(rep[i], 1);  // no triangle uses it

  // Commit: room first, so an allocation failure leaves the mesh as it was.
  const std::size_t total = n + copy_of.size();
  mesh.vertices.reserve(total);
  if (!mesh.uv1.empty()) mesh.uv1.reserve(total);
  if (!mesh.colors.empty()) mesh.colors.reserve(total);
  for (const std::uint32_t src : copy_of) {
    mesh.vertices.push_back(mesh.vertices[src]);
    if (!mesh.uv1.empty()) mesh.uv1.push_back(mesh.uv1[src]);
    if (!mesh.colors.empty()) mesh.colors.push_back(mesh.colors[src]);
  }
  mesh.indices = std::move(indices);
  mesh.tangents = std::move(tangents);
}

}  // namespace softpbr::pbr
