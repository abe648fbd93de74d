// libFuzzer target: the rasterizer on triangles decoded from the fuzzer's bytes.
//
// Every input is a frame: a target of 1×1 up to 1024×1024 pixels (odd sizes included,
// memory stays bounded), a renderer with 1–4 threads, an even tile size from 8 to 4096 and
// a packet width, then a few draws of triangles whose clip-space coordinates come from a
// table of hostile values (NaN, ±Inf, ±FLT_MAX, huge, denormal, ±0, w ≤ 0) or from raw
// float bits, with random depth/cull/blend state, drawn by a scalar or a packet shader,
// or by the PBR shader (the same hostile values as object-space positions, normals and
// UVs; material and lights from the bytes when they pass validation).
//
// Checked beyond "no crash, no sanitizer report": the image (colour and depth bits) is the
// same when the frame is rendered again on one thread with 64×64 tiles and scalar
// shading — the determinism contract (docs/design.md, "Determinism") must hold for any
// geometry. A colour that is NaN must be NaN in both, of any sign and payload.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>
#include <glm/vec3.hpp>

#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {

struct Vertex {
  glm::vec4 position;  // clip space
  glm::vec3 color;
};

// Three varyings; the fragment reads them and their quad derivatives, so interpolation and
// derivatives of hostile values run too.
struct ScalarShader {
  using Vertex = ::Vertex;
  struct Varyings {
    float r, g, b;
  };
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out = {in.color.r, in.color.g, in.color.b};
    return in.position;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    return {f.v.r + f.ddx.r, f.v.g - f.ddy.g, f.v.b * f.depth, f.front_facing ? 0.75f : 0.25f};
  }
};

// The same colour, in packets: lane for lane the same operations.
struct PacketShader : ScalarShader {
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return {p.v[0] + p.ddx[0], p.v[1] - p.ddy[1], p.v[2] * p.depth, F(p.front_facing ? 0.75f : 0.25f)};
  }
};

// Coordinates that have broken rasterizers: non-finite, at the edges of the float range,
// denormal, signed zeros, around w = 0 and the guard band (2^15 pixels).
constexpr float kInf = std::numeric_limits<float>::infinity();
const float kHostile[] = {
    std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN(), kInf, -kInf,
    std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), 1e30f, -1e30f, 1e10f, -1e10f,
    std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min(),
    std::numeric_limits<float>::min(), 0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -0.5f, 2.0f, -2.0f, 1e-7f, -1e-7f,
    32768.0f, -32768.0f, 65536.0f, 1e6f, -1e6f, 0.999999f, 1.000001f, 3.0f, 1e-30f};

float hostile_float(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange(0, 3)) {
    case 0: return in.PickValueInArray(kHostile);
    case 1: return static_cast<float>(in.ConsumeIntegralInRange(-8, 8)) * 0.25f;  // on-screen, snaps exactly
    case 2: return in.ConsumeFloatingPointInRange(-4.0f, 4.0f);
    default: {
      const std::uint32_t bits = in.ConsumeIntegral<std::uint32_t>();
      float f;
      static_assert(sizeof f == sizeof bits);
      __builtin_memcpy(&f, &bits, sizeof f);
      return f;
    }
  }
}

enum class Kind { Scalar, Packet, Pbr };

struct Draw {
  std::vector<Vertex> vertices;
  std::vector<std::uint32_t> indices;
  raster::DrawState state;
  Kind kind = Kind::Scalar;
  pbr::PbrShader pbr;  // Kind::Pbr: uniforms from the bytes, materials and lights validated
  std::vector<pbr::MeshVertex> mesh;  // Kind::Pbr: the vertices as positions, normals, UVs
};

struct Frame {
  int width = 1, height = 1;
  bool clear = true;
  std::vector<Draw> draws;
};

glm::vec3 hostile_vec3(FuzzedDataProvider& in) {
  const float x = hostile_float(in), y = hostile_float(in);
  return {x, y, hostile_float(in)};
}

