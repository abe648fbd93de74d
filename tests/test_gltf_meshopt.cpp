// EXT_meshopt_compression: .glb files built here with meshoptimizer's own encoder (as
// gltfpack writes them: a placeholder fallback buffer, the extension required) load to the
// same meshes, and render the same bits, as the uncompressed files; the filters against
// meshoptimizer's; every invalid extension object is one line with its JSON pointer.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include "gltf/meshopt.h"  // loaders/src: the filters
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
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "gltf-meshopt";
  fs::create_directories(dir);
  return dir;
}

void append(Bytes& to, const void* p, std::size_t n) {
  const auto* b = static_cast<const std::uint8_t*>(p);
  to.insert(to.end(), b, b + n);
  while (to.size() % 4 != 0) to.push_back(0);
}

Bytes glb(const Json& json, const Bytes& bin) {
  std::string text = json.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
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

// One stream of a primitive: its raw bytes, element layout and how it is compressed.
struct Stream {
  Bytes raw;  // what the uncompressed file holds (for filtered streams: the filter's output)
  Bytes encoded_input;  // what the attribute codec encodes (filtered streams: the filter's input)
  std::size_t count = 0, stride = 0;
  std::string mode, filter;
  bool attribute = true;  // a vertex attribute (the bufferView has a byteStride)
};

// A wavy 9 × 9 grid, two primitives sharing its attributes: one indexed through a
// TRIANGLES-coded view (u16), one through an INDICES-coded view (u32).
struct Model {
  std::vector<Stream> streams;  // POSITION, NORMAL, TEXCOORD_0, indices (u16), indices (u32)
  Json accessors;
};

Model grid(bool filters) {
  constexpr int kN = 9;
  std::vector<float> pos, nrm, uv;
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i) {
      const float x = static_cast<float>(i) / (kN - 1) * 2.0f - 1.0f, y = static_cast<float>(j) / (kN - 1) * 2.0f - 1.0f;
      pos.insert(pos.end(), {x, y, 0.3f * (x * x - y * y)});
      const float nx = -0.6f * x, ny = 0.6f * y, len = std::sqrt(nx * nx + ny * ny + 1.0f);
      nrm.insert(nrm.end(), {nx / len, ny / len, 1.0f / len});
      uv.insert(uv.end(), {static_cast<float>(i) / (kN - 1) * 3.0f, static_cast<float>(j) / (kN - 1) * 1.7f});
    }
  std::vector<std::uint32_t> tri;
  for (int j = 0; j + 1 < kN; ++j)
    for (int i = 0; i + 1 < kN; ++i) {
      const std::uint32_t a = static_cast<std::uint32_t>(j * kN + i), b = a + 1, c = a + kN, d = c + 1;
      tri.insert(tri.end(), {a, b, d, a, d, c});
    }
  const std::size_t nv = pos.size() / 3;
  Model m;
  Stream p{{}, {}, nv, 12, "ATTRIBUTES", "NONE"};
  append(p.raw, pos.data(), pos.size() * 4);
  p.encoded_input = p.raw;
  m.streams.push_back(p);
  Json normal_accessor, uv_accessor;
  if (filters) {
    // Normals: 8-bit octahedral (4 bytes a vertex, the accessor BYTE normalized);
    // texture coordinates: the exponential filter with 15-bit mantissas.
    Stream n{{}, {}, nv, 4, "ATTRIBUTES", "OCTAHEDRAL"};
    std::vector<float> n4;
    for (std::size_t v = 0; v < nv; ++v) n4.insert(n4.end(), {nrm[3 * v], nrm[3 * v + 1], nrm[3 * v + 2], 0.0f});
    n.encoded_input.resize(nv * 4);
    meshopt_encodeFilterOct(n.encoded_input.data(), nv, 4, 8, n4.data());
    n.raw = n.encoded_input;
    meshopt_decodeFilterOct(n.raw.data(), nv, 4);
    m.streams.push_back(n);
    normal_accessor = {{"bufferView", 1}, {"componentType", 5120}, {"normalized", true}, {"count", nv}, {"type", "VEC3"}};
    Stream t{{}, {}, nv, 8, "ATTRIBUTES", "EXPONENTIAL"};
    t.encoded_input.resize(nv * 8);
    meshopt_encodeFilterExp(t.encoded_input.data(), nv, 8, 15, uv.data());
    t.raw = t.encoded_input;
    meshopt_decodeFilterExp(t.raw.data(), nv, 8);
    m.streams.push_back(t);
  } else {
    Stream n{{}, {}, nv, 12, "ATTRIBUTES", "NONE"};
    append(n.raw, nrm.data(), nrm.size() * 4);
    n.encoded_input = n.raw;
    m.streams.push_back(n);
    normal_accessor = {{"bufferView", 1}, {"componentType", 5126}, {"count", nv}, {"type", "VEC3"}};
    Stream t{{}, {}, nv, 8, "ATTRIBUTES", "NONE"};
    append(t.raw, uv.data(), uv.size() * 4);
    t.encoded_input = t.raw;
    m.streams.push_back(t);
  }
  // The triangle codec may rotate a triangle's corners (keeping its winding): the
  // uncompressed file holds the indices as meshoptimizer decodes them.
  {
    Bytes code(meshopt_encodeIndexBufferBound(tri.size(), nv));
    code.resize(meshopt_encodeIndexBuffer(code.data(), code.size(), tri.data(), tri.size()));
    std::vector<std::uint32_t> rotated(tri.size());
    REQUIRE(meshopt_decodeIndexBuffer(rotated.data(), rotated.size(), 4, code.data(), code.size()) == 0);
    tri = rotated;
  }
  std::vector<std::uint16_t> tri16(tri.begin(), tri.end());
  Stream i16{{}, {}, tri.size(), 2, "TRIANGLES", "NONE", false};
  append(i16.raw, tri16.data(), tri16.size() * 2);
  m.streams.push_back(i16);
  Stream i32{{}, {}, tri.size(), 4, "INDICES", "NONE", false};
  append(i32.raw, tri.data(), tri.size() * 4);
  m.streams.push_back(i32);
  m.accessors = Json::array(
      {{{"bufferView", 0}, {"componentType", 5126}, {"count", nv}, {"type", "VEC3"}, {"min", {-1, -1, -0.3}}, {"max", {1, 1, 0.3}}},
       normal_accessor,
       {{"bufferView", 2}, {"componentType", 5126}, {"count", nv}, {"type", "VEC2"}},
       {{"bufferView", 3}, {"componentType", 5123}, {"count", tri.size()}, {"type", "SCALAR"}},
       {{"bufferView", 4}, {"componentType", 5125}, {"count", tri.size()}, {"type", "SCALAR"}}});
  return m;
}

