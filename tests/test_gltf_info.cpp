// pbr::inspect_gltf (softpbr info's listing of a glTF file): counts, materials, textures,
// image sizes from their headers; against the Khronos samples of ../shared/gltf when present.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/gltf_info.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace fs = std::filesystem;

namespace {

// Every field of a listing, one line each, to compare two.
std::string listing(const pbr::GltfInfo& i) {
  std::string s = i.version + "|" + i.generator + "|" + i.copyright + "\n";
  for (const std::size_t n : {i.scenes, i.nodes, i.accessors, i.buffer_views, i.buffers, i.samplers, i.skins, i.animations})
    s += std::to_string(n) + " ";
  s += std::to_string(i.default_scene) + " " + std::to_string(i.buffer_bytes) + "\n";
  auto list = [&](const std::vector<std::string>& v) {
    for (const std::string& x : v) s += x + ",";
    s += "\n";
  };
  for (const pbr::GltfMeshInfo& m : i.meshes) {
    s += "mesh " + m.name + " " + std::to_string(m.triangles) + " " + std::to_string(m.morph_targets) + "\n";
    for (const pbr::GltfPrimitiveInfo& p : m.primitives) {
      s += "  " + std::to_string(p.mode) + " " + std::to_string(p.triangles) + " " + std::to_string(p.material) + " " +
           std::to_string(p.indexed) + "\n";
      list(p.attributes);
      list(p.extensions);
    }
  }
  for (const pbr::GltfMaterialInfo& m : i.materials) {
    s += "material " + m.name + " " + m.alpha_mode + " " + std::to_string(m.double_sided) + "\n";
    for (const auto& [slot, index] : m.textures) s += slot + "=" + std::to_string(index) + ",";
    list(m.extensions);
  }
  for (const pbr::GltfTextureInfo& t : i.textures)
    s += "texture " + t.name + " " + std::to_string(t.source) + " " + std::to_string(t.sampler) + "\n";
  for (const pbr::GltfImageInfo& im : i.images)
    s += "image " + im.name + " " + im.location + " " + im.mime_type + " " + im.format + " " + std::to_string(im.width) +
         "x" + std::to_string(im.height) + " " + std::to_string(im.bytes) + "\n";
  for (const pbr::GltfNamedInfo& c : i.cameras) s += "camera " + c.name + " " + c.type + "\n";
  for (const pbr::GltfNamedInfo& l : i.lights) s += "light " + l.name + " " + l.type + "\n";
  list(i.extensions_used);
  list(i.extensions_required);
  list(i.parser_warnings);
  return s;
}

}  // namespace

TEST_CASE("inspect_gltf lists a small file's scenes, nodes, meshes, triangles, material, texture and its image's size") {
  const fs::path file = fs::path(SOFTPBR_SOURCE_DIR) / "fuzz" / "corpus" / "gltf" / "triangle.gltf";
  const pbr::GltfInfo info = pbr::inspect_gltf(file);
  CHECK(info.version == "2.0");
  CHECK(info.scenes == 1);
  CHECK(info.default_scene == 0);
  CHECK(info.nodes == 2);
  REQUIRE(info.meshes.size() == 1);
  REQUIRE(info.meshes[0].primitives.size() == 2);
  // An indexed triangle list of 3 indices, and a strip of 3 positions: one triangle each.
  CHECK(info.meshes[0].primitives[0].mode == 4);
  CHECK(info.meshes[0].primitives[0].indexed);
  CHECK(info.meshes[0].primitives[0].triangles == 1);
  CHECK(info.meshes[0].primitives[0].material == 0);
  CHECK(info.meshes[0].primitives[0].attributes == std::vector<std::string>{"POSITION", "TEXCOORD_0"});
  CHECK(info.meshes[0].primitives[1].mode == 5);
  CHECK(!info.meshes[0].primitives[1].indexed);
  CHECK(info.meshes[0].primitives[1].triangles == 1);
  CHECK(info.meshes[0].primitives[1].material == -1);
  CHECK(info.primitives() == 2);
  CHECK(info.triangles() == 2);
  REQUIRE(info.materials.size() == 1);
  CHECK(info.materials[0].alpha_mode == "MASK");
  CHECK(info.materials[0].double_sided);
  CHECK(info.materials[0].textures == std::vector<std::pair<std::string, int>>{{"base_color", 0}});
  REQUIRE(info.textures.size() == 1);
  CHECK(info.textures[0].source == 0);
  CHECK(info.textures[0].sampler == 0);
  CHECK(info.samplers == 1);
  REQUIRE(info.images.size() == 1);
  CHECK(info.images[0].location == "data URI");
  CHECK(info.images[0].format == "png");
  CHECK(info.images[0].width == 2);
  CHECK(info.images[0].height == 2);
  CHECK(info.images[0].bytes > 0);
  CHECK(info.extensions_used.empty());
  CHECK(info.extensions_required.empty());
  CHECK(info.cameras.empty());
  CHECK(info.lights.empty());
  CHECK(info.buffers == 1);
  CHECK(info.buffer_bytes == 44);
}

TEST_CASE("inspect_gltf: a missing or non-glTF file is a LoadError naming it") {
  const std::string readme = std::string(SOFTPBR_SOURCE_DIR) + "/README.md";
  for (const std::string& name : {std::string("/nonexistent/model.glb"), readme}) {
    CAPTURE(name);
    try {
      pbr::inspect_gltf(name);
      FAIL("expected a LoadError");
    } catch (const pbr::LoadError& e) {
      CHECK(std::string(e.what()).rfind(name + ": ", 0) == 0);
    }
  }
}

