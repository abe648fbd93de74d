// Morph targets and skins on the CPU (see deform.h).
#include "gltf/deform.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "softpbr/raster/pool.h"

namespace softpbr::pbr::gltf {

namespace {

// Vertices per task: large enough that a task outweighs its dispatch, small enough to
// share a mesh of a few thousand vertices between threads.
constexpr std::size_t kVerticesPerTask = 4096;

glm::dvec3 d3(const glm::vec3& v) { return glm::dvec3(v); }

// The inverse transpose of m's upper 3×3 (cofactors over the determinant); the identity
// gives the identity exactly. A singular matrix gives its cofactor matrix (the normals of
// a flattened part keep a direction rather than becoming NaN).
glm::dmat3 normal_matrix(const glm::dmat4& m) {
  const glm::dmat3 a(m);
  glm::dmat3 c;
  c[0][0] = a[1][1] * a[2][2] - a[2][1] * a[1][2];
  c[0][1] = a[2][0] * a[1][2] - a[1][0] * a[2][2];
  c[0][2] = a[1][0] * a[2][1] - a[2][0] * a[1][1];
  c[1][0] = a[2][1] * a[0][2] - a[0][1] * a[2][2];
  c[1][1] = a[0][0] * a[2][2] - a[2][0] * a[0][2];
  c[1][2] = a[2][0] * a[0][1] - a[0][0] * a[2][1];
  c[2][0] = a[0][1] * a[1][2] - a[1][1] * a[0][2];
  c[2][1] = a[1][0] * a[0][2] - a[0][0] * a[1][2];
  c[2][2] = a[0][0] * a[1][1] - a[1][0] * a[0][1];
  const double det = a[0][0] * c[0][0] + a[1][0] * c[1][0] + a[2][0] * c[2][0];
  if (det == 1.0 || !std::isfinite(det) || det == 0.0) return c;
  return c * (1.0 / det);
}

}  // namespace

Mesh deform(const Mesh& base, const Deformation& d, raster::ThreadPool* pool) {
  Mesh out = base;
  const std::size_t n = base.vertices.size();
  const bool has_sources = d.sources != nullptr && !d.sources->empty();
  const bool tangents = !base.tangents.empty();
  auto run = [&](std::size_t task) {
    const std::size_t begin = task * kVerticesPerTask, end = std::min(n, begin + kVerticesPerTask);
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t s = has_sources ? (*d.sources)[i] : i;
      const MeshVertex& v = base.vertices[i];
      glm::dvec3 p = d3(v.position), nn = d3(v.normal);
      glm::dvec3 t = tangents ? glm::dvec3(base.tangents[i]) : glm::dvec3(0.0);
      for (const MorphTarget& m : d.targets) {
        if (!m.position.empty()) p += m.weight * glm::dvec3(m.position[3 * s], m.position[3 * s + 1], m.position[3 * s + 2]);
        if (!m.normal.empty() && !d.flat)
          nn += m.weight * glm::dvec3(m.normal[3 * s], m.normal[3 * s + 1], m.normal[3 * s + 2]);
        if (!m.tangent.empty() && tangents)
          t += m.weight * glm::dvec3(m.tangent[3 * s], m.tangent[3 * s + 1], m.tangent[3 * s + 2]);
      }
      MeshVertex& o = out.vertices[i];
      o.position = glm::vec3(p);
      o.normal = glm::vec3(nn);
      if (tangents) out.tangents[i] = glm::vec4(glm::vec3(t), base.tangents[i].w);
    }
  };
  const std::size_t tasks = (n + kVerticesPerTask - 1) / kVerticesPerTask;
  auto for_tasks = [&](auto&& fn) {
    if (pool != nullptr && tasks > 1) pool->parallel_for(tasks, [&](std::size_t k) { fn(k); });
    else
      for (std::size_t k = 0; k < tasks; ++k) fn(k);
  };
  if (!d.targets.empty()) {
    for_tasks(run);
    // Flat normals follow the morphed faces: each triangle owns its three vertices.
    if (d.flat)
      for (std::size_t c = 0; c + 2 < out.indices.size(); c += 3) {
        MeshVertex& a = out.vertices[out.indices[c]];
        MeshVertex& b = out.vertices[out.indices[c + 1]];
        MeshVertex& e = out.vertices[out.indices[c + 2]];
        const glm::dvec3 cr = glm::cross(d3(b.position) - d3(a.position), d3(e.position) - d3(a.position));
        const double len = std::sqrt(glm::dot(cr, cr));
        const glm::vec3 fn = len > 0.0 && std::isfinite(len) ? glm::vec3(cr / len) : glm::vec3(0.0f, 1.0f, 0.0f);
        a.normal = b.normal = e.normal = fn;
      }
  }
  if (d.skin != nullptr) {
    const SkinInfluences& k = *d.skin;
    const std::vector<glm::dmat4>& J = *k.matrices;
    const Mesh morphed = d.targets.empty() ? Mesh{} : out;
    const Mesh& from = d.targets.empty() ? base : morphed;
    for_tasks([&](std::size_t task) {
      const std::size_t begin = task * kVerticesPerTask, end = std::min(n, begin + kVerticesPerTask);
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t s = has_sources ? (*d.sources)[i] : i;
        // The skin matrix, Σ wⱼ·Jⱼ in the order of the influences (§3.7.3.3).
        glm::dmat4 M(0.0);
        for (std::size_t j = 0; j < k.influences; ++j) {
          const double w = k.weights[s * k.influences + j];
          if (w == 0.0) continue;
          const glm::dmat4& Jj = J[k.joints[s * k.influences + j]];
          for (int c = 0; c < 4; ++c) M[c] += w * Jj[c];
        }
        const MeshVertex& v = from.vertices[i];
        MeshVertex& o = out.vertices[i];
        o.position = glm::vec3(glm::dvec3(M * glm::dvec4(d3(v.position), 1.0)));
        o.normal = glm::vec3(normal_matrix(M) * d3(v.normal));
        if (tangents) {
          const glm::vec4& t = from.tangents[i];
          out.tangents[i] = glm::vec4(glm::vec3(glm::dmat3(M) * glm::dvec3(t.x, t.y, t.z)), t.w);
        }
      }
    });
  }
  return out;
}

}  // namespace softpbr::pbr::gltf