Json document(const Model& m) {
  Json j = {{"asset", {{"version", "2.0"}}},
            {"scene", 0},
            {"scenes", {{{"nodes", {0}}}}},
            {"nodes", {{{"mesh", 0}}}},
            {"materials", {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.5, 0.2, 1}}, {"metallicFactor", 0}}}}}},
            {"meshes",
             {{{"primitives",
                {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}}, {"indices", 3}, {"material", 0}},
                 {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}}, {"indices", 4}, {"material", 0}}}}}}},
            {"accessors", m.accessors}};
  j["extensionsUsed"] = Json::array({"KHR_mesh_quantization"});
  return j;
}

// The uncompressed file.
Bytes plain_glb(const Model& m) {
  Json j = document(m);
  Bytes bin;
  Json views = Json::array();
  for (const Stream& s : m.streams) {
    Json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", s.count * s.stride}};
    if (s.attribute) v["byteStride"] = s.stride;
    views.push_back(v);
    append(bin, s.raw.data(), s.count * s.stride);
  }
  j["bufferViews"] = views;
  j["buffers"] = {{{"byteLength", bin.size()}}};
  return glb(j, bin);
}

// The compressed file, as gltfpack -cc writes one: compressed data in the GLB buffer 0, the
// views' own buffer 1 a placeholder without data marked as the fallback.
Json compressed_json(const Model& m, Bytes& bin) {
  Json j = document(m);
  j["extensionsUsed"].push_back("EXT_meshopt_compression");
  j["extensionsRequired"] = {"EXT_meshopt_compression", "KHR_mesh_quantization"};
  Json views = Json::array();
  std::size_t fallback = 0;
  for (const Stream& s : m.streams) {
    Bytes code;
    if (s.mode == "ATTRIBUTES") {
      code.resize(meshopt_encodeVertexBufferBound(s.count, s.stride));
      code.resize(meshopt_encodeVertexBuffer(code.data(), code.size(), s.encoded_input.data(), s.count, s.stride));
    } else {
      std::vector<std::uint32_t> idx(s.count);
      for (std::size_t k = 0; k < s.count; ++k) {
        if (s.stride == 2) {
          std::uint16_t v;
          std::memcpy(&v, s.raw.data() + 2 * k, 2);
          idx[k] = v;
        } else {
          std::memcpy(&idx[k], s.raw.data() + 4 * k, 4);
        }
      }
      if (s.mode == "TRIANGLES") {
        code.resize(meshopt_encodeIndexBufferBound(s.count, 81));
        code.resize(meshopt_encodeIndexBuffer(code.data(), code.size(), idx.data(), s.count));
      } else {
        code.resize(meshopt_encodeIndexSequenceBound(s.count, 81));
        code.resize(meshopt_encodeIndexSequence(code.data(), code.size(), idx.data(), s.count));
      }
    }
    Json x = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", code.size()}, {"byteStride", s.stride},
              {"count", s.count}, {"mode", s.mode}};
    if (s.filter != "NONE") x["filter"] = s.filter;
    Json v = {{"buffer", 1}, {"byteOffset", fallback}, {"byteLength", s.count * s.stride},
              {"extensions", {{"EXT_meshopt_compression", x}}}};
    if (s.attribute) v["byteStride"] = s.stride;
    views.push_back(v);
    append(bin, code.data(), code.size());
    fallback += (s.count * s.stride + 3) / 4 * 4;
  }
  j["bufferViews"] = views;
  j["buffers"] = {{{"byteLength", bin.size()}},
                  {{"byteLength", fallback}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
  return j;
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
  int covered = 0;
  for (float d : target.depths()) covered += d < 1.0f;
  CHECK(covered > 80 * 60 / 8);
  return raster::hash_colors(target);
}

}  // namespace

