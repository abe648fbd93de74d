// The benchmark scenes (see scenes.h).
#include "scenes.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/loaders/obj.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/mesh.h"

namespace softpbr::bench {

namespace {

std::size_t count_triangles(const pbr::Scene& s) {
  std::size_t n = 0;
  for (const pbr::Object& o : s.objects) n += o.mesh->triangle_count();
  return n;
}

std::string size_suffix(int width, int height) {
  if (width == 1920 && height == 1080) return "1080p";
  return std::to_string(width) + "x" + std::to_string(height);
}

// The three rows: gold and copper metal, red dielectric (0.8, 0.1, 0.1) — the
// "plastic_red" preset, whose roughness the gallery overrides per column.
pbr::GalleryOptions benchmark_gallery_options() {
  pbr::GalleryOptions o;
  o.rows = {"gold", "copper", "plastic_red"};
  o.columns = 7;
  o.first_roughness = 0.05f;
  o.last_roughness = 1.0f;
  return o;
}

// A 32-bit integer hash (the finalizer of MurmurHash3).
std::uint32_t mix(std::uint32_t h) {
  h ^= h >> 16;
  h *= 0x85ebca6bu;
  h ^= h >> 13;
  h *= 0xc2b2ae35u;
  h ^= h >> 16;
  return h;
}

// `material` with benchmark_texture() as its base colour texture through `sampler`.
pbr::Material with_base_texture(pbr::Material material, const raster::Sampler& sampler) {
  material.base_color_texture.texture = benchmark_texture();
  material.base_color_texture.sampler = sampler;
  return material;
}

}  // namespace

std::shared_ptr<const raster::Texture> benchmark_texture() {
  static const std::shared_ptr<const raster::Texture> texture = [] {
    constexpr int kSize = 2048, kCell = 64;
    image::Image8 im;
    im.width = im.height = kSize;
    im.rgba.resize(static_cast<std::size_t>(kSize) * kSize * 4);
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        std::uint8_t* p = &im.rgba[(static_cast<std::size_t>(y) * kSize + static_cast<std::size_t>(x)) * 4];
        const int cx = x / kCell, cy = y / kCell;
        const std::uint32_t cell = mix(static_cast<std::uint32_t>(cx) * 0x9e3779b1u + static_cast<std::uint32_t>(cy));
        const std::uint32_t noise = mix(static_cast<std::uint32_t>(y) * 0x01000193u ^ static_cast<std::uint32_t>(x) * 0x27d4eb2fu);
        const bool dark = (cx + cy) % 2 == 1;
        const bool line = x % kCell < 2 || y % kCell < 2;
        for (int ch = 0; ch < 3; ++ch) {
          int c = 40 + static_cast<int>((cell >> (8 * ch)) & 0xffu) * 190 / 255;  // 40 … 230
          if (dark) c = c * 3 / 5;
          c += static_cast<int>((noise >> (8 * ch)) % 49u) - 24;
          if (line) c = 235;
          p[ch] = static_cast<std::uint8_t>(std::clamp(c, 0, 255));
        }
        p[3] = 255;
      }
    return std::make_shared<const raster::Texture>(im, raster::ColorSpace::Srgb);
  }();
  return texture;
}

BenchScene gallery_scene(int segments, int width, int height) {
  BenchScene b;
  b.name = "gallery" + std::to_string(segments) + "_" + size_suffix(width, height);
  b.width = width;
  b.height = height;
  b.scene = pbr::make_gallery(benchmark_gallery_options());
  // make_gallery uses segments/2 rings; the triangle counts (169k at 64, 2.7M at
  // 256) are those of segments × segments: one shared sphere, rings = segments.
  auto sphere = std::make_shared<const pbr::Mesh>(pbr::uv_sphere(0.4f, segments, segments));
  for (pbr::Object& o : b.scene.objects) o.mesh = sphere;
  b.output = pbr::gallery_output();
  b.triangles = count_triangles(b.scene);
  return b;
}

