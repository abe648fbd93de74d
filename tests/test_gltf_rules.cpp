// glTF 2.0's MUST rules, checked on the document before anything is built (loaders/src/gltf/
// schema.cpp): the version rules, integers read as the exact values they are (tinygltf
// holds many as int), the node hierarchy, transforms, accessor types, and the references
// of skins, animations and extensions. Each hostile file is one line with its JSON pointer;
// each valid variant loads. Files are built here as small JSON documents (and .glb bytes).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "softpbr/loaders/gltf.h"

namespace pbr = softpbr::pbr;
using Json = nlohmann::json;

namespace {

// One triangle: 3 float positions (36 bytes) then 3 u16 indices (6 bytes, padded to 8).
const char* kTriangle = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
  "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";

std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

// The message load_gltf throws for `bytes` named `name`, or "(no error)".
std::string load_error(const std::vector<std::uint8_t>& bytes, const std::string& name) {
  try {
    pbr::load_gltf(bytes, name, "/nonexistent-folder");
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return "(no error)";
}

// A .glb of `json` (no binary chunk) with the header's version `version`.
std::vector<std::uint8_t> glb(std::string json, std::uint32_t version) {
  while (json.size() % 4 != 0) json.push_back(' ');
  std::vector<std::uint8_t> out;
  auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  for (const char c : {'g', 'l', 'T', 'F'}) out.push_back(static_cast<std::uint8_t>(c));
  u32(version);
  u32(static_cast<std::uint32_t>(12 + 8 + json.size()));
  u32(static_cast<std::uint32_t>(json.size()));
  u32(0x4E4F534Au);
  out.insert(out.end(), json.begin(), json.end());
  return out;
}

struct Case {
  const char* name;
  std::function<void(Json&)> change;
  std::string message;  // "" : the file loads
};

void check_cases(const std::vector<Case>& cases) {
  const Json base = Json::parse(kTriangle);
  for (const Case& c : cases) {
    const std::string case_name = c.name;
    CAPTURE(case_name);
    Json g = base;
    c.change(g);
    const std::string name = std::string(c.name) + ".gltf";
    const std::string message = load_error(bytes_of(g.dump()), name);
    CAPTURE(message);
    if (c.message.empty()) {
      CHECK(message == "(no error)");
    } else {
      CHECK(message == name + ": " + c.message);
    }
  }
}

}  // namespace

TEST_CASE("glTF version rules: 2.x loads, another major version, a minVersion above 2.0 and a malformed version are refused") {
  check_cases({
      {"v20", [](Json&) {}, ""},
      {"v21", [](Json& g) { g["asset"]["version"] = "2.1"; }, ""},  // Asset Generator Compatibility 01-03
      {"v21_min20", [](Json& g) { g["asset"]["version"] = "2.1", g["asset"]["minVersion"] = "2.0"; }, ""},
      {"v10", [](Json& g) { g["asset"]["version"] = "1.0"; },
       "/asset/version: glTF 1.0 is not glTF 2: this reader reads glTF 2.x files only"},
      {"v30", [](Json& g) { g["asset"]["version"] = "3.0"; },
       "/asset/version: glTF 3.0 is not glTF 2: this reader reads glTF 2.x files only"},
      {"v2", [](Json& g) { g["asset"]["version"] = "2"; },
       "/asset/version: must be \"<major>.<minor>\" (such as \"2.0\"), got \"2\""},
      {"v2x", [](Json& g) { g["asset"]["version"] = "2.0a"; },
       "/asset/version: must be \"<major>.<minor>\" (such as \"2.0\"), got \"2.0a\""},
      {"min21", [](Json& g) { g["asset"]["version"] = "2.1", g["asset"]["minVersion"] = "2.1"; },  // Compatibility 04
       "/asset/minVersion: the file needs a reader of glTF 2.1; this one implements glTF 2.0"},
      {"min_above", [](Json& g) { g["asset"]["minVersion"] = "2.1"; },
       "/asset/minVersion: 2.1 is newer than the file's version 2.0"},
      {"min_bad", [](Json& g) { g["asset"]["minVersion"] = "2.0.0"; },
       "/asset/minVersion: must be \"<major>.<minor>\" (such as \"2.0\"), got \"2.0.0\""},
  });
  // A .glb whose header says version 1 (glTF 1.0's binary extension) is refused; 2 loads.
  CHECK(load_error(glb(kTriangle, 2), "v2.glb") == "(no error)");
  CHECK(load_error(glb(kTriangle, 1), "v1.glb") ==
        "v1.glb: the .glb header's version is 1: glTF 2.0 binary files are version 2");
}

TEST_CASE("glTF integers are read as the exact values they are: beyond int they are refused, in extensions too") {
  const Json lights = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}}}}}}};
  check_cases({
      // tinygltf reads these into an int: 2^32 + 1 became 1, 2^31 became negative.
      {"child", [](Json& g) { g["nodes"][0]["children"] = {4294967297ll}; },
       "/nodes/0/children/0: must be at most 2147483647, got 4294967297"},
      {"mesh", [](Json& g) { g["nodes"][0]["mesh"] = 4294967296ll; }, "/nodes/0/mesh: must be at most 2147483647, got 4294967296"},
      {"attribute", [](Json& g) { g["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 4294967296ll; },
       "/meshes/0/primitives/0/attributes/POSITION: must be at most 2147483647, got 4294967296"},
      {"indices", [](Json& g) { g["meshes"][0]["primitives"][0]["indices"] = 4294967297ll; },
       "/meshes/0/primitives/0/indices: must be at most 2147483647, got 4294967297"},
      {"scene_node", [](Json& g) { g["scenes"][0]["nodes"] = {4294967296ll}; },
       "/scenes/0/nodes/0: must be at most 2147483647, got 4294967296"},
      // Sizes are read as 64-bit values; an accessor's count is held to the reader's limit.
      {"count", [](Json& g) { g["accessors"][0]["count"] = 4294967299ll; },
       "/accessors/0/count: must be at most 268435456, got 4294967299"},
      // KHR_lights_punctual: a light index 2^32 + 1 (read as light 1 before).
      {"light_index",
       [&](Json& g) {
         g["extensions"] = lights;
         g["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 4294967297ll;
       },
       "/nodes/0/extensions/KHR_lights_punctual/light: must be at most 2147483647, got 4294967297"},
      {"light_missing",
       [&](Json& g) {
         g["extensions"] = lights;
         g["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 1;
       },
       "/nodes/0/extensions/KHR_lights_punctual/light: light 1 does not exist (1 light)"},
      {"light_float",
       [&](Json& g) {
         g["extensions"] = lights;
         g["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 1e300;
       },
       "/nodes/0/extensions/KHR_lights_punctual/light: must be an index (an integer >= 0), got 1e+300"},
      {"light_ok",
       [&](Json& g) {
         g["extensions"] = lights;
         g["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       },
       ""},
      // Any extension's integer: its value would be read modulo 2^32.
      {"unknown_extension", [](Json& g) { g["nodes"][0]["extensions"]["EXT_whatever"]["n"] = {1, -4294967296ll}; },
       "/nodes/0/extensions/EXT_whatever/n/1: is beyond the integers an extension's values may hold here "
       "(-2147483648 … 2147483647), got -4294967296"},
      // extras are not read: left alone.
      {"extras", [](Json& g) { g["nodes"][0]["extras"]["n"] = 4294967297ll; }, ""},
  });
}

TEST_CASE("glTF MUST rules: one parent a node, root nodes in scenes, matrix or TRS, affine matrices, accessor types") {
  check_cases({
      {"two_parents",
       [](Json& g) {
         g["nodes"] = Json::parse(R"([{"children": [2]}, {"children": [2]}, {"mesh": 0}])");
         g["scenes"][0]["nodes"] = {0, 1};
       },
       "/nodes/1/children/0: node 2 is already a child of node 0 (a node has one parent at most, glTF 2.0 §3.5.1)"},
      {"child_twice",
       [](Json& g) {
         g["nodes"] = Json::parse(R"([{"children": [1, 1]}, {"mesh": 0}])");
       },
       "/nodes/0/children/1: node 1 is listed twice"},
      {"scene_twice", [](Json& g) { g["scenes"][0]["nodes"] = {0, 0}; }, "/scenes/0/nodes/1: node 0 is listed twice"},
      {"scene_child",
       [](Json& g) {
         g["nodes"] = Json::parse(R"([{"children": [1]}, {"mesh": 0}])");
         g["scenes"][0]["nodes"] = {0, 1};
       },
       "/scenes/0/nodes/1: node 1 is a child of node 0, not a root node (glTF 2.0 §3.5.2)"},
      {"missing_child", [](Json& g) { g["nodes"][0]["children"] = {5}; }, "/nodes/0/children/0: node 5 does not exist (1 node)"},
      {"matrix_and_trs",
       [](Json& g) {
         g["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
         g["nodes"][0]["scale"] = {2, 2, 2};
       },
       "/nodes/0/matrix: a node with a matrix must not have scale too (glTF 2.0 §5.25: a matrix or TRS properties)"},
      {"projective",
       [](Json& g) { g["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -1, 0, 0, 0, 0}; },
       "/nodes/0/matrix: must be an affine transform (last row 0, 0, 0, 1: elements 3, 7, 11, 15 of the array), got 0, 0, "
       "-1, 0"},
      {"affine", [](Json& g) { g["nodes"][0]["matrix"] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 5, 0, 0, 1}; }, ""},
      {"normalized_float", [](Json& g) { g["accessors"][0]["normalized"] = true; },
       "/accessors/0/normalized: must not be true for FLOAT components (glTF 2.0 §5.1.4)"},
      {"normalized_uint",
       [](Json& g) {
         g["accessors"][1]["componentType"] = 5125;
         g["accessors"][1]["normalized"] = true;
       },
       "/accessors/1/normalized: must not be true for UNSIGNED_INT components (glTF 2.0 §5.1.4)"},
      // Positions as integers need KHR_mesh_quantization, and unsigned ints never fit.
      {"uint_positions",
       [](Json& g) {
         g["accessors"][0]["componentType"] = 5125;
         g["extensionsUsed"] = {"KHR_mesh_quantization"};
       },
       "/accessors/0/componentType: component type 5125 is not allowed for POSITION "
       "(/meshes/0/primitives/0/attributes/POSITION) even with KHR_mesh_quantization"},
      {"short_positions",
       [](Json& g) {
         g["accessors"][0]["componentType"] = 5122;
         g["accessors"][0]["count"] = 3;
       },
       "/accessors/0/componentType: component type 5122 is not allowed for POSITION "
       "(/meshes/0/primitives/0/attributes/POSITION): integer attributes need KHR_mesh_quantization in extensionsUsed"},
  });
}

TEST_CASE("glTF skins and animations: every reference names something that exists") {
  const Json skin = Json::parse(R"([{"joints": [0]}])");
  const Json animation = Json::parse(
      R"([{"samplers": [{"input": 0, "output": 0}], "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]}])");
  check_cases({
      {"skin_ok", [&](Json& g) { g["skins"] = skin, g["nodes"][0]["skin"] = 0; }, ""},
      {"node_skin", [](Json& g) { g["nodes"][0]["skin"] = 7; }, "/nodes/0/skin: skin 7 does not exist (0 skins)"},
      {"joint", [&](Json& g) { g["skins"] = skin, g["skins"][0]["joints"][0] = 99999; },
       "/skins/0/joints/0: node 99999 does not exist (1 node)"},
      {"inverse_bind", [&](Json& g) { g["skins"] = skin, g["skins"][0]["inverseBindMatrices"] = 999; },
       "/skins/0/inverseBindMatrices: accessor 999 does not exist (2 accessors)"},
      {"skeleton", [&](Json& g) { g["skins"] = skin, g["skins"][0]["skeleton"] = 3; },
       "/skins/0/skeleton: node 3 does not exist (1 node)"},
      {"animation_ok", [&](Json& g) { g["animations"] = animation; }, ""},
      {"target_node", [&](Json& g) { g["animations"] = animation, g["animations"][0]["channels"][0]["target"]["node"] = 99999; },
       "/animations/0/channels/0/target/node: node 99999 does not exist (1 node)"},
      {"sampler_input", [&](Json& g) { g["animations"] = animation, g["animations"][0]["samplers"][0]["input"] = 999; },
       "/animations/0/samplers/0/input: accessor 999 does not exist (2 accessors)"},
      {"channel_sampler", [&](Json& g) { g["animations"] = animation, g["animations"][0]["channels"][0]["sampler"] = 1; },
       "/animations/0/channels/0/sampler: sampler 1 does not exist (1 sampler in /animations/0)"},
      {"no_channels", [&](Json& g) { g["animations"] = animation, g["animations"][0].erase("channels"); },
       "/animations/0: missing required property \"channels\""},
      {"accessor_2_30", [&](Json& g) { g["accessors"].push_back({{"componentType", 5126}, {"count", 1 << 30}, {"type", "SCALAR"}}); },
       "/accessors/2/count: must be at most 268435456, got 1073741824"},
  });
}

TEST_CASE("glTF instancing: the draws of every mesh instance are counted from the JSON before any mesh is built") {
  // One mesh of 1000 triangles (3000 positions without a bufferView: zeros, allowed) placed
  // by `nodes` nodes. 2000 instances need far more than 32 MiB of draws: refused before the
  // mesh is built (20 000 instances of a 130 000-triangle mesh took 8.6 s to be refused).
  auto model = [](int nodes) {
    Json g = {{"asset", {{"version", "2.0"}}},
              {"meshes", Json::parse(R"([{"primitives": [{"attributes": {"POSITION": 0}}]}])")},
              {"accessors", Json::parse(R"([{"componentType": 5126, "count": 3000, "type": "VEC3"}])")}};
    std::vector<int> roots;
    for (int i = 0; i < nodes; ++i) {
      g["nodes"].push_back({{"mesh", 0}, {"translation", {i, 0, 0}}});
      roots.push_back(i);
    }
    g["scenes"] = {{{"nodes", roots}}};
    const std::string text = g.dump();
    return std::vector<std::uint8_t>(text.begin(), text.end());
  };
  pbr::GltfOptions options;
  options.memory_limit = std::uint64_t{32} << 20;
  CHECK(pbr::load_gltf(model(1), "one.gltf", "/nonexistent-folder", options).objects.size() == 1);
  std::string message = "(no error)";
  try {
    pbr::load_gltf(model(2000), "many.gltf", "/nonexistent-folder", options);
  } catch (const pbr::LoadError& e) {
    message = e.what();
  }
  CAPTURE(message);
  CHECK(message.rfind("many.gltf: /scenes/0/nodes: its nodes place 2000 mesh instances, whose draws need an estimated ", 0) == 0);
  CHECK(message.find("over the memory limit of 32.0 MiB (counted before any mesh is built)") != std::string::npos);
}

TEST_CASE("glTF material extensions: transmission and volume are read, required or not, each value checked") {
  const auto with_material = [](const Json& extensions, bool required = false) {
    Json j = Json::parse(kTriangle);
    j["materials"] = Json::array({Json{{"extensions", extensions}}});
    j["meshes"][0]["primitives"][0]["material"] = 0;
    Json used = Json::array();
    for (const auto& item : extensions.items()) used.push_back(item.key());
    j["extensionsUsed"] = used;
    if (required) j["extensionsRequired"] = used;
    return bytes_of(j.dump());
  };
  const Json glass = {{"KHR_materials_transmission", {{"transmissionFactor", 0.9}}},
                      {"KHR_materials_volume",
                       {{"thicknessFactor", 0.25}, {"attenuationDistance", 0.5}, {"attenuationColor", {0.9, 0.5, 0.2}}}}};
  const pbr::GltfScene g = pbr::load_gltf(with_material(glass, true), "glass.gltf", "/nonexistent-folder");
  REQUIRE(g.objects.size() == 1);
  const pbr::Material& m = g.objects[0].material;
  CHECK(m.transmission.factor == 0.9f);
  CHECK(m.volume.thickness == 0.25f);
  CHECK(m.volume.attenuation_distance == 0.5f);
  CHECK(m.volume.attenuation_color == glm::vec3(0.9f, 0.5f, 0.2f));
  CHECK(m.transmissive());
  CHECK(m.layered());
  for (const std::string& w : g.warnings) CHECK(w.find("not supported") == std::string::npos);
  // Defaults: no transmission, a thin wall, no attenuation.
  const pbr::GltfScene d = pbr::load_gltf(
      with_material({{"KHR_materials_transmission", Json::object()}, {"KHR_materials_volume", Json::object()}}),
      "defaults.gltf", "/nonexistent-folder");
  const pbr::Material& dm = d.objects[0].material;
  CHECK_FALSE(dm.transmissive());
  CHECK_FALSE(dm.layered());
  CHECK(dm.volume.thickness == 0.0f);
  CHECK(std::isinf(dm.volume.attenuation_distance));
  const std::vector<std::string>& rendered = pbr::gltf_extensions_rendered();
  for (const char* e : {"KHR_materials_transmission", "KHR_materials_volume"})
    CHECK(std::find(rendered.begin(), rendered.end(), e) != rendered.end());
  const struct {
    Json extensions;
    const char* message;
  } bad[] = {
      {{{"KHR_materials_transmission", {{"transmissionFactor", "x"}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_transmission/transmissionFactor: expected a finite number"},
      {{{"KHR_materials_volume", {{"attenuationDistance", 0}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_volume/attenuationDistance: must be a finite number > 0"},
      {{{"KHR_materials_volume", {{"attenuationDistance", -2.0}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_volume/attenuationDistance: must be a finite number > 0"},
      {{{"KHR_materials_volume", {{"attenuationDistance", 1e-300}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_volume/attenuationDistance: must be a finite number > 0"},
      {{{"KHR_materials_volume", {{"thicknessFactor", "thick"}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_volume/thicknessFactor: expected a finite number"},
      {{{"KHR_materials_volume", {{"attenuationColor", {1, 1}}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_volume/attenuationColor: expected three numbers"},
      {{{"KHR_materials_transmission", {{"transmissionTexture", {{"index", 4}}}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_transmission/transmissionTexture/index: texture 4 does not exist"},
  };
  for (const auto& b : bad) {
    CAPTURE(b.extensions.dump());
    CHECK(load_error(with_material(b.extensions), "bad.gltf") == b.message);
  }
  // Out-of-range values are clamped as the schema's ranges (a negative thickness is 0, a
  // colour channel above 1 is 1), as the other extensions' factors are.
  const pbr::GltfScene c = pbr::load_gltf(
      with_material({{"KHR_materials_transmission", {{"transmissionFactor", 7}}},
                     {"KHR_materials_volume", {{"thicknessFactor", -3}, {"attenuationColor", {2, 0.5, -1}}}}}),
      "clamped.gltf", "/nonexistent-folder");
  CHECK(c.objects[0].material.transmission.factor == 1.0f);
  CHECK(c.objects[0].material.volume.thickness == 0.0f);
  CHECK(c.objects[0].material.volume.attenuation_color == glm::vec3(1.0f, 0.5f, 0.0f));
}

TEST_CASE("glTF material extensions: ior, specular, clearcoat and sheen are read into the layers, each checked") {
  const auto with_material = [](const Json& extensions, const char* required = nullptr) {
    Json j = Json::parse(kTriangle);
    j["materials"] = Json::array({Json{{"extensions", extensions}}});
    j["meshes"][0]["primitives"][0]["material"] = 0;
    Json used = Json::array();
    for (const auto& [name, value] : extensions.items()) used.push_back(name);
    j["extensionsUsed"] = used;
    if (required != nullptr) j["extensionsRequired"] = Json::array({required});
    return bytes_of(j.dump());
  };
  const Json all = {{"KHR_materials_ior", {{"ior", 1.7}}},
                    {"KHR_materials_specular", {{"specularFactor", 0.5}, {"specularColorFactor", {1.0, 0.5, 2.0}}}},
                    {"KHR_materials_clearcoat", {{"clearcoatFactor", 0.8}, {"clearcoatRoughnessFactor", 0.2}}},
                    {"KHR_materials_sheen", {{"sheenColorFactor", {0.9, 0.8, 0.7}}, {"sheenRoughnessFactor", 0.4}}}};
  const pbr::GltfScene g = pbr::load_gltf(with_material(all, "KHR_materials_clearcoat"), "layers.gltf", "/nonexistent-folder");
  REQUIRE(g.objects.size() == 1);
  const pbr::Material& m = g.objects[0].material;
  CHECK(m.ior == 1.7f);
  CHECK(m.specular.factor == 0.5f);
  CHECK(m.specular.color == glm::vec3(1.0f, 0.5f, 2.0f));  // may exceed 1 (F0 is clamped)
  CHECK(m.clearcoat.factor == 0.8f);
  CHECK(m.clearcoat.roughness == 0.2f);
  CHECK(m.sheen.color == glm::vec3(0.9f, 0.8f, 0.7f));
  CHECK(m.sheen.roughness == 0.4f);
  CHECK(m.layered());
  for (const std::string& w : g.warnings) CHECK(w.find("not supported") == std::string::npos);
  // Defaults: a material listing the extensions with no values is the core material.
  const pbr::GltfScene d = pbr::load_gltf(
      with_material({{"KHR_materials_ior", Json::object()}, {"KHR_materials_clearcoat", Json::object()},
                     {"KHR_materials_sheen", Json::object()}, {"KHR_materials_specular", Json::object()}}),
      "defaults.gltf", "/nonexistent-folder");
  CHECK_FALSE(d.objects[0].material.layered());
  // Each bad value is one line with its JSON pointer.
  const struct {
    Json extensions;
    const char* message;
  } bad[] = {
      {{{"KHR_materials_ior", {{"ior", 0.5}}}}, "bad.gltf: /materials/0/extensions/KHR_materials_ior/ior: must be 0 or a finite number ≥ 1"},
      {{{"KHR_materials_clearcoat", {{"clearcoatFactor", "x"}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_clearcoat/clearcoatFactor: expected a finite number"},
      {{{"KHR_materials_sheen", {{"sheenColorFactor", {1, 2}}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_sheen/sheenColorFactor: expected three numbers"},
      {{{"KHR_materials_specular", {{"specularTexture", {{"index", 7}}}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_specular/specularTexture/index: texture 7 does not exist"},
      {{{"KHR_materials_clearcoat", {{"clearcoatNormalTexture", 3}}}},
       "bad.gltf: /materials/0/extensions/KHR_materials_clearcoat/clearcoatNormalTexture: expected a textureInfo object"},
  };
  for (const auto& b : bad) {
    CAPTURE(b.extensions.dump());
    CHECK(load_error(with_material(b.extensions), "bad.gltf") == b.message);
  }
}
