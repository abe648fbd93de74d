// textured — a fragment shader that samples a texture: the raster library's texture API.
//
//   textured [out.png] [--image picture.png|.jpg] [--anisotropy N] [--threads N]
//
// A floor quad stretching to the horizon, textured with the given image (or a built-in
// checkerboard) through a mipmapped, anisotropically filtered sampler, and an unlit
// shader: colour = texture(uv). Both forms of the shader are shown — fragment() for one
// pixel and fragment_packet<F>() for lanes of pixels — and give the same bits.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

#include <glm/glm.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "softpbr/pbr/camera.h"
#include "softpbr/raster/raster.h"

namespace raster = softpbr::raster;
namespace image = softpbr::image;
namespace pbr = softpbr::pbr;

struct TexturedShader {
  struct Vertex {
    glm::vec3 position;
    glm::vec2 uv;
  };
  struct Varyings {
    glm::vec2 uv;
  };
  // Lookups need the UV derivatives (the default; shaders that read none say false).
  static constexpr bool kUsesDerivatives = true;

  glm::mat4 view_projection;
  std::shared_ptr<const raster::Texture> texture;
  raster::Sampler sampler;

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.uv = in.uv;
    return view_projection * glm::vec4(in.position, 1.0f);
  }
  // One pixel: the UV and its screen-space derivatives pick the mip level and footprint.
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    return texture->sample(sampler, f.v.uv, f.ddx.uv, f.ddy.uv);
  }
  // Lanes of pixels: varying k of every lane is p.v[k] (uv.x is 0, uv.y is 1).
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return raster::sample(*texture, sampler, p.v[0], p.v[1], p.ddx[0], p.ddx[1], p.ddy[0], p.ddy[1]);
  }
};

static image::Image8 checkerboard() {
  image::Image8 im;
  im.width = im.height = 512;
  im.rgba.resize(512 * 512 * 4);
  for (int y = 0; y < 512; ++y)
    for (int x = 0; x < 512; ++x) {
      const bool dark = ((x / 64) + (y / 64)) % 2 == 1;
      std::uint8_t* p = &im.rgba[(static_cast<std::size_t>(y) * 512 + x) * 4];
      p[0] = dark ? 30 : 235;
      p[1] = dark ? 80 : 200;
      p[2] = dark ? 140 : 120;
      p[3] = 255;
    }
  return im;
}

int main(int argc, char** argv) {
  std::string out = "textured.png", picture;
  int anisotropy = 16;
  raster::RendererOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--image" && i + 1 < argc) {
      picture = argv[++i];
    } else if (arg == "--anisotropy" && i + 1 < argc) {
      anisotropy = std::atoi(argv[++i]);
    } else if (arg == "--threads" && i + 1 < argc) {
      const int value = std::atoi(argv[++i]);
      options.threads = static_cast<unsigned>(value < 0 ? 0 : value);
    } else if (arg == "-h" || arg == "--help") {
      std::printf("usage: textured [out.png] [--image picture.png] [--anisotropy N] [--threads N]\n");
      return 0;
    } else {
      out = arg;
    }
  }
  try {
    const int width = 960, height = 540;
    raster::Renderer renderer(options);
    raster::Target target(width, height);

    TexturedShader shader;
    // The image's colours are sRGB: decoded exactly before filtering. The mip chain is
    // built once, on the renderer's threads.
    const image::Image8 im = picture.empty() ? checkerboard() : image::load_image8(picture);
    shader.texture = std::make_shared<const raster::Texture>(im, raster::ColorSpace::Srgb, raster::TextureOptions{},
                                                             &renderer.pool());
    shader.sampler.max_anisotropy = anisotropy;  // 1 = trilinear only
    raster::validate(shader.sampler);
    shader.view_projection =
        pbr::perspective(static_cast<float>(softpbr::dmath::radians(50.0)), static_cast<float>(width) / height, 0.1f,
                         200.0f) *
        pbr::look_at({0.0f, 1.0f, 4.0f}, {0.0f, 0.0f, -10.0f}, {0.0f, 1.0f, 0.0f});
    // A 100 × 100 floor with the image repeated 25 times each way (UV beyond [0, 1] wraps).
    const std::vector<TexturedShader::Vertex> floor = {
        {{-50, 0, -50}, {0, 0}}, {{-50, 0, 50}, {0, 25}}, {{50, 0, 50}, {25, 25}}, {{50, 0, -50}, {25, 0}}};
    const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};

    renderer.begin_frame(target, raster::ClearValues{{0.5f, 0.65f, 0.9f, 1.0f}, 1.0f});
    renderer.draw(shader, std::span<const TexturedShader::Vertex>(floor), indices);
    renderer.end_frame();

    image::write_png(out, raster::resolve_srgb8(target));
    std::printf("wrote %s (%dx%d, %d mip levels, %dx anisotropy, hash %016llx)\n", out.c_str(), width, height,
                shader.texture->level_count(), anisotropy, static_cast<unsigned long long>(raster::hash_colors(target)));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "textured: %s\n", e.what());
    return 1;
  }
  return 0;
}
