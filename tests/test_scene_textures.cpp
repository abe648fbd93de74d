// Textures in scene files: every key of a material's texture slots parsed into the
// Material, one Texture per image file and colour space per scene load (shared with the
// OBJ models' MTL maps), texture memory in the scene's budget, and every bad image one line
// naming the scene file, the JSON pointer and the image file with the image library's reason.
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "softpbr/dmath/dmath.h"
#include "softpbr/image/write.h"
#include "softpbr/loaders/scene_file.h"
#include "ktx2_writer.h"
#include "texture_file_helpers.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace image = softpbr::image;
namespace fs = std::filesystem;
using texture_test::scratch;
using texture_test::solid;

namespace {

// A scene of one cube with `material` (JSON), read as "t.json" from `dir`.
std::string scene_with(const std::string& material, const std::string& more_objects = "") {
  return R"({"objects": [{"mesh": {"type": "cube"}, "material": )" + material + "}" + more_objects + "]}";
}

pbr::SceneFile parse_in(const fs::path& dir, const std::string& text, const pbr::SceneLoadOptions& options = {}) {
  return pbr::parse_scene_file(text, "t.json", dir, options);
}

std::string error_in(const fs::path& dir, const std::string& text, const pbr::SceneLoadOptions& options = {}) {
  try {
    parse_in(dir, text, options);
  } catch (const pbr::SceneFileError& e) {
    return e.what();
  }
  return "";
}

// The metallic-roughness texture of a cube whose material names `file`, written into `dir`
// with `bytes` first.
std::shared_ptr<const raster::Texture> metallic_roughness_from(const fs::path& dir, const std::string& file,
                                                               const std::vector<std::uint8_t>& bytes) {
  texture_test::write_bytes(dir / file, bytes);
  const pbr::Material m =
      parse_in(dir, scene_with(R"({"metallic_roughness_texture": ")" + file + R"("})")).scene.objects[0].material;
  REQUIRE(m.metallic_roughness_texture);
  return m.metallic_roughness_texture.texture;
}

// Five small images, one per slot.
void write_slot_images(const fs::path& dir) {
  image::write_png(dir / "color.png", solid(4, 4, 200, 100, 50));
  image::write_png(dir / "mr.png", solid(4, 4, 255, 128, 0));
  image::write_png(dir / "normal.png", solid(4, 4, 128, 128, 255));
  image::write_png(dir / "ao.png", solid(4, 4, 180, 180, 180));
  image::write_png(dir / "glow.png", solid(2, 2, 255, 255, 0));
}

}  // namespace