// The PBR shader as pbr::render() sets it up (a camera at (0, 0, 3) looking at the
// origin), with a material and lights from the bytes that pass validation (or defaults):
// hostile values reach shading only through vertex data, as in a real scene.
void decode_pbr(FuzzedDataProvider& in, Draw& draw) {
  for (const Vertex& v : draw.vertices)
    draw.mesh.push_back({glm::vec3(v.position), v.color, {v.position.w, v.color.r}});
  pbr::Camera camera;
  draw.pbr.view_projection = camera.projection(1.0f) * camera.view();
  draw.pbr.eye = camera.position;
  draw.pbr.ambient = glm::vec3(in.ConsumeFloatingPointInRange(0.0f, 1.0f));
  pbr::Material m;
  m.base_color = hostile_vec3(in);
  m.metallic = hostile_float(in);
  m.roughness = hostile_float(in);
  m.emissive = hostile_vec3(in);
  try {
    draw.pbr.material = pbr::prepare_material(m);
  } catch (const std::invalid_argument&) {
    draw.pbr.material = pbr::prepare_material(pbr::Material{});
  }
  auto lights = std::make_shared<std::vector<pbr::PreparedLight>>();
  for (int i = in.ConsumeIntegralInRange(0, 3); i > 0; --i) {
    pbr::Light l;
    l.type = in.PickValueInArray({pbr::LightType::Point, pbr::LightType::Directional, pbr::LightType::Spot});
    l.position = hostile_vec3(in);
    l.direction = hostile_vec3(in);
    l.color = hostile_vec3(in);
    l.intensity = hostile_float(in);
    l.range = hostile_float(in);
    l.inner_cone = hostile_float(in);
    l.outer_cone = hostile_float(in);
    try {
      lights->push_back(pbr::prepare_light(l));
    } catch (const std::invalid_argument&) {
    }
  }
  draw.pbr.lights = lights;
}

Frame decode(FuzzedDataProvider& in) {
  Frame f;
  // Mostly small targets (fast executions); sometimes up to 1100 pixels a side, so
  // million-pixel triangles happen.
  const bool big = in.ConsumeIntegralInRange(0, 31) == 0;
  const int max_side = big ? 1024 : 96;
  f.width = in.ConsumeIntegralInRange(1, max_side);
  f.height = in.ConsumeIntegralInRange(1, max_side);
  f.clear = in.ConsumeBool();
  const int draws = in.ConsumeIntegralInRange(1, 3);
  for (int d = 0; d < draws && in.remaining_bytes() > 0; ++d) {
    Draw draw;
    draw.kind = in.PickValueInArray({Kind::Scalar, Kind::Packet, Kind::Pbr});
    draw.state.depth_test = in.PickValueInArray({raster::DepthTest::Less, raster::DepthTest::LessEqual,
                                                 raster::DepthTest::Always});
    draw.state.depth_write = in.ConsumeBool();
    draw.state.cull = in.PickValueInArray({raster::Cull::None, raster::Cull::Back, raster::Cull::Front});
    draw.state.front_face = in.PickValueInArray({raster::FrontFace::CounterClockwise, raster::FrontFace::Clockwise});
    draw.state.blend = in.PickValueInArray({raster::Blend::Replace, raster::Blend::Over});
    const int vertices = in.ConsumeIntegralInRange(0, 24);
    for (int v = 0; v < vertices; ++v) {
      Vertex vert;
      for (int k = 0; k < 4; ++k) vert.position[k] = hostile_float(in);
      for (int k = 0; k < 3; ++k) vert.color[k] = hostile_float(in);
      draw.vertices.push_back(vert);
    }
    // Indices: mostly valid; an index past the buffer or a count that is not a multiple
    // of 3 must be refused with an exception, drawing nothing.
    const int indices = in.ConsumeIntegralInRange(0, 48);
    for (int i = 0; i < indices; ++i)
      draw.indices.push_back(in.ConsumeIntegralInRange<std::uint32_t>(0, static_cast<std::uint32_t>(vertices)));
    if (draw.kind == Kind::Pbr) decode_pbr(in, draw);
    f.draws.push_back(std::move(draw));
  }
  return f;
}

