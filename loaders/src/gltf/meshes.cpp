// The glTF reader's meshes (see meshes.h).
#include "gltf/meshes.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include <glm/geometric.hpp>

#include "gltf/draco.h"
#include "softpbr/loaders/loaded_scene.h"

namespace softpbr::pbr::gltf {

void Meshes::check_draco_indices(std::size_t mesh, std::size_t k, const std::string& pointer) const {
  if (const auto d = draco_indices_.find({mesh, k}); d != draco_indices_.end())
    if (d->second < 0 || static_cast<std::size_t>(d->second) >= m_.accessors.size())
      fail(pointer + "/indices", "accessor " + std::to_string(d->second) + " does not exist");
}

std::uint64_t Meshes::draw_bytes_lower_bound(int index) const {
  const tg::Mesh& mesh = m_.meshes[static_cast<std::size_t>(index)];
  auto count = [&](int a) -> std::uint64_t {
    return a >= 0 && static_cast<std::size_t>(a) < m_.accessors.size() ? m_.accessors[static_cast<std::size_t>(a)].count : 0;
  };
  std::uint64_t bytes = 0;
  for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
    const tg::Primitive& p = mesh.primitives[k];
    const auto position = p.attributes.find("POSITION");
    const std::uint64_t vertices = position != p.attributes.end() ? count(position->second) : 0;
    const auto d = draco_indices_.find({static_cast<std::size_t>(index), k});
    const std::uint64_t corners = d != draco_indices_.end() ? count(d->second) : p.indices >= 0 ? count(p.indices) : vertices;
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    const std::uint64_t triangles = mode == TINYGLTF_MODE_TRIANGLES ? corners / 3
                                    : mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN
                                        ? (corners >= 2 ? corners - 2 : 0)
                                        : 0;
    if (triangles > 0) bytes += object_draw_bytes(std::min(vertices, kMaxElements), std::min(triangles, kMaxElements));
  }
  return bytes;
}

std::shared_ptr<const Mesh> Meshes::primitive(int mesh, std::size_t k, bool mirrored, const std::string& pointer,
                                              bool normal_mapped) {
  const auto key = std::make_tuple(mesh, k, mirrored);
  auto it = meshes_.find(key);
  if (it == meshes_.end()) {
    const auto unmirrored = std::make_tuple(mesh, k, false);
    auto base = meshes_.find(unmirrored);
    const tg::Primitive& p = m_.meshes[static_cast<std::size_t>(mesh)].primitives[k];
    const auto d = draco_indices_.find({static_cast<std::size_t>(mesh), k});
    const int draco_indices = d != draco_indices_.end() ? d->second : -1;
    std::shared_ptr<const Mesh> m =
        base != meshes_.end() ? base->second : primitive_mesh(p, pointer, normal_mapped, draco_indices);
    if (base == meshes_.end()) meshes_[unmirrored] = m;
    if (mirrored) {
      // A mirroring transform turns counter-clockwise triangles clockwise on screen.
      auto flipped = std::make_shared<Mesh>(*m);
      for (std::size_t t = 0; t + 2 < flipped->indices.size(); t += 3) std::swap(flipped->indices[t + 1], flipped->indices[t + 2]);
      m = flipped;
      meshes_[key] = m;
    }
    it = meshes_.find(key);
  }
  return it->second;
}

const Meshes::VertexSources Meshes::no_sources_{};

const Meshes::VertexSources& Meshes::vertex_sources(int mesh, std::size_t k) const {
  const auto it = meshes_.find(std::make_tuple(mesh, k, false));
  if (it == meshes_.end()) return no_sources_;
  const auto s = sources_.find(it->second.get());
  return s == sources_.end() ? no_sources_ : s->second;
}

// The triangles of a primitive's index list for its mode (glTF 2.0, §3.7.2.1).
std::vector<std::uint32_t> Meshes::triangles(int mode, const std::vector<std::uint32_t>& v) const {
  std::vector<std::uint32_t> t;
  const std::size_t n = v.size();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    t.assign(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n - n % 3));
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t i = 0; i + 2 < n; ++i) {
      const std::size_t odd = i % 2;
      t.insert(t.end(), {v[i], v[i + 1 + odd], v[i + 2 - odd]});
    }
  } else {  // TRIANGLE_FAN
    for (std::size_t i = 1; i + 1 < n; ++i) t.insert(t.end(), {v[i], v[i + 1], v[0]});
  }
  return t;
}

