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
// share a mesh of a few thousand vertices between threads. The blocks do not depend on
// the thread count (nor would the result: each vertex is computed alone).
constexpr std::size_t kVerticesPerTask = 4096;

// One pass over vertices [begin, end) of `from` into `out` (which may be `from`: each
// vertex is read whole before it is written): morphed when `morph`, skinned when `skin`.
void deform_range(const Mesh& from, const Deformation& d, const std::vector<float>& morph_weights, bool morph,
                  bool skin, Mesh& out, std::size_t begin, std::size_t end) {
  const std::uint32_t* sources = d.sources != nullptr && !d.sources->empty() ? d.sources->data() : nullptr;
  const bool tangents = !from.tangents.empty();
  const std::size_t influences = skin ? d.skin->influences : 0;
  const JointMatrix* palette = skin ? d.skin->palette->data() : nullptr;
  const std::uint32_t* joints = skin ? d.skin->joints.data() : nullptr;
  const float* weights = skin ? d.skin->weights.data() : nullptr;
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t s = sources != nullptr ? sources[i] : i;
    const MeshVertex& v = from.vertices[i];
    float p[3] = {v.position.x, v.position.y, v.position.z};
    float n[3] = {v.normal.x, v.normal.y, v.normal.z};
    float t[3] = {0.0f, 0.0f, 0.0f};
    const float tw = tangents ? from.tangents[i].w : 0.0f;
    if (tangents) t[0] = from.tangents[i].x, t[1] = from.tangents[i].y, t[2] = from.tangents[i].z;
    // Morph targets (§3.7.2.2), in the targets' order: x + w₁·Δ₁ + w₂·Δ₂ + …
    if (morph)
      for (std::size_t k = 0; k < d.targets.size(); ++k) {
        const MorphTarget& m = d.targets[k];
        const float w = morph_weights[k];
        if (m.position != nullptr)
          for (int c = 0; c < 3; ++c) p[c] = p[c] + w * m.position[3 * s + static_cast<std::size_t>(c)];
        if (m.normal != nullptr && !d.flat)
          for (int c = 0; c < 3; ++c) n[c] = n[c] + w * m.normal[3 * s + static_cast<std::size_t>(c)];
        if (m.tangent != nullptr && tangents)
          for (int c = 0; c < 3; ++c) t[c] = t[c] + w * m.tangent[3 * s + static_cast<std::size_t>(c)];
      }
    if (skin) {
      // The blend of the joints' palette entries (§3.7.3.3), in the order of the
      // influences: B = w₁·P₁ + w₂·P₂ + … (24 floats, each element alone).
      float B[24] = {};
      for (std::size_t j = 0; j < influences; ++j) {
        const float w = weights[s * influences + j];
        if (w == 0.0f) continue;
        const float* P = palette[joints[s * influences + j]].data();
        for (int c = 0; c < 24; ++c) B[c] += w * P[c];
      }
      float q[3], m[3], u[3];
      for (int r = 0; r < 3; ++r) {
        const float* row = B + 4 * r;
        const float* nrow = B + 12 + 3 * r;
        q[r] = row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + row[3];
        m[r] = nrow[0] * n[0] + nrow[1] * n[1] + nrow[2] * n[2];
        u[r] = row[0] * t[0] + row[1] * t[1] + row[2] * t[2];
      }
      for (int c = 0; c < 3; ++c) p[c] = q[c], n[c] = m[c], t[c] = u[c];
    }
    MeshVertex& o = out.vertices[i];
    o.position = glm::vec3(p[0], p[1], p[2]);
    o.normal = glm::vec3(n[0], n[1], n[2]);
    if (tangents) out.tangents[i] = glm::vec4(t[0], t[1], t[2], tw);
  }
}

}  // namespace

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


JointPalette joint_palette(const std::vector<glm::dmat4>& J) {
  JointPalette out(J.size());
  for (std::size_t j = 0; j < J.size(); ++j) {
    JointMatrix& P = out[j];
    P.fill(0.0f);
    const glm::dmat3 N = normal_matrix(J[j]);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) P[static_cast<std::size_t>(4 * r + c)] = static_cast<float>(J[j][c][r]);  // glm: [column][row]
      for (int c = 0; c < 3; ++c) P[static_cast<std::size_t>(12 + 3 * r + c)] = static_cast<float>(N[c][r]);
    }
  }
  return out;
}

void deform(const Mesh& base, const Deformation& d, Mesh& out, raster::ThreadPool* pool) {
  const std::size_t n = base.vertices.size();
  const std::size_t tasks = (n + kVerticesPerTask - 1) / kVerticesPerTask;
  std::vector<float> morph_weights(d.targets.size());
  for (std::size_t k = 0; k < d.targets.size(); ++k) morph_weights[k] = static_cast<float>(d.targets[k].weight);
  auto pass = [&](const Mesh& from, bool morph, bool skin) {
    auto run = [&](std::size_t task) {
      const std::size_t begin = task * kVerticesPerTask;
      deform_range(from, d, morph_weights, morph, skin, out, begin, std::min(n, begin + kVerticesPerTask));
    };
    if (pool != nullptr && tasks > 1) pool->parallel_for(tasks, run);
    else
      for (std::size_t k = 0; k < tasks; ++k) run(k);
  };
  const bool morph = !d.targets.empty(), skin = d.skin != nullptr;
  if (!morph && !skin) {
    pass(base, false, false);  // the base's positions, normals and tangents
    return;
  }
  if (!(morph && d.flat)) {
    pass(base, morph, skin);  // one pass: each vertex morphed, then skinned
    return;
  }
  // Flat normals follow the morphed faces (each triangle owns its three vertices): the
  // positions morphed, the normals made again per triangle, then the skin in place.
  pass(base, true, false);
  for (std::size_t c = 0; c + 2 < out.indices.size(); c += 3) {
    MeshVertex& a = out.vertices[out.indices[c]];
    MeshVertex& b = out.vertices[out.indices[c + 1]];
    MeshVertex& e = out.vertices[out.indices[c + 2]];
    const glm::dvec3 pa(a.position), pb(b.position), pe(e.position);
    const glm::dvec3 cr = glm::cross(pb - pa, pe - pa);
    const double len = std::sqrt(glm::dot(cr, cr));
    const glm::vec3 fn = len > 0.0 && std::isfinite(len) ? glm::vec3(cr / len) : glm::vec3(0.0f, 1.0f, 0.0f);
    a.normal = b.normal = e.normal = fn;
  }
  if (skin) pass(out, false, true);
}

Mesh deform(const Mesh& base, const Deformation& d, raster::ThreadPool* pool) {
  Mesh out = base;
  deform(base, d, out, pool);
  return out;
}

}  // namespace softpbr::pbr::gltf