TEST_CASE("scene textures: every material and texture key is parsed into the Material") {
  const fs::path dir = scratch("keys");
  write_slot_images(dir);
  const pbr::SceneFile f = parse_in(dir, scene_with(R"({
    "base_color": [1, 1, 1], "alpha": 0.25, "alpha_mode": "mask", "alpha_cutoff": 0.3, "double_sided": true,
    "base_color_texture": {"image": "color.png", "uv_set": 1,
      "sampler": {"wrap_u": "clamp_to_edge", "wrap_v": "mirrored_repeat", "mag_filter": "nearest",
                  "min_filter": "nearest", "mip_filter": "none", "anisotropy": 8, "lod_bias": -0.5,
                  "min_lod": 1, "max_lod": 4},
      "uv_transform": {"offset": [0.5, -0.25], "rotation": 90, "scale": [2, 3]}},
    "metallic_roughness_texture": {"image": "mr.png", "sampler": {"wrap": "clamp_to_edge", "mip_filter": "nearest"}},
    "normal_texture": "normal.png", "normal_scale": -0.5,
    "occlusion_texture": {"image": "ao.png"}, "occlusion_strength": 0.75,
    "emissive_texture": "glow.png", "emissive": [2, 2, 2]})"));
  REQUIRE(f.scene.objects.size() == 1);
  const pbr::Material& m = f.scene.objects[0].material;
  CHECK(m.alpha == 0.25f);
  CHECK(m.alpha_mode == pbr::AlphaMode::Mask);
  CHECK(m.alpha_cutoff == 0.3f);
  CHECK(m.double_sided);
  CHECK(m.normal_scale == -0.5f);
  CHECK(m.occlusion_strength == 0.75f);
  CHECK(m.textured());

  const pbr::TextureSlot& base = m.base_color_texture;
  REQUIRE(base);
  CHECK(base.texture->width() == 4);
  CHECK(base.texture->color_space() == raster::ColorSpace::Srgb);
  CHECK(base.uv_set == 1);
  CHECK(base.sampler.wrap_u == raster::Wrap::ClampToEdge);
  CHECK(base.sampler.wrap_v == raster::Wrap::MirroredRepeat);
  CHECK(base.sampler.mag_filter == raster::Filter::Nearest);
  CHECK(base.sampler.min_filter == raster::Filter::Nearest);
  CHECK(base.sampler.mip_filter == raster::MipFilter::None);
  CHECK(base.sampler.max_anisotropy == 8);
  CHECK(base.sampler.lod_bias == -0.5f);
  CHECK(base.sampler.min_lod == 1.0f);
  CHECK(base.sampler.max_lod == 4.0f);
  CHECK(base.transform.offset == glm::vec2(0.5f, -0.25f));
  CHECK(base.transform.rotation == static_cast<float>(softpbr::dmath::radians(90.0)));  // degrees in the file
  CHECK(base.transform.scale == glm::vec2(2.0f, 3.0f));
  // The texel is the PNG's code, decoded from sRGB.
  CHECK(base.texture->texel(0, 0, 0).r == raster::srgb8_decode_table()[200]);

  const pbr::TextureSlot& mr = m.metallic_roughness_texture;
  REQUIRE(mr);
  CHECK(mr.texture->color_space() == raster::ColorSpace::Linear);
  CHECK(mr.sampler.wrap_u == raster::Wrap::ClampToEdge);  // "wrap" sets both
  CHECK(mr.sampler.wrap_v == raster::Wrap::ClampToEdge);
  CHECK(mr.sampler.mip_filter == raster::MipFilter::Nearest);
  CHECK(mr.uv_set == 0);
  CHECK(mr.texture->texel(0, 0, 0).g == 128.0f / 255.0f);

  // The string form: defaults for everything but the image.
  const raster::Sampler defaults;
  for (const pbr::TextureSlot* slot : {&m.normal_texture, &m.occlusion_texture, &m.emissive_texture}) {
    REQUIRE(*slot);
    CHECK(slot->uv_set == 0);
    CHECK(slot->sampler.wrap_u == defaults.wrap_u);
    CHECK(slot->sampler.mip_filter == defaults.mip_filter);
    CHECK(slot->sampler.max_anisotropy == 1);
    CHECK(slot->transform.offset == glm::vec2(0.0f));
    CHECK(slot->transform.rotation == 0.0f);
    CHECK(slot->transform.scale == glm::vec2(1.0f));
  }
  CHECK(m.normal_texture.texture->color_space() == raster::ColorSpace::Linear);
  CHECK(m.occlusion_texture.texture->color_space() == raster::ColorSpace::Linear);
  CHECK(m.emissive_texture.texture->color_space() == raster::ColorSpace::Srgb);
  CHECK(m.emissive == glm::vec3(2.0f));

  // Untextured materials keep glTF's defaults.
  const pbr::Material plain = parse_in(dir, scene_with(R"({"roughness": 0.2})")).scene.objects[0].material;
  CHECK(!plain.textured());
  CHECK(plain.alpha == 1.0f);
  CHECK(plain.alpha_mode == pbr::AlphaMode::Opaque);
  CHECK(!plain.double_sided);
  // A preset with a texture on top.
  const pbr::Material gold = parse_in(dir, scene_with(R"({"preset": "gold", "base_color_texture": "color.png"})"))
                                 .scene.objects[0].material;
  CHECK(gold.metallic == 1.0f);
  CHECK(gold.base_color_texture);
}