constexpr unsigned kThreads[] = {1, 2, 3, 4};
constexpr int kTileSizes[] = {8, 10, 16, 42, 64, 4096};  // even, kMinTileSize … kMaxTileSize
constexpr int kLanes[] = {1, 4, 8, 16};

// One renderer per option set, kept across inputs: starting threads for every input would
// dominate the run time, and renderers do live for many frames (recycled draw memory).
raster::Renderer& renderer_for(std::size_t threads, std::size_t tile, std::size_t lanes) {
  static std::unique_ptr<raster::Renderer> cache[std::size(kThreads)][std::size(kTileSizes)][std::size(kLanes)];
  auto& r = cache[threads][tile][lanes];
  if (!r)
    r = std::make_unique<raster::Renderer>(
        raster::RendererOptions{.threads = kThreads[threads], .tile_size = kTileSizes[tile], .lanes = kLanes[lanes]});
  return *r;
}

// Renders the frame into a new target.
raster::Target render(const Frame& f, raster::Renderer& renderer) {
  raster::Target target(f.width, f.height);
  target.clear({0.1f, 0.2f, 0.3f, 0.5f}, 0.75f);
  if (f.clear) renderer.begin_frame(target, raster::ClearValues{{0, 0, 0, 1}, 1.0f});
  else renderer.begin_frame(target);
  for (const Draw& d : f.draws) {
    try {
      switch (d.kind) {
        case Kind::Scalar: renderer.draw(ScalarShader{}, std::span<const Vertex>(d.vertices), d.indices, d.state); break;
        case Kind::Packet: renderer.draw(PacketShader{}, std::span<const Vertex>(d.vertices), d.indices, d.state); break;
        case Kind::Pbr: renderer.draw(d.pbr, std::span<const pbr::MeshVertex>(d.mesh), d.indices, d.state); break;
      }
    } catch (const std::invalid_argument&) {  // index count not a multiple of 3
    } catch (const std::out_of_range&) {      // index past the vertices
    }
  }
  renderer.end_frame();
  // The 8-bit resolve of hostile colours too (on small targets only: its table search per
  // pixel is slow under coverage instrumentation).
  if (f.width * f.height <= 96 * 96) {
    const raster::Image8 image = raster::resolve_srgb8(target);
    if (image.rgba.size() != target.colors().size() * 4) std::abort();
  }
  return target;
}

bool same_bits(std::span<const float> a, std::span<const float> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

// The same bits, except that any NaN matches any NaN: a NaN's sign and payload are not part
// of the contract (docs/design.md, "Determinism"). Compilers commute the operands of + and
// ×, and which operand's payload survives differs (this input's vertex colours hold NaNs
// with two payloads; a build with coverage instrumentation chose the other one at 4 lanes).
bool same_values(std::span<const float> a, std::span<const float> b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] != a[i] && b[i] != b[i]) continue;
    if (std::memcmp(&a[i], &b[i], sizeof(float)) != 0) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const std::size_t threads = in.ConsumeIntegralInRange<std::size_t>(0, std::size(kThreads) - 1);
  const std::size_t tile = in.ConsumeIntegralInRange<std::size_t>(0, std::size(kTileSizes) - 1);
  const std::size_t lanes = in.ConsumeIntegralInRange<std::size_t>(0, std::size(kLanes) - 1);
  const Frame frame = decode(in);

  raster::Renderer& renderer = renderer_for(threads, tile, lanes);
  const raster::Target fuzzed = render(frame, renderer);
  const raster::Target reference = render(frame, renderer_for(0, 4, 0));  // 1 thread, 64×64 tiles, scalar
  const auto floats = [](const raster::Target& t) {
    return std::span<const float>(&t.colors().data()->x, t.colors().size() * 4);
  };
  const bool same_colors = same_values(floats(fuzzed), floats(reference));
  if (!same_colors || !same_bits(fuzzed.depths(), reference.depths())) {
    std::fprintf(stderr, "determinism: %u threads, tile %d, lanes %d differ from 1 thread, tile 64, lanes 1 in %s\n",
                 renderer.threads(), renderer.tile_size(), renderer.lanes(), same_colors ? "depth" : "colour");
    std::abort();
  }
  return 0;
}
