// Rendering a scene with the PBR shader (see scene.h).
#include "softpbr/pbr/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/pbr/textured_shading.h"
#include "ground.h"
#include "scene_kernels.h"

namespace softpbr::pbr {

namespace {
template <class F>
auto with_context(const std::string& where, F&& f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(where + ": " + e.what());
  }
}
}  // namespace

namespace {
void render_frame(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                  const raster::Renderer::TileCallback& after_tile);
}  // namespace

std::uint64_t transmission_memory(int width, int height) {
  if (width < 1 || height < 1) return 0;
  // The resolved copy and its texture (every level, counted level by level).
  std::uint64_t bytes = 16 * static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
  for (int w = width, h = height;; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
    bytes += 16 * static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
    if (w == 1 && h == 1) break;
  }
  return bytes;
}

std::uint64_t shadow_memory(const Scene& scene) {
  std::uint64_t bytes = 0;
  for (const Light& l : scene.lights) bytes += detail::shadow_map_bytes(l);
  if (scene.ground.shadow) bytes += detail::ground_bytes();
  return bytes;
}

std::uint64_t occlusion_memory(int width, int height) {
  return raster::Target::bytes(width, height, 1) +
         2 * sizeof(float) * static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
}

void render(const Scene& scene, raster::Renderer& renderer, raster::Target& target) {
  render_frame(scene, renderer, target, nullptr);
}

void render_rgba8(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                  const OutputSettings& output, raster::Image8& image) {
  render_outputs(scene, renderer, target, output, &image, nullptr);
}

void render_outputs(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                    const OutputSettings& output, raster::Image8* image, raster::Target* linear) {
  if (linear != nullptr && (linear->samples() != 1 || linear->width() != target.width() ||
                            linear->height() != target.height()))
    throw std::invalid_argument("render_outputs: the linear target must have 1 sample and the target's size");
  const ToneMapper mapper(output);
  if (image != nullptr) {
    image->width = target.width();
    image->height = target.height();
    image->rgba.resize(static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(target.height()) * 4);
  }
  // Taken once, before the frame: the tiles write disjoint rectangles of them.
  glm::vec4* const linear_colors = linear != nullptr ? linear->colors().data() : nullptr;
  float* const linear_depths = linear != nullptr ? linear->depths().data() : nullptr;
  const std::size_t width = static_cast<std::size_t>(target.width());
  // What resolve_box makes of a pixel whose samples all hold the background (a tile that
  // only holds the clear values may have no pixels to resolve).
  glm::vec4 cleared;
  {
    std::array<glm::vec4, raster::kMaxSamples> colors;
    std::array<float, raster::kMaxSamples> depths{};
    colors.fill(scene.background);
    raster::resolve_box(raster::TargetPixels{colors.data(), depths.data(), 1, 1, target.samples(), 1, 0}, 0, 0, 1, 1,
                        &cleared, 1);
  }
  render_frame(scene, renderer, target, [&](const raster::TileRect& r, bool only_clear, const raster::TargetPixels& px) {
    if (image != nullptr) {
      if (only_clear) mapper.encode_uniform(scene.background, r.x0, r.y0, r.x1, r.y1, *image);
      else if (px.samples > 1) mapper.encode(px, r.x0, r.y0, r.x1, r.y1, *image);  // the tile's samples, in cache
      else mapper.encode(target, r.x0, r.y0, r.x1, r.y1, *image);
    }
    if (linear_colors == nullptr) return;
    const std::size_t at = static_cast<std::size_t>(r.y0) * width + static_cast<std::size_t>(r.x0);
    const std::size_t n = static_cast<std::size_t>(r.x1 - r.x0);
    for (int y = r.y0; y < r.y1; ++y) {
      const std::size_t row = at + static_cast<std::size_t>(y - r.y0) * width;
      if (only_clear) {  // every sample holds the clear values (a transient target's: nowhere)
        std::fill_n(linear_colors + row, n, cleared);
        std::fill_n(linear_depths + row, n, 1.0f);
      } else {
        for (int x = r.x0; x < r.x1; ++x)  // sample 0's (multisampled: kept by 2×2 quads, raster::depth_index)
          linear_depths[row + static_cast<std::size_t>(x - r.x0)] = px.depths[px.depth_index(x, y, 0)];
      }
    }
    if (!only_clear) raster::resolve_box(px, r.x0, r.y0, r.x1, r.y1, linear_colors + at, width);
  });
}

