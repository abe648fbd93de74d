// KHR_draco_mesh_compression: a .glb built here with Draco's own encoder loads to the mesh
// Draco's own decoder gives (quantized positions, texture coordinates, octahedral normals,
// integer colours), within a unit of the last place of Draco's dequantization, and close to
// the mesh encoded; every invalid extension object is one line with its JSON pointer.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <nlohmann/json.hpp>

#include "softpbr/loaders/gltf.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;
using Json = nlohmann::json;
using Bytes = std::vector<std::uint8_t>;

namespace {

fs::path out_dir() {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "gltf-draco";
  fs::create_directories(dir);
  return dir;
}

Bytes glb(const Json& json, Bytes bin) {
  std::string text = json.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  while (bin.size() % 4 != 0) bin.push_back(0);
  Bytes out;
  auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  for (const char c : {'g', 'l', 'T', 'F'}) out.push_back(static_cast<std::uint8_t>(c));
  u32(2);
  u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
  u32(static_cast<std::uint32_t>(text.size()));
  u32(0x4E4F534Au);
  out.insert(out.end(), text.begin(), text.end());
  u32(static_cast<std::uint32_t>(bin.size()));
  u32(0x004E4942u);
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

fs::path write(const std::string& name, const Bytes& bytes) {
  const fs::path p = out_dir() / name;
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return p;
}

struct Encoded {
  Bytes data;
  int position = 0, normal = 0, uv = 0, color = 0;  // unique ids
  std::size_t points = 0;
};

// A wavy 9 × 9 grid (128 triangles) with normals, texture coordinates and 8-bit colours,
// encoded by Draco (edgebreaker, 14/10/12-bit quantization).
Encoded encode_grid() {
  constexpr int kN = 9;
  auto at = [](int i, int j, float out[9]) {
    const float x = static_cast<float>(i) / (kN - 1) * 2.0f - 1.0f, y = static_cast<float>(j) / (kN - 1) * 2.0f - 1.0f;
    out[0] = x, out[1] = y, out[2] = 0.3f * (x * x - y * y);
    const float nx = -0.6f * x, ny = 0.6f * y, len = std::sqrt(nx * nx + ny * ny + 1.0f);
    out[3] = nx / len, out[4] = ny / len, out[5] = 1.0f / len;
    out[6] = static_cast<float>(i) / (kN - 1) * 3.0f, out[7] = static_cast<float>(j) / (kN - 1) * 1.7f;
  };
  draco::TriangleSoupMeshBuilder b;
  const int faces = (kN - 1) * (kN - 1) * 2;
  b.Start(faces);
  const int pos = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int nrm = b.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
  const int uv = b.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
  const int col = b.AddAttribute(draco::GeometryAttribute::COLOR, 4, draco::DT_UINT8);
  int f = 0;
  for (int j = 0; j + 1 < kN; ++j)
    for (int i = 0; i + 1 < kN; ++i) {
      const int corners[2][3][2] = {{{i, j}, {i + 1, j}, {i + 1, j + 1}}, {{i, j}, {i + 1, j + 1}, {i, j + 1}}};
      for (const auto& tri : corners) {
        float v[3][9];
        std::uint8_t c[3][4];
        for (int k = 0; k < 3; ++k) {
          at(tri[k][0], tri[k][1], v[k]);
          c[k][0] = static_cast<std::uint8_t>(tri[k][0] * 30), c[k][1] = static_cast<std::uint8_t>(tri[k][1] * 30);
          c[k][2] = 200, c[k][3] = 255;
        }
        const draco::FaceIndex fi(static_cast<std::uint32_t>(f++));
        b.SetAttributeValuesForFace(pos, fi, &v[0][0], &v[1][0], &v[2][0]);
        b.SetAttributeValuesForFace(nrm, fi, &v[0][3], &v[1][3], &v[2][3]);
        b.SetAttributeValuesForFace(uv, fi, &v[0][6], &v[1][6], &v[2][6]);
        b.SetAttributeValuesForFace(col, fi, c[0], c[1], c[2]);
      }
    }
  std::unique_ptr<draco::Mesh> mesh = b.Finalize();
  REQUIRE(mesh);
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeMeshToBuffer(*mesh, &buffer);
  REQUIRE(status.ok());
  Encoded e;
  e.data.assign(buffer.data(), buffer.data() + buffer.size());
  e.position = static_cast<int>(mesh->attribute(pos)->unique_id());
  e.normal = static_cast<int>(mesh->attribute(nrm)->unique_id());
  e.uv = static_cast<int>(mesh->attribute(uv)->unique_id());
  e.color = static_cast<int>(mesh->attribute(col)->unique_id());
  return e;
}

// Draco's own decoding of the data: points' values and the faces.
struct Reference {
  std::vector<float> pos, nrm, uv;
  std::vector<std::uint8_t> col;
  std::vector<std::uint32_t> indices;
};

Reference reference(const Encoded& e) {
  draco::DecoderBuffer in;
  in.Init(reinterpret_cast<const char*>(e.data.data()), e.data.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&in);
  REQUIRE(decoded.ok());
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  Reference r;
  const std::size_t n = mesh->num_points();
  auto read = [&](int id, int comps, std::vector<float>& out) {
    const draco::PointAttribute* a = mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(id));
    out.resize(n * static_cast<std::size_t>(comps));
    for (std::size_t p = 0; p < n; ++p)
      a->ConvertValue<float>(a->mapped_index(draco::PointIndex(static_cast<std::uint32_t>(p))), static_cast<std::int8_t>(comps),
                             &out[p * static_cast<std::size_t>(comps)]);
  };
  read(e.position, 3, r.pos);
  read(e.normal, 3, r.nrm);
  read(e.uv, 2, r.uv);
  const draco::PointAttribute* c = mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(e.color));
  r.col.resize(n * 4);
  for (std::size_t p = 0; p < n; ++p) c->GetMappedValue(draco::PointIndex(static_cast<std::uint32_t>(p)), &r.col[p * 4]);
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
    for (int k = 0; k < 3; ++k) r.indices.push_back(mesh->face(f)[static_cast<std::size_t>(k)].value());
  return r;
}

