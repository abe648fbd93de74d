// softpbr/pbr/mesh.h — triangle meshes with optional vertex streams, procedural shapes, smooth normals,
// MikkTSpace tangents and bounds.
//
// Procedural shapes are built with the deterministic dmath functions (and the deterministic
// dmath::atan2), so a shape has the same bits on every platform. Every shape has unit
// normals, UVs in [0, 1] and counter-clockwise triangles seen from outside (front faces for
// FrontFace::CounterClockwise with a GL-style camera). Invalid parameters throw
// std::invalid_argument saying which parameter and what was expected.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace softpbr::pbr {

struct MeshVertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
};
// The untextured fast path draws MeshVertex as is: new attributes go in Mesh's streams.
static_assert(sizeof(MeshVertex) == 32);

// MeshVertex is what the rasterizer draws (32 bytes: the untextured fast path relies on its
// layout); attributes only some meshes have live in optional streams beside it, so meshes
// without them pay nothing.
struct Mesh {
  std::vector<MeshVertex> vertices;
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from outside
  // Optional per-vertex streams: each is empty or holds one entry per vertex.
  std::vector<glm::vec4> tangents;  // xyz unit tangent (along +u), w = ±1: bitangent = w · cross(normal, tangent.xyz)
  std::vector<glm::vec2> uv1;       // second texture-coordinate set
  std::vector<glm::vec4> colors;    // linear RGBA vertex colour

  std::size_t triangle_count() const { return indices.size() / 3; }
};

// Throws std::invalid_argument naming the stream if a non-empty optional stream (tangents,
// uv1, colors) does not hold exactly one entry per vertex. Functions that read or copy the
// streams check them with it first.
void validate_streams(const Mesh& mesh);

// A procedural shape may have at most this many vertices: 2^24 vertices of 32 bytes are
// 512 MiB, far beyond any use of these shapes, and the counts stay exact in float.
inline constexpr std::size_t kMaxProceduralVertices = std::size_t{1} << 24;

// A UV sphere centred at the origin: `segments` slices around the y axis (≥ 3) and `rings`
// stacks from pole to pole (≥ 2). Throws std::invalid_argument for fewer or for a
// non-positive radius.
Mesh uv_sphere(float radius, int segments, int rings);

// A geodesic sphere centred at the origin: an icosahedron with vertices at the poles (0, ±r, 0),
// each face split into 4 `subdivisions` times (0 … 8; 20·4^n triangles before the seam cut)
// and every vertex pushed onto the sphere. UVs are the same equirectangular map as
// uv_sphere's (u = longitude / 2π from +z towards +x, v = 0 at +y): triangles crossing the
// seam are cut along it and the pole vertices are split per triangle, so UVs stay in [0, 1]
// without wrapping. Positions are shared bit for bit along the cut: the mesh is watertight.
Mesh icosphere(float radius, int subdivisions);

// An axis-aligned cube centred at the origin with edge `size` > 0: 24 vertices (4 per face,
// flat normals), 12 triangles; each face maps the whole [0, 1]² texture, upright for side
// faces (v = 0 at the top, +y).
Mesh cube(float size);

// A plane in y = 0 facing +y, centred at the origin: `width` along x, `depth` along z (both
// > 0), split into `subdivisions` × `subdivisions` quads (≥ 1; 1 gives a single quad).
// u runs along +x and v along +z, both over [0, 1].
Mesh plane(float width, float depth, int subdivisions = 1);

// A ring torus around the y axis: tube centre at distance `major` from the origin, tube
// radius `minor` (0 < minor < major, so it does not intersect itself), `segments` around
// the ring (≥ 3) and `sides` around the tube (≥ 3). u follows the ring from +z towards +x,
// v goes around the tube starting at the outer equator and going up first.
Mesh torus(float major, float minor, int segments, int sides);