namespace {

// Whether an object needs the textured shader: anything PbrShader does not do.
bool needs_textured_shader(const Object& o) {
  const Material& m = o.material;
  return m.textured() || m.alpha_mode != AlphaMode::Opaque || m.double_sided || m.unlit || !o.mesh->colors.empty() ||
         m.layered();
}

// One object's draw: its shader, the vertices it reads and its state.
struct ObjectDraw {
  enum class Kind { Plain, Textured, TexturedUv0, Layered };
  std::size_t object = 0;
  Kind kind = Kind::Plain;
  PbrShader plain;
  TexturedPbrShader textured;
  TexturedUv0PbrShader textured_uv0;   // mesh->vertices as they are
  LayeredPbrShader layered;              // Layered (its `textured` draws its masked occlusion pass)
  std::vector<TexturedVertex> vertices;  // Textured and Layered
  const Mesh* mesh = nullptr;
  std::shared_ptr<const Mesh> generated;  // the mesh with MikkTSpace tangents, when it had none
  raster::DrawState state;
  float distance2 = 0.0f;  // blended objects: from the eye to the centre of their bounds

  int varying_count() const {
    switch (kind) {
      case Kind::Textured: return raster::kVaryingCount<TexturedPbrShader::Varyings>;
      case Kind::TexturedUv0: return raster::kVaryingCount<TexturedUv0PbrShader::Varyings>;
      case Kind::Layered: return raster::kVaryingCount<LayeredPbrShader::Varyings>;
      case Kind::Plain: break;
    }
    return raster::kVaryingCount<PbrShader::Varyings>;
  }
};

using detail::BackgroundShader;

std::array<BackgroundShader::Vertex, 3> background_triangle(const Camera& camera, float aspect) {
  const glm::mat3 to_world = glm::transpose(glm::mat3(camera.view()));  // the view's rotation, inverted
  if (camera.orthographic) {
    // Parallel rays: every pixel sees the environment in the view direction.
    std::array<BackgroundShader::Vertex, 3> v{};
    const float corners[3][2] = {{-1.0f, -1.0f}, {3.0f, -1.0f}, {-1.0f, 3.0f}};
    for (int i = 0; i < 3; ++i) {
      v[static_cast<std::size_t>(i)].clip = glm::vec4(corners[i][0], corners[i][1], 0.0f, 1.0f);
      v[static_cast<std::size_t>(i)].direction = to_world * glm::vec3(0.0f, 0.0f, -1.0f);
    }
    return v;
  }
  const double half = 0.5 * static_cast<double>(camera.fovy);
  const auto ty = static_cast<float>(dmath::sin(half) / dmath::cos(half));
  const float tx = ty * aspect;
  std::array<BackgroundShader::Vertex, 3> v{};
  const float corners[3][2] = {{-1.0f, -1.0f}, {3.0f, -1.0f}, {-1.0f, 3.0f}};
  for (int i = 0; i < 3; ++i) {
    v[static_cast<std::size_t>(i)].clip = glm::vec4(corners[i][0], corners[i][1], 1.0f, 1.0f);
    v[static_cast<std::size_t>(i)].direction = to_world * glm::vec3(corners[i][0] * tx, corners[i][1] * ty, -1.0f);
  }
  return v;
}

// The occlusion's radius, in world units: this fraction of the half height of the view at
// the camera's target (distance · tan(fovy / 2); orthographic: ymag), so that it follows
// the framing of the scene. Its strength, and how much of it the specular term takes
// (PreparedEnvironment::specular_occlusion). Tuned against Blender Cycles on the four
// fidelity models (docs/design.md, "Image-based lighting").
constexpr float kOcclusionRadius = 0.1f;
constexpr float kOcclusionStrength = 1.5f;
constexpr float kSpecularOcclusion = 1.0f;

// The occlusion factor of every pixel (occlusion.h): the opaque and alpha-masked objects
// (blended ones neither occlude nor are occluded) drawn into a 1-sample depth and normal
// buffer of the frame's size, each with its draw's culling (masked ones with their alpha
// cut by their own shader), then compute_occlusion.
void draw_occlusion(const Scene& scene, raster::Renderer& renderer, int width, int height,
                    const glm::mat4& view_projection, const std::vector<ObjectDraw>& opaque, std::vector<float>& out) {
  raster::Target gbuffer(width, height, 1, &renderer.pool());
  const glm::mat4 view = scene.camera.view();
  const glm::mat3 view_rotation(view);
  const glm::mat4 projection = scene.camera.projection(static_cast<float>(width) / static_cast<float>(height));
  renderer.begin_frame(gbuffer, raster::ClearValues{glm::vec4(0.0f), 1.0f});
  try {
    for (const ObjectDraw& d : opaque) {
      const Object& o = scene.objects[d.object];
      if (o.material.alpha_mode == AlphaMode::Mask) {
        // The textured shader finds the alpha (its environment, `occluded`, has no factors yet).
        raster::DrawState state;
        state.cull = d.state.cull;
        state.alpha_test = true;
        state.alpha_ref = detail::kMaskedAlphaRef;
        const auto draw_masked = [&](const auto& shader, const auto& vertices) {
          detail::MaskedGBufferShader<std::decay_t<decltype(shader)>> g;
          g.inner = shader;
          g.inner.alpha_to_coverage = false;
          g.view = view;
          g.view_rotation = view_rotation;
          renderer.draw(g, vertices, d.mesh->indices, state);
        };
        if (d.kind != ObjectDraw::Kind::TexturedUv0) draw_masked(d.textured, std::span<const TexturedVertex>(d.vertices));
        else draw_masked(d.textured_uv0, std::span<const MeshVertex>(d.mesh->vertices));
        continue;
      }
      detail::GBufferShader g;
      g.model = o.transform;
      g.view = view;
      g.normal_matrix = view_rotation * glm::transpose(glm::inverse(glm::mat3(o.transform)));
      g.view_projection = view_projection;
      raster::DrawState state;
      state.cull = d.state.cull;
      renderer.draw(g, d.mesh->vertices, d.mesh->indices, state);
    }
  } catch (...) {
    renderer.end_frame();
    throw;
  }
  renderer.end_frame();
  detail::OcclusionSettings settings;
  settings.width = width;
  settings.height = height;
  settings.orthographic = scene.camera.orthographic;
  settings.p00 = projection[0][0];
  settings.p11 = projection[1][1];
  const float half_height = scene.camera.orthographic
                                ? scene.camera.ymag
                                : glm::length(scene.camera.target - scene.camera.position) / projection[1][1];
  settings.radius = kOcclusionRadius * half_height;
  settings.strength = kOcclusionStrength;
  settings.lanes = renderer.lanes();
  settings.isa = renderer.isa();
  detail::compute_occlusion(gbuffer, settings, renderer.pool(), out);
}

// A frame's shadow maps: each light's map and the depth-only targets its faces point into.
struct ShadowFrame {
  std::vector<std::unique_ptr<ShadowMap>> maps;
  std::vector<std::unique_ptr<raster::Target>> faces;
};

// The bounds of every object in world space (the corners of each mesh's bounds, transformed).
Bounds scene_bounds(const Scene& scene) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  Bounds world{glm::vec3(inf), glm::vec3(-inf)};
  for (const Object& o : scene.objects) {
    const Bounds b = bounds(*o.mesh);
    if (b.empty()) continue;
    for (int i = 0; i < 8; ++i) {
      const glm::vec3 corner((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y, (i & 4) ? b.max.z : b.min.z);
      const glm::vec3 w(o.transform * glm::vec4(corner, 1.0f));
      world = merge(world, Bounds{w, w});
    }
  }
  return world;
}

// What blocks the lights and lies above the ground: an object with cast_shadows, drawn
// depth-only. Masked and blended ones are cut out where their alpha is below ½, by their
// own textured shader made unlit.
struct Caster {
  const ObjectDraw* draw;
  bool cut_out;
  TexturedPbrShader textured;
  TexturedUv0PbrShader textured_uv0;
};

// The casters of `opaque` and `blended`, their textured shaders for the alpha made once
// (unlit, no lights, no environment).
std::vector<Caster> shadow_casters(const Scene& scene, const std::vector<ObjectDraw>& opaque,
                                   const std::vector<ObjectDraw>& blended) {
  std::vector<Caster> casters;
  const auto no_lights = std::make_shared<const std::vector<PreparedLight>>();
  for (const auto* list : {&opaque, &blended})
    for (const ObjectDraw& d : *list) {
      const Object& o = scene.objects[d.object];
      if (!o.cast_shadows) continue;
      Caster c{&d, o.material.alpha_mode != AlphaMode::Opaque, {}, {}};
      if (c.cut_out) {
        const auto cut = [&](auto& shader, const auto& from) {
          shader = from;
          auto material = std::make_shared<TexturedMaterial>(*from.material);
          material->unlit = true;
          shader.material = material;
          shader.lights = no_lights;
          shader.environment = nullptr;
          shader.alpha_to_coverage = false;
        };
        if (d.kind == ObjectDraw::Kind::TexturedUv0) cut(c.textured_uv0, d.textured_uv0);
        else cut(c.textured, d.textured);
      }
      casters.push_back(std::move(c));
    }
  return casters;
}

// The casters' depth seen through `view_projection`, drawn into the depth-only target
// `face` (cleared to 1) with their draws' culling, or with none when `cull_none` (the
// ground's view from below sees the undersides of open surfaces too).
void draw_caster_depths(const Scene& scene, raster::Renderer& renderer, std::vector<Caster>& casters,
                        const glm::mat4& view_projection, raster::Target& face, bool cull_none) {
  renderer.begin_frame(face, raster::ClearValues{glm::vec4(0.0f), 1.0f});
  try {
    for (Caster& c : casters) {
      const ObjectDraw& d = *c.draw;
      raster::DrawState state;
      state.cull = cull_none ? raster::Cull::None : d.state.cull;
      if (!c.cut_out) {
        detail::ShadowDepthShader s;
        s.model = scene.objects[d.object].transform;
        s.view_projection = view_projection;
        renderer.draw(s, d.mesh->vertices, d.mesh->indices, state);
        continue;
      }
      state.alpha_test = true;
      state.alpha_ref = 0.5f;
      if (d.kind == ObjectDraw::Kind::TexturedUv0) {
        detail::MaskedShadowDepthShader<TexturedUv0PbrShader> s;
        s.inner = c.textured_uv0;
        s.inner.view_projection = view_projection;
        renderer.draw(s, d.mesh->vertices, d.mesh->indices, state);
      } else {
        detail::MaskedShadowDepthShader<TexturedPbrShader> s;
        s.inner = c.textured;
        s.inner.view_projection = view_projection;
        renderer.draw(s, std::span<const TexturedVertex>(d.vertices), d.mesh->indices, state);
      }
    }
  } catch (...) {
    renderer.end_frame();
    throw;
  }
  renderer.end_frame();
}

// The shadow maps (docs/design.md, "Shadows"): for each light with shadows, its faces fitted
// to `world`, the scene's bounds (shadow_setup), each drawn into a depth-only target with the
// casters, then the light's PreparedLight::shadow set to it.
void draw_shadow_maps(const Scene& scene, const Bounds& world, raster::Renderer& renderer, std::vector<Caster>& casters,
                      std::vector<PreparedLight>& lights, ShadowFrame& frame) {
  for (PreparedLight& light : lights) {
    if (!light.light.shadows) continue;
    detail::ShadowSetup setup;
    if (!detail::shadow_setup(light, world, setup)) continue;
    auto map = std::make_unique<ShadowMap>(setup.map);
    for (std::size_t f = 0; f < setup.view_projection.size(); ++f) {
      frame.faces.push_back(std::make_unique<raster::Target>(
          raster::Target::depth_only(setup.map.size, setup.map.size, &renderer.pool())));
      raster::Target& face = *frame.faces.back();
      draw_caster_depths(scene, renderer, casters, setup.view_projection[f], face, false);
      map->faces[f] = std::as_const(face).depths().data();
    }
    light.shadow = map.get();
    frame.maps.push_back(std::move(map));
  }
}

// The ground's shadow catcher (ground.h), or false when the scene has nothing to stand on
// it: the casters seen from below, their depths, the lights' maps and a map along the
// environment's dominant light (when `env` has one) made its texture.
bool make_ground(const Scene& scene, const Bounds& world, raster::Renderer& renderer, std::vector<Caster>& casters,
                 const std::vector<PreparedLight>& lights, const PreparedEnvironment* env, Object& out) {
  // The lights whose shadows fall on the ground: the square holds them.
  std::vector<detail::GroundLight> shadow_lights;
  for (const PreparedLight& l : lights) {
    if (l.shadow == nullptr) continue;
    if (l.light.type == LightType::Directional) shadow_lights.push_back({true, -l.unit_direction, glm::vec3(0.0f)});
    else shadow_lights.push_back({false, glm::vec3(0.0f), l.light.position});
  }
  detail::DominantLight dominant;
  const bool sky_light = env != nullptr && detail::dominant_light(*env, dominant);
  if (sky_light) shadow_lights.push_back({true, dominant.to_light, glm::vec3(0.0f)});
  detail::GroundSetup setup;
  if (!detail::ground_setup(world, scene.ground, shadow_lights, setup)) return false;
  raster::Target below = raster::Target::depth_only(detail::kGroundSize, detail::kGroundSize, &renderer.pool());
  draw_caster_depths(scene, renderer, casters, setup.view_projection, below, true);
  std::optional<raster::Target> sky_face;
  ShadowMap sky;
  if (sky_light) {
    Light l;
    l.type = LightType::Directional;
    l.direction = -dominant.to_light;
    l.shadows = true;
    detail::ShadowSetup sky_setup;
    if (detail::shadow_setup(prepare_light(l), world, sky_setup)) {
      sky_face.emplace(raster::Target::depth_only(sky_setup.map.size, sky_setup.map.size, &renderer.pool()));
      draw_caster_depths(scene, renderer, casters, sky_setup.view_projection[0], *sky_face, false);
      sky = sky_setup.map;
      sky.faces[0] = std::as_const(*sky_face).depths().data();
    }
  }
  out = detail::ground_object(setup, detail::ground_texture(setup, scene.ground, std::as_const(below).depths(), lights,
                                                            sky_face ? &sky : nullptr, dominant, renderer.pool()));
  return true;
}

void render_frame(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                  const raster::Renderer::TileCallback& after_tile) {
  validate(scene.camera);
  // The environment, if any, prepared once for every shader of the frame.
  PreparedEnvironment environment;
  const PreparedEnvironment* env = nullptr;
  if (scene.environment.map) {
    environment = prepare_environment(scene.environment);
    env = &environment;
  }
  // With occlusion, opaque and masked objects read the environment through `occluded`, whose factors
  // the depth and normal pass below fills before the frame; everything else through `env`.
  const bool occluding = env != nullptr && scene.environment.occlusion;
  PreparedEnvironment occluded = environment;
  std::vector<float> occlusion;
  if (scene.background_mode != BackgroundMode::Color && env == nullptr)
    throw std::invalid_argument("background: an environment background needs an environment");
  if (!(scene.background_blur >= 0.0f && scene.background_blur <= 1.0f))
    throw std::invalid_argument("background_blur must be in [0, 1]");
  // Validate and prepare everything before the frame starts.
  auto lights = std::make_shared<std::vector<PreparedLight>>();
  lights->reserve(scene.lights.size());
  for (std::size_t i = 0; i < scene.lights.size(); ++i)
    lights->push_back(with_context("lights[" + std::to_string(i) + "]", [&] { return prepare_light(scene.lights[i]); }));
  // Objects that receive no shadows read the lights without their maps (the list as it is
  // before draw_shadow_maps sets them).
  const bool shadowed = std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) { return l.shadows; });
  std::shared_ptr<const std::vector<PreparedLight>> unshadowed_lights = lights;
  if (shadowed) unshadowed_lights = std::make_shared<const std::vector<PreparedLight>>(*lights);
  const glm::mat4 view_projection =
      scene.camera.projection(static_cast<float>(target.width()) / static_cast<float>(target.height())) *
      scene.camera.view();
  // An orthographic camera's one direction towards the camera (validate(): not zero).
  const glm::vec3 view_direction = glm::normalize(scene.camera.position - scene.camera.target);
  std::vector<ObjectDraw> opaque, blended, transmissive;
  // What the transmissive draws read: the opaque pass's colour (filled after that pass).
  TransmissionSource source;
  // Object `o` (scene.objects[i], or the ground) as a draw in `opaque`, `transmissive` or
  // `blended`.
  const auto add_draw = [&](const Object& o, std::size_t i) {
    const std::string where = "objects[" + std::to_string(i) + "]";
    if (!o.mesh) throw std::invalid_argument(where + ": has no mesh");
    ObjectDraw d;
    d.object = i;
    d.mesh = o.mesh.get();
    d.state.cull = raster::Cull::Back;
    // What every shader of render() reads besides its material.
    const auto set_up_frame = [&](auto& s) {
      s.model = o.transform;
      s.normal_matrix = glm::transpose(glm::inverse(glm::mat3(o.transform)));
      s.view_projection = view_projection;
      s.eye = scene.camera.position;
      s.orthographic = scene.camera.orthographic;
      s.view_direction = view_direction;
      s.ambient = scene.ambient;
      s.lights = o.receive_shadows ? std::shared_ptr<const std::vector<PreparedLight>>(lights) : unshadowed_lights;
      // Transmissive objects are not in the occlusion pass (they are seen through).
      s.environment =
          occluding && o.material.alpha_mode != AlphaMode::Blend && !o.material.transmissive() ? &occluded : env;
    };
    if (!needs_textured_shader(o)) {
      d.plain.material = with_context(where, [&] { return prepare_material(o.material); });
      set_up_frame(d.plain);
      opaque.push_back(std::move(d));
      return;
    }
    auto material = std::make_shared<const TexturedMaterial>(
        with_context(where, [&] { return prepare_textured_material(o.material); }));
    with_context(where, [&] { check_textured_streams(*o.mesh); });
    bool alpha_to_coverage = false;
    const auto set_up = [&](auto& s) {
      set_up_frame(s);
      s.material = material;
      s.handedness = glm::determinant(glm::mat3(o.transform)) < 0.0f ? -1.0f : 1.0f;
      s.alpha_to_coverage = alpha_to_coverage;
    };
    if (o.material.alpha_mode == AlphaMode::Mask) {
      d.state.alpha_test = true;  // the shader's alpha is 1 (kept) or 0
      d.state.alpha_ref = 0.5f;
      // With MSAA the shader's alpha is sharpened around the cutoff and becomes samples.
      d.state.alpha_to_coverage = alpha_to_coverage = target.samples() > 1;
    }
    const TexturedStreams streams = textured_streams(*material, !o.mesh->colors.empty());
    if (streams == TexturedStreams::Uv0) {
      d.kind = ObjectDraw::Kind::TexturedUv0;
      set_up(d.textured_uv0);
    } else {
      d.kind = streams == TexturedStreams::Layered ? ObjectDraw::Kind::Layered : ObjectDraw::Kind::Textured;
      const bool coat_map = material->layered && material->layers.coat_normal.texture != nullptr;
      const bool anisotropic = material->layered && material->layers.anisotropy;
      if ((o.material.normal_texture || coat_map || anisotropic) && o.mesh->tangents.empty()) {
        // A normal map (and an anisotropic lobe) needs tangents: MikkTSpace, as glTF prescribes
        // (per frame here; loaders generate them once, when they build the mesh).
        auto copy = std::make_shared<Mesh>(*o.mesh);
        with_context(where, [&] { generate_tangents(*copy); });
        d.generated = copy;
        d.mesh = copy.get();
      }
      d.vertices = with_context(where, [&] { return textured_vertices(*d.mesh); });
      set_up(d.textured);
      if (d.kind == ObjectDraw::Kind::Layered) {
        set_up(d.layered);
        if (material->layers.transmission)
          d.layered.transmission = transmission_uniforms(material->layers, &source, view_projection, o.transform);
      }
    }
    if (o.material.double_sided) d.state.cull = raster::Cull::None;
    if (o.material.alpha_mode == AlphaMode::Blend) {
      d.state.blend = raster::Blend::Over;
      d.state.depth_write = false;
    }
    if (o.material.alpha_mode == AlphaMode::Blend || o.material.transmissive()) {
      const Bounds b = bounds(*o.mesh);
      const glm::vec3 centre = b.empty() ? glm::vec3(0.0f) : glm::vec3(o.transform * glm::vec4(b.centre(), 1.0f));
      const glm::vec3 to_eye = centre - scene.camera.position;
      // Orthographic: the distance along the view direction, farthest first as well.
      d.distance2 = scene.camera.orthographic ? -glm::dot(to_eye, view_direction) : glm::dot(to_eye, to_eye);
    }
    (o.material.transmissive() ? transmissive : o.material.alpha_mode == AlphaMode::Blend ? blended : opaque)
        .push_back(std::move(d));
  };
  for (std::size_t i = 0; i < scene.objects.size(); ++i) add_draw(scene.objects[i], i);
  // Blended objects after every opaque one, farthest first (ties: scene order); the
  // transmissive ones between the two, farthest first too (the glTF Sample Viewer's order).
  const auto farthest_first = [](const ObjectDraw& a, const ObjectDraw& b) { return a.distance2 > b.distance2; };
  std::stable_sort(blended.begin(), blended.end(), farthest_first);
  std::stable_sort(transmissive.begin(), transmissive.end(), farthest_first);

  ShadowFrame shadow_frame;  // the maps live until the frame is drawn
  Object ground;             // the ground's draw points into it
  if (shadowed || scene.ground.shadow) {
    std::vector<Caster> casters = shadow_casters(scene, opaque, blended);
    const Bounds world = scene_bounds(scene);  // the maps and the ground are fitted to it
    if (shadowed) draw_shadow_maps(scene, world, renderer, casters, *lights, shadow_frame);
    // The ground first of the blended draws: it lies under everything.
    if (scene.ground.shadow && make_ground(scene, world, renderer, casters, *lights, env, ground)) {
      add_draw(ground, scene.objects.size());
      std::rotate(blended.begin(), blended.end() - 1, blended.end());
    }
  }
  // What the draws will bin, so that a transient target's frame that fits is one pass.
  std::size_t geometry = raster::draw_geometry_bytes(3, 1, raster::kVaryingCount<BackgroundShader::Varyings>);
  for (const auto* list : {&opaque, &transmissive, &blended})
    for (const ObjectDraw& d : *list)
      geometry += raster::draw_geometry_bytes(d.mesh->vertices.size(), d.mesh->indices.size() / 3, d.varying_count());
  if (occluding) {
    draw_occlusion(scene, renderer, target.width(), target.height(), view_projection, opaque, occlusion);
    occluded.occlusion = occlusion.data();
    occluded.occlusion_width = target.width();
    occluded.occlusion_height = target.height();
    occluded.specular_occlusion = kSpecularOcclusion;
  }
  // What resolve_box makes of a pixel holding only the clear value (the transmission's copy).
  glm::vec4 cleared_color = scene.background;
  if (!transmissive.empty()) {
    std::array<glm::vec4, raster::kMaxSamples> colors;
    std::array<float, raster::kMaxSamples> depths{};
    colors.fill(scene.background);
    raster::resolve_box(raster::TargetPixels{colors.data(), depths.data(), 1, 1, target.samples(), 1, 0}, 0, 0, 1, 1,
                        &cleared_color, 1);
  }
  std::optional<raster::Texture> opaque_copy;  // the transmission's source, until the frame ends
  renderer.begin_frame(target, raster::ClearValues{scene.background, 1.0f}, geometry);
  try {
    const auto draw_objects = [&](const std::vector<ObjectDraw>& list) {
      for (const ObjectDraw& d : list) {
        switch (d.kind) {
          case ObjectDraw::Kind::Textured:
            renderer.draw(d.textured, std::span<const TexturedVertex>(d.vertices), d.mesh->indices, d.state);
            break;
          case ObjectDraw::Kind::TexturedUv0:
            renderer.draw(d.textured_uv0, d.mesh->vertices, d.mesh->indices, d.state);
            break;
          case ObjectDraw::Kind::Layered:
            renderer.draw(d.layered, std::span<const TexturedVertex>(d.vertices), d.mesh->indices, d.state);
            break;
          case ObjectDraw::Kind::Plain:
            renderer.draw(d.plain, d.mesh->vertices, d.mesh->indices, d.state);
            break;
        }
      }
    };
    draw_objects(opaque);
    // The background after the opaque objects, at the far plane (depth 1, the clear value)
    // with the depth test ≤ and no depth write: only pixels (samples) no opaque object
    // covered are shaded, as a GPU engine draws its skybox. The image is the same as
    // drawing it first: an opaque draw replaces what is beneath it.
    if (scene.background_mode != BackgroundMode::Color) {
      BackgroundShader bg;
      bg.environment = env;
      bg.roughness = scene.background_mode == BackgroundMode::Blur ? scene.background_blur : 0.0f;
      const auto tri = background_triangle(
          scene.camera, static_cast<float>(target.width()) / static_cast<float>(target.height()));
      raster::DrawState state;
      state.depth_test = raster::DepthTest::LessEqual;
      state.depth_write = false;
      renderer.draw(bg, std::span<const BackgroundShader::Vertex>(tri), state);
    }
    if (!transmissive.empty()) {
      // The transmission pass (docs/design.md, "Shading"): what the opaque draws and the
      // background left, resolved tile by tile by the threads that drew them, becomes a
      // float texture with its mip chain (built on the renderer's threads; the same bits
      // for any thread count), which the transmissive draws read. Non-finite colours
      // (a shader's overflow) read as 0 there.
      const int w = target.width(), h = target.height();
      std::vector<glm::vec4> copy(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
      const std::size_t width = static_cast<std::size_t>(w);
      renderer.flush([&](const raster::TileRect& r, bool only_clear, const raster::TargetPixels& px) {
        glm::vec4* const at = copy.data() + static_cast<std::size_t>(r.y0) * width + static_cast<std::size_t>(r.x0);
        const std::size_t n = static_cast<std::size_t>(r.x1 - r.x0);
        if (only_clear) {
          for (int y = r.y0; y < r.y1; ++y) std::fill_n(at + static_cast<std::size_t>(y - r.y0) * width, n, cleared_color);
        } else {
          raster::resolve_box(px, r.x0, r.y0, r.x1, r.y1, at, width);
        }
        for (int y = r.y0; y < r.y1; ++y)
          for (glm::vec4& c : std::span<glm::vec4>(at + static_cast<std::size_t>(y - r.y0) * width, n))
            for (int k = 0; k < 4; ++k)
              if (!std::isfinite(c[k])) c[k] = 0.0f;
      });
      const image::ImageViewF view(w, h, std::span<const float>(&copy[0].x, copy.size() * 4));
      opaque_copy.emplace(view, raster::TextureOptions{}, &renderer.pool());
      std::vector<glm::vec4>().swap(copy);
      source.texture = &*opaque_copy;
      source.sampler.wrap_u = source.sampler.wrap_v = raster::Wrap::ClampToEdge;
      source.levels = static_cast<float>(dmath::log(static_cast<double>(std::max(w, h))) / dmath::log(2.0));
      draw_objects(transmissive);
    }
    draw_objects(blended);
  } catch (...) {
    renderer.end_frame();
    throw;
  }
  renderer.end_frame(after_tile);
}
}  // namespace

}  // namespace softpbr::pbr