BenchScene fill_scene(int width, int height, int layers) {
  BenchScene b;
  b.name = "fill" + std::to_string(layers) + "x_" + size_suffix(width, height);
  b.width = width;
  b.height = height;
  b.scene = pbr::make_gallery(benchmark_gallery_options());  // camera, lights, ambient
  const auto gallery_objects = b.scene.objects;
  b.scene.objects.clear();
  // A 40 × 40 plane facing +z covers the whole view from z = −3.5 to 0 (the view is at
  // most 2 × 12.5 · tan 22.5° × 16/9 ≈ 18.4 wide there); nearer each layer, so with the
  // depth test Less every layer is shaded.
  auto plane = std::make_shared<pbr::Mesh>(pbr::plane(40.0f, 40.0f, 1));
  // plane() lies in y = 0 with normal +y: turn it to face the camera (+z).
  // A quarter turn about x, written out (glm::rotate would call libm): y → z, z → −y.
  glm::mat4 face_camera(1.0f);
  face_camera[1] = {0.0f, 0.0f, 1.0f, 0.0f};   // image of the y axis
  face_camera[2] = {0.0f, -1.0f, 0.0f, 0.0f};  // image of the z axis
  for (int l = 0; l < layers; ++l) {
    const float z = -3.5f + 0.5f * static_cast<float>(l);
    const pbr::Object& like = gallery_objects[static_cast<std::size_t>(l * 3) % gallery_objects.size()];
    b.scene.objects.push_back({plane, like.material, glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, z}) * face_camera});
  }
  b.output = pbr::gallery_output();
  b.overdraw = layers;
  b.triangles = count_triangles(b.scene);
  return b;
}

BenchScene textured_fill_scene(int width, int height, const std::string& tag, glm::vec2 uv_scale,
                               int max_anisotropy, int layers) {
  BenchScene b = fill_scene(width, height, layers);
  b.name = "fill" + std::to_string(layers) + "x_" + tag + "_" + size_suffix(width, height);
  auto plane = std::make_shared<pbr::Mesh>(*b.scene.objects.front().mesh);
  for (pbr::MeshVertex& v : plane->vertices) v.uv *= uv_scale;
  raster::Sampler sampler;  // repeat, trilinear
  sampler.max_anisotropy = max_anisotropy;
  for (pbr::Object& o : b.scene.objects) {
    o.mesh = plane;
    o.material = with_base_texture(o.material, sampler);
  }
  return b;
}

BenchScene textured_gallery_scene(int segments, int width, int height) {
  BenchScene b = gallery_scene(segments, width, height);
  b.name = "gallery" + std::to_string(segments) + "_tex_" + size_suffix(width, height);
  for (pbr::Object& o : b.scene.objects) o.material = with_base_texture(o.material, raster::Sampler{});
  return b;
}

BenchScene ibl_gallery_scene(int width, int height) {
  pbr::SceneFile file =
      pbr::load_scene_file(std::filesystem::path(SOFTPBR_SOURCE_DIR) / "examples" / "scenes" / "gallery_ibl.json");
  BenchScene b;
  b.name = "gallery_ibl_" + size_suffix(width, height);
  b.width = width;
  b.height = height;
  b.scene = std::move(file.scene);
  b.output = file.render.output;
  b.triangles = count_triangles(b.scene);
  return b;
}

std::vector<BenchScene> shadow_gallery_scenes(int width, int height) {
  pbr::SceneFile file =
      pbr::load_scene_file(std::filesystem::path(SOFTPBR_SOURCE_DIR) / "examples" / "scenes" / "gallery_shadows.json");
  BenchScene b;
  b.name = "gallery_shadows_" + size_suffix(width, height);
  b.width = width;
  b.height = height;
  b.scene = std::move(file.scene);
  b.output = file.render.output;
  b.triangles = count_triangles(b.scene);
  BenchScene off = b;
  off.name = "gallery_noshadows_" + size_suffix(width, height);
  for (pbr::Light& l : off.scene.lights) l.shadows = false;
  return {std::move(b), std::move(off)};
}