TEST_CASE("inspect_gltf on the Khronos samples: every image's header size is a size the loader decoded") {
  const fs::path shared = fs::path(SOFTPBR_SOURCE_DIR) / ".." / "shared" / "gltf";
  if (!fs::is_directory(shared)) {
    MESSAGE("skipped: " << shared << " is absent");
    return;
  }
  softpbr::raster::ThreadPool pool(2);
  int models = 0;
  for (const auto& entry : fs::recursive_directory_iterator(shared)) {
    const fs::path p = entry.path();
    if (p.extension() != ".glb" && p.extension() != ".gltf") continue;
    if (p.parent_path().filename() != "glTF" && p.parent_path().filename() != "glTF-Binary") continue;
    CAPTURE(p.string());
    const pbr::GltfInfo info = pbr::inspect_gltf(p);
    const pbr::GltfScene g = pbr::load_gltf(p, {.pool = &pool});
    CHECK(info.meshes.size() > 0);
    CHECK(info.triangles() > 0);
    std::set<std::pair<int, int>> header_sizes;
    for (const pbr::GltfImageInfo& im : info.images) {
      CHECK((im.format == "png" || im.format == "jpeg"));
      CHECK(im.width > 0);
      CHECK(im.height > 0);
      header_sizes.insert({im.width, im.height});
    }
    for (const pbr::Object& o : g.objects)
      for (const pbr::TextureSlot* t : {&o.material.base_color_texture, &o.material.metallic_roughness_texture,
                                        &o.material.normal_texture, &o.material.occlusion_texture,
                                        &o.material.emissive_texture})
        if (t->texture) CHECK(header_sizes.count({t->texture->width(), t->texture->height()}) == 1);
    ++models;
  }
  CHECK(models >= 17);
}

TEST_CASE("load_and_inspect_gltf: load_gltf's scene and inspect_gltf's listing from one parse") {
  // The corpus (meshopt.glb and draco.glb are rewritten for tinygltf by both), then the
  // Khronos samples when present.
  std::vector<fs::path> files;
  for (const char* name : {"triangle.gltf", "meshopt.glb", "draco.glb"})
    files.push_back(fs::path(SOFTPBR_SOURCE_DIR) / "fuzz" / "corpus" / "gltf" / name);
  const fs::path shared = fs::path(SOFTPBR_SOURCE_DIR) / ".." / "shared" / "gltf";
  if (fs::is_directory(shared))
    for (const auto& entry : fs::recursive_directory_iterator(shared)) {
      const fs::path p = entry.path();
      if ((p.extension() == ".glb" || p.extension() == ".gltf") &&
          (p.parent_path().filename() == "glTF" || p.parent_path().filename() == "glTF-Binary"))
        files.push_back(p);
    }
  softpbr::raster::ThreadPool pool(2);
  for (const fs::path& p : files) {
    CAPTURE(p.string());
    // inspect_gltf's listing, or its error: the same either way.
    std::string expected, got;
    try {
      expected = listing(pbr::inspect_gltf(p));
    } catch (const pbr::LoadError& e) {
      expected = e.what();
    }
    pbr::GltfModelInfo both;
    try {
      both = pbr::load_and_inspect_gltf(p, {.pool = &pool});
      got = listing(both.info);
    } catch (const pbr::LoadError& e) {
      got = e.what();
    }
    CHECK(got == expected);
    if (both.scene.objects.empty()) continue;  // (it threw)
    const pbr::GltfScene g = pbr::load_gltf(p, {.pool = &pool});
    CHECK(both.scene.objects.size() == g.objects.size());
    CHECK(both.scene.triangles == g.triangles);
    CHECK(both.scene.warnings == g.warnings);
    CHECK(both.scene.files == g.files);
    CHECK(both.scene.cameras.size() == g.cameras.size());
    CHECK(both.scene.lights.size() == g.lights.size());
  }
}

TEST_CASE("a file with EXT_meshopt_compression or Draco lists as written: indexed primitives, their triangles, no placeholder bytes") {
  // Both files are rewritten for tinygltf (document.h's pre-pass: Draco primitives' indices
  // taken out, meshopt's placeholder buffer given one byte); the listing says what the file
  // holds. tinygltf alone refuses both, which `softpbr info` did too.
  softpbr::raster::ThreadPool pool(2);
  for (const char* name : {"meshopt.glb", "draco.glb"}) {
    const fs::path p = fs::path(SOFTPBR_SOURCE_DIR) / "fuzz" / "corpus" / "gltf" / name;
    CAPTURE(name);
    const pbr::GltfInfo info = pbr::inspect_gltf(p);
    const pbr::GltfModelInfo both = pbr::load_and_inspect_gltf(p, {.pool = &pool});
    CHECK(listing(both.info) == listing(info));
    const std::string ext = std::string(name) == "draco.glb" ? "KHR_draco_mesh_compression" : "EXT_meshopt_compression";
    CHECK(std::find(info.extensions_used.begin(), info.extensions_used.end(), ext) != info.extensions_used.end());
    REQUIRE(!info.meshes.empty());
    std::size_t listed = 0;
    for (const pbr::GltfMeshInfo& m : info.meshes)
      for (const pbr::GltfPrimitiveInfo& prim : m.primitives) {
        CHECK(prim.indexed);
        listed += prim.triangles;
      }
    // Each mesh drawn once in these files: the triangles load_gltf draws.
    CHECK(listed == both.scene.triangles);
    CHECK(listed > 0);
  }
  // meshopt.glb's placeholder buffer holds nothing: the bytes listed are the BIN chunk's.
  const fs::path meshopt = fs::path(SOFTPBR_SOURCE_DIR) / "fuzz" / "corpus" / "gltf" / "meshopt.glb";
  const pbr::GltfInfo info = pbr::inspect_gltf(meshopt);
  CHECK(info.buffers == 2);
  CHECK(info.buffer_bytes == 1664);
}