Json document(std::size_t points, std::size_t indices) {
  return {{"asset", {{"version", "2.0"}}},
          {"scene", 0},
          {"scenes", {{{"nodes", {0}}}}},
          {"nodes", {{{"mesh", 0}}}},
          {"materials", {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.9, 0.9, 1}}, {"metallicFactor", 0}}}}}},
          {"accessors",
           {{{"componentType", 5126}, {"count", points}, {"type", "VEC3"}, {"min", {-1, -1, -0.3}}, {"max", {1, 1, 0.3}}},
            {{"componentType", 5126}, {"count", points}, {"type", "VEC3"}},
            {{"componentType", 5126}, {"count", points}, {"type", "VEC2"}},
            {{"componentType", 5121}, {"normalized", true}, {"count", points}, {"type", "VEC4"}},
            {{"componentType", 5125}, {"count", indices}, {"type", "SCALAR"}}}}};
}

Json draco_json(const Encoded& e, const Reference& r) {
  Json j = document(r.pos.size() / 3, r.indices.size());
  j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  j["bufferViews"] = {{{"buffer", 0}, {"byteLength", e.data.size()}}};
  j["buffers"] = {{{"byteLength", e.data.size()}}};
  j["meshes"] = {{{"primitives",
                   {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}, {"COLOR_0", 3}}},
                     {"indices", 4},
                     {"material", 0},
                     {"extensions",
                      {{"KHR_draco_mesh_compression",
                        {{"bufferView", 0},
                         {"attributes", {{"POSITION", e.position}, {"NORMAL", e.normal}, {"TEXCOORD_0", e.uv}, {"COLOR_0", e.color}}}}}}}}}}}};
  return j;
}

// The same mesh uncompressed, with Draco's decoded values.
Bytes plain_glb(const Reference& r) {
  Json j = document(r.pos.size() / 3, r.indices.size());
  Bytes bin;
  Json views = Json::array();
  auto add = [&](const void* p, std::size_t n) {
    views.push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", n}});
    const auto* b = static_cast<const std::uint8_t*>(p);
    bin.insert(bin.end(), b, b + n);
    while (bin.size() % 4 != 0) bin.push_back(0);
  };
  add(r.pos.data(), r.pos.size() * 4);
  add(r.nrm.data(), r.nrm.size() * 4);
  add(r.uv.data(), r.uv.size() * 4);
  add(r.col.data(), r.col.size());
  add(r.indices.data(), r.indices.size() * 4);
  for (std::size_t a = 0; a < 5; ++a) j["accessors"][a]["bufferView"] = a;
  j["bufferViews"] = views;
  j["buffers"] = {{{"byteLength", bin.size()}}};
  j["meshes"] = {{{"primitives",
                   {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}, {"COLOR_0", 3}}}, {"indices", 4}, {"material", 0}}}}}};
  return glb(j, bin);
}

