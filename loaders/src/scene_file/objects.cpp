// Scene files: objects, a mesh placed by a transform with a material, and what drawing them
// costs (see scene_file/loader.h).
#include "loader.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/raster/renderer.h"

namespace softpbr::pbr::scene_file {

namespace {

// Bytes drawing a mesh with the PbrShader holds until the frame is rasterized, as the
// rasterizer counts them.
std::uint64_t draw_bytes(std::uint64_t vertices, std::uint64_t triangles) {
  return raster::draw_geometry_bytes(vertices, triangles, raster::kVaryingCount<PbrShader::Varyings>);
}

// Rotation about one axis by `degrees` (0 x, 1 y, 2 z), sine and cosine from dmath.
glm::mat4 axis_rotation(int axis, double degrees) {
  const double angle = static_cast<float>(dmath::radians(degrees));
  const float c = static_cast<float>(dmath::cos(angle)), s = static_cast<float>(dmath::sin(angle));
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // the plane the rotation turns
  glm::mat4 m(1.0f);
  m[i][i] = c;
  m[i][j] = s;
  m[j][i] = -s;
  m[j][j] = c;
  return m;
}

}  // namespace

glm::mat4 read_transform(const Reader& r, const Node& spec) {
  if (auto m = r.member(spec, "matrix")) {
    r.object(spec, {"matrix"});
    if (!m->value.is_array() || m->value.size() != 4)
      r.fail(*m, "expected 4 rows of 4 numbers, got " + json_reader::show(m->value));
    glm::mat4 out;
    for (int row = 0; row < 4; ++row) {
      const std::vector<float> v = r.numbers(m->at(row), 4, -1e30, 1e30);
      for (int col = 0; col < 4; ++col) out[col][row] = v[col];  // glm is column-major
    }
    if (out[0][3] != 0 || out[1][3] != 0 || out[2][3] != 0 || out[3][3] != 1)
      r.fail(m->pointer + "/3", "expected the last row to be [0, 0, 0, 1] (an affine transform), got " + json_reader::show(m->value.at(3)));
    const float det = glm::determinant(glm::mat3(out));
    if (!std::isfinite(det) || det == 0.0f) r.fail(*m, "expected an invertible matrix, its 3x3 part has determinant " + json_reader::show_number(det));
    return out;
  }
  r.object(spec, {"translate", "rotate", "scale", "matrix"});
  // M = T · Rz · Ry · Rx · S (scale first, then rotate x, y, z, then translate); factors not
  // given are skipped, not multiplied as identities.
  glm::mat4 out(1.0f);
  bool any = false;
  auto apply = [&](const glm::mat4& m) { out = any ? m * out : m, any = true; };
  if (auto s = r.member(spec, "scale")) {
    glm::vec3 v;
    if (s->value.is_number()) v = glm::vec3(r.number_f(*s, 0, 1e30, true));
    else v = r.vec3(*s, -1e30, 1e30);
    if (v.x == 0 || v.y == 0 || v.z == 0) r.fail(*s, "expected non-zero scale factors, got " + json_reader::show(s->value));
    apply(glm::scale(glm::mat4(1.0f), v));
  }
  if (auto rot = r.member(spec, "rotate")) {
    const std::vector<float> deg = r.numbers(*rot, 3, -360, 360);
    const double exact[3] = {rot->value[0].get<double>(), rot->value[1].get<double>(), rot->value[2].get<double>()};
    for (int axis = 0; axis < 3; ++axis)
      if (deg[axis] != 0.0f) apply(axis_rotation(axis, exact[axis]));
  }
  if (auto t = r.member(spec, "translate")) apply(glm::translate(glm::mat4(1.0f), r.vec3(*t)));
  return out;
}

void read_object(const Reader& r, const Node& spec, MeshLibrary& meshes, TextureLibrary& textures, MemoryBudget& budget,
                 SceneFile& out) {
  r.object(spec, {"name", "mesh", "material", "transform", "cast_shadows", "receive_shadows"});
  if (auto n = r.member(spec, "name")) r.string(*n);
  bool cast_shadows = true, receive_shadows = true;
  if (auto c = r.member(spec, "cast_shadows")) cast_shadows = r.boolean(*c);
  if (auto c = r.member(spec, "receive_shadows")) receive_shadows = r.boolean(*c);
  LoadedMesh& m = meshes.mesh(r.required(spec, "mesh"));
  const glm::mat4 placed = [&] {
    const auto t = r.member(spec, "transform");
    if (!t) return m.fit;
    const glm::mat4 tr = read_transform(r, *t);
    return m.has_fit ? tr * m.fit : tr;
  }();
  auto add = [&](std::shared_ptr<const Mesh> mesh, const Material& material, const Node& where) {
    if (material.normal_texture && mesh->tangents.empty()) {
      // A normal map needs tangents: generated once here, not by every frame's render().
      auto& generated = m.with_tangents[mesh.get()];
      if (!generated) {
        auto copy = std::make_shared<Mesh>(*mesh);
        check_at(r, where, [&] { generate_tangents(*copy); });
        budget.charge(where, mesh_bytes(copy->vertices.size(), copy->triangle_count()) +
                                 copy->tangents.size() * sizeof(glm::vec4),
                      "this mesh's tangents");
        generated = copy;
      }
      mesh = generated;
    }
    if (out.scene.objects.size() >= kMaxObjects)
      r.fail(where, "too many objects to draw (the limit is " + std::to_string(kMaxObjects) + ": each is a draw call)");
    budget.charge(where, draw_bytes(mesh->vertices.size(), mesh->triangle_count()), "drawing this object");
    out.triangles += mesh->triangle_count();
    out.scene.objects.push_back({std::move(mesh), material, placed, cast_shadows, receive_shadows});
  };
  if (auto mat = r.member(spec, "material")) {
    const Material material = read_material(r, *mat, textures);
    if (m.parts.size() == 1) {
      add(m.parts[0], material, spec);
    } else {
      // One material for a whole OBJ model: draw its shapes merged, as make_gallery does.
      if (!m.merged) {
        auto merged = std::make_shared<const Mesh>(merge_shapes(*m.obj));
        budget.charge(spec, mesh_bytes(merged->vertices.size(), merged->triangle_count()), "merging this model");
        m.merged = merged;
      }
      add(m.merged, material, spec);
    }
  } else {
    for (std::size_t i = 0; i < m.parts.size(); ++i) {
      const int k = m.part_material[i];
      add(m.parts[i], k >= 0 ? m.materials[static_cast<std::size_t>(k)] : Material{}, spec);
    }
  }
}

}  // namespace softpbr::pbr::scene_file
