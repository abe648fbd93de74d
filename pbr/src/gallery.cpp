// The paper's gallery scene (see gallery.h).
#include "softpbr/pbr/gallery.h"

#include <algorithm>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr {

Scene make_gallery(const GalleryOptions& o) {
  if (o.rows.empty() || o.columns < 1) throw std::invalid_argument("gallery: needs at least one row and one column");
  std::shared_ptr<const Mesh> mesh = o.mesh;
  glm::mat4 fit(1.0f);
  if (mesh) {
    // Rotation about y from deterministic sin/cos (glm::rotate would call libm).
    const float c = static_cast<float>(dmath::cos(o.mesh_yaw)), s = static_cast<float>(dmath::sin(o.mesh_yaw));
    glm::mat4 turn(1.0f);
    turn[0][0] = c;
    turn[0][2] = -s;
    turn[2][0] = s;
    turn[2][2] = c;
    fit = turn * fit_transform(bounds(*mesh), 0.8f);
  } else {
    mesh = std::make_shared<Mesh>(uv_sphere(0.4f, o.segments, std::max(2, o.segments / 2)));
  }

  Scene scene;
  scene.camera.position = {0.0f, 0.0f, 9.0f};
  scene.camera.target = {0.0f, 0.0f, 0.0f};
  scene.camera.fovy = static_cast<float>(dmath::radians(45.0));
  scene.camera.near = 0.1f;
  scene.camera.far = 100.0f;
  scene.ambient = glm::vec3(0.03f);
  for (const glm::vec3 p : {glm::vec3(-4, 4, 6), glm::vec3(4, 4, 6), glm::vec3(0, -4, 6)}) {
    Light l;
    l.type = LightType::Point;
    l.position = p;
    l.intensity = 60.0f;
    scene.lights.push_back(l);
  }

  const int rows = static_cast<int>(o.rows.size());
  for (int r = 0; r < rows; ++r) {
    const auto preset = material_preset(o.rows[r]);
    if (!preset) throw std::invalid_argument("gallery: unknown material preset \"" + o.rows[r] + "\"");
    for (int c = 0; c < o.columns; ++c) {
      Material m = *preset;
      const float t = o.columns > 1 ? static_cast<float>(c) / static_cast<float>(o.columns - 1) : 0.0f;
      m.roughness = std::clamp(o.first_roughness + (o.last_roughness - o.first_roughness) * t, 0.0f, 1.0f);
      const glm::vec3 centre(static_cast<float>(c) - 0.5f * static_cast<float>(o.columns - 1),
                             0.5f * static_cast<float>(rows - 1) - static_cast<float>(r), 0.0f);
      scene.objects.push_back({mesh, m, glm::translate(glm::mat4(1.0f), centre) * fit});
    }
  }
  return scene;
}

}  // namespace softpbr::pbr
