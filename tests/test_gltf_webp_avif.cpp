// EXT_texture_webp and EXT_texture_avif in the glTF reader: a texture's extension source
// replaces its core source (the PNG or JPEG fallback of an optional extension is not read;
// a required one needs none), decoded as image::load_webp / load_avif decode it; a model
// renders with it exactly as with a PNG of the same pixels; a bad reference or a cut file
// is one line with its JSON pointer; `info` names the images' formats. The decoders
// themselves: test_image_webp_avif.cpp.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "softpbr/image/load.h"
#include "softpbr/job/render_job.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/gltf_info.h"
#include "softpbr/raster/pool.h"

namespace pbr = softpbr::pbr;
namespace job = softpbr::job;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

const fs::path kImages = fs::path(SOFTPBR_SOURCE_DIR) / "tests" / "webp_avif";

// One folder a process: ctest runs the cases as parallel processes, and each writes
// quad.bin (two sharing a folder read each other's half-written file).
fs::path folder() {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / ("test_gltf_webp_avif." + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

void write(const fs::path& p, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// An unlit quad facing +Z (its buffer written to folder()/quad.bin) whose base colour
// texture has the core source image 0 (`fallback`, may be a file that is not there) and,
// unless `extension` is empty, that extension's source image 1 (`source`).
Json model(const std::string& extension, const std::string& fallback, const std::string& source) {
  std::vector<std::uint8_t> buffer;
  auto f32 = [&](float v) {
    std::uint32_t b;
    std::memcpy(&b, &v, 4);
    for (int i = 0; i < 4; ++i) buffer.push_back(static_cast<std::uint8_t>(b >> (8 * i)));
  };
  for (float v : {-1.f, -1.f, 0.f, 1.f, -1.f, 0.f, 1.f, 1.f, 0.f, -1.f, 1.f, 0.f}) f32(v);  // positions, 48 bytes
  for (float v : {0.f, 1.f, 1.f, 1.f, 1.f, 0.f, 0.f, 0.f}) f32(v);                      // UVs, 32 bytes
  for (std::uint8_t b : {0, 0, 1, 0, 2, 0, 0, 0, 2, 0, 3, 0}) buffer.push_back(b);        // indices, 12 bytes
  Json g = Json::parse(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "extensionsUsed": ["KHR_materials_unlit"],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "extensions": {"KHR_materials_unlit": {}}}],
    "textures": [{"source": 0, "sampler": 0}],
    "samplers": [{"magFilter": 9728, "minFilter": 9728}],
    "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                    {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]})");
  g["images"] = Json::array({{{"uri", fallback}}});
  if (!extension.empty()) {
    g["images"].push_back({{"uri", source}});
    g["textures"][0]["extensions"][extension]["source"] = 1;
    g["extensionsUsed"].push_back(extension);
  }
  write(folder() / "quad.bin", buffer);
  g["buffers"] = Json::array({{{"byteLength", buffer.size()}, {"uri", "quad.bin"}}});
  return g;
}

fs::path save(const Json& g, const std::string& name) {
  const fs::path p = folder() / name;
  std::ofstream(p, std::ios::trunc) << g.dump();
  return p;
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

// The model rendered as `softpbr render` renders it (96×96, its automatic camera and the
// studio environment), its 8-bit image.
std::vector<std::uint8_t> render(const fs::path& path) {
  softpbr::raster::ThreadPool pool(2);
  const job::Settings settings{.width = 96, .height = 96, .threads = 2};
  const pbr::LoadedScene file = job::load(path.string(), settings, pool);
  const pbr::RenderSettings s = job::resolve(file.render, settings);
  softpbr::raster::Renderer renderer({s.threads, s.tile_size});
  job::Frame frame;
  frame.render(pbr::animate(file, 0), s, renderer, {.rgba8 = true});
  const auto& rgba = frame.rgba().rgba;
  return std::vector<std::uint8_t>(rgba.begin(), rgba.end());
}

void copy_image(const std::string& name) {
  fs::copy_file(kImages / name, folder() / name, fs::copy_options::overwrite_existing);
}

}  // namespace

TEST_CASE("gltf EXT_texture_webp and EXT_texture_avif: the extension's image replaces the core source, optional or required") {
  struct Case {
    const char* extension;
    const char* file;
  };
  for (const Case& c : {Case{"EXT_texture_webp", "lossless.webp"}, Case{"EXT_texture_webp", "lossy_alpha.webp"},
                        Case{"EXT_texture_avif", "lossless.avif"}, Case{"EXT_texture_avif", "422_bt709_limited_10bit.avif"}})
    for (bool required : {false, true}) {
      const std::string file(c.file);
      CAPTURE(file);
      CAPTURE(required);
      copy_image(file);
      // The fallback is not there: it must not be read.
      Json g = model(c.extension, "fallback-not-there.png", file);
      if (required) {
        g["extensionsRequired"] = Json::array({c.extension});
        g["textures"][0].erase("source");  // a required extension needs no fallback
      }
      const std::string text = g.dump();
      const pbr::GltfScene scene = pbr::load_gltf(std::vector<std::uint8_t>(text.begin(), text.end()), "m.gltf", folder());
      REQUIRE(scene.objects.size() == 1);
      const auto& slot = scene.objects[0].material.base_color_texture;
      REQUIRE(slot.texture != nullptr);
      const softpbr::image::Image8 want = softpbr::image::load_image8(kImages / file);
      CHECK(slot.texture->width() == want.width);
      CHECK(slot.texture->height() == want.height);
      CHECK(slot.texture->color_space() == softpbr::raster::ColorSpace::Srgb);
      const std::span<const std::uint8_t> t = slot.texture->texels8();
      CHECK(std::equal(want.rgba.begin(), want.rgba.end(), t.begin()));
      for (const std::string& w : scene.warnings) CHECK(w.find(c.extension) == std::string::npos);
    }
}

TEST_CASE("gltf EXT_texture_webp: a model renders with its lossless WebP exactly as with the PNG of the same pixels") {
  copy_image("pattern.png");
  copy_image("smooth.png");
  copy_image("lossless.webp");
  const std::vector<std::uint8_t> png = render(save(model("", "pattern.png", ""), "png.gltf"));
  // The fallback (smooth.png) differs from the WebP (pattern.png's pixels): the WebP is used.
  const std::vector<std::uint8_t> webp = render(save(model("EXT_texture_webp", "smooth.png", "lossless.webp"), "webp.gltf"));
  const std::vector<std::uint8_t> fallback = render(save(model("", "smooth.png", ""), "fallback.gltf"));
  CHECK(webp == png);
  CHECK(webp != fallback);
}

TEST_CASE("gltf EXT_texture_webp and EXT_texture_avif: a bad source, or a cut file, is one line with its pointer") {
  for (const char* extension : {"EXT_texture_webp", "EXT_texture_avif"}) {
    CAPTURE(std::string(extension));
    Json g = model(extension, "fallback-not-there.png", "x");
    const std::string pointer = std::string("m.gltf: /textures/0/extensions/") + extension + "/source: ";
    g["textures"][0]["extensions"][extension]["source"] = 5;
    CHECK(load_error(g).rfind(pointer, 0) == 0);
    g["textures"][0]["extensions"][extension]["source"] = "one";
    CHECK(load_error(g).rfind(pointer, 0) == 0);
  }
  std::vector<std::uint8_t> cut = softpbr::image::read_file(kImages / "lossy.webp");
  const std::size_t size = cut.size();
  cut.resize(100);
  write(folder() / "cut.webp", cut);
  CHECK(load_error(model("EXT_texture_webp", "fallback-not-there.png", "cut.webp")) ==
        "m.gltf: /images/1 (cut.webp): truncated: the RIFF header says " + std::to_string(size) + " bytes, the file has 100");
  cut = softpbr::image::read_file(kImages / "420_bt601_limited.avif");
  cut.resize(cut.size() - 20);
  write(folder() / "cut.avif", cut);
  const std::string m = load_error(model("EXT_texture_avif", "fallback-not-there.png", "cut.avif"));
  CAPTURE(m);
  CHECK(m.rfind("m.gltf: /images/1 (cut.avif): cannot decode (Truncated data", 0) == 0);
  CHECK(m.find('\n') == std::string::npos);
}

TEST_CASE("gltf EXT_texture_webp and EXT_texture_avif: info gives the images' formats and sizes, the textures their sources") {
  copy_image("lossy.webp");
  copy_image("lossless.avif");
  Json g = model("EXT_texture_webp", "fallback-not-there.png", "lossy.webp");
  g["images"].push_back({{"uri", "lossless.avif"}});
  g["textures"].push_back({{"source", 0}, {"extensions", {{"EXT_texture_avif", {{"source", 2}}}}}});
  g["extensionsUsed"].push_back("EXT_texture_avif");
  const pbr::GltfInfo info = pbr::inspect_gltf(save(g, "info.gltf"));
  REQUIRE(info.textures.size() == 2);
  CHECK(info.textures[0].source == 1);
  CHECK(info.textures[1].source == 2);
  REQUIRE(info.images.size() == 3);
  CHECK(info.images[1].format == "webp");
  CHECK(info.images[1].width == 24);
  CHECK(info.images[1].height == 18);
  CHECK(info.images[2].format == "avif");
  CHECK(info.images[2].width == 13);
  CHECK(info.images[2].height == 11);
}