std::string load_error(const fs::path& p) {
  try {
    pbr::load_gltf(p);
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return "(no error)";
}

std::uint64_t render_hash(const pbr::GltfScene& g) {
  pbr::Scene s;
  s.objects = g.objects;
  s.camera = pbr::framing_camera(pbr::world_bounds(s.objects), 4.0f / 3.0f, 0.3f, 0.4f);
  s.lights = pbr::default_light_rig(s.camera);
  s.ambient = glm::vec3(pbr::kDefaultAmbient);
  raster::Renderer renderer({.threads = 2});
  raster::Target target(80, 60);
  pbr::render(s, renderer, target);
  return raster::hash_colors(target);
}

bool close(float a, float b) { return std::abs(a - b) <= 1e-6f * std::max(1.0f, std::abs(b)); }

}  // namespace

TEST_CASE("KHR_draco_mesh_compression: a Draco-encoded mesh loads as Draco decodes it") {
  const Encoded e = encode_grid();
  const Reference r = reference(e);
  const pbr::GltfScene a = pbr::load_gltf(write("grid.glb", glb(draco_json(e, r), e.data)));
  const pbr::GltfScene b = pbr::load_gltf(write("grid_plain.glb", plain_glb(r)));
  for (const std::string& w : a.warnings) CHECK(w.find("draco") == std::string::npos);
  REQUIRE(a.objects.size() == 1);
  REQUIRE(b.objects.size() == 1);
  const pbr::Mesh& ma = *a.objects[0].mesh;
  const pbr::Mesh& mb = *b.objects[0].mesh;
  CHECK(ma.triangle_count() == 128);
  CHECK(ma.indices == mb.indices);
  REQUIRE(ma.vertices.size() == mb.vertices.size());
  REQUIRE(ma.colors.size() == mb.colors.size());
  int differ = 0;
  for (std::size_t v = 0; v < ma.vertices.size(); ++v) {
    for (int k = 0; k < 3; ++k) {
      CHECK(close(ma.vertices[v].position[k], mb.vertices[v].position[k]));
      CHECK(close(ma.vertices[v].normal[k], mb.vertices[v].normal[k]));
      differ += ma.vertices[v].position[k] != mb.vertices[v].position[k] || ma.vertices[v].normal[k] != mb.vertices[v].normal[k];
    }
    for (int k = 0; k < 2; ++k) CHECK(close(ma.vertices[v].uv[k], mb.vertices[v].uv[k]));
    CHECK(ma.colors[v] == mb.colors[v]);  // integers, normalized alike
    // Close to what was encoded: the grid's surface and normal, to the quantization.
    const glm::vec3 p = ma.vertices[v].position;
    CHECK(std::abs(p.z - 0.3f * (p.x * p.x - p.y * p.y)) < 1e-3f);
    const glm::vec3 want = glm::normalize(glm::vec3(-0.6f * p.x, 0.6f * p.y, 1.0f));
    CHECK(glm::length(ma.vertices[v].normal - want) < 0.01f);
  }
  // libdraco's dequantization is the same formula; built without FMA contraction (x86-64)
  // its floats are these bits, and then the renders are too.
  MESSAGE(differ << " position/normal components differ from libdraco's own dequantization");
  if (differ == 0) CHECK(render_hash(a) == render_hash(b));
}