std::vector<BenchScene> ibl_gallery_variants(int width, int height) {
  const BenchScene base = ibl_gallery_scene(width, height);
  const std::string size = size_suffix(width, height);
  std::vector<BenchScene> v;
  auto variant = [&](const char* tag) -> BenchScene& {
    v.push_back(base);
    v.back().name = std::string("gallery_ibl_") + tag + "_" + size;
    return v.back();
  };
  for (pbr::Object& o : variant("onelevel").scene.objects) {
    const float level = static_cast<float>(static_cast<int>(o.material.roughness * 5.0f + 0.5f));
    o.material.roughness = level / 5.0f;
  }
  variant("nobg").scene.background_mode = pbr::BackgroundMode::Color;
  variant("noocclusion").scene.environment.occlusion = false;
  BenchScene& ambient = variant("ambient");
  ambient.scene.environment = {};
  ambient.scene.background_mode = pbr::BackgroundMode::Color;
  BenchScene& bg = variant("bgonly");
  bg.scene.objects.clear();
  bg.triangles = 1;
  BenchScene& empty = variant("empty");
  empty.scene.objects.clear();
  empty.scene.background_mode = pbr::BackgroundMode::Color;
  empty.triangles = 0;
  return v;
}

std::vector<BenchScene> layered_gallery_variants(int width, int height) {
  const BenchScene base = ibl_gallery_scene(width, height);
  const std::string size = size_suffix(width, height);
  std::vector<BenchScene> v;
  // The IBL gallery with every material given one layer of glTF's material extensions
  // (issue 48): each against gallery_ibl_<size>, the same gallery without it.
  auto variant = [&](const char* tag, auto&& change) {
    v.push_back(base);
    v.back().name = std::string("gallery_layers_") + tag + "_" + size;
    for (pbr::Object& o : v.back().scene.objects) change(o.material);
  };
  variant("specular", [](pbr::Material& m) {
    m.ior = 1.7f;
    m.specular.color = {1.0f, 0.8f, 0.6f};
  });
  variant("clearcoat", [](pbr::Material& m) {
    m.clearcoat.factor = 1.0f;
    m.clearcoat.roughness = 0.1f;
  });
  variant("sheen", [](pbr::Material& m) {
    m.sheen.color = {0.8f, 0.8f, 1.0f};
    m.sheen.roughness = 0.5f;
  });
  variant("all", [](pbr::Material& m) {
    m.ior = 1.7f;
    m.clearcoat.factor = 1.0f;
    m.clearcoat.roughness = 0.1f;
    m.sheen.color = {0.8f, 0.8f, 1.0f};
    m.sheen.roughness = 0.5f;
  });
  variant("anisotropy", [](pbr::Material& m) {
    m.anisotropy.strength = 0.8f;
    m.anisotropy.rotation = 0.5f;
  });
  variant("iridescence", [](pbr::Material& m) {
    m.iridescence.factor = 1.0f;
    m.iridescence.thickness_max = 500.0f;
  });
  // Glass (issue 49): every sphere transmissive, with a volume — the frame adds the opaque
  // pass' copy and its mip chain (here the environment background alone) and the refraction.
  variant("transmission", [](pbr::Material& m) {
    m.transmission.factor = 1.0f;
    m.volume.thickness = 0.5f;
    m.volume.attenuation_distance = 1.0f;
    m.volume.attenuation_color = {0.9f, 0.7f, 0.5f};
  });
  // The same with three punctual lights (the gallery has none: its layers' per-light terms
  // are measured here), against gallery_ibl_lit_<size>.
  const auto lit = [&](BenchScene s, const std::string& name) {
    s.name = name;
    for (const glm::vec3& d : {glm::vec3(-0.4f, -0.6f, -1.0f), glm::vec3(0.7f, -0.3f, -0.6f), glm::vec3(0.0f, 1.0f, -0.5f)}) {
      pbr::Light l;
      l.type = pbr::LightType::Directional;
      l.direction = glm::normalize(d);
      l.intensity = 1.5f;
      s.scene.lights.push_back(l);
    }
    return s;
  };
  const std::size_t layered = v.size();
  v.push_back(lit(base, "gallery_ibl_lit_" + size));
  for (std::size_t i = 0; i < layered; ++i) {
    std::string name = v[i].name;
    name.insert(name.size() - size.size() - 1, "_lit");
    v.push_back(lit(v[i], name));
  }
  return v;
}

