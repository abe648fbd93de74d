// The memory estimate of a scene made object by object (see loaded_scene.h).
#include "softpbr/loaders/loaded_scene.h"

#include "softpbr/pbr/textured_shading.h"
#include "softpbr/raster/renderer.h"

namespace softpbr::pbr {

namespace {
// Floats a vertex of a textured draw carries to the rasterizer: the most of any shader a
// loaded material selects (pbr/src/scene.cpp picks it per object).
constexpr int kDrawVaryings = raster::kVaryingCount<TexturedPbrShader::Varyings>;
static_assert(kDrawVaryings >= raster::kVaryingCount<PbrShader::Varyings>);
}  // namespace

std::uint64_t object_draw_bytes(std::uint64_t vertices, std::uint64_t triangles) {
  return raster::draw_geometry_bytes(static_cast<std::size_t>(vertices), static_cast<std::size_t>(triangles), kDrawVaryings);
}

void count_object_memory(LoadedScene& f, const Object& o, std::set<const void*>& counted) {
  f.mesh_bytes += object_draw_bytes(o.mesh->vertices.size(), o.mesh->triangle_count());
  if (counted.insert(o.mesh.get()).second)
    f.mesh_bytes += o.mesh->vertices.size() * sizeof(MeshVertex) + o.mesh->indices.size() * 4;
  for (const TextureSlot* t : {&o.material.base_color_texture, &o.material.metallic_roughness_texture,
                               &o.material.normal_texture, &o.material.occlusion_texture, &o.material.emissive_texture})
    if (t->texture && counted.insert(t->texture.get()).second) f.texture_bytes += t->texture->texel_bytes();
}

}  // namespace softpbr::pbr
