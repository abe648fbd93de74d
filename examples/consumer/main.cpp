// Draws one triangle with a user-defined shader through the installed softpbr package,
// checks that it covers the pixels it should, and that its PNG (softpbr::image, in memory)
// loads back with the same bytes.
#include <cstdio>

#include <glm/glm.hpp>

#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "softpbr/pbr/camera.h"
#include "softpbr/raster/raster.h"

struct FlatShader {
  struct Vertex {
    glm::vec2 ndc;
  };
  struct Varyings {};
  glm::vec4 vertex(const Vertex& in, Varyings&) const { return {in.ndc, 0.0f, 1.0f}; }
  glm::vec4 fragment(const softpbr::raster::Fragment<Varyings>&) const { return {1, 1, 1, 1}; }
};

int main() {
  softpbr::raster::Renderer renderer({.threads = 2, .tile_size = 16});
  softpbr::raster::Target target(32, 32);
  target.clear({0, 0, 0, 1});
  const FlatShader::Vertex tri[] = {{{-1, -1}}, {{1, -1}}, {{-1, 1}}};  // lower-left half
  renderer.begin_frame(target);
  renderer.draw(FlatShader{}, tri);
  renderer.end_frame();
  int lit = 0;
  for (const glm::vec4& c : target.colors()) lit += c.r > 0.5f;
  // The diagonal's pixel centres all lie exactly on the edge: one side owns them.
  const bool ok = lit == 32 * 31 / 2 || lit == 32 * 33 / 2;
  std::printf("consumer: %d of 1024 pixels lit: %s\n", lit, ok ? "ok" : "WRONG");
  const softpbr::image::Image8 image = softpbr::raster::resolve_srgb8(target);
  const bool png_ok = softpbr::image::load_png(softpbr::image::encode_png(image, "consumer"), "consumer").rgba == image.rgba;
  std::printf("consumer: PNG round trip through softpbr::image: %s\n", png_ok ? "ok" : "WRONG");
  return ok && png_ok ? 0 : 1;
}
