// spheres — the first softpbr program: lit spheres drawn by the raster library to a PNG.
//
//   spheres [out.png] [--threads N] [--tile-size T]
//
// A 5×3 grid of spheres, each a different colour, lit by one directional light with a
// Lambert term and a little ambient light. The shader is a plain C++ type.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <glm/glm.hpp>

#include "softpbr/image/write.h"
#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/raster/raster.h"

namespace raster = softpbr::raster;
namespace pbr = softpbr::pbr;

struct LambertShader {
  using Vertex = pbr::MeshVertex;
  struct Varyings {
    glm::vec3 normal;  // world space
  };
  glm::mat4 view_projection;
  glm::vec3 offset;      // this sphere's position in the world
  glm::vec3 albedo;      // linear
  glm::vec3 to_light;    // normalised direction towards the light

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.normal = in.normal;
    return view_projection * glm::vec4(in.position + offset, 1.0f);
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const glm::vec3 n = glm::normalize(f.v.normal);
    const float diffuse = glm::max(glm::dot(n, to_light), 0.0f);
    return glm::vec4(albedo * (0.03f + 0.97f * diffuse), 1.0f);
  }
};

int main(int argc, char** argv) {
  std::string out = "spheres.png";
  raster::RendererOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--threads" || arg == "--tile-size") && i + 1 < argc) {
      const int value = std::atoi(argv[++i]);
      if (arg == "--threads") options.threads = static_cast<unsigned>(value < 0 ? 0 : value);
      else options.tile_size = value;
    } else if (arg == "-h" || arg == "--help") {
      std::printf("usage: spheres [out.png] [--threads N] [--tile-size T]\n");
      return 0;
    } else {
      out = arg;
    }
  }
  try {
    const int width = 960, height = 540;
    raster::Renderer renderer(options);
    raster::Target target(width, height);
    target.clear({0.02f, 0.02f, 0.025f, 1.0f});

    const pbr::Mesh sphere = pbr::uv_sphere(0.42f, 64, 32);
    const glm::mat4 vp = pbr::perspective(static_cast<float>(softpbr::dmath::radians(40.0)),
                                          static_cast<float>(width) / height, 0.1f, 100.0f) *
                         pbr::look_at({0, 0, 5.6f}, {0, 0, 0}, {0, 1, 0});
    const glm::vec3 colors[3][5] = {
        {{0.80f, 0.10f, 0.10f}, {0.90f, 0.45f, 0.05f}, {0.85f, 0.80f, 0.10f}, {0.20f, 0.70f, 0.15f}, {0.10f, 0.50f, 0.80f}},
        {{0.30f, 0.20f, 0.80f}, {0.65f, 0.20f, 0.75f}, {0.90f, 0.90f, 0.90f}, {0.40f, 0.40f, 0.40f}, {0.10f, 0.10f, 0.10f}},
        {{1.00f, 0.71f, 0.29f}, {0.95f, 0.64f, 0.54f}, {0.95f, 0.93f, 0.88f}, {0.56f, 0.57f, 0.58f}, {0.91f, 0.92f, 0.92f}},
    };

    renderer.begin_frame(target);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 5; ++col) {
        const LambertShader shader{vp, {(col - 2) * 1.0f, (1 - row) * 1.0f, 0.0f}, colors[row][col],
                                   glm::normalize(glm::vec3(-0.5f, 0.7f, 0.6f))};
        raster::DrawState state;
        state.cull = raster::Cull::Back;
        renderer.draw(shader, sphere.vertices, sphere.indices, state);
      }
    renderer.end_frame();

    softpbr::image::write_png(out, raster::resolve_srgb8(target));
    std::printf("wrote %s (%dx%d, %u threads, hash %016llx)\n", out.c_str(), width, height, renderer.threads(),
                static_cast<unsigned long long>(raster::hash_colors(target)));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "spheres: %s\n", e.what());
    return 1;
  }
  return 0;
}