TEST_CASE("scene textures: one Texture per image file and colour space per scene load, shared by slots, materials and MTL maps") {
  const fs::path dir = scratch("cache");
  write_slot_images(dir);
  fs::create_directories(dir / "sub");
  image::write_hdr(dir / "sky.hdr", image::ImageF{2, 2, std::vector<float>(16, 0.5f)});
  // An OBJ model whose MTL names color.png too.
  texture_test::write_text(dir / "tri.mtl", "newmtl painted\nmap_Kd color.png\n");
  texture_test::write_text(dir / "tri.obj", "mtllib tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl painted\nf 1/1 2/1 3/1\n");
  const std::string text = scene_with(R"({"base_color_texture": "color.png", "occlusion_texture": "color.png",
                                          "metallic_roughness_texture": "sky.hdr", "emissive_texture": "sky.hdr"})",
                                      R"(, {"mesh": {"type": "cube"}, "material": {"base_color_texture": "./sub/../color.png"}},
                                          {"mesh": {"type": "cube"}, "material": {"emissive_texture": {"image": "color.png", "uv_set": 1}}},
                                          {"mesh": {"file": "tri.obj"}})");
  const pbr::SceneFile f = parse_in(dir, text);
  REQUIRE(f.scene.objects.size() == 4);
  const pbr::Material& a = f.scene.objects[0].material;
  const pbr::Material& b = f.scene.objects[1].material;
  const pbr::Material& c = f.scene.objects[2].material;
  const pbr::Material& obj = f.scene.objects[3].material;
  // sRGB colour.png: one texture for every spelling of the path, every sRGB slot and the MTL map.
  CHECK(a.base_color_texture.texture == b.base_color_texture.texture);
  CHECK(a.base_color_texture.texture == c.emissive_texture.texture);
  CHECK(a.base_color_texture.texture == obj.base_color_texture.texture);
  CHECK(c.emissive_texture.uv_set == 1);  // the slot's own settings stay its own
  // Read as linear it is another texture.
  CHECK(a.occlusion_texture.texture != a.base_color_texture.texture);
  CHECK(a.occlusion_texture.texture->color_space() == raster::ColorSpace::Linear);
  // A float image has no colour space: one texture for both slots.
  CHECK(a.metallic_roughness_texture.texture == a.emissive_texture.texture);
  CHECK(a.emissive_texture.texture->is_float());
  // Each texture is counted once.
  CHECK(f.texture_bytes == a.base_color_texture.texture->texel_bytes() + a.occlusion_texture.texture->texel_bytes() +
                               a.emissive_texture.texture->texel_bytes());
  // Another scene load loads the files again.
  CHECK(parse_in(dir, text).scene.objects[0].material.base_color_texture.texture != a.base_color_texture.texture);
}

