// KHR_materials_pbrSpecularGlossiness (archived), converted at load time into the
// metal/roughness material with KHR_materials_ior and _specular's fields
// (loaders/src/gltf/material_extensions.cpp; docs/design.md, "glTF"): the converted fields,
// the textures it reads and makes, one-line errors with their JSON pointers, and a render that is
// bit-identical to the metal/roughness material it equals.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "scratch_file.h"
#include "softpbr/image/write.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace image = softpbr::image;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// One triangle facing +z: 3 float positions (36 bytes) then 3 u16 indices (6 bytes, padded to 8).
const char* kTriangle = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
  "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";

const std::string kExt = "KHR_materials_pbrSpecularGlossiness";

// The triangle with material 0 = `material`, the extension listed as used and required.
std::vector<std::uint8_t> with_material(const Json& material) {
  Json j = Json::parse(kTriangle);
  j["materials"] = Json::array({material});
  j["extensionsUsed"] = Json::array({kExt});
  j["extensionsRequired"] = Json::array({kExt});
  const std::string s = j.dump();
  return {s.begin(), s.end()};
}

Json spec_gloss(const Json& values) { return Json{{"extensions", {{kExt, values}}}}; }

std::string load_error(const std::vector<std::uint8_t>& bytes) {
  try {
    pbr::load_gltf(bytes, "sg.gltf", "/nonexistent-folder");
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("KHR_materials_pbrSpecularGlossiness factors become a dielectric whose F0 is the specular colour") {
  // The core values are there too (a fallback for other clients): the extension replaces them.
  Json material = spec_gloss({{"diffuseFactor", {0.25, 0.5, 0.75, 0.6}},
                              {"specularFactor", {1.0, 0.766, 0.336}},
                              {"glossinessFactor", 0.875}});
  material["pbrMetallicRoughness"] = {{"baseColorFactor", {0.1, 0.1, 0.1, 1.0}}, {"metallicFactor", 1.0},
                                      {"roughnessFactor", 0.1}};
  const pbr::GltfScene g = pbr::load_gltf(with_material(material), "sg.gltf", "/nonexistent-folder");
  REQUIRE(g.objects.size() == 1);
  const pbr::Material& m = g.objects[0].material;
  CHECK(m.base_color == glm::vec3(0.25f, 0.5f, 0.75f));
  CHECK(m.alpha == 0.6f);
  CHECK(m.metallic == 0.0f);
  CHECK(m.roughness == 1.0f - 0.875f);
  CHECK(m.ior == 0.0f);  // F0(ior) = 1: F0 = min(1 · specular colour, 1) = the specular colour
  CHECK(m.specular.color == glm::vec3(1.0f, 0.766f, 0.336f));
  CHECK(m.specular.factor == 1.0f);
  CHECK_FALSE(m.specular.texture);
  CHECK_FALSE(m.specular.color_texture);
  CHECK(m.layered());
  for (const std::string& w : g.warnings) CHECK(w.find("not supported") == std::string::npos);

  // The specification's defaults: diffuse 1, specular 1 (a white mirror's F0), glossiness 1.
  const pbr::Material d = pbr::load_gltf(with_material(spec_gloss(Json::object())), "d.gltf", "/x").objects[0].material;
  CHECK(d.base_color == glm::vec3(1.0f));
  CHECK(d.alpha == 1.0f);
  CHECK(d.metallic == 0.0f);
  CHECK(d.roughness == 0.0f);
  CHECK(d.ior == 0.0f);
  CHECK(d.specular.color == glm::vec3(1.0f));

  // Out-of-range factors are clamped to [0, 1], as the core material's are.
  const pbr::Material c =
      pbr::load_gltf(with_material(spec_gloss({{"diffuseFactor", {2.0, -1.0, 0.5, 3.0}},
                                               {"specularFactor", {1.5, 0.5, -0.5}},
                                               {"glossinessFactor", -2.0}})),
                     "c.gltf", "/x")
          .objects[0]
          .material;
  CHECK(c.base_color == glm::vec3(1.0f, 0.0f, 0.5f));
  CHECK(c.alpha == 1.0f);
  CHECK(c.specular.color == glm::vec3(1.0f, 0.5f, 0.0f));
  CHECK(c.roughness == 1.0f);

  // KHR_materials_ior and _specular beside it are not read (the extension sets both).
  Json both = spec_gloss({{"specularFactor", {0.5, 0.5, 0.5}}});
  both["extensions"]["KHR_materials_ior"] = {{"ior", 1.7}};
  both["extensions"]["KHR_materials_specular"] = {{"specularColorFactor", {0.1, 0.2, 0.3}}};
  const pbr::Material b = pbr::load_gltf(with_material(both), "b.gltf", "/x").objects[0].material;
  CHECK(b.ior == 0.0f);
  CHECK(b.specular.color == glm::vec3(0.5f));
}

TEST_CASE("KHR_materials_pbrSpecularGlossiness bad values are one line with their JSON pointer") {
  const std::string at = "sg.gltf: /materials/0/extensions/" + kExt;
  const struct {
    Json values;
    std::string message;
  } bad[] = {
      {{{"diffuseFactor", {1, 1, 1}}}, at + "/diffuseFactor: expected four numbers"},
      {{{"diffuseFactor", 0.5}}, at + "/diffuseFactor: expected four numbers"},
      {{{"diffuseFactor", {1, 1, "x", 1}}}, at + "/diffuseFactor/2: expected a finite number"},
      {{{"specularFactor", {1, 1, 1, 1}}}, at + "/specularFactor: expected three numbers"},
      {{{"specularFactor", {1, "x", 1}}}, at + "/specularFactor/1: expected a finite number"},
      {{{"specularFactor", {1, nullptr, 1}}}, at + "/specularFactor: expected three numbers"},  // tinygltf drops null
      {{{"glossinessFactor", "0.5"}}, at + "/glossinessFactor: expected a finite number"},
      {{{"glossinessFactor", {0.5}}}, at + "/glossinessFactor: expected a finite number"},
      {{{"diffuseTexture", {{"index", 4}}}}, at + "/diffuseTexture/index: texture 4 does not exist"},
      {{{"specularGlossinessTexture", 0}}, at + "/specularGlossinessTexture: expected a textureInfo object"},
  };
  for (const auto& b : bad) {
    CAPTURE(b.values.dump());
    CHECK(load_error(with_material(spec_gloss(b.values))) == b.message);
  }
}

TEST_CASE("KHR_materials_pbrSpecularGlossiness textures: diffuse as base colour, specular RGB as F0, 1 - A as roughness") {
  const fs::path dir = test_files::scratch_file("test_gltf_specgloss", "textures");
  fs::create_directories(dir);
  // Two 2×1 images: the diffuse, and a specular-glossiness one whose alpha (glossiness) varies.
  const std::vector<std::uint8_t> diffuse = {200, 100, 50, 255, 10, 20, 30, 128};
  const std::vector<std::uint8_t> specgloss = {60, 61, 62, 255, 240, 230, 220, 0};
  for (const auto& [name, texels] : {std::pair{"diffuse.png", diffuse}, std::pair{"specgloss.png", specgloss}}) {
    image::Image8 im;
    im.width = 2;
    im.height = 1;
    im.rgba.assign(texels.begin(), texels.end());
    image::write_png(dir / name, im);
  }
  Json material = spec_gloss({{"diffuseTexture", {{"index", 0}}},
                              {"specularGlossinessTexture", {{"index", 1}}},
                              {"specularFactor", {0.5, 0.5, 0.5}},
                              {"glossinessFactor", 0.25}});
  // A core metallic-roughness texture is not read beside the extension.
  material["pbrMetallicRoughness"] = {{"metallicRoughnessTexture", {{"index", 1}}}};
  Json j = Json::parse(with_material(material));
  j["images"] = Json::array({{{"uri", "diffuse.png"}}, {{"uri", "specgloss.png"}}});
  j["textures"] = Json::array({{{"source", 0}}, {{"source", 1}}});
  const std::string s = j.dump();
  const pbr::GltfScene g = pbr::load_gltf(std::vector<std::uint8_t>(s.begin(), s.end()), "tex.gltf", dir);
  const pbr::Material& m = g.objects[0].material;
  REQUIRE(m.base_color_texture);
  REQUIRE(m.specular.color_texture);
  REQUIRE(m.metallic_roughness_texture);
  CHECK_FALSE(m.specular.texture);
  CHECK(m.base_color_texture.texture->color_space() == raster::ColorSpace::Srgb);
  CHECK(m.specular.color_texture.texture->color_space() == raster::ColorSpace::Srgb);
  CHECK(m.metallic_roughness_texture.texture->color_space() == raster::ColorSpace::Linear);
  const auto first_texels = [](const pbr::TextureSlot& slot) {
    const auto t = slot.texture->texels8();
    REQUIRE(t.size() >= 8);
    return std::vector<std::uint8_t>(t.begin(), t.begin() + 8);
  };
  CHECK(first_texels(m.base_color_texture) == diffuse);
  CHECK(first_texels(m.specular.color_texture) == specgloss);
  // Roughness = 1 − glossinessFactor · A: G = 255 − round(0.25 · A), read with factor 1
  // (A 255 → 255 − 64; A 0 → 255); B (× metallic 0) is 0. Not the core texture's texels.
  CHECK(first_texels(m.metallic_roughness_texture) == std::vector<std::uint8_t>{0, 191, 0, 255, 0, 255, 0, 255});
  CHECK(m.roughness == 1.0f);
  CHECK(m.metallic == 0.0f);
  CHECK(m.specular.color == glm::vec3(0.5f));
  CHECK(g.warnings.empty());

  // Glossiness factor 1: G = 255 − A exactly.
  material["extensions"][kExt]["glossinessFactor"] = 1.0;
  Json j1 = Json::parse(with_material(material));
  j1["images"] = j["images"];
  j1["textures"] = j["textures"];
  const std::string s1 = j1.dump();
  const pbr::Material m1 = pbr::load_gltf(std::vector<std::uint8_t>(s1.begin(), s1.end()), "tex1.gltf", dir).objects[0].material;
  REQUIRE(m1.metallic_roughness_texture);
  CHECK(first_texels(m1.metallic_roughness_texture) == std::vector<std::uint8_t>{0, 0, 0, 255, 0, 255, 0, 255});
}

TEST_CASE("a specular-glossiness grey renders bit-identically to the metal/roughness grey it converts to") {
  // Diffuse 0.5, specular 0.04, glossiness 0.5 → F0 = min(F0(ior 0) · 0.04, 1) = 1 · 0.04f, the
  // core material's F0 at ior 1.5 (0.04f), roughness 1 − 0.5 = 0.5: the layered shader with
  // these values performs the core shader's operations on the same values.
  const auto render = [](Json material, bool layered) {
    material["doubleSided"] = true;
    raster::Renderer renderer({.threads = 0});
    const pbr::GltfScene g = pbr::load_gltf(with_material(material), "r.gltf", "/nonexistent-folder");
    REQUIRE(g.objects.size() == 1);
    CHECK(g.objects[0].material.layered() == layered);
    pbr::Scene s;
    s.objects = g.objects;
    s.camera = pbr::framing_camera(pbr::world_bounds(s.objects), 1.0f, 0.3f, 0.2f);
    s.lights = pbr::default_light_rig(s.camera);
    s.ambient = glm::vec3(pbr::kDefaultAmbient);
    s.environment.map = pbr::Environment::studio();
    raster::Target target(48, 48);
    pbr::render(s, renderer, target);
    const auto c = target.colors();
    return std::vector<glm::vec4>(c.begin(), c.end());
  };
  const std::vector<glm::vec4> sg = render(spec_gloss({{"diffuseFactor", {0.5, 0.5, 0.5, 1.0}},
                                                       {"specularFactor", {0.04, 0.04, 0.04}},
                                                       {"glossinessFactor", 0.5}}),
                                           true);
  Json mr = Json::object();
  mr["pbrMetallicRoughness"] = {{"baseColorFactor", {0.5, 0.5, 0.5, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.5}};
  const std::vector<glm::vec4> core = render(mr, false);
  REQUIRE(sg.size() == core.size());
  // The triangle covers pixels (not only the background), and they differ from the background.
  std::size_t lit = 0;
  for (const glm::vec4& p : core) lit += p != core.front();
  CHECK(lit > 100);
  CHECK(std::memcmp(sg.data(), core.data(), sg.size() * sizeof(glm::vec4)) == 0);
  // A different specular colour changes the picture (the comparison can fail).
  const std::vector<glm::vec4> shiny = render(spec_gloss({{"diffuseFactor", {0.5, 0.5, 0.5, 1.0}},
                                                          {"specularFactor", {0.5, 0.5, 0.5}},
                                                          {"glossinessFactor", 0.5}}),
                                              true);
  CHECK(std::memcmp(shiny.data(), core.data(), shiny.size() * sizeof(glm::vec4)) != 0);
}

TEST_CASE("a textured specular-glossiness grey renders as the metal/roughness grey with the roughness texture it makes") {
  // The specular-glossiness texture is white with glossiness A = 128 (F0 = 0.04 · 1, roughness
  // G = 255 − 128 = 127); the metal/roughness file reads G = 127 from its own texture.
  const fs::path dir = test_files::scratch_file("test_gltf_specgloss", "render_textured");
  fs::create_directories(dir);
  const auto png = [&](const char* name, std::vector<std::uint8_t> texels) {
    image::Image8 im;
    im.width = 2;
    im.height = 2;
    im.rgba.assign(texels.begin(), texels.end());
    image::write_png(dir / name, im);
  };
  std::vector<std::uint8_t> sg_texels, mr_texels;
  for (int i = 0; i < 4; ++i) {
    sg_texels.insert(sg_texels.end(), {255, 255, 255, 128});
    mr_texels.insert(mr_texels.end(), {0, 127, 0, 255});
  }
  png("sg.png", sg_texels);
  png("mr.png", mr_texels);
  const auto render = [&](Json material, const char* image) {
    material["doubleSided"] = true;
    Json j = Json::parse(with_material(material));
    j["images"] = Json::array({{{"uri", image}}});
    j["textures"] = Json::array({{{"source", 0}}});
    // Texture coordinates: the triangle's corners (0,0), (1,0), (0,1) as UVs 0.25…0.75.
    j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2;
    j["buffers"].push_back({{"byteLength", 24},
                            {"uri", "data:application/octet-stream;base64,AACAPgAAgD4AAEA/AACAPgAAgD4AAEA/"}});
    j["bufferViews"].push_back({{"buffer", 1}, {"byteLength", 24}});
    j["accessors"].push_back({{"bufferView", 2}, {"componentType", 5126}, {"count", 3}, {"type", "VEC2"}});
    const std::string s = j.dump();
    raster::Renderer renderer({.threads = 0});
    const pbr::GltfScene g = pbr::load_gltf(std::vector<std::uint8_t>(s.begin(), s.end()), "r.gltf", dir);
    REQUIRE(g.objects.size() == 1);
    REQUIRE(g.objects[0].material.metallic_roughness_texture);
    pbr::Scene sc;
    sc.objects = g.objects;
    sc.camera = pbr::framing_camera(pbr::world_bounds(sc.objects), 1.0f, 0.3f, 0.2f);
    sc.lights = pbr::default_light_rig(sc.camera);
    sc.ambient = glm::vec3(pbr::kDefaultAmbient);
    sc.environment.map = pbr::Environment::studio();
    raster::Target target(48, 48);
    pbr::render(sc, renderer, target);
    const auto c = target.colors();
    return std::vector<glm::vec4>(c.begin(), c.end());
  };
  const std::vector<glm::vec4> sg = render(spec_gloss({{"diffuseFactor", {0.5, 0.5, 0.5, 1.0}},
                                                       {"specularFactor", {0.04, 0.04, 0.04}},
                                                       {"specularGlossinessTexture", {{"index", 0}}}}),
                                           "sg.png");
  Json mr = Json::object();
  mr["pbrMetallicRoughness"] = {{"baseColorFactor", {0.5, 0.5, 0.5, 1.0}},
                                {"metallicFactor", 0.0},
                                {"metallicRoughnessTexture", {{"index", 0}}}};
  const std::vector<glm::vec4> core = render(mr, "mr.png");
  std::size_t lit = 0;
  for (const glm::vec4& p : core) lit += p != core.front();
  CHECK(lit > 100);
  REQUIRE(sg.size() == core.size());
  CHECK(std::memcmp(sg.data(), core.data(), sg.size() * sizeof(glm::vec4)) == 0);
}