std::shared_ptr<const Mesh> Meshes::primitive_mesh(const tg::Primitive& p, const std::string& pointer, bool normal_mapped,
                                                   int draco_indices) {
  auto attribute = [&](const char* name) {
    const auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
  };
  const int position = attribute("POSITION");
  if (position < 0) fail(pointer + "/attributes", "has no POSITION");
  const std::string ap = pointer + "/attributes/";
  // KHR_draco_mesh_compression: the attributes it names and the triangles come from the
  // Draco data, described by the primitive's accessors.
  std::optional<DracoMesh> draco;
  if (const auto it = p.extensions.find(kDraco); it != p.extensions.end())
    draco = resources_.draco_mesh(it->second, pointer + "/extensions/" + kDraco);
  auto values = [&](const char* name, int a, std::initializer_list<int> allowed, int* comps) {
    if (!draco || draco->attributes.count(name) == 0) return resources_.read_floats(a, ap + name, allowed, comps);
    return resources_.draco_values(*draco, name, a, ap + name, allowed, comps);
  };
  const std::vector<float> pos = values("POSITION", position, {3}, nullptr);
  const std::size_t n = pos.size() / 3;
  for (std::size_t i = 0; i < pos.size(); ++i)
    if (!std::isfinite(pos[i]))
      fail("/accessors/" + std::to_string(position), "position " + str(i / 3) + " is not finite");
  auto optional = [&](const char* name, std::initializer_list<int> allowed, int* comps = nullptr) {
    const int a = attribute(name);
    if (a < 0) return std::vector<float>{};
    std::vector<float> v = values(name, a, allowed, comps);
    if (v.size() / static_cast<std::size_t>(comps != nullptr ? *comps : *allowed.begin()) != n)
      fail(ap + name, "has " + str(m_.accessors[static_cast<std::size_t>(a)].count) + " elements for " + str(n) +
                          " positions");
    for (float x : v)
      if (!std::isfinite(x)) fail("/accessors/" + std::to_string(a), "holds a value that is not finite");
    return v;
  };
  const std::vector<float> normal = optional("NORMAL", {3});
  const std::vector<float> tangent = optional("TANGENT", {4});
  const std::vector<float> uv0 = optional("TEXCOORD_0", {2});
  const std::vector<float> uv1 = optional("TEXCOORD_1", {2});
  int color_comps = 4;
  const std::vector<float> color = optional("COLOR_0", {3, 4}, &color_comps);

  std::vector<std::uint32_t> order;
  if (draco) {
    // The triangles, held to their indices accessor's description when there is one.
    order = draco_indices >= 0 ? resources_.draco_indices(*draco, draco_indices, pointer + "/indices") : draco->indices;
  } else if (p.indices >= 0) {
    order = resources_.read_indices(p.indices, n, pointer + "/indices");
  } else {
    order.resize(n);
    std::iota(order.begin(), order.end(), 0u);
  }
  const int mode = draco ? TINYGLTF_MODE_TRIANGLES : p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  auto mesh = std::make_shared<Mesh>();
  mesh->indices = triangles(mode, order);
  mesh->vertices.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    MeshVertex& v = mesh->vertices[i];
    v.position = {pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]};
    v.normal = normal.empty() ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(normal[3 * i], normal[3 * i + 1], normal[3 * i + 2]);
    v.uv = uv0.empty() ? glm::vec2(0.0f) : glm::vec2(uv0[2 * i], uv0[2 * i + 1]);
  }
  if (!tangent.empty()) {
    mesh->tangents.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      mesh->tangents[i] = {tangent[4 * i], tangent[4 * i + 1], tangent[4 * i + 2], tangent[4 * i + 3] < 0.0f ? -1.0f : 1.0f};
  }
  if (!uv1.empty()) {
    mesh->uv1.resize(n);
    for (std::size_t i = 0; i < n; ++i) mesh->uv1[i] = {uv1[2 * i], uv1[2 * i + 1]};
  }
  if (!color.empty()) {
    const auto c = static_cast<std::size_t>(color_comps);
    mesh->colors.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      mesh->colors[i] = {color[c * i], color[c * i + 1], color[c * i + 2], c == 4 ? color[c * i + 3] : 1.0f};
  }
  // Where each vertex comes from, when flat normals or split tangents make new ones.
  VertexSources sources;
  if (normal.empty()) {
    sources.sources = mesh->indices;  // flat_normals gives each corner a vertex of its own
    sources.flat = true;
    flat_normals(*mesh);
  }
  if (normal_mapped && mesh->tangents.empty()) {
    const std::vector<std::uint32_t> before = mesh->indices;
    const std::size_t count = mesh->vertices.size();
    generate_tangents(*mesh);
    if (mesh->vertices.size() > count) {
      // A split vertex is a copy appended for some corners: its source is theirs before.
      if (sources.sources.empty()) {
        sources.sources.resize(count);
        std::iota(sources.sources.begin(), sources.sources.end(), 0u);
      }
      const std::vector<std::uint32_t> old = sources.sources;
      sources.sources.resize(mesh->vertices.size());
      for (std::size_t c = 0; c < before.size(); ++c)
        if (mesh->indices[c] >= count) sources.sources[mesh->indices[c]] = old[before[c]];
    }
  }
  out_.triangles += mesh->triangle_count();
  if (!sources.sources.empty()) sources_[mesh.get()] = std::move(sources);
  return mesh;
}

// glTF: "When normals are not specified, client implementations MUST calculate flat
// normals": every triangle gets vertices of its own with the face's normal.
void Meshes::flat_normals(Mesh& mesh) {
  Mesh flat;
  const std::size_t corners = mesh.indices.size();
  flat.vertices.reserve(corners);
  flat.indices.resize(corners);
  const bool t = !mesh.tangents.empty(), u = !mesh.uv1.empty(), c = !mesh.colors.empty();
  for (std::size_t k = 0; k < corners; k += 3) {
    const glm::vec3 a = mesh.vertices[mesh.indices[k]].position, b = mesh.vertices[mesh.indices[k + 1]].position,
                    d = mesh.vertices[mesh.indices[k + 2]].position;
    const glm::vec3 cr = glm::cross(b - a, d - a);
    const float len = std::sqrt(glm::dot(cr, cr));
    const glm::vec3 n = len > 0.0f && std::isfinite(len) ? cr / len : glm::vec3(0.0f, 1.0f, 0.0f);
    for (std::size_t j = 0; j < 3; ++j) {
      const std::uint32_t src = mesh.indices[k + j];
      MeshVertex v = mesh.vertices[src];
      v.normal = n;
      flat.indices[k + j] = static_cast<std::uint32_t>(flat.vertices.size());
      flat.vertices.push_back(v);
      if (t) flat.tangents.push_back(mesh.tangents[src]);
      if (u) flat.uv1.push_back(mesh.uv1[src]);
      if (c) flat.colors.push_back(mesh.colors[src]);
    }
  }
  mesh = std::move(flat);
}

}  // namespace softpbr::pbr::gltf