TEST_CASE("scene textures: each bad texture value or image is one line with the pointer and the image file's problem") {
  const fs::path dir = scratch("errors");
  write_slot_images(dir);
  texture_test::write_bytes(dir / "truncated.png", texture_test::truncated_png(texture_test::image_of(64, 64, [](int x, int y) {
    return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>(x * 4), static_cast<std::uint8_t>(y * 4), 7, 255};
  }), 100));
  texture_test::write_bytes(dir / "wide.png", texture_test::png_declaring(100000, 16));
  texture_test::write_bytes(dir / "huge.png", texture_test::png_declaring(100000, 100000));
  texture_test::write_bytes(dir / "empty.png", texture_test::png_declaring(0, 0));
  texture_test::write_text(dir / "notes.png", "not an image\n");
  fs::create_directories(dir / "folder.png");
  const std::string d = dir.string() + "/";
  struct Case {
    std::string material, message;
  };
  const std::vector<Case> cases = {
      {R"({"base_color_texture": "missing.png"})",
       "t.json: /objects/0/material/base_color_texture: " + d + "missing.png: no such file"},
      {R"({"base_color_texture": {"image": "missing.png"}})",
       "t.json: /objects/0/material/base_color_texture/image: " + d + "missing.png: no such file"},
      {R"({"normal_texture": {"image": "folder.png"}})",
       "t.json: /objects/0/material/normal_texture/image: " + d + "folder.png: is a folder, not an image"},
      {R"({"emissive_texture": "wide.png"})",
       "t.json: /objects/0/material/emissive_texture: " + d + "wide.png: image size 100000x16 is outside 1x1 .. 16384x16384"},
      // stb_image's header scan refuses a PNG of more than 2^30 bytes of pixels, or of zero
      // pixels, before it gives the size; stbi_info then reports no known type, and
      // softpbr::image passes that reason on. Refused before decoding all the same.
      {R"({"emissive_texture": "huge.png"})",
       "t.json: /objects/0/material/emissive_texture: " + d + "huge.png: image size 100000x100000 is outside 1x1 .. 16384x16384"},
      {R"({"emissive_texture": "empty.png"})",
       "t.json: /objects/0/material/emissive_texture: " + d + "empty.png: image size 0x0 is outside 1x1 .. 16384x16384"},
      {R"({"occlusion_texture": "notes.png"})",
       "t.json: /objects/0/material/occlusion_texture: " + d + "notes.png: not a readable image (no PNG, JPEG, KTX2, WebP or AVIF signature)"},
      {R"({"base_color_texture": ""})", "t.json: /objects/0/material/base_color_texture: expected a file name, got \"\""},
      {R"({"base_color_texture": 7})",
       "t.json: /objects/0/material/base_color_texture: expected an image path or a texture object {\"image\": …}, got 7"},
      {R"({"base_color_texture": {"sampler": {}}})", "t.json: /objects/0/material/base_color_texture: missing key \"image\""},
      {R"({"base_color_texture": {"imag": "color.png"}})",
       "t.json: /objects/0/material/base_color_texture/imag: unknown key \"imag\" (did you mean \"image\"?)"},
      {R"({"base_color_texture": {"image": "color.png", "uv_set": 2}})",
       "t.json: /objects/0/material/base_color_texture/uv_set: expected an integer in [0, 1], got 2"},
      {R"({"base_color_texture": {"image": "color.png", "sampler": {"wrap_u": "clamp"}}})",
       "t.json: /objects/0/material/base_color_texture/sampler/wrap_u: expected one of repeat, clamp_to_edge, mirrored_repeat, got \"clamp\""},
      {R"({"base_color_texture": {"image": "color.png", "sampler": {"wrap": "repeat", "wrap_v": "repeat"}}})",
       "t.json: /objects/0/material/base_color_texture/sampler/wrap_v: \"wrap\" sets wrap_u and wrap_v already: give \"wrap\" or \"wrap_v\", not both"},
      {R"({"base_color_texture": {"image": "color.png", "sampler": {"mip_filter": "trilinear"}}})",
       "t.json: /objects/0/material/base_color_texture/sampler/mip_filter: expected one of none, nearest, linear, got \"trilinear\""},
      {R"({"base_color_texture": {"image": "color.png", "sampler": {"anisotropy": 17}}})",
       "t.json: /objects/0/material/base_color_texture/sampler/anisotropy: expected an integer in [1, 16], got 17"},
      {R"({"base_color_texture": {"image": "color.png", "sampler": {"min_lod": 3, "max_lod": 2}}})",
       "t.json: /objects/0/material/base_color_texture/sampler/min_lod: expected min_lod <= max_lod (3 > 2)"},
      {R"({"base_color_texture": {"image": "color.png", "sampler": {"lod_bias": 1e31}}})",
       "t.json: /objects/0/material/base_color_texture/sampler/lod_bias: expected a number at most 1e+30 in magnitude, got 1e+31"},
      {R"({"base_color_texture": {"image": "color.png", "uv_transform": {"rotation": 400}}})",
       "t.json: /objects/0/material/base_color_texture/uv_transform/rotation: expected a number in [-360, 360], got 400"},
      {R"({"base_color_texture": {"image": "color.png", "uv_transform": {"scale": [1]}}})",
       "t.json: /objects/0/material/base_color_texture/uv_transform/scale: expected an array of 2 numbers, got [1]"},
      {R"({"alpha": 1.5})", "t.json: /objects/0/material/alpha: expected a number in [0, 1], got 1.5"},
      {R"({"alpha_mode": "cutout"})",
       "t.json: /objects/0/material/alpha_mode: expected one of opaque, mask, blend, got \"cutout\""},
      {R"({"alpha_cutoff": -0.1})", "t.json: /objects/0/material/alpha_cutoff: expected a number in [0, 1], got -0.1"},
      {R"({"double_sided": "yes"})", "t.json: /objects/0/material/double_sided: expected true or false, got \"yes\""},
      {R"({"normal_scale": 1e31})",
       "t.json: /objects/0/material/normal_scale: expected a number at most 1e+30 in magnitude, got 1e+31"},
      {R"({"occlusion_strength": 2})", "t.json: /objects/0/material/occlusion_strength: expected a number in [0, 1], got 2"},
      {R"({"normal_textures": "normal.png"})",
       "t.json: /objects/0/material/normal_textures: unknown key \"normal_textures\" (did you mean \"normal_texture\"?)"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.material);
    CHECK(error_in(dir, scene_with(c.material)) == c.message);
  }
  // A message whose reason depends on the encoder's bytes: its start and the reason's kind.
  const std::string truncated = error_in(dir, scene_with(R"({"base_color_texture": {"image": "truncated.png"}})"));
  CHECK(truncated.rfind("t.json: /objects/0/material/base_color_texture/image: " + d + "truncated.png: cannot decode (", 0) == 0);
  CHECK(truncated.find("truncated: chunk 'IDAT'") != std::string::npos);
  CHECK(truncated.find('\n') == std::string::npos);
}

