// KHR_texture_basisu in the glTF reader: a texture's KTX2 source replaces its core source
// (a PNG fallback is not read), decoded in the slot's colour space; a required extension
// loads; a bad reference or a bad KTX2 file is one line with its JSON pointer; `info`
// describes the KTX2 image. The KTX2 decoder itself: test_ktx2*.cpp.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ktx2_writer.h"
#include "shared_assets.h"
#include "softpbr/image/ktx2.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/gltf_info.h"
#include "softpbr/raster/pool.h"

namespace pbr = softpbr::pbr;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// An 8×4 R8G8B8A8_SRGB KTX2 texture, texel (x, y) = (32x, 64y, 7, 255), and a 4×2 level 1
// of its own (every texel (1, 2, 3, 4): no average of level 0).
const std::vector<std::uint8_t> kLevel1 = {1, 2, 3, 4, 1, 2, 3, 4, 1, 2, 3, 4, 1, 2, 3, 4,
                                           1, 2, 3, 4, 1, 2, 3, 4, 1, 2, 3, 4, 1, 2, 3, 4};
std::vector<std::uint8_t> ktx2_texture() {
  ktx2_test::Ktx2Spec s;
  s.vk_format = 43;
  s.transfer = 2;
  s.width = 8;
  s.height = 4;
  std::vector<std::uint8_t> level;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) level.insert(level.end(), {std::uint8_t(32 * x), std::uint8_t(64 * y), 7, 255});
  s.levels.push_back(level);
  s.levels.push_back(kLevel1);
  return ktx2_test::write_ktx2(s);
}

// One folder a process: ctest runs the cases as parallel processes, each writing the
// same file names.
fs::path folder() {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / ("test_gltf_basisu." + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

void write(const fs::path& p, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// One textured triangle (its buffer written to folder()/tri.bin) whose base colour texture
// has a PNG fallback (image 0, a file that is not there: it must not be read) and a KTX2
// source (image 1, ktx2_name).
Json model(const std::string& ktx2_name) {
  std::vector<std::uint8_t> buffer;
  auto f32 = [&](float v) {
    std::uint32_t b;
    std::memcpy(&b, &v, 4);
    for (int i = 0; i < 4; ++i) buffer.push_back(static_cast<std::uint8_t>(b >> (8 * i)));
  };
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) f32(v);  // positions, 36 bytes
  for (float v : {0.f, 0.f, 1.f, 0.f, 0.f, 1.f}) f32(v);                // UVs, 24 bytes
  for (std::uint8_t b : {0, 0, 1, 0, 2, 0, 0, 0}) buffer.push_back(b);   // indices, 6 + 2 bytes
  Json g = Json::parse(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "extensionsUsed": ["KHR_texture_basisu"],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0, "extensions": {"KHR_texture_basisu": {"source": 1}}}],
    "images": [{"uri": "fallback-not-there.png"}, {"uri": "x"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                    {"buffer": 0, "byteOffset": 60, "byteLength": 6}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                  {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}]})");
  g["images"][1]["uri"] = ktx2_name;
  write(folder() / "tri.bin", buffer);
  g["buffers"] = Json::array({{{"byteLength", buffer.size()}, {"uri", "tri.bin"}}});
  return g;
}

