// softpbr/pbr/mesh.h — triangle meshes and procedural shapes.
//
// Procedural shapes are built with the deterministic dmath functions, so a shape has the
// same bits on every platform.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace softpbr::pbr {

struct MeshVertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
};

struct Mesh {
  std::vector<MeshVertex> vertices;
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from outside

  std::size_t triangle_count() const { return indices.size() / 3; }
};

// A UV sphere centred at the origin: `segments` slices around the y axis (≥ 3) and `rings`
// stacks from pole to pole (≥ 2). Throws std::invalid_argument for fewer or for a
// non-positive radius.
Mesh uv_sphere(float radius, int segments, int rings);

}  // namespace softpbr::pbr