TEST_CASE("scene textures: a 16-bit PNG loads as its high bytes (stb_image's reduction to 8 bits)") {
  const std::shared_ptr<const raster::Texture> texture =
      metallic_roughness_from(scratch("png16"), "deep.png", texture_test::png16(3, 2, 0xab54));
  const raster::Texture& t = *texture;
  CHECK(t.width() == 3);
  CHECK(t.height() == 2);
  CHECK(t.texels8()[0] == 0xab);
  CHECK(t.texels8()[1] == 0xab);
  CHECK(t.texels8()[3] == 0xff);  // RGB: opaque
}

TEST_CASE("scene textures: a KTX2 image is read as its level 0 (an R8G8 Zstandard texture as Vulkan samples it), a damaged one is one line") {
  const fs::path dir = scratch("ktx2");
  ktx2_test::Ktx2Spec k;
  k.vk_format = 16;  // VK_FORMAT_R8G8_UNORM
  k.scheme = 2;
  k.width = 3;
  k.height = 2;
  k.levels = {{10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120}, {5, 6}};
  const std::shared_ptr<const raster::Texture> texture = metallic_roughness_from(dir, "rg.ktx2", ktx2_test::write_ktx2(k));
  const raster::Texture& t = *texture;
  CHECK(t.width() == 3);
  CHECK(t.height() == 2);
  const std::vector<int> expected = {10, 20, 0, 255, 30, 40, 0, 255, 50, 60, 0, 255};
  for (std::size_t i = 0; i < expected.size(); ++i) CHECK(t.texels8()[i] == expected[i]);
  std::vector<std::uint8_t> cut = ktx2_test::write_ktx2(k);
  cut.resize(cut.size() - 3);
  texture_test::write_bytes(dir / "cut.ktx2", cut);
  const std::string message = error_in(dir, scene_with(R"({"base_color_texture": "cut.ktx2"})"));
  CAPTURE(message);
  CHECK(message.rfind("t.json: /objects/0/material/base_color_texture: ", 0) == 0);
  CHECK(message.find("cut.ktx2: level 0: its data") != std::string::npos);
}