TEST_CASE("EXT_meshopt_compression: meshoptimizer-encoded streams load and render as the uncompressed file") {
  const Model m = grid(false);
  Bytes bin;
  const Json j = compressed_json(m, bin);
  const fs::path packed = write("packed.glb", glb(j, bin));
  const fs::path plain = write("plain.glb", plain_glb(m));
  const pbr::GltfScene a = pbr::load_gltf(packed);
  const pbr::GltfScene b = pbr::load_gltf(plain);
  for (const std::string& w : a.warnings) CHECK(w.find("EXT_meshopt") == std::string::npos);
  REQUIRE(a.objects.size() == 2);
  REQUIRE(b.objects.size() == 2);
  for (std::size_t o = 0; o < 2; ++o) {
    const pbr::Mesh& ma = *a.objects[o].mesh;
    const pbr::Mesh& mb = *b.objects[o].mesh;
    CHECK(ma.indices == mb.indices);
    REQUIRE(ma.vertices.size() == mb.vertices.size());
    for (std::size_t v = 0; v < ma.vertices.size(); ++v) {
      CHECK(ma.vertices[v].position == mb.vertices[v].position);
      CHECK(ma.vertices[v].normal == mb.vertices[v].normal);
      CHECK(ma.vertices[v].uv == mb.vertices[v].uv);
    }
  }
  CHECK(a.objects[0].mesh->triangle_count() == 128);
  CHECK(render_hash(a) == render_hash(b));

  // The same in a .gltf whose compressed data is an external .bin, the placeholder buffer
  // being any buffer without a uri.
  Json text = j;
  text["buffers"][0]["uri"] = "packed.bin";
  {
    std::ofstream(out_dir() / "packed.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
    std::ofstream(out_dir() / "packed.gltf") << text.dump();
  }
  const pbr::GltfScene c = pbr::load_gltf(out_dir() / "packed.gltf");
  REQUIRE(c.objects.size() == 2);
  CHECK(render_hash(c) == render_hash(b));
}

TEST_CASE("EXT_meshopt_compression: octahedral normals and exponential texture coordinates") {
  const Model m = grid(true);
  Bytes bin;
  const Json j = compressed_json(m, bin);
  const pbr::GltfScene a = pbr::load_gltf(write("filtered.glb", glb(j, bin)));
  // The reference holds meshoptimizer's own filter output; the specification allows one
  // unit in the last place between decoders.
  const pbr::GltfScene b = pbr::load_gltf(write("filtered_plain.glb", plain_glb(m)));
  REQUIRE(a.objects.size() == 2);
  const pbr::Mesh& ma = *a.objects[0].mesh;
  const pbr::Mesh& mb = *b.objects[0].mesh;
  REQUIRE(ma.vertices.size() == mb.vertices.size());
  int differ = 0;
  for (std::size_t v = 0; v < ma.vertices.size(); ++v) {
    CHECK(ma.vertices[v].position == mb.vertices[v].position);
    CHECK(ma.vertices[v].uv == mb.vertices[v].uv);  // the exponential filter is exact
    for (int k = 0; k < 3; ++k) {
      CHECK(std::abs(ma.vertices[v].normal[k] - mb.vertices[v].normal[k]) <= 1.0f / 127.0f + 1e-6f);
      differ += ma.vertices[v].normal[k] != mb.vertices[v].normal[k];
    }
    // And the decoded normal is the grid's, to 8 bits.
    const glm::vec3 p = ma.vertices[v].position;
    const glm::vec3 want = glm::normalize(glm::vec3(-0.6f * p.x, 0.6f * p.y, 1.0f));
    CHECK(glm::length(ma.vertices[v].normal - want) < 0.03f);
  }
  MESSAGE(differ << " normal components differ by one unit from meshoptimizer's decoder");
  CHECK(std::abs(ma.vertices[80].uv.x - 3.0f) < 1e-3f);
}

TEST_CASE("EXT_meshopt_compression filters: softpbr's decoders against meshoptimizer's, within one unit") {
  std::mt19937 rng(7);
  std::normal_distribution<float> gauss;
  constexpr std::size_t kCount = 4096;
  std::vector<float> v4(kCount * 4);
  for (std::size_t i = 0; i < kCount; ++i) {
    float x = gauss(rng), y = gauss(rng), z = gauss(rng), w = gauss(rng);
    const float len = std::sqrt(x * x + y * y + z * z + w * w);
    v4[4 * i] = x / len, v4[4 * i + 1] = y / len, v4[4 * i + 2] = z / len, v4[4 * i + 3] = w / len;
  }
  auto max_unit_difference = [](const Bytes& a, const Bytes& b, int bytes) {
    int worst = 0;
    for (std::size_t k = 0; k < a.size(); k += static_cast<std::size_t>(bytes)) {
      int x, y;
      if (bytes == 1) {
        x = static_cast<std::int8_t>(a[k]), y = static_cast<std::int8_t>(b[k]);
      } else {
        std::int16_t p, q;
        std::memcpy(&p, &a[k], 2);
        std::memcpy(&q, &b[k], 2);
        x = p, y = q;
      }
      worst = std::max(worst, std::abs(x - y));
    }
    return worst;
  };
  for (int bits : {8, 12, 16}) {
    CAPTURE(bits);
    const std::size_t stride = bits > 8 ? 8 : 4;
    // Octahedral: unit vectors (x, y, z) with the fourth component passed through.
    Bytes enc(kCount * stride);
    meshopt_encodeFilterOct(enc.data(), kCount, stride, bits, v4.data());
    Bytes mine = enc, theirs = enc;
    softpbr::pbr::gltf::filter_octahedral(mine.data(), kCount, stride);
    meshopt_decodeFilterOct(theirs.data(), kCount, stride);
    CHECK(max_unit_difference(mine, theirs, stride == 4 ? 1 : 2) <= 1);
    for (std::size_t i = 0; i < kCount; ++i) {  // the fourth component is untouched
      CHECK(std::memcmp(&mine[i * stride + 3 * stride / 4], &enc[i * stride + 3 * stride / 4], stride / 4) == 0);
    }
    if (bits == 8) continue;
    // Quaternions (16-bit components only).
    Bytes q(kCount * 8);
    meshopt_encodeFilterQuat(q.data(), kCount, 8, bits, v4.data());
    Bytes qm = q, qt = q;
    softpbr::pbr::gltf::filter_quaternion(qm.data(), kCount);
    meshopt_decodeFilterQuat(qt.data(), kCount, 8);
    CHECK(max_unit_difference(qm, qt, 2) <= 1);
    // The result is the quaternion (up to sign), to the precision of `bits`.
    for (std::size_t i = 0; i < kCount; i += 97) {
      std::int16_t c[4];
      std::memcpy(c, &qm[i * 8], 8);
      float dot = 0.0f;
      for (int k = 0; k < 4; ++k) dot += static_cast<float>(c[k]) / 32767.0f * v4[4 * i + static_cast<std::size_t>(k)];
      CHECK(std::abs(dot) > 0.995f);
    }
  }
  // Exponential: exact, so equal to meshoptimizer's bit for bit.
  std::vector<float> values(kCount);
  for (std::size_t i = 0; i < kCount; ++i) values[i] = gauss(rng) * 1000.0f;
  Bytes e(kCount * 4);
  meshopt_encodeFilterExp(e.data(), kCount / 4, 16, 17, values.data());
  Bytes em = e, et = e;
  softpbr::pbr::gltf::filter_exponential(em.data(), kCount / 4, 16);
  meshopt_decodeFilterExp(et.data(), kCount / 4, 16);
  CHECK(em == et);
  float decoded;
  std::memcpy(&decoded, &em[4 * 5], 4);
  CHECK(std::abs(decoded - values[5]) <= std::abs(values[5]) * 1e-4f);
}

TEST_CASE("EXT_meshopt_compression: each invalid extension object or placeholder use is one line with its pointer") {
  const Model m = grid(true);
  Bytes bin;
  const Json good = compressed_json(m, bin);
  const std::string x = "/bufferViews/1/extensions/EXT_meshopt_compression";
  struct Case {
    std::string name;
    std::function<void(Json&)> edit;
    std::string message;
  };
  auto ext = [](Json& j, int view) -> Json& { return j["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]; };
  const std::vector<Case> cases = {
      {"mode", [&](Json& j) { ext(j, 1)["mode"] = "STRIPS"; }, x + "/mode: must be ATTRIBUTES, TRIANGLES or INDICES"},
      {"filter", [&](Json& j) { ext(j, 1)["filter"] = "LOG"; }, x + "/filter: must be NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL"},
      {"no_count", [&](Json& j) { ext(j, 1).erase("count"); }, x + ": missing required property \"count\""},
      {"no_mode", [&](Json& j) { ext(j, 1).erase("mode"); }, x + ": has no mode (required)"},
      {"count_string", [&](Json& j) { ext(j, 1)["count"] = "81"; }, x + "/count: must be an index (an integer >= 0), got \"81\""},
      {"stride_mismatch", [&](Json& j) { j["bufferViews"][1]["byteStride"] = 8; },
       x + "/byteStride: is 4, but the bufferView's byteStride is 8"},
      {"length", [&](Json& j) { ext(j, 1)["count"] = 80; },
       x + "/count: 80 elements of 4 bytes are 320 bytes, but the bufferView's byteLength is 324"},
      {"attr_stride", [&](Json& j) {
         ext(j, 1)["byteStride"] = 6;
         ext(j, 1)["count"] = 54;
         j["bufferViews"][1].erase("byteStride");  // (tinygltf refuses a bufferView's stride of 6 itself)
       },
       x + "/byteStride: must be a multiple of 4 in [4, 256] for ATTRIBUTES, got 6"},
      {"oct_stride", [&](Json& j) {
         ext(j, 1)["byteStride"] = 12;
         ext(j, 1)["count"] = 27;
         j["bufferViews"][1]["byteStride"] = 12;
       },
       x + "/byteStride: must be 4 or 8 for the OCTAHEDRAL filter, got 12"},
      {"quat_stride", [&](Json& j) { ext(j, 1)["filter"] = "QUATERNION"; },
       x + "/byteStride: must be 8 for the QUATERNION filter, got 4"},
      {"index_stride", [&](Json& j) {
         ext(j, 3)["byteStride"] = 1;
         ext(j, 3)["count"] = 768;
       },
       "/bufferViews/3/extensions/EXT_meshopt_compression/byteStride: must be 2 or 4 for TRIANGLES, got 1"},
      {"index_filter", [&](Json& j) { ext(j, 3)["filter"] = "EXPONENTIAL"; },
       "/bufferViews/3/extensions/EXT_meshopt_compression/filter: must be NONE for TRIANGLES, got EXPONENTIAL"},
      {"triangles", [&](Json& j) {
         ext(j, 3)["count"] = 383;
         ext(j, 3)["byteStride"] = 2;
         j["bufferViews"][3]["byteLength"] = 766;
       },
       "/bufferViews/3/extensions/EXT_meshopt_compression/count: must be a multiple of 3 for TRIANGLES, got 383"},
      {"past_buffer", [&](Json& j) { ext(j, 1)["byteOffset"] = 1000000; },
       x + ": " + std::to_string(good["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["byteLength"].get<int>()) +
           " bytes at offset 1000000 run past buffer 0 (" + std::to_string(bin.size()) + " bytes)"},
      {"no_buffer", [&](Json& j) { ext(j, 1)["buffer"] = 5; }, x + "/buffer: buffer 5 does not exist (2 buffers)"},
      // Integers beyond int (tinygltf's Value read them modulo 2^32: 2^33 was offset 0, and
      // the file rendered as the valid one).
      {"offset_2_33", [&](Json& j) { ext(j, 1)["byteOffset"] = 8589934592ull; },
       x + "/byteOffset: must be at most 2147483647, got 8589934592"},
      {"length_2_32", [&](Json& j) { ext(j, 1)["byteLength"] = 4294967296ull + ext(j, 1)["byteLength"].get<std::uint64_t>(); },
       x + "/byteLength: must be at most 2147483647, got " +
           std::to_string(4294967296ull + good["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["byteLength"].get<std::uint64_t>())},
      {"count_2_32", [&](Json& j) { ext(j, 1)["count"] = 4294967296ull + 81; }, x + "/count: must be at most 2147483647, got 4294967377"},
      {"count_2_31", [&](Json& j) { ext(j, 1)["count"] = 2147483648ull; }, x + "/count: must be at most 2147483647, got 2147483648"},
      {"fallback_source", [&](Json& j) { ext(j, 1)["buffer"] = 1; },
       x + "/buffer: buffer 1 has no data (it has no uri): compressed data must be in a buffer that has"},
      {"truncated", [&](Json& j) { ext(j, 1)["byteLength"] = 20; },
       x + ": the 20 bytes of compressed ATTRIBUTES data cannot be decoded (meshoptimizer: error -2)"},
      {"plain_view_on_fallback", [&](Json& j) { j["bufferViews"][2].erase("extensions"); },
       "/bufferViews/2/buffer: buffer 1 has no data (it has no uri): only EXT_meshopt_compression views may use it"},
      {"placeholder_small", [&](Json& j) { j["buffers"][1]["byteLength"] = 100; },
       "/bufferViews/0: 972 bytes at offset 0 run past buffer 1 (100 bytes)"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    Json j = good;
    c.edit(j);
    const fs::path p = write(c.name + ".glb", glb(j, bin));
    CHECK(load_error(p) == p.string() + ": " + c.message);
  }
  // A .glb whose binary chunk claims 8 bytes more than the file holds (tinygltf 2.7 checks
  // the chunk's length without its header and read past the end: fuzz_gltf).
  {
    Bytes cut = glb(good, bin);
    cut.resize(cut.size() - 8);
    const auto total = static_cast<std::uint32_t>(cut.size());
    for (int i = 0; i < 4; ++i) cut[8 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(total >> (8 * i));
    std::uint32_t json_length;
    std::memcpy(&json_length, &cut[12], 4);
    const fs::path short_file = write("short_bin.glb", cut);
    CHECK(load_error(short_file) == short_file.string() + ": the .glb's binary chunk (" + std::to_string(bin.size()) +
                                        " bytes at byte " + std::to_string(28 + json_length) +
                                        ") runs past the end of the file (" + std::to_string(total) + " bytes)");
  }
  // Garbage instead of the compressed stream (the header byte is checked first).
  Bytes broken = bin;
  const auto at = good["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteOffset"].get<std::size_t>();
  broken[at] = 0x55;
  const fs::path p = write("garbage.glb", glb(good, broken));
  CHECK(load_error(p) == p.string() +
                             ": /bufferViews/0/extensions/EXT_meshopt_compression: the " +
                             std::to_string(good["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"].get<int>()) +
                             " bytes of compressed ATTRIBUTES data cannot be decoded (meshoptimizer: error -1)");
  // Past the decoded-size limit: the .glb and the decoded views together count against
  // max_file_bytes (4248 bytes decoded from a smaller file).
  const fs::path ok = write("limit.glb", glb(good, bin));
  const auto size = fs::file_size(ok);
  REQUIRE(size < 4248);
  try {
    pbr::load_gltf(ok, {.max_file_bytes = size});
    FAIL("no error");
  } catch (const pbr::LoadError& e) {
    CHECK(std::string(e.what()).find(": decoded, the compressed bufferViews reach ") != std::string::npos);
    CHECK(std::string(e.what()).find(" bytes, over the limit of " + std::to_string(size)) != std::string::npos);
  }
}