std::vector<BenchScene> fill_variants(int width, int height) {
  const BenchScene base = fill_scene(width, height);
  const std::string size = size_suffix(width, height);
  std::vector<BenchScene> v;
  for (std::size_t lights = 0; lights < base.scene.lights.size(); ++lights) {
    v.push_back(base);
    v.back().name = "fill8x_lights" + std::to_string(lights) + "_" + size;
    v.back().scene.lights.resize(lights);
  }
  v.push_back(fill_scene(width, height, 1));
  return v;
}

BenchScene mesh_scene(const std::string& name, const std::filesystem::path& obj, int width, int height) {
  pbr::GalleryOptions o = benchmark_gallery_options();
  o.mesh = std::make_shared<const pbr::Mesh>(pbr::merge_shapes(pbr::load_obj(obj)));
  BenchScene b;
  b.name = "mesh_" + name + "_" + size_suffix(width, height);
  b.width = width;
  b.height = height;
  b.scene = pbr::make_gallery(o);
  b.output = pbr::gallery_output();
  b.triangles = count_triangles(b.scene);
  return b;
}

std::vector<BenchScene> all_scenes(const std::filesystem::path& shared_models) {
  std::vector<BenchScene> scenes;
  scenes.push_back(gallery_scene(64, 1920, 1080));
  scenes.push_back(gallery_scene(16, 1920, 1080));
  scenes.push_back(gallery_scene(256, 1920, 1080));
  scenes.push_back(gallery_scene(64, 512, 512));
  scenes.push_back(fill_scene(1920, 1080));
  scenes.push_back(textured_fill_scene(1920, 1080, "tex", {8.0f, 8.0f}, 1));
  scenes.push_back(textured_fill_scene(1920, 1080, "aniso16", {30.0f, 4.0f}, 16));
  scenes.push_back(textured_gallery_scene(64, 1920, 1080));
  scenes.push_back(ibl_gallery_scene(1920, 1080));
  const struct {
    const char* name;
    const char* file;
  } meshes[] = {{"bunny", "stanford-bunny/stanford-bunny.obj"}, {"armadillo", "armadillo/armadillo.obj"}, {"spot", "spot/spot_triangulated.obj"}};
  std::error_code ec;
  if (!std::filesystem::is_directory(shared_models, ec)) {
    std::fprintf(stderr, "note: %s not found: the shared-mesh scenes are skipped\n", shared_models.string().c_str());
    return scenes;
  }
  for (const auto& m : meshes) {
    const std::filesystem::path path = shared_models / m.file;
    if (!std::filesystem::is_regular_file(path, ec)) {
      std::fprintf(stderr, "note: %s not found: mesh_%s skipped\n", path.string().c_str(), m.name);
      continue;
    }
    scenes.push_back(mesh_scene(m.name, path, 1920, 1080));
  }
  return scenes;
}

std::filesystem::path default_shared_models() {
  if (const char* env = std::getenv("SOFTPBR_SHARED_MODELS")) return env;
  return std::filesystem::path(SOFTPBR_SOURCE_DIR) / ".." / "shared" / "models";
}

}  // namespace softpbr::bench