TEST_CASE("scene textures: texels are charged to the memory budget, and an image too large for what is left is refused from its header") {
  const fs::path dir = scratch("budget");
  image::write_png(dir / "wall.png", solid(256, 256, 90, 90, 90));
  const pbr::SceneFile f = parse_in(dir, scene_with(R"({"base_color_texture": "wall.png"})"));
  const raster::Texture& t = *f.scene.objects[0].material.base_color_texture.texture;
  CHECK(f.texture_bytes == t.texel_bytes());
  CHECK(t.texel_bytes() == 349524);  // 256² · 4 · (1 + 1/4 + … + 1/4^8)
  // The mesh estimate leaves the texture out.
  const pbr::SceneFile plain = parse_in(dir, scene_with(R"("gold")"));
  CHECK(f.mesh_bytes == plain.mesh_bytes);
  CHECK(plain.texture_bytes == 0);

  // A 16384² header over one row of data: refused by its size for what the 64 MiB limit
  // leaves (decoding it would fail on the missing data instead).
  texture_test::write_bytes(dir / "big.png", texture_test::png_declaring(16384, 16384));
  const std::string e = error_in(dir, scene_with(R"({"base_color_texture": "big.png"})"), {.memory_limit = std::uint64_t{64} << 20});
  CAPTURE(e);
  CHECK(e.rfind("t.json: /objects/0/material/base_color_texture: " + (dir / "big.png").string() +
                    ": image size 16384x16384 needs 1073741824 bytes decoded, over the limit of ", 0) == 0);
  CHECK(e.find("(the memory limit leaves 64.0 MiB for this texture, and its mip levels add a third to the image)") !=
        std::string::npos);
  // An elongated image's chain passes the 4/3 estimate (1024×1: 2047 texels, not 1365):
  // decoded within the bound, then refused by its exact size. The cube's arrays (912 bytes)
  // are charged before its material is read.
  image::write_png(dir / "strip.png", solid(1024, 1, 1, 2, 3));
  CHECK(error_in(dir, scene_with(R"({"base_color_texture": "strip.png"})"), {.memory_limit = 7000}) ==
        "t.json: /objects/0/material/base_color_texture: this texture brings the scene's estimated memory to 8.9 KiB, "
        "over the limit of 6.8 KiB");
}

TEST_CASE("scene textures: examples/scenes/textured.json loads with its textures, the ORM image shared by two slots") {
  const pbr::SceneFile f = pbr::load_scene_file(fs::path(SOFTPBR_SOURCE_DIR) / "examples/scenes/textured.json");
  CHECK(f.warnings.empty());
  int textured = 0, normal_mapped = 0;
  for (const pbr::Object& o : f.scene.objects) {
    textured += o.material.textured();
    if (o.material.occlusion_texture && o.material.metallic_roughness_texture)
      CHECK(o.material.occlusion_texture.texture == o.material.metallic_roughness_texture.texture);
    // Normal-mapped shapes get their MikkTSpace tangents at load, once, not per frame.
    if (o.material.normal_texture) {
      CHECK(o.mesh->tangents.size() == o.mesh->vertices.size());
      ++normal_mapped;
    }
  }
  CHECK(textured >= 3);
  CHECK(normal_mapped == 2);
  CHECK(f.texture_bytes > 0);
}
