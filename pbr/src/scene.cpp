// Rendering a scene with the PBR shader (see scene.h).
#include "softpbr/pbr/scene.h"

#include <stdexcept>
#include <string>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "softpbr/pbr/shading.h"

namespace softpbr::pbr {

namespace {
template <class F>
auto with_context(const std::string& where, F&& f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(where + ": " + e.what());
  }
}
}  // namespace

namespace {
void render_frame(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                  const raster::Renderer::TileCallback& after_tile);
}  // namespace

void render(const Scene& scene, raster::Renderer& renderer, raster::Target& target) {
  render_frame(scene, renderer, target, nullptr);
}

void render_rgba8(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                  const OutputSettings& output, raster::Image8& image) {
  const ToneMapper mapper(output);
  image.width = target.width();
  image.height = target.height();
  image.rgba.resize(static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(target.height()) * 4);
  render_frame(scene, renderer, target, [&](const raster::TileRect& r, bool only_clear) {
    if (only_clear) mapper.encode_uniform(scene.background, r.x0, r.y0, r.x1, r.y1, image);
    else mapper.encode(target, r.x0, r.y0, r.x1, r.y1, image);
  });
}

namespace {
void render_frame(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                  const raster::Renderer::TileCallback& after_tile) {
  validate(scene.camera);
  // Validate and prepare everything before the frame starts.
  auto lights = std::make_shared<std::vector<PreparedLight>>();
  lights->reserve(scene.lights.size());
  for (std::size_t i = 0; i < scene.lights.size(); ++i)
    lights->push_back(with_context("lights[" + std::to_string(i) + "]", [&] { return prepare_light(scene.lights[i]); }));
  std::vector<PbrShader> shaders;
  shaders.reserve(scene.objects.size());
  const glm::mat4 view_projection =
      scene.camera.projection(static_cast<float>(target.width()) / static_cast<float>(target.height())) *
      scene.camera.view();
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    const std::string where = "objects[" + std::to_string(i) + "]";
    if (!o.mesh) throw std::invalid_argument(where + ": has no mesh");
    PbrShader s;
    s.material = with_context(where, [&] { return prepare_material(o.material); });
    s.model = o.transform;
    s.normal_matrix = glm::transpose(glm::inverse(glm::mat3(o.transform)));
    s.view_projection = view_projection;
    s.eye = scene.camera.position;
    s.ambient = scene.ambient;
    s.lights = lights;
    shaders.push_back(s);
  }

  raster::DrawState state;
  state.cull = raster::Cull::Back;
  renderer.begin_frame(target, raster::ClearValues{scene.background, 1.0f});
  try {
    for (std::size_t i = 0; i < scene.objects.size(); ++i)
      renderer.draw(shaders[i], scene.objects[i].mesh->vertices, scene.objects[i].mesh->indices, state);
  } catch (...) {
    renderer.end_frame();
    throw;
  }
  renderer.end_frame(after_tile);
}
}  // namespace

}  // namespace softpbr::pbr
