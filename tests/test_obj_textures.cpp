// MTL texture maps: each map statement onto its slot with its -o/-s options (paths relative
// to the MTL file), map_Pr/map_Pm/map_Ns combined into one metallic-roughness texture and
// map_d into the base colour's alpha, bump maps used only when they are normal maps, one
// texture per file, and every bad map a LoadError naming the MTL file, line and keyword.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "softpbr/image/write.h"
#include "softpbr/loaders/obj.h"
#include "texture_file_helpers.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace image = softpbr::image;
namespace fs = std::filesystem;
using texture_test::image_of;
using texture_test::scratch;
using texture_test::solid;
using texture_test::write_text;

namespace {

using Texel = std::array<std::uint8_t, 4>;

// A one-triangle OBJ in `dir` using material "m" of `mtl` (written as `mtl_name`, which may
// be in a subfolder).
fs::path obj_with(const fs::path& dir, const std::string& mtl, const std::string& mtl_name = "m.mtl") {
  fs::create_directories((dir / mtl_name).parent_path());
  write_text(dir / mtl_name, mtl);
  write_text(dir / "t.obj", "mtllib " + mtl_name + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0.25\nusemtl m\nf 1/1 2/1 3/1\n");
  return dir / "t.obj";
}

const pbr::Material& material(const pbr::ObjModel& model) {
  REQUIRE(model.materials.size() >= 1);
  return model.materials[0].second;
}

std::string load_error(const fs::path& path, const pbr::ObjOptions& options = {}) {
  try {
    pbr::load_obj(path, options);
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return "";
}

bool any_contains(const std::vector<std::string>& list, const std::string& part) {
  for (const std::string& s : list)
    if (s.find(part) != std::string::npos) return true;
  return false;
}

// The 8-bit codes of base-level texel (x, y).
Texel codes(const raster::Texture& t, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(t.width()) + static_cast<std::size_t>(x)) * 4;
  return {t.texels8()[i], t.texels8()[i + 1], t.texels8()[i + 2], t.texels8()[i + 3]};
}

}  // namespace

TEST_CASE("obj textures: map_Kd, map_Ke and norm go to their slots with -o, -s, -clamp and -bm, relative to the MTL file") {
  const fs::path dir = scratch("obj-slots");
  fs::create_directories(dir / "mtl" / "tex");
  image::write_png(dir / "mtl" / "tex" / "color.png", solid(4, 4, 200, 100, 50));
  image::write_png(dir / "mtl" / "glow.png", solid(2, 2, 255, 128, 0));
  image::write_png(dir / "mtl" / "normal.png", solid(2, 2, 128, 128, 255));
  const pbr::ObjModel model = pbr::load_obj(obj_with(dir, R"(newmtl m
map_Kd -o 0.25 0.5 0 -s 2 3 1 -clamp on tex/color.png
Ke 0.5 0.5 0.5
map_Ke -blendu off glow.png
norm -bm 0.5 normal.png
)", "mtl/m.mtl"));
  CHECK(model.warnings.empty());
  const pbr::Material& m = material(model);
  REQUIRE(m.base_color_texture);
  CHECK(m.base_color_texture.texture->color_space() == raster::ColorSpace::Srgb);
  CHECK(m.base_color == glm::vec3(1.0f));  // map_Kd without Kd: the map as it is
  CHECK(m.base_color_texture.transform.scale == glm::vec2(2.0f, 3.0f));
  // MTL's v-up t = s·v + o becomes s·v' + (1 − s − o) for the flipped v' = 1 − v.
  CHECK(m.base_color_texture.transform.offset == glm::vec2(0.25f, 1.0f - 3.0f - 0.5f));
  CHECK(m.base_color_texture.transform.rotation == 0.0f);
  CHECK(m.base_color_texture.sampler.wrap_u == raster::Wrap::ClampToEdge);
  CHECK(m.base_color_texture.sampler.wrap_v == raster::Wrap::ClampToEdge);
  REQUIRE(m.emissive_texture);
  CHECK(m.emissive_texture.texture->color_space() == raster::ColorSpace::Srgb);
  CHECK(m.emissive == glm::vec3(0.5f));  // Ke given: it stays the factor
  CHECK(m.emissive_texture.transform.offset == glm::vec2(0.0f));  // -blendu: ignored
  CHECK(m.emissive_texture.sampler.wrap_u == raster::Wrap::Repeat);
  REQUIRE(m.normal_texture);
  CHECK(m.normal_texture.texture->color_space() == raster::ColorSpace::Linear);
  CHECK(m.normal_scale == 0.5f);
  CHECK(!m.metallic_roughness_texture);
  CHECK(!m.occlusion_texture);
  CHECK(model.texture_bytes == m.base_color_texture.texture->texel_bytes() + m.emissive_texture.texture->texel_bytes() +
                                   m.normal_texture.texture->texel_bytes());
  // OBJ's vt (0, 0.25), v up, is (0, 0.75) in softpbr's v-down convention.
  CHECK(model.shapes.at(0).mesh.vertices.at(0).uv == glm::vec2(0.0f, 0.75f));
  // map_Ke without Ke: a factor of 1.
  image::write_png(dir / "glow.png", solid(2, 2, 255, 128, 0));
  CHECK(material(pbr::load_obj(obj_with(dir, "newmtl m\nmap_Ke glow.png\n"))).emissive == glm::vec3(1.0f));
}

TEST_CASE("obj textures: map_Pr and map_Pm become one metallic-roughness texture (G, B) at the larger size, nearest-resampled") {
  const fs::path dir = scratch("obj-mr");
  // Roughness 4×2: code 10·x + 100·y; metallic 2×1: left 0, right 255.
  image::write_png(dir / "rough.png", image_of(4, 2, [](int x, int y) {
    const auto c = static_cast<std::uint8_t>(10 * x + 100 * y);
    return Texel{c, c, c, 255};
  }));
  image::write_png(dir / "metal.png", image_of(2, 1, [](int x, int) {
    const auto c = static_cast<std::uint8_t>(x ? 255 : 0);
    return Texel{c, c, c, 255};
  }));
  const pbr::ObjModel model = pbr::load_obj(obj_with(dir, "newmtl m\nPr 0.5\nmap_Pr rough.png\nmap_Pm metal.png\n"));
  const pbr::Material& m = material(model);
  REQUIRE(m.metallic_roughness_texture);
  const raster::Texture& t = *m.metallic_roughness_texture.texture;
  CHECK(t.color_space() == raster::ColorSpace::Linear);
  CHECK(t.width() == 4);
  CHECK(t.height() == 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      CAPTURE(x);
      CAPTURE(y);
      const Texel c = codes(t, x, y);
      CHECK(c[0] == 255);
      CHECK(c[1] == 10 * x + 100 * y);      // roughness in G
      CHECK(c[2] == (x >= 2 ? 255 : 0));    // metallic in B: texel ⌊(x + ½)·2/4⌋
      CHECK(c[3] == 255);
    }
  CHECK(m.roughness == 0.5f);  // Pr given: the factor
  CHECK(m.metallic == 1.0f);   // map_Pm without Pm: the map as it is

  // Either alone: the other channel is 1 and its factor stays the constant's.
  const pbr::Material pr_only = material(pbr::load_obj(obj_with(dir, "newmtl m\nPm 0.25\nmap_Pr rough.png\n")));
  REQUIRE(pr_only.metallic_roughness_texture);
  CHECK(codes(*pr_only.metallic_roughness_texture.texture, 1, 1) == Texel{255, 110, 255, 255});
  CHECK(pr_only.roughness == 1.0f);
  CHECK(pr_only.metallic == 0.25f);
  const pbr::Material pm_only = material(pbr::load_obj(obj_with(dir, "newmtl m\nPr 0.3\nmap_Pm metal.png\n")));
  REQUIRE(pm_only.metallic_roughness_texture);
  CHECK(pm_only.metallic_roughness_texture.texture->width() == 2);
  CHECK(codes(*pm_only.metallic_roughness_texture.texture, 1, 0) == Texel{255, 255, 255, 255});
  CHECK(codes(*pm_only.metallic_roughness_texture.texture, 0, 0) == Texel{255, 255, 0, 255});
  CHECK(pm_only.roughness == 0.3f);
}

TEST_CASE("obj textures: map_Ns gives roughness through roughness_from_phong_exponent only without Pr and map_Pr") {
  const fs::path dir = scratch("obj-ns");
  image::write_png(dir / "shiny.png", image_of(3, 1, [](int x, int) {
    const auto c = static_cast<std::uint8_t>(x * 127);
    return Texel{c, c, c, 255};
  }));
  const pbr::Material m = material(pbr::load_obj(obj_with(dir, "newmtl m\nNs 100\nmap_Ns shiny.png\n")));
  REQUIRE(m.metallic_roughness_texture);
  for (int x = 0; x < 3; ++x) {
    const float expected = pbr::roughness_from_phong_exponent(static_cast<float>(100.0 * (x * 127) / 255.0));
    CHECK(codes(*m.metallic_roughness_texture.texture, x, 0)[1] == std::lround(255.0f * expected));
  }
  CHECK(codes(*m.metallic_roughness_texture.texture, 0, 0)[1] == 255);  // exponent 0: fully rough
  CHECK(m.roughness == 1.0f);
  // With Pr the map is not used (and said so).
  const pbr::ObjModel with_pr = pbr::load_obj(obj_with(dir, "newmtl m\nPr 0.4\nmap_Ns shiny.png\n"));
  CHECK(!material(with_pr).metallic_roughness_texture);
  CHECK(material(with_pr).roughness == 0.4f);
  CHECK(any_contains(with_pr.warnings, ":3: map_Ns: ignored: Pr or map_Pr gives the roughness"));
}

TEST_CASE("obj textures: a bump map is the normal map when it is one, a height map is skipped with a warning") {
  const fs::path dir = scratch("obj-bump");
  // A bumpy normal map around (0.5, 0.5, 1), and a grey height map.
  image::write_png(dir / "nmap.png", image_of(8, 8, [](int x, int y) {
    return Texel{static_cast<std::uint8_t>(112 + 4 * x), static_cast<std::uint8_t>(112 + 4 * y), 250, 255};
  }));
  image::write_png(dir / "height.png", image_of(8, 8, [](int x, int) {
    const auto c = static_cast<std::uint8_t>(30 * x);
    return Texel{c, c, c, 255};
  }));
  const pbr::ObjModel normal = pbr::load_obj(obj_with(dir, "newmtl m\nmap_Bump -bm 2 nmap.png\n"));
  REQUIRE(material(normal).normal_texture);
  CHECK(material(normal).normal_scale == 2.0f);
  CHECK(material(normal).normal_texture.texture->color_space() == raster::ColorSpace::Linear);
  const pbr::ObjModel height = pbr::load_obj(obj_with(dir, "newmtl m\nKd 1 1 1\n\nbump height.png\n"));
  CHECK(!material(height).normal_texture);
  CHECK(any_contains(height.warnings, (dir / "m.mtl").string() + ":4: bump: " + (dir / "height.png").string() +
                                          " is a height map"));
  // norm wins over bump.
  const pbr::ObjModel both = pbr::load_obj(obj_with(dir, "newmtl m\nnorm nmap.png\nbump height.png\n"));
  REQUIRE(material(both).normal_texture);
  CHECK(any_contains(both.warnings, ":3: bump: ignored: norm gives the normal map"));
}

TEST_CASE("obj textures: map_d is the base colour's alpha, with alpha mode mask") {
  const fs::path dir = scratch("obj-alpha");
  image::write_png(dir / "leaf.png", solid(4, 4, 40, 160, 20));
  image::write_png(dir / "mask.png", image_of(2, 2, [](int x, int) {
    const auto c = static_cast<std::uint8_t>(x ? 255 : 0);
    return Texel{c, c, c, 255};
  }));
  image::write_png(dir / "cutout.png", image_of(2, 2, [](int, int y) {
    return Texel{9, 9, 9, static_cast<std::uint8_t>(y ? 200 : 0)};
  }));
  const pbr::Material m = material(pbr::load_obj(obj_with(dir, "newmtl m\nKd 0.5 0.5 0.5\nmap_Kd leaf.png\nmap_d mask.png\n")));
  REQUIRE(m.base_color_texture);
  CHECK(m.alpha_mode == pbr::AlphaMode::Mask);
  CHECK(m.alpha_cutoff == 0.5f);
  CHECK(m.base_color == glm::vec3(0.5f));
  const raster::Texture& t = *m.base_color_texture.texture;
  CHECK(t.color_space() == raster::ColorSpace::Srgb);
  CHECK(t.width() == 4);
  CHECK(codes(t, 0, 0) == Texel{40, 160, 20, 0});    // grey mask: its red channel
  CHECK(codes(t, 3, 3) == Texel{40, 160, 20, 255});
  // An image with alpha gives its alpha; without map_Kd the colour is white.
  const pbr::Material cut = material(pbr::load_obj(obj_with(dir, "newmtl m\nmap_d cutout.png\n")));
  REQUIRE(cut.base_color_texture);
  CHECK(codes(*cut.base_color_texture.texture, 0, 0) == Texel{255, 255, 255, 0});
  CHECK(codes(*cut.base_color_texture.texture, 1, 1) == Texel{255, 255, 255, 200});
}

TEST_CASE("obj textures: a file named by several maps and materials is one texture, textures = false loads none") {
  const fs::path dir = scratch("obj-cache");
  image::write_png(dir / "shared.png", solid(4, 4, 10, 20, 30));
  const fs::path path = obj_with(dir, "newmtl m\nmap_Kd shared.png\nmap_Ke shared.png\nnewmtl n\nmap_Kd shared.png\n");
  const pbr::ObjModel model = pbr::load_obj(path);
  REQUIRE(model.materials.size() == 2);
  const auto& a = model.materials[0].second;
  const auto& b = model.materials[1].second;
  CHECK(a.base_color_texture.texture == a.emissive_texture.texture);
  CHECK(a.base_color_texture.texture == b.base_color_texture.texture);
  CHECK(model.texture_bytes == a.base_color_texture.texture->texel_bytes());
  const pbr::ObjModel bare = pbr::load_obj(path, {.textures = false});
  CHECK(!bare.materials[0].second.textured());
  CHECK(bare.texture_bytes == 0);
}

TEST_CASE("obj textures: a bad map is a LoadError naming the MTL file, its line and the keyword") {
  const fs::path dir = scratch("obj-errors");
  image::write_png(dir / "ok.png", solid(4, 4, 1, 2, 3));
  texture_test::write_bytes(dir / "huge.png", texture_test::png_declaring(100000, 16));
  texture_test::write_bytes(dir / "cut.png", texture_test::truncated_png(texture_test::image_of(64, 64, [](int x, int y) {
    return Texel{static_cast<std::uint8_t>(x * 3), static_cast<std::uint8_t>(y * 3), 0, 255};
  }), 90));
  image::write_hdr(dir / "float.hdr", image::ImageF{2, 2, std::vector<float>(16, 0.5f)});
  const std::string mtl = (dir / "m.mtl").string() + ":";
  const std::string d = dir.string() + "/";
  struct Case {
    std::string text, message;  // message: the whole line, or its start when it ends with "("
  };
  const std::vector<Case> cases = {
      {"newmtl m\nKd 1 1 1\nmap_Kd missing.png\n", mtl + "3: map_Kd: " + d + "missing.png: no such file"},
      {"newmtl m\n  map_Ke   huge.png\n",
       mtl + "2: map_Ke: " + d + "huge.png: image size 100000x16 is outside 1x1 .. 16384x16384"},
      {"newmtl m\nnorm cut.png\n", mtl + "2: norm: " + d + "cut.png: cannot decode ("},
      {"newmtl m\nmap_Bump nothing.png\n", mtl + "2: map_Bump: " + d + "nothing.png: no such file"},
      {"newmtl m\nmap_Pr float.hdr\n",
       mtl + "2: map_Pr: " + d + "float.hdr: a float image cannot be a channel of an 8-bit texture (use a PNG or JPEG)"},
      {"newmtl a\nnewmtl m\nmap_Pm ok.png\nmap_d gone.png\n", mtl + "4: map_d: " + d + "gone.png: no such file"},
      {"newmtl m\nmap_Kd -s 2 2 ok.png\n",
       mtl + "2: map_Kd: no image file name after the options (-o, -s and -t take three numbers here: write -s 2 2 1, "
             "not -s 2 2)"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    const std::string e = load_error(obj_with(dir, c.text));
    if (c.message.back() == '(') CHECK(e.rfind(c.message, 0) == 0);
    else CHECK(e == c.message);
    CHECK(e.find('\n') == std::string::npos);
  }
  // The memory bound refuses a map from its header.
  texture_test::write_bytes(dir / "big.png", texture_test::png_declaring(4096, 4096));
  const std::string e = load_error(obj_with(dir, "newmtl m\nmap_Kd big.png\n"), {.texture_memory_limit = 1 << 20});
  CHECK(e.rfind(mtl + "2: map_Kd: " + d + "big.png: image size 4096x4096 needs 67108864 bytes decoded, over the limit of 786432 "
                      "(the memory limit leaves 1.0 MiB for this texture", 0) == 0);
  // Without textures the same files load.
  CHECK(load_error(obj_with(dir, "newmtl m\nmap_Kd missing.png\n"), {.textures = false}).empty());
}