TEST_CASE("KHR_draco_mesh_compression: each invalid extension object is one line with its pointer") {
  const Encoded e = encode_grid();
  const Reference r = reference(e);
  const Json good = draco_json(e, r);
  const std::string x = "/meshes/0/primitives/0/extensions/KHR_draco_mesh_compression";
  auto ext = [](Json& j) -> Json& { return j["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]; };
  struct Case {
    std::string name;
    std::function<void(Json&)> edit;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"no_view", [&](Json& j) { ext(j).erase("bufferView"); }, x + ": missing required property \"bufferView\""},
      {"bad_view", [&](Json& j) { ext(j)["bufferView"] = 7; }, x + "/bufferView: bufferView 7 does not exist (1 bufferView)"},
      // 2^32: tinygltf's Value read it as bufferView 0, and the file rendered.
      {"view_2_32", [&](Json& j) { ext(j)["bufferView"] = 4294967296ull; }, x + "/bufferView: must be at most 2147483647, got 4294967296"},
      {"attribute_2_32", [&](Json& j) { ext(j)["attributes"]["POSITION"] = 4294967296ull; },
       x + "/attributes/POSITION: must be a Draco attribute id (an integer in 0 … 2147483647), got 4294967296"},
      {"view_string", [&](Json& j) { ext(j)["bufferView"] = "0"; }, x + "/bufferView: must be an index (an integer >= 0), got \"0\""},
      {"no_attributes", [&](Json& j) { ext(j).erase("attributes"); }, x + ": missing required property \"attributes\""},
      {"attribute_id", [&](Json& j) { ext(j)["attributes"]["NORMAL"] = 9; }, x + "/attributes/NORMAL: the Draco data has no attribute 9"},
      {"count", [&](Json& j) { j["accessors"][1]["count"] = 5; },
       "/accessors/1/count: is 5, but the Draco mesh has " + std::to_string(r.pos.size() / 3) + " points"},
      {"type", [&](Json& j) { j["accessors"][2]["type"] = "VEC3"; },
       "/accessors/2/type: has 3 components, which /meshes/0/primitives/0/attributes/TEXCOORD_0 cannot use"},
      {"components", [&](Json& j) { j["accessors"][3]["type"] = "VEC3"; },
       "/accessors/3/type: has 3 components, but the Draco attribute has 4"},
      // The decoded data is held to its accessors as stored data is (an indices accessor
      // claiming 300 000 indices, or FLOAT indices, rendered Draco's triangles before).
      {"indices_count", [&](Json& j) { j["accessors"][4]["count"] = 300000; },
       "/accessors/4/count: is 300000, but the Draco mesh has " + std::to_string(r.indices.size()) + " indices (" +
           std::to_string(r.indices.size() / 3) + " triangles)"},
      {"indices_float", [&](Json& j) { j["accessors"][4]["componentType"] = 5126; },
       "/accessors/4/componentType: indices must be unsigned bytes, shorts or ints"},
      {"indices_vec2", [&](Json& j) { j["accessors"][4]["type"] = "VEC2"; }, "/accessors/4/type: indices must be SCALAR"},
      {"float_integers", [&](Json& j) { j["accessors"][3]["componentType"] = 5126, j["accessors"][3].erase("normalized"); },
       "/accessors/3/componentType: is FLOAT, but the Draco attribute holds integers"},
      {"integer_floats", [&](Json& j) {
         j["accessors"][2]["componentType"] = 5123;
         j["accessors"][2]["normalized"] = true;
       },
       "/accessors/2/componentType: is an integer type, but the Draco attribute holds floats"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    Json j = good;
    c.edit(j);
    const fs::path p = write(c.name + ".glb", glb(j, e.data));
    CHECK(load_error(p) == p.string() + ": " + c.message);
  }
  // Damaged Draco data: the decoder's own reason, after the pointer.
  Bytes broken = e.data;
  for (std::size_t i = 8; i < broken.size(); ++i) broken[i] = static_cast<std::uint8_t>(broken[i] * 31 + 7);
  const fs::path p = write("damaged.glb", glb(good, broken));
  const std::string message = load_error(p);
  CAPTURE(message);
  CHECK(message.rfind(p.string() + ": " + x + ": the Draco data cannot be decoded (", 0) == 0);
  CHECK(message.find('\n') == std::string::npos);
  Bytes cut(e.data.begin(), e.data.begin() + 10);
  Json short_view = good;
  short_view["bufferViews"][0]["byteLength"] = 10;
  short_view["buffers"][0]["byteLength"] = 12;
  const fs::path q2 = write("cut.glb", glb(short_view, cut));
  CHECK(load_error(q2).rfind(q2.string() + ": " + x + ": the Draco data cannot be decoded (", 0) == 0);
}