// Replaces every vertex normal with the angle-weighted sum of the normals of the triangles
// around it (Thürmer & Wüthrich 1998, "Computing vertex normals from polygonal facets"),
// normalised. Vertices at bitwise-equal positions share their normal, so vertices split for
// UV seams or flat shading are smoothed across (a cube's corners get normals along its
// diagonals). Angles come from a deterministic atan2 (IEEE basic operations only, no libm),
// so results are identical on every platform. Zero-area triangles contribute nothing; a
// vertex with no contribution keeps its old normal if non-zero, else gets (0, 1, 0).
// Throws std::invalid_argument if an index is out of range.
void compute_smooth_normals(Mesh& mesh);

// MikkTSpace tangents (Mikkelsen 2008, "Simulation of Wrinkled Surfaces Revisited", the
// tangent space glTF 2.0 asks for when a mesh has none) from positions, normals and uv, into
// mesh.tangents (replacing any there). Convention: glTF's, UV (0, 0) at the top left of the
// image and normal textures +Y up, so the bitangent w · cross(normal, tangent.xyz) points
// up the image, along −∂position/∂v: MikkTSpace run on (u, −v). An unmirrored mapping seen
// from the front has w = +1; plane() gets (1, 0, 0, +1).
//
// As in MikkTSpace, vertices with identical position, normal and uv are welded, and at each
// welded vertex the triangles around it form groups, joined across shared edges, whose UV
// orientation (the sign of the UV area) agrees; a group's tangent is the sum of its corners'
// face tangents (∂position/∂u) projected into the plane of the normal and normalised,
// weighted by the corner's angle, then normalised. A vertex whose corners fall into groups
// with different results (typically faces with mirrored UVs on both sides of it) is SPLIT:
// the first result keeps the vertex, each further one appends a copy of it (its MeshVertex
// and its entries in uv1 and colors) and that group's corners are re-indexed to the copy.
// Positions, normals, uv and the triangle order never change; vertices are only appended.
//
// Degenerate input never gives NaN. A triangle with zero UV area adds no tangent but joins
// the group of the first oriented neighbour that reaches it, taking its orientation. A
// zero-area (or non-finite) triangle joins no group: its corners take the result of the
// first group at their welded vertex. A group with nothing to add (only zero-UV triangles)
// takes the result of the first group at its welded vertex that has one. Failing those, and
// for a vertex no triangle uses, the tangent is the unit vector perpendicular to the normal
// of Duff et al. 2017 ("Building an Orthonormal Basis, Revisited"; (1, 0, 0) for a normal
// along ±y) with w = the group's orientation or +1; (1, 0, 0) for a zero or non-finite
// normal. "First" is in the order of the triangles and their corners.
// Deterministic: IEEE basic operations and dmath only, a fixed order.
// Throws std::invalid_argument if indices are not a multiple of 3, an index is out of range,
// or a stream has the wrong length (validate_streams), and std::length_error if the corners
// or the split vertices would not fit 32-bit indices; the mesh is then unchanged.
void generate_tangents(Mesh& mesh);

// Axis-aligned bounds of the mesh's vertex positions.
struct Bounds {
  glm::vec3 min;
  glm::vec3 max;

  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  glm::vec3 centre() const { return (min + max) * 0.5f; }
  glm::vec3 extent() const { return max - min; }
};

// The bounds of all vertices (referenced or not); for a mesh without vertices min = +∞ and
// max = −∞, and empty() is true. Positions are expected finite (load_obj checks them).
Bounds bounds(const Mesh& mesh);

// The smallest bounds holding both (exact: only min and max).
Bounds merge(const Bounds& a, const Bounds& b);

// Uniform scale and offset that fit `b`, centred, into a cube of side `size`:
// scale(size / largest extent) · translate(−centre). The identity for empty bounds or a
// single point. make_gallery() and scene files' "fit" both use it, so they agree bit for bit.
glm::mat4 fit_transform(const Bounds& b, float size);

}  // namespace softpbr::pbr
