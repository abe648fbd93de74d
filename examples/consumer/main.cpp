// Draws one triangle with a user-defined shader through the installed softpbr package,
// checks that it covers the pixels it should, that its PNG (softpbr::image, in memory)
// loads back with the same bytes, and that softpbr::loaders reads a one-triangle glTF
// through the header path of the releases before loaders/ (a forwarding header), and that
// softpbr::job checks a render's settings.
#include <cstdint>
#include <cstdio>
#include <string_view>

#include <glm/glm.hpp>

#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "softpbr/job/render_job.h"
#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/gltf.h"  // the old path of softpbr/loaders/gltf.h, kept for one release
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
  // One triangle, (0,0,0) (1,0,0) (0,1,0), its positions in a data URI.
  constexpr std::string_view gltf =
      R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],)"
      R"( "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],)"
      R"( "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",)"
      R"( "min": [0, 0, 0], "max": [1, 1, 0]}],)"
      R"( "bufferViews": [{"buffer": 0, "byteLength": 36}],)"
      R"( "buffers": [{"byteLength": 36,)"
      R"( "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
  const softpbr::pbr::GltfScene model = softpbr::pbr::load_gltf(
      {reinterpret_cast<const std::uint8_t*>(gltf.data()), gltf.size()}, "triangle.gltf", ".");
  const bool gltf_ok = model.objects.size() == 1 && model.triangles == 1;
  std::printf("consumer: a glTF triangle through softpbr::loaders: %s\n", gltf_ok ? "ok" : "WRONG");
  bool job_ok = false;
  try {
    softpbr::job::validate({.msaa = 3});
  } catch (const softpbr::job::Error& e) {
    job_ok = softpbr::job::option_text(e) == "--msaa: expected 1, 4 or 8, got 3";
  }
  std::printf("consumer: a render's settings checked by softpbr::job: %s\n", job_ok ? "ok" : "WRONG");
  return ok && png_ok && gltf_ok && job_ok ? 0 : 1;
}