std::string load_error(const Json& g) {
  const std::string text = g.dump();
  try {
    pbr::load_gltf(std::vector<std::uint8_t>(text.begin(), text.end()), "m.gltf", folder());
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("gltf KHR_texture_basisu: the KTX2 source is decoded in the slot's colour space with its own mip levels, and the PNG fallback is not read") {
  write(folder() / "tex.ktx2", ktx2_texture());
  for (bool required : {false, true}) {
    CAPTURE(required);
    Json g = model("tex.ktx2");
    if (required) g["extensionsRequired"] = Json::array({"KHR_texture_basisu"});
    const std::string text = g.dump();
    const pbr::GltfScene scene = pbr::load_gltf(std::vector<std::uint8_t>(text.begin(), text.end()), "m.gltf", folder());
    REQUIRE(scene.objects.size() == 1);
    const auto& slot = scene.objects[0].material.base_color_texture;
    REQUIRE(slot.texture != nullptr);
    CHECK(slot.texture->width() == 8);
    CHECK(slot.texture->height() == 4);
    CHECK(slot.texture->color_space() == softpbr::raster::ColorSpace::Srgb);
    const std::span<const std::uint8_t> t = slot.texture->texels8();
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 8; ++x) {
        CHECK(t[static_cast<std::size_t>((y * 8 + x) * 4 + 0)] == 32 * x);
        CHECK(t[static_cast<std::size_t>((y * 8 + x) * 4 + 1)] == 64 * y);
      }
    // The file's level 1 is used as stored, not rebuilt from level 0.
    const softpbr::raster::Texture::Level& l1 = slot.texture->level(1);
    REQUIRE(l1.width == 4);
    REQUIRE(l1.height == 2);
    CHECK(std::equal(kLevel1.begin(), kLevel1.end(), t.begin() + static_cast<std::ptrdiff_t>(l1.offset * 4)));
    for (const std::string& w : scene.warnings) CHECK(w.find("KHR_texture_basisu") == std::string::npos);
  }
}

TEST_CASE("gltf KHR_texture_basisu: a source that is not an image, or a KTX2 file that cannot be read, is one line with its pointer") {
  Json g = model("tex.ktx2");
  g["textures"][0]["extensions"]["KHR_texture_basisu"]["source"] = 5;
  CHECK(load_error(g).rfind("m.gltf: /textures/0/extensions/KHR_texture_basisu/source: ", 0) == 0);
  g["textures"][0]["extensions"]["KHR_texture_basisu"]["source"] = "one";
  CHECK(load_error(g).rfind("m.gltf: /textures/0/extensions/KHR_texture_basisu/source: ", 0) == 0);
  std::vector<std::uint8_t> cut = ktx2_texture();
  cut.resize(cut.size() - 10);
  write(folder() / "cut.ktx2", cut);
  const std::string message = load_error(model("cut.ktx2"));
  CAPTURE(message);
  CHECK(message.rfind("m.gltf: /images/1", 0) == 0);
  CHECK(message.find("level 0: its data") != std::string::npos);
  CHECK(message.find('\n') == std::string::npos);
}

TEST_CASE("gltf KHR_texture_basisu: a model's only texture, a real ETC1S file, decodes on the pool's threads to the bytes it has without one") {
  // One texture: the loader lends it the pool's threads (image::ParallelFor).
  fs::copy_file(fs::path(SOFTPBR_SOURCE_DIR) / "tests/ktx2/etc1s_pattern_256x192.ktx2", folder() / "etc1s.ktx2",
                fs::copy_options::overwrite_existing);
  const std::string text = model("etc1s.ktx2").dump();
  const std::vector<std::uint8_t> bytes(text.begin(), text.end());
  softpbr::raster::ThreadPool pool(2);
  pbr::GltfOptions with_pool;
  with_pool.pool = &pool;
  const pbr::GltfScene alone = pbr::load_gltf(bytes, "m.gltf", folder());
  const pbr::GltfScene pooled = pbr::load_gltf(bytes, "m.gltf", folder(), with_pool);
  REQUIRE(alone.objects.size() == 1);
  REQUIRE(pooled.objects.size() == 1);
  const auto& a = alone.objects[0].material.base_color_texture.texture;
  const auto& p = pooled.objects[0].material.base_color_texture.texture;
  REQUIRE(a != nullptr);
  REQUIRE(p != nullptr);
  CHECK(p->width() == 256);
  CHECK(p->height() == 192);
  const std::span<const std::uint8_t> ta = a->texels8(), tp = p->texels8();
  CHECK(std::equal(ta.begin(), ta.end(), tp.begin(), tp.end()));
  const softpbr::image::Ktx2Image k = softpbr::image::load_ktx2(folder() / "etc1s.ktx2");
  CHECK(std::equal(k.levels[0].rgba.begin(), k.levels[0].rgba.end(), tp.begin()));
}

TEST_CASE("gltf KHR_texture_basisu: info lists the texture's KTX2 image with its format, supercompression and levels") {
  write(folder() / "tex.ktx2", ktx2_texture());
  const fs::path path = folder() / "m.gltf";
  const std::string text = model("tex.ktx2").dump();
  std::ofstream(path) << text;
  const pbr::GltfInfo info = pbr::inspect_gltf(path);
  REQUIRE(info.textures.size() == 1);
  CHECK(info.textures[0].source == 1);
  REQUIRE(info.images.size() == 2);
  CHECK(info.images[1].format == "ktx2");
  CHECK(info.images[1].width == 8);
  CHECK(info.images[1].height == 4);
  CHECK(info.images[1].detail == "R8G8B8A8_SRGB, none, 2 levels, sRGB");
}

TEST_CASE("gltf KHR_texture_basisu: AnisotropyBarnLamp's KTX2 variant loads its four UASTC textures, each slot in its colour space") {
  const fs::path dir = shared_assets::folder() / "gltf/AnisotropyBarnLamp/glTF-KTX2-Basisu";
  if (!fs::exists(dir)) {
    MESSAGE("skipped: " << dir << " is absent");
    return;
  }
  const pbr::GltfScene scene = pbr::load_gltf(dir / "AnisotropyBarnLamp.gltf");
  const pbr::Material* metal = nullptr;
  for (const pbr::Object& o : scene.objects)
    if (o.material.base_color_texture) metal = &o.material;
  REQUIRE(metal != nullptr);
  using softpbr::raster::ColorSpace;
  struct Slot {
    const pbr::TextureSlot* slot;
    const char* file;
    ColorSpace space;
  };
  for (const Slot& s : {Slot{&metal->base_color_texture, "AnisotropyBarnLamp_basecolor.ktx2", ColorSpace::Srgb},
                        Slot{&metal->metallic_roughness_texture, "AnisotropyBarnLamp_occlusionroughnessmetal.ktx2", ColorSpace::Linear},
                        Slot{&metal->occlusion_texture, "AnisotropyBarnLamp_occlusionroughnessmetal.ktx2", ColorSpace::Linear},
                        Slot{&metal->normal_texture, "AnisotropyBarnLamp_normalbump.ktx2", ColorSpace::Linear}}) {
    CAPTURE(s.file);
    REQUIRE(s.slot->texture != nullptr);
    CHECK(s.slot->texture->color_space() == s.space);
    // Level 0 holds the file's decoded texels, byte for byte.
    const softpbr::image::Ktx2Image k = softpbr::image::load_ktx2(dir / s.file);
    REQUIRE(s.slot->texture->width() == k.levels[0].width);
    REQUIRE(s.slot->texture->height() == k.levels[0].height);
    const std::span<const std::uint8_t> base = s.slot->texture->texels8().first(k.levels[0].rgba.size());
    CHECK(std::equal(base.begin(), base.end(), k.levels[0].rgba.begin()));
  }
}
