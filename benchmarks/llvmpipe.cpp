// The llvmpipe side of the comparison (see llvmpipe.h).
#include "llvmpipe.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/glext.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <span>
#include <stdexcept>
#include <utility>

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <glm/matrix.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/raster/texture.h"

namespace softpbr::bench {

namespace {

constexpr int kMaxLights = 8;

// The object shaders are compiled per variant, when a scene needs it (load()): with TEXTURED
// defined for TexturedPbrShader's objects (a base colour texture read through the mesh's
// uv), with IBL (and MULTISCATTER) when the scene has an environment, and with ACES / SRGB
// for the scene's output transform.
const char* kVersion = "#version 330 core\n";

const char* kVertexShader = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
#ifdef TEXTURED
layout(location = 2) in vec2 a_uv;
out vec2 v_uv;
#endif
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;
out vec3 v_world;
out vec3 v_normal;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
#ifdef TEXTURED
  v_uv = a_uv;
#endif
  gl_Position = u_view_projection * world;
}
)";

// OutputSettings' transform (pbr/tonemap.cpp, tone_map_operators.h): Reinhard (as it always
// was here: c / (1 + c)) or, with ACES defined, the operators' limit to [0, 1e9] and
// Narkowicz's fit clamped to [0, 1]; then the gamma curve or, with SRGB defined, the exact
// piecewise sRGB curve. The RGBA8 buffer rounds the result to 8 bits.
const char* kOutputTransform = R"(
uniform float u_inv_gamma;
vec3 output_transform(vec3 c) {
#ifdef ACES
  c = min(max(c, vec3(0.0)), vec3(1e9));
  c = clamp((c * (2.51 * c + vec3(0.03))) / (c * (2.43 * c + vec3(0.59)) + vec3(0.14)), 0.0, 1.0);
#else
  c = c / (vec3(1.0) + c);  // Reinhard
#endif
#ifdef SRGB
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - vec3(0.055), greaterThan(c, vec3(0.0031308)));
#else
  return pow(c, vec3(u_inv_gamma));
#endif
}
)";

// With IBL defined: pbr/environment.h's lookups and pbr/shading.h's ibl(), term for term, on
// the same prefiltered data — the Environment's 8 octahedral levels and its irradiance map
// (with their one-texel borders) and dfg_table() as GL_RGBA32F textures, GL_LINEAR, clamp
// to edge, level 0 only (textureLod 0, as sample_lod with Environment::level_sampler()), the
// levels' α as uniforms. As in softpbr, a level is read only when its weight is above 0
// (uniform per draw: the roughness is the material's).
const char* kEnvironment = R"(
uniform sampler2D u_env_level[8];
uniform vec3 u_env_oct[8];  // per level: 0.5 size, 0.5 size + 1, 1 / (size + 2)
uniform float u_level_alpha[8];
uniform float u_level_inv[7];  // 1 / (α_{l+1} − α_l)
uniform sampler2D u_irradiance;
uniform vec3 u_irradiance_oct;
uniform sampler2D u_dfg;
uniform float u_env_cos;
uniform float u_env_sin;
uniform float u_env_intensity;
vec3 to_environment(vec3 d) {
  return vec3(u_env_cos * d.x - u_env_sin * d.z, d.y, u_env_sin * d.x + u_env_cos * d.z);
}
vec2 env_octahedral(vec3 d, vec3 oct) {
  float l1 = abs(d.x) + abs(d.y) + abs(d.z);
  float inv = 1.0 / (l1 > 0.0 ? l1 : 1.0);
  float px = d.x * inv, pz = d.z * inv;
  bool lower = d.y < 0.0;
  float fx = (1.0 - abs(pz)) * (px < 0.0 ? -1.0 : 1.0), fz = (1.0 - abs(px)) * (pz < 0.0 ? -1.0 : 1.0);
  px = lower ? fx : px;
  pz = lower ? fz : pz;
  return vec2((px * oct.x + oct.y) * oct.z, (pz * oct.x + oct.y) * oct.z);
}
vec3 env_irradiance(vec3 d) {
  return textureLod(u_irradiance, env_octahedral(d, u_irradiance_oct), 0.0).rgb * u_env_intensity;
}
#define ENV_LEVEL(L)                                                     \
  {                                                                      \
    float dl = lod - float(L);                                           \
    float w = max(1.0 - max(dl, -dl), 0.0);                              \
    if (w > 0.0) c = c + w * textureLod(u_env_level[L], env_octahedral(d, u_env_oct[L]), 0.0).rgb; \
  }
vec3 env_radiance(vec3 d, float roughness) {
  float r = clamp(roughness, 0.0, 1.0), alpha = r * r, lod = 0.0;
  for (int l = 0; l < 7; ++l) lod = lod + clamp((alpha - u_level_alpha[l]) * u_level_inv[l], 0.0, 1.0);
  vec3 c = vec3(0.0);
  ENV_LEVEL(0) ENV_LEVEL(1) ENV_LEVEL(2) ENV_LEVEL(3) ENV_LEVEL(4) ENV_LEVEL(5) ENV_LEVEL(6) ENV_LEVEL(7)
  return c * u_env_intensity;
}
)";

// The background pass (pbr/src/scene.cpp's BackgroundShader): one triangle over the view at
// the far plane, drawn after the objects with the depth test ≤ and no depth write, each
// vertex carrying the world direction of its camera ray; the
// prefiltered radiance along the interpolated direction at u_bg_roughness (0: level 0).
const char* kBackgroundVertex = R"(
layout(location = 0) in vec4 a_clip;
layout(location = 1) in vec3 a_direction;
out vec3 v_direction;
void main() {
  v_direction = a_direction;
  gl_Position = a_clip;
}
)";
const char* kBackgroundFragment = R"(
in vec3 v_direction;
out vec4 o_color;
uniform float u_bg_roughness;
void main() {
  o_color = vec4(output_transform(env_radiance(to_environment(v_direction), u_bg_roughness)), 1.0);
}
)";

// pbr/shading.h's shade() with the output transform; names as there. TEXTURED: the base
// colour is u_albedo × texture.rgb and F0 is computed from it per pixel, as
// TexturedPbrShader's (textured_shading.h: base = base_color × vertex colour × texture.rgb,
// the vertex colour 1 here; f0 = f0_of(base, metallic)); the ambient and diffuse terms read
// that base colour.
const char* kFragmentShader = R"(
in vec3 v_world;
in vec3 v_normal;
#ifdef TEXTURED
in vec2 v_uv;
uniform sampler2D u_base_color_texture;
#endif
out vec4 o_color;
uniform vec3 u_eye;
uniform vec3 u_ambient;
uniform vec3 u_albedo;
uniform vec3 u_f0;
uniform float u_metallic;
uniform float u_alpha;
uniform float u_k;
uniform float u_ao;
uniform vec3 u_emissive;
uniform int u_light_count;
uniform vec3 u_light_position[8];  // a point light's position; DIRECTIONAL: a directional light's unit direction to it
uniform vec3 u_light_radiance[8];
#ifdef DIRECTIONAL
uniform bool u_light_directional[8];
#endif
#ifdef IBL
uniform float u_roughness;
#endif
const float kPi = 3.14159265358979323846;
const float kMinNoV = 1e-4;
#ifdef SHADOWS
// pbr/shadow.h's shadow_visibility() for an orthographic map (a directional light), term for
// term: the point moved 4 sin θ texels along n and 1.5 texels towards the light (a texel
// u_shadow_texel wide, w = 1), projected by the map's matrix; window coordinates as
// softpbr's viewport transform (row 0 at the top) less the half texel, clamped to
// [1, size − 3]; the 4×4 texels from ⌊g⌋ − 1 read with texelFetch (GL's rows count from the
// bottom: softpbr's row r is GL's size − 1 − r), each passing when z ≤ its depth, columns
// weighted 1 − fx, 1, 1, fx and rows likewise; lit / (lit + shadowed). No hardware
// comparison or filtering: the same filter as softpbr.
uniform sampler2DArray u_shadow_maps;  // GL_DEPTH_COMPONENT32F, one layer a map
uniform int u_light_shadow[8];          // the light's layer, or −1 without a map
uniform mat4 u_shadow_matrix[8];        // world → the map's clip space
uniform float u_shadow_texel[8];        // ShadowMap::texel
uniform float u_shadow_size;            // texels a side
uniform bool u_receive_shadows;         // the object's receive_shadows
float shadow_visibility(int i, vec3 position, vec3 n, vec3 l, float n_dot_l) {
  float texel = u_shadow_texel[i];
  float c = clamp(n_dot_l, 0.0, 1.0);
  float sin_theta = sqrt(max(1.0 - c * c, 0.0));
  vec3 p = position + n * (sin_theta * texel * 4.0) + l * (texel * 1.5);
  vec4 clip = u_shadow_matrix[i] * vec4(p, 1.0);
  float z = min(clip.z * 0.5 + 0.5, 1.0);
  float fs = u_shadow_size, half_size = 0.5 * fs;
  float gx = clamp((clip.x + 1.0) * half_size - 0.5, 1.0, fs - 3.0);
  float gy = clamp((1.0 - clip.y) * half_size - 0.5, 1.0, fs - 3.0);
  float ix = floor(gx), iy = floor(gy);
  float fx = gx - ix, fy = gy - iy;
  int x0 = int(ix) - 1;
  int y0 = int(fs) - int(iy);  // GL's row of softpbr's row ⌊gy⌋ − 1
  int layer = u_light_shadow[i];
  vec4 wx = vec4(1.0 - fx, 1.0, 1.0, fx);
  vec4 wy = vec4(1.0 - fy, 1.0, 1.0, fy);
  float lit = 0.0, shadowed = 0.0;
  for (int r = 0; r < 4; ++r) {
    float row_lit = 0.0, row_shadowed = 0.0;
    for (int k = 0; k < 4; ++k) {
      bool passes = z <= texelFetch(u_shadow_maps, ivec3(x0 + k, y0 - r, layer), 0).r;
      row_lit = row_lit + (passes ? wx[k] : 0.0);
      row_shadowed = row_shadowed + (passes ? 0.0 : wx[k]);
    }
    lit = lit + row_lit * wy[r];
    shadowed = shadowed + row_shadowed * wy[r];
  }
  return lit / (lit + shadowed);
}
#endif

vec3 normalize_or(vec3 v, vec3 fallback) {
  float len2 = dot(v, v);
  return (len2 > 0.0 && len2 < 1.0 / 0.0) ? v / sqrt(len2) : fallback;
}
vec3 F_Schlick(vec3 f0, float VoH) {
  float m = 1.0 - VoH;
  float m2 = m * m;
  float m5 = m2 * m2 * m;
  return f0 + (vec3(1.0) - f0) * m5;
}
vec3 brdf(vec3 n, vec3 l, vec3 v, vec3 albedo, vec3 f0) {
  vec3 lv = l + v;
  float lv2 = dot(lv, lv);
  bool has_h = lv2 > 0.0 && lv2 < 1.0 / 0.0;
  float lv_len = sqrt(has_h ? lv2 : 1.0);
  float NoL = clamp(dot(n, l), 0.0, 1.0);
  float NoV = clamp(dot(n, v), kMinNoV, 1.0);
  float NoH = clamp(has_h ? dot(n, lv) / lv_len : dot(n, n), 0.0, 1.0);
  float VoH = clamp(has_h ? dot(v, lv) / lv_len : dot(v, n), 0.0, 1.0);
  float a2 = u_alpha * u_alpha;
  float d = NoH * NoH * (a2 - 1.0) + 1.0;
  float g_v = NoV * (1.0 - u_k) + u_k, g_l = NoL * (1.0 - u_k) + u_k;
  vec3 F = F_Schlick(f0, VoH);
  vec3 specular = F * ((a2 * NoL) / (4.0 * kPi * d * d * g_v * g_l * max(NoL, kMinNoV)));
  vec3 kD = max(vec3(1.0) - F, vec3(0.0)) * (1.0 - u_metallic);
  return kD * albedo * (1.0 / kPi) + specular;
}
#ifdef IBL
// pbr/shading.h's ibl(): split sum along the lobe's dominant direction with
// Fresnel-with-roughness kS, the diffuse weighted by the dielectric layer's reflection and,
// with MULTISCATTER, Fdez-Agüera's energy compensation.
vec3 ibl(vec3 n, vec3 v, vec3 albedo, vec3 f0) {
  float n_dot_v = dot(n, v);
  float NoV = clamp(n_dot_v, kMinNoV, 1.0);
  vec3 r0 = n * (n_dot_v + n_dot_v) - v;
  float s_ = 1.0 - u_alpha;
  vec3 r = n + (r0 - n) * (s_ * (sqrt(s_) + u_alpha));
  vec3 irr = env_irradiance(to_environment(n));
  vec3 pre = env_radiance(to_environment(r), u_roughness);
  vec2 ab = textureLod(u_dfg, vec2(NoV, u_roughness), 0.0).rg;
  float A = ab.x, B = ab.y;
  float c = 1.0 - NoV, c2 = c * c;
  float c5 = c2 * c2 * c;
  float smooth_ = 1.0 - u_roughness;
  vec3 ks = f0 + (max(vec3(smooth_), f0) - f0) * c5;
  vec3 fss_ess = ks * A + vec3(B);
  float ksd = 0.04 + (max(smooth_, 0.04) - 0.04) * c5;
  float fss_d = ksd * A + B;
  vec3 diffuse;
#ifdef MULTISCATTER
  float ems = 1.0 - (A + B);
  vec3 favg = f0 + (vec3(1.0) - f0) * (1.0 / 21.0);
  vec3 fe = favg * ems;
  vec3 fms_ems = fss_ess * fe / max(vec3(1.0) - fe, vec3(1e-3));
  float fe_d = (0.04 + 0.96 * (1.0 / 21.0)) * ems;
  float fms_d = fss_d * fe_d / max(1.0 - fe_d, 1e-3);
  diffuse = fms_ems + albedo * (1.0 - u_metallic) * max(1.0 - (fss_d + fms_d), 0.0);
#else
  diffuse = vec3(max(1.0 - ksd, 0.0)) * (1.0 - u_metallic) * albedo;
#endif
  return (irr * diffuse + pre * fss_ess) * u_ao;
}
#endif
void main() {
  vec3 albedo = u_albedo, f0 = u_f0;
#ifdef TEXTURED
  albedo = u_albedo * texture(u_base_color_texture, v_uv).rgb;
  f0 = vec3(0.04) + (albedo - vec3(0.04)) * u_metallic;
#endif
  vec3 v = normalize_or(u_eye - v_world, vec3(0.0, 0.0, 1.0));
  vec3 n = normalize_or(v_normal, v);
  vec3 lo = vec3(0.0);
  for (int i = 0; i < u_light_count; ++i) {
    // pbr/light.h's sample_light(): a directional light's direction to it with falloff 1, a
    // point light's inverse square.
    vec3 l;
    float falloff;
#ifdef DIRECTIONAL
    if (u_light_directional[i]) {
      l = u_light_position[i];
      falloff = 1.0;
    } else
#endif
    {
      vec3 d = u_light_position[i] - v_world;
      float dist2 = max(dot(d, d), 1e-8);
      float inv_dist = 1.0 / sqrt(dist2);
      l = d * inv_dist;
      falloff = inv_dist * inv_dist;
    }
    float NoL = dot(n, l);
    if (NoL > 0.0) {
#ifdef SHADOWS
      if (u_receive_shadows && u_light_shadow[i] >= 0) falloff = falloff * shadow_visibility(i, v_world, n, l, NoL);
#endif
      lo += brdf(n, l, v, albedo, f0) * (u_light_radiance[i] * falloff) * NoL;
    }
  }
#ifdef IBL
  vec3 c = ibl(n, v, albedo, f0) + lo + u_emissive;
#else
  vec3 c = u_ambient * albedo * u_ao + lo + u_emissive;
#endif
  o_color = vec4(output_transform(c), 1.0);
}
)";

GLuint compile(GLenum type, const std::string& defines, std::initializer_list<const char*> sources) {
  const GLuint s = glCreateShader(type);
  std::vector<const char*> parts{kVersion, defines.c_str()};
  parts.insert(parts.end(), sources.begin(), sources.end());
  glShaderSource(s, static_cast<GLsizei>(parts.size()), parts.data(), nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("llvmpipe: GLSL compile error: ") + log);
  }
  return s;
}

GLuint link(GLuint vs, GLuint fs) {
  const GLuint p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("llvmpipe: GLSL link error: ") + log);
  }
  glDeleteShader(vs);
  glDeleteShader(fs);
  return p;
}

GLenum gl_wrap(raster::Wrap w) {
  switch (w) {
    case raster::Wrap::ClampToEdge:
      return GL_CLAMP_TO_EDGE;
    case raster::Wrap::MirroredRepeat:
      return GL_MIRRORED_REPEAT;
    case raster::Wrap::Repeat:
    default:
      return GL_REPEAT;
  }
}

GLenum gl_min_filter(const raster::Sampler& s) {
  const bool linear = s.min_filter == raster::Filter::Linear;
  switch (s.mip_filter) {
    case raster::MipFilter::None:
      return linear ? GL_LINEAR : GL_NEAREST;
    case raster::MipFilter::Nearest:
      return linear ? GL_LINEAR_MIPMAP_NEAREST : GL_NEAREST_MIPMAP_NEAREST;
    case raster::MipFilter::Linear:
    default:
      return linear ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST_MIPMAP_LINEAR;
  }
}

// The shadow maps' depth pass: the casters' positions as the object shader's
// (view_projection · (model · p)), no colour.
const char* kDepthVertexShader = R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_model;
uniform mat4 u_view_projection;
void main() {
  gl_Position = u_view_projection * (u_model * vec4(a_position, 1.0));
}
)";
const char* kDepthFragmentShader = R"(
void main() {}
)";

// pbr/src/shadows.h's constants (internal to softpbr::pbr, so repeated here): a directional
// light's map is 2048² texels, fitted with 4 texels free around the scene's bounds.
constexpr int kShadowMapSize = 2048;
constexpr int kShadowBorder = 4;
// The texture unit of the shadow maps (0: the base colour texture, 1–10: the environment).
constexpr int kShadowUnit = 11;

// pbr/src/scene.cpp's scene_bounds(): the corners of each object's mesh bounds transformed
// to world space, in float.
pbr::Bounds world_bounds(const pbr::Scene& scene) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  pbr::Bounds world{glm::vec3(inf), glm::vec3(-inf)};
  for (const pbr::Object& o : scene.objects) {
    const pbr::Bounds b = pbr::bounds(*o.mesh);
    if (b.empty()) continue;
    for (int i = 0; i < 8; ++i) {
      const glm::vec3 corner((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y, (i & 4) ? b.max.z : b.min.z);
      const glm::vec3 w(o.transform * glm::vec4(corner, 1.0f));
      world = pbr::merge(world, pbr::Bounds{w, w});
    }
  }
  return world;
}

// pbr/src/shadows.cpp's shadow_setup() for a directional light (internal to softpbr::pbr, so
// copied): axes u, v across the light as glm::lookAt's, the bounds' corners' extent across
// it widened by the border, their depth range along it with a 1% margin; in double, rounded
// once to float. False for empty bounds (softpbr then draws no map either).
bool fit_directional(const glm::vec3& unit_direction, const pbr::Bounds& world, glm::mat4& view_projection,
                     float& texel) {
  if (world.empty()) return false;
  using D3 = glm::dvec3;
  const auto dot = [](const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  const D3 f(unit_direction.x, unit_direction.y, unit_direction.z);
  const D3 up = std::abs(f.y) < 0.99 ? D3(0.0, 1.0, 0.0) : D3(1.0, 0.0, 0.0);
  const D3 c(f.y * up.z - f.z * up.y, f.z * up.x - f.x * up.z, f.x * up.y - f.y * up.x);
  const D3 u = c / std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
  const D3 v(u.y * f.z - u.z * f.y, u.z * f.x - u.x * f.z, u.x * f.y - u.y * f.x);
  constexpr double inf = std::numeric_limits<double>::infinity();
  double u0 = inf, u1 = -inf, v0 = inf, v1 = -inf, s0 = inf, s1 = -inf;
  for (int i = 0; i < 8; ++i) {
    const D3 q((i & 1) ? world.max.x : world.min.x, (i & 2) ? world.max.y : world.min.y,
               (i & 4) ? world.max.z : world.min.z);
    u0 = std::min(u0, dot(u, q)), u1 = std::max(u1, dot(u, q));
    v0 = std::min(v0, dot(v, q)), v1 = std::max(v1, dot(v, q));
    s0 = std::min(s0, dot(f, q)), s1 = std::max(s1, dot(f, q));
  }
  const double border = static_cast<double>(kShadowMapSize) / static_cast<double>(kShadowMapSize - 2 * kShadowBorder);
  const double extent = std::max({u1 - u0, v1 - v0, s1 - s0, 1e-6});
  const double half = 0.5 * std::max(u1 - u0, v1 - v0) * border + 1e-6 * extent;
  const double cu = 0.5 * (u0 + u1), cv = 0.5 * (v0 + v1);
  const double margin = 0.01 * extent;
  s0 -= margin, s1 += margin;
  const D3 r0 = u / half, r1 = v / half, r2 = f * (2.0 / (s1 - s0));
  const double rows[4][4] = {{r0.x, r0.y, r0.z, -cu / half},
                             {r1.x, r1.y, r1.z, -cv / half},
                             {r2.x, r2.y, r2.z, -(s0 + s1) / (s1 - s0)},
                             {0.0, 0.0, 0.0, 1.0}};
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) view_projection[k][r] = static_cast<float>(rows[r][k]);
  texel = static_cast<float>(2.0 * half / kShadowMapSize);
  return true;
}

bool has_extension(const char* name) {
  GLint n = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &n);
  for (GLint i = 0; i < n; ++i) {
    const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
    if (e != nullptr && std::string(e) == name) return true;
  }
  return false;
}

}  // namespace

struct LlvmpipeRenderer::Impl {
  OSMesaContext context = nullptr;
  int width = 0, height = 0;
  GLuint fbo = 0, color_rb = 0, depth_rb = 0;  // multisampled only
  // One program per variant of the object shader, by its defines (see kVersion).
  struct Program {
    GLuint id = 0;
    GLint u_model = -1, u_normal_matrix = -1, u_albedo = -1, u_f0 = -1, u_metallic = -1, u_alpha = -1, u_k = -1,
          u_ao = -1, u_emissive = -1, u_roughness = -1, u_receive_shadows = -1;
  };
  std::map<std::string, Program> programs;
  // The environment: its levels and the DFG table as textures, the background pass.
  GLuint env_levels[pbr::Environment::kLevels] = {};
  GLuint env_irradiance = 0;
  GLuint dfg = 0;
  const pbr::Environment* env_map = nullptr;  // what env_levels hold
  GLuint background_program = 0;
  std::string background_defines;
  GLuint background_vao = 0, background_vbo = 0;
  bool background = false;  // drawn this frame
  struct GpuMesh {
    GLuint vao = 0, vbo = 0, ebo = 0;
    GLsizei count = 0;
  };
  std::map<std::pair<const pbr::Mesh*, bool>, GpuMesh> meshes;  // (mesh, textured): the uv attribute only when read
  std::map<const raster::Texture*, GLuint> textures;
  std::vector<GLuint> samplers;
  struct Draw {
    const GpuMesh* mesh;
    const Program* program;
    GLuint texture;  // 0: untextured
    GLuint sampler;
    glm::mat4 model;
    glm::mat3 normal_matrix;
    pbr::ShadingMaterial material;
    bool cast_shadows;     // drawn into the shadow maps
    bool receive_shadows;  // reads them
  };
  std::vector<Draw> draws;
  // The shadow maps: one GL_DEPTH_COMPONENT32F layer of shadow_texture a directional light
  // with shadows, drawn each frame through its depth-only framebuffer (shadow_fbos[layer])
  // by depth_program with the light's fitted matrix.
  GLuint depth_program = 0;
  GLint depth_u_model = -1, depth_u_view_projection = -1;
  GLuint shadow_texture = 0;
  int shadow_layers = 0;  // layers allocated in shadow_texture
  std::vector<GLuint> shadow_fbos;
  std::vector<glm::mat4> shadow_passes;  // this scene's maps: layer i's view-projection
  glm::vec4 clear{0, 0, 0, 1};
  std::string anisotropy_extension;  // "" when llvmpipe reports none
  float max_anisotropy = 1.0f;

  GLuint upload(const raster::Texture& t) {
    auto [it, fresh] = textures.try_emplace(&t, 0);
    if (!fresh) return it->second;
    glGenTextures(1, &it->second);
    glBindTexture(GL_TEXTURE_2D, it->second);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // softpbr's own mip chain, level by level, so both sample the same texels.
    const std::span<const raster::Texture::Level> levels = t.levels();
    for (std::size_t l = 0; l < levels.size(); ++l) {
      const raster::Texture::Level& lv = levels[l];
      const GLint level = static_cast<GLint>(l);
      if (t.is_float())
        glTexImage2D(GL_TEXTURE_2D, level, GL_RGBA32F, lv.width, lv.height, 0, GL_RGBA, GL_FLOAT,
                     t.texels_f().data() + lv.offset * 4);
      else
        glTexImage2D(GL_TEXTURE_2D, level,
                     t.color_space() == raster::ColorSpace::Srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, lv.width, lv.height,
                     0, GL_RGBA, GL_UNSIGNED_BYTE, t.texels8().data() + lv.offset * 4);
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, static_cast<GLint>(levels.size()) - 1);
    return it->second;
  }

  Program& program(const std::string& defines) {
    auto [it, fresh] = programs.try_emplace(defines);
    Program& pr = it->second;
    if (!fresh) return pr;
    const bool ibl = defines.find("#define IBL") != std::string::npos;
    const GLuint vs = compile(GL_VERTEX_SHADER, defines, {kVertexShader});
    const GLuint fs = compile(GL_FRAGMENT_SHADER, defines,
                              {kOutputTransform, ibl ? kEnvironment : "", kFragmentShader});
    pr.id = link(vs, fs);
    const GLuint p = pr.id;
    pr.u_model = glGetUniformLocation(p, "u_model");
    pr.u_normal_matrix = glGetUniformLocation(p, "u_normal_matrix");
    pr.u_albedo = glGetUniformLocation(p, "u_albedo");
    pr.u_f0 = glGetUniformLocation(p, "u_f0");
    pr.u_metallic = glGetUniformLocation(p, "u_metallic");
    pr.u_alpha = glGetUniformLocation(p, "u_alpha");
    pr.u_k = glGetUniformLocation(p, "u_k");
    pr.u_ao = glGetUniformLocation(p, "u_ao");
    pr.u_emissive = glGetUniformLocation(p, "u_emissive");
    pr.u_roughness = glGetUniformLocation(p, "u_roughness");
    pr.u_receive_shadows = glGetUniformLocation(p, "u_receive_shadows");
    glUseProgram(p);
    if (defines.find("#define TEXTURED") != std::string::npos)
      glUniform1i(glGetUniformLocation(p, "u_base_color_texture"), 0);
    if (defines.find("#define SHADOWS") != std::string::npos)
      glUniform1i(glGetUniformLocation(p, "u_shadow_maps"), kShadowUnit);
    return pr;
  }

  // `layers` shadow maps of kShadowMapSize² depths (a GL_TEXTURE_2D_ARRAY, nearest, one
  // level, no comparison mode: the shader compares), each a framebuffer with it as its only
  // attachment; bound to kShadowUnit.
  void allocate_shadow_maps(int layers) {
    if (depth_program == 0) {
      depth_program = link(compile(GL_VERTEX_SHADER, "", {kDepthVertexShader}),
                           compile(GL_FRAGMENT_SHADER, "", {kDepthFragmentShader}));
      depth_u_model = glGetUniformLocation(depth_program, "u_model");
      depth_u_view_projection = glGetUniformLocation(depth_program, "u_view_projection");
    }
    if (layers > shadow_layers) {
      if (!shadow_fbos.empty()) glDeleteFramebuffers(static_cast<GLsizei>(shadow_fbos.size()), shadow_fbos.data());
      shadow_fbos.clear();
      if (shadow_texture != 0) glDeleteTextures(1, &shadow_texture);
      glGenTextures(1, &shadow_texture);
      glActiveTexture(GL_TEXTURE0 + kShadowUnit);
      glBindTexture(GL_TEXTURE_2D_ARRAY, shadow_texture);
      glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_DEPTH_COMPONENT32F, kShadowMapSize, kShadowMapSize, layers, 0,
                   GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
      glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BASE_LEVEL, 0);
      glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, 0);
      glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_MODE, GL_NONE);
      glActiveTexture(GL_TEXTURE0);
      shadow_fbos.assign(static_cast<std::size_t>(layers), 0);
      glGenFramebuffers(layers, shadow_fbos.data());
      for (int i = 0; i < layers; ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbos[static_cast<std::size_t>(i)]);
        glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, shadow_texture, 0, i);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
          throw std::runtime_error("llvmpipe: the shadow map's framebuffer is incomplete");
      }
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      shadow_layers = layers;
    }
  }

  // A float texture of one level as GL_RGBA32F, linear, clamp to edge.
  static GLuint upload_float(const raster::Texture& t) {
    GLuint id = 0;
    glGenTextures(1, &id);
    glBindTexture(GL_TEXTURE_2D, id);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, t.width(), t.height(), 0, GL_RGBA, GL_FLOAT, t.texels_f().data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return id;
  }

  // The environment's textures (units 1–8: the levels, 9: the irradiance map, 10: the DFG
  // table) and uniforms.
  static constexpr int kLevelUnit = 1, kIrradianceUnit = 1 + pbr::Environment::kLevels,
                       kDfgUnit = 2 + pbr::Environment::kLevels;
  void upload_environment(const pbr::Environment& env) {
    if (env_map != &env) {
      for (GLuint& id : env_levels)
        if (id != 0) glDeleteTextures(1, &id);
      for (int i = 0; i < pbr::Environment::kLevels; ++i) env_levels[i] = upload_float(env.level(i));
      if (env_irradiance != 0) glDeleteTextures(1, &env_irradiance);
      env_irradiance = upload_float(env.irradiance());
      env_map = &env;
    }
    if (dfg == 0) dfg = upload_float(pbr::dfg_table());
    for (int i = 0; i < pbr::Environment::kLevels; ++i) {
      glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + kLevelUnit + i));
      glBindTexture(GL_TEXTURE_2D, env_levels[i]);
    }
    glActiveTexture(GL_TEXTURE0 + kIrradianceUnit);
    glBindTexture(GL_TEXTURE_2D, env_irradiance);
    glActiveTexture(GL_TEXTURE0 + kDfgUnit);
    glBindTexture(GL_TEXTURE_2D, dfg);
    glActiveTexture(GL_TEXTURE0);
  }
  static void set_environment_uniforms(GLuint p, const pbr::PreparedEnvironment& e) {
    glUseProgram(p);
    for (int i = 0; i < pbr::Environment::kLevels; ++i) {
      std::string idx = "[";
      idx += std::to_string(i);
      idx += "]";
      glUniform1i(glGetUniformLocation(p, ("u_env_level" + idx).c_str()), kLevelUnit + i);
      // env_octahedral's constants for a level of side `size`, in float as there.
      const int size = e.map->level_size(i);
      const glm::vec3 oct(0.5f * static_cast<float>(size), 0.5f * static_cast<float>(size) + 1.0f,
                          1.0f / static_cast<float>(size + 2));
      glUniform3fv(glGetUniformLocation(p, ("u_env_oct" + idx).c_str()), 1, glm::value_ptr(oct));
      glUniform1f(glGetUniformLocation(p, ("u_level_alpha" + idx).c_str()), pbr::kEnvironmentLevelAlpha[i]);
      if (i + 1 < pbr::Environment::kLevels)
        glUniform1f(glGetUniformLocation(p, ("u_level_inv" + idx).c_str()),
                    1.0f / (pbr::kEnvironmentLevelAlpha[i + 1] - pbr::kEnvironmentLevelAlpha[i]));
    }
    const int isize = pbr::kIrradianceSize;
    const glm::vec3 ioct(0.5f * static_cast<float>(isize), 0.5f * static_cast<float>(isize) + 1.0f,
                         1.0f / static_cast<float>(isize + 2));
    glUniform1i(glGetUniformLocation(p, "u_irradiance"), kIrradianceUnit);
    glUniform3fv(glGetUniformLocation(p, "u_irradiance_oct"), 1, glm::value_ptr(ioct));
    glUniform1i(glGetUniformLocation(p, "u_dfg"), kDfgUnit);
    glUniform1f(glGetUniformLocation(p, "u_env_cos"), e.cos_r);
    glUniform1f(glGetUniformLocation(p, "u_env_sin"), e.sin_r);
    glUniform1f(glGetUniformLocation(p, "u_env_intensity"), e.intensity);
  }

  GLuint make_sampler(const raster::Sampler& s) {
    GLuint id = 0;
    glGenSamplers(1, &id);
    samplers.push_back(id);
    glSamplerParameteri(id, GL_TEXTURE_WRAP_S, static_cast<GLint>(gl_wrap(s.wrap_u)));
    glSamplerParameteri(id, GL_TEXTURE_WRAP_T, static_cast<GLint>(gl_wrap(s.wrap_v)));
    glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, s.mag_filter == raster::Filter::Linear ? GL_LINEAR : GL_NEAREST);
    glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(gl_min_filter(s)));
    glSamplerParameterf(id, GL_TEXTURE_LOD_BIAS, s.lod_bias);
    glSamplerParameterf(id, GL_TEXTURE_MIN_LOD, s.min_lod);
    glSamplerParameterf(id, GL_TEXTURE_MAX_LOD, s.max_lod);
    if (!anisotropy_extension.empty())
      glSamplerParameterf(id, GL_TEXTURE_MAX_ANISOTROPY, std::min(static_cast<float>(s.max_anisotropy), max_anisotropy));
    return id;
  }
};

LlvmpipeRenderer::LlvmpipeRenderer(int width, int height, int samples) : impl_(std::make_unique<Impl>()) {
  const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 0,
                         OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
  impl_->context = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!impl_->context) throw std::runtime_error("llvmpipe: OSMesaCreateContextAttribs failed");
  impl_->width = width;
  impl_->height = height;
  pixels_.assign(static_cast<std::size_t>(width) * height * 4, 0);
  if (!OSMesaMakeCurrent(impl_->context, pixels_.data(), GL_UNSIGNED_BYTE, width, height))
    throw std::runtime_error("llvmpipe: OSMesaMakeCurrent failed");
  OSMesaPixelStore(OSMESA_Y_UP, 0);  // row 0 at the top, as softpbr
  // Anisotropic filtering: core in GL 4.6, else ARB_ or EXT_texture_filter_anisotropic (one enum).
  for (const char* e : {"GL_ARB_texture_filter_anisotropic", "GL_EXT_texture_filter_anisotropic"})
    if (has_extension(e)) {
      impl_->anisotropy_extension = e;
      glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY, &impl_->max_anisotropy);
      break;
    }
  if (samples > 1) {
    GLint most = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &most);
    if (most < samples)
      throw std::runtime_error("llvmpipe: " + std::to_string(samples) + " samples asked, GL_MAX_SAMPLES is " +
                               std::to_string(most));
    glGenRenderbuffers(1, &impl_->color_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, impl_->color_rb);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
    glGenRenderbuffers(1, &impl_->depth_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, impl_->depth_rb);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
    glGenFramebuffers(1, &impl_->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, impl_->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, impl_->color_rb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, impl_->depth_rb);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("llvmpipe: the multisampled framebuffer is incomplete");
    GLint got = 0;
    glGetIntegerv(GL_SAMPLES, &got);
    if (got != samples) throw std::runtime_error("llvmpipe: the framebuffer has " + std::to_string(got) + " samples");
  }
  glViewport(0, 0, width, height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
}

LlvmpipeRenderer::~LlvmpipeRenderer() {
  for (auto& [mesh, gpu] : impl_->meshes) {
    glDeleteVertexArrays(1, &gpu.vao);
    glDeleteBuffers(1, &gpu.vbo);
    glDeleteBuffers(1, &gpu.ebo);
  }
  for (auto& [texture, id] : impl_->textures) glDeleteTextures(1, &id);
  if (!impl_->samplers.empty()) glDeleteSamplers(static_cast<GLsizei>(impl_->samplers.size()), impl_->samplers.data());
  for (auto& [defines, pr] : impl_->programs)
    if (pr.id) glDeleteProgram(pr.id);
  for (GLuint id : impl_->env_levels)
    if (id != 0) glDeleteTextures(1, &id);
  if (impl_->env_irradiance != 0) glDeleteTextures(1, &impl_->env_irradiance);
  if (impl_->dfg != 0) glDeleteTextures(1, &impl_->dfg);
  if (impl_->background_program != 0) glDeleteProgram(impl_->background_program);
  if (impl_->background_vao != 0) {
    glDeleteVertexArrays(1, &impl_->background_vao);
    glDeleteBuffers(1, &impl_->background_vbo);
  }
  if (!impl_->shadow_fbos.empty())
    glDeleteFramebuffers(static_cast<GLsizei>(impl_->shadow_fbos.size()), impl_->shadow_fbos.data());
  if (impl_->shadow_texture != 0) glDeleteTextures(1, &impl_->shadow_texture);
  if (impl_->depth_program != 0) glDeleteProgram(impl_->depth_program);
  if (impl_->fbo) {
    glDeleteFramebuffers(1, &impl_->fbo);
    glDeleteRenderbuffers(1, &impl_->color_rb);
    glDeleteRenderbuffers(1, &impl_->depth_rb);
  }
  if (impl_->context) OSMesaDestroyContext(impl_->context);
}

namespace {
// What the textured program draws: a base colour texture (uv set 0, no transform) on an
// opaque, single-sided material without vertex colours; anything else throws.
bool check_textured(const pbr::Object& o) {
  const pbr::Material& m = o.material;
  if (!m.textured() && m.alpha_mode == pbr::AlphaMode::Opaque && !m.double_sided && o.mesh->colors.empty())
    return false;
  const pbr::TextureSlot& b = m.base_color_texture;
  const bool transformed = !(b.transform.offset == glm::vec2(0.0f) && b.transform.rotation == 0.0f &&
                             b.transform.scale == glm::vec2(1.0f));
  if (!b || b.uv_set != 0 || transformed || m.metallic_roughness_texture || m.normal_texture || m.occlusion_texture ||
      m.emissive_texture || m.alpha_mode != pbr::AlphaMode::Opaque || m.double_sided || !o.mesh->colors.empty())
    throw std::invalid_argument(
        "llvmpipe: textured objects may have only a base colour texture (uv set 0, no transform), opaque, "
        "single-sided, without vertex colours");
  return true;
}
}  // namespace

void LlvmpipeRenderer::load(const pbr::Scene& scene, const pbr::OutputSettings& output) {
  if ((output.tone_map != pbr::ToneMap::Reinhard && output.tone_map != pbr::ToneMap::Aces) ||
      output.exposure != 0.0f || !(output.gamma >= 0.0f))
    throw std::invalid_argument("llvmpipe: only Reinhard or ACES, with the sRGB or a gamma curve, exposure 0");
  if (scene.lights.size() > kMaxLights) throw std::invalid_argument("llvmpipe: at most 8 lights");
  Impl& m = *impl_;
  // The lights: point lights without range, directional lights; only directional ones may
  // cast shadows (an orthographic map fitted as softpbr's, one layer each).
  std::vector<pbr::PreparedLight> lights;
  bool any_directional = false;
  for (const pbr::Light& l : scene.lights) {
    if (!((l.type == pbr::LightType::Point && l.range == 0.0f) || l.type == pbr::LightType::Directional))
      throw std::invalid_argument("llvmpipe: point lights without range and directional lights only");
    if (l.shadows && l.type != pbr::LightType::Directional)
      throw std::invalid_argument("llvmpipe: shadows are ported for directional lights only");
    any_directional = any_directional || l.type == pbr::LightType::Directional;
    lights.push_back(pbr::prepare_light(l));
  }
  std::vector<int> shadow_layer(lights.size(), -1);
  std::vector<float> shadow_texel(lights.size(), 0.0f);
  m.shadow_passes.clear();
  if (std::any_of(lights.begin(), lights.end(), [](const pbr::PreparedLight& l) { return l.light.shadows; })) {
    const pbr::Bounds world = world_bounds(scene);
    for (std::size_t i = 0; i < lights.size(); ++i) {
      glm::mat4 view_projection(1.0f);
      if (!lights[i].light.shadows || !fit_directional(lights[i].unit_direction, world, view_projection, shadow_texel[i]))
        continue;
      shadow_layer[i] = static_cast<int>(m.shadow_passes.size());
      m.shadow_passes.push_back(view_projection);
    }
    if (!m.shadow_passes.empty()) m.allocate_shadow_maps(static_cast<int>(m.shadow_passes.size()));
  }
  std::string output_defines;
  if (output.tone_map == pbr::ToneMap::Aces) output_defines += "#define ACES 1\n";
  if (output.gamma == 0.0f) output_defines += "#define SRGB 1\n";
  // The lights' variants, only where a scene has them (the point-light scenes' shader is
  // unchanged): directional lights, shadow maps.
  std::string light_defines;
  if (any_directional) light_defines += "#define DIRECTIONAL 1\n";
  if (!m.shadow_passes.empty()) light_defines += "#define SHADOWS 1\n";
  pbr::PreparedEnvironment env;
  std::string env_defines;
  if (scene.environment.map) {
    env = pbr::prepare_environment(scene.environment);
    env_defines = env.multiscatter ? "#define IBL 1\n#define MULTISCATTER 1\n" : "#define IBL 1\n";
    m.upload_environment(*scene.environment.map);
  }
  // The variants this scene draws with: [textured].
  Impl::Program* variants[2] = {&m.program(output_defines + env_defines + light_defines), nullptr};
  const bool any_textured =
      std::any_of(scene.objects.begin(), scene.objects.end(), [](const pbr::Object& o) { return check_textured(o); });
  if (any_textured) {
    if (scene.environment.map)
      throw std::invalid_argument("llvmpipe: textured objects under an environment are not ported");
    variants[1] = &m.program("#define TEXTURED 1\n" + output_defines + light_defines);
  }
  m.background = scene.background_mode != pbr::BackgroundMode::Color;
  if (m.background) {
    if (!scene.environment.map) throw std::invalid_argument("llvmpipe: an environment background needs an environment");
    if (m.background_program == 0 || m.background_defines != output_defines) {
      if (m.background_program != 0) glDeleteProgram(m.background_program);
      m.background_program =
          link(compile(GL_VERTEX_SHADER, output_defines, {kBackgroundVertex}),
               compile(GL_FRAGMENT_SHADER, output_defines, {kOutputTransform, kEnvironment, kBackgroundFragment}));
      m.background_defines = output_defines;
    }
    const GLuint p = m.background_program;
    Impl::set_environment_uniforms(p, env);
    glUniform1f(glGetUniformLocation(p, "u_inv_gamma"), output.gamma > 0.0f ? 1.0f / output.gamma : 1.0f);
    glUniform1f(glGetUniformLocation(p, "u_bg_roughness"),
                scene.background_mode == pbr::BackgroundMode::Blur ? scene.background_blur : 0.0f);
    // pbr/src/scene.cpp's background_triangle(), with the same dmath: clip (−1, −1), (3, −1),
    // (−1, 3), each with the world direction of its camera ray.
    const float aspect = static_cast<float>(m.width) / static_cast<float>(m.height);
    const glm::mat3 to_world = glm::transpose(glm::mat3(scene.camera.view()));
    const double half = 0.5 * static_cast<double>(scene.camera.fovy);
    const auto ty = static_cast<float>(dmath::sin(half) / dmath::cos(half));
    const float tx = ty * aspect;
    const float corners[3][2] = {{-1.0f, -1.0f}, {3.0f, -1.0f}, {-1.0f, 3.0f}};
    float vertices[3][7];
    for (int i = 0; i < 3; ++i) {
      const glm::vec3 d = to_world * glm::vec3(corners[i][0] * tx, corners[i][1] * ty, -1.0f);
      const float v[7] = {corners[i][0], corners[i][1], 1.0f, 1.0f, d.x, d.y, d.z};
      std::copy(v, v + 7, vertices[i]);
    }
    if (m.background_vao == 0) {
      glGenVertexArrays(1, &m.background_vao);
      glGenBuffers(1, &m.background_vbo);
    }
    glBindVertexArray(m.background_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m.background_vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof vertices, vertices, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 7 * sizeof(float), nullptr);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), reinterpret_cast<void*>(4 * sizeof(float)));
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
  }
  const glm::mat4 vp =
      scene.camera.projection(static_cast<float>(m.width) / static_cast<float>(m.height)) * scene.camera.view();
  for (const Impl::Program* pr : variants) {
    if (pr == nullptr) continue;
    const GLuint p = pr->id;
    glUseProgram(p);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_view_projection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform3fv(glGetUniformLocation(p, "u_eye"), 1, glm::value_ptr(scene.camera.position));
    glUniform3fv(glGetUniformLocation(p, "u_ambient"), 1, glm::value_ptr(scene.ambient));
    glUniform1f(glGetUniformLocation(p, "u_inv_gamma"), output.gamma > 0.0f ? 1.0f / output.gamma : 1.0f);
    glUniform1i(glGetUniformLocation(p, "u_light_count"), static_cast<GLint>(scene.lights.size()));
    if (scene.environment.map && pr == variants[0]) Impl::set_environment_uniforms(p, env);
    glUniform1f(glGetUniformLocation(p, "u_shadow_size"), static_cast<float>(kShadowMapSize));
    for (std::size_t i = 0; i < lights.size(); ++i) {
      const pbr::Light& l = lights[i].light;
      const glm::vec3 radiance = l.color * l.intensity;
      const bool directional = l.type == pbr::LightType::Directional;
      // pbr/light.h's sample_light(): a directional light's to_light is −unit_direction.
      const glm::vec3 position = directional ? -lights[i].unit_direction : l.position;
      // Appended piece by piece: GCC 12 misreads "[" + std::to_string(i) (-Wrestrict).
      std::string idx = "[";
      idx += std::to_string(i);
      idx += "]";
      glUniform3fv(glGetUniformLocation(p, ("u_light_position" + idx).c_str()), 1, glm::value_ptr(position));
      glUniform3fv(glGetUniformLocation(p, ("u_light_radiance" + idx).c_str()), 1, glm::value_ptr(radiance));
      // Absent from the variants without them (location −1: ignored).
      glUniform1i(glGetUniformLocation(p, ("u_light_directional" + idx).c_str()), directional ? 1 : 0);
      glUniform1i(glGetUniformLocation(p, ("u_light_shadow" + idx).c_str()), shadow_layer[i]);
      if (shadow_layer[i] >= 0) {
        const glm::mat4& shadow_matrix = m.shadow_passes[static_cast<std::size_t>(shadow_layer[i])];
        glUniformMatrix4fv(glGetUniformLocation(p, ("u_shadow_matrix" + idx).c_str()), 1, GL_FALSE,
                           glm::value_ptr(shadow_matrix));
        glUniform1f(glGetUniformLocation(p, ("u_shadow_texel" + idx).c_str()), shadow_texel[i]);
      }
    }
  }
  m.clear = scene.background;
  m.draws.clear();
  for (const pbr::Object& o : scene.objects) {
    const bool textured = check_textured(o);
    auto [it, fresh] = m.meshes.try_emplace({o.mesh.get(), textured});
    Impl::GpuMesh& g = it->second;
    if (fresh) {
      glGenVertexArrays(1, &g.vao);
      glBindVertexArray(g.vao);
      glGenBuffers(1, &g.vbo);
      glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
      glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(o.mesh->vertices.size() * sizeof(pbr::MeshVertex)),
                   o.mesh->vertices.data(), GL_STATIC_DRAW);
      glGenBuffers(1, &g.ebo);
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ebo);
      glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(o.mesh->indices.size() * sizeof(std::uint32_t)),
                   o.mesh->indices.data(), GL_STATIC_DRAW);
      glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(pbr::MeshVertex),
                            reinterpret_cast<void*>(offsetof(pbr::MeshVertex, position)));
      glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(pbr::MeshVertex),
                            reinterpret_cast<void*>(offsetof(pbr::MeshVertex, normal)));
      glEnableVertexAttribArray(0);
      glEnableVertexAttribArray(1);
      if (textured) {
        glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(pbr::MeshVertex),
                              reinterpret_cast<void*>(offsetof(pbr::MeshVertex, uv)));
        glEnableVertexAttribArray(2);
      }
      g.count = static_cast<GLsizei>(o.mesh->indices.size());
    }
    Impl::Draw d{&g, variants[textured], 0, 0, o.transform, glm::transpose(glm::inverse(glm::mat3(o.transform))),
                 pbr::prepare_material(o.material), o.cast_shadows, o.receive_shadows};
    if (textured) {
      d.texture = m.upload(*o.material.base_color_texture.texture);
      d.sampler = m.make_sampler(o.material.base_color_texture.sampler);
    }
    m.draws.push_back(d);
  }
  if (glGetError() != GL_NO_ERROR) throw std::runtime_error("llvmpipe: GL error while loading the scene");
}

void LlvmpipeRenderer::render() {
  Impl& m = *impl_;
  // The shadow maps first, every frame (softpbr redraws its maps every frame too): each
  // light's layer cleared to depth 1, then the casters' depths with their culling (back
  // faces: llvmpipe draws single-sided materials only), depth test less.
  if (!m.shadow_passes.empty()) {
    glUseProgram(m.depth_program);
    glViewport(0, 0, kShadowMapSize, kShadowMapSize);
    glClearDepth(1.0);
    for (std::size_t layer = 0; layer < m.shadow_passes.size(); ++layer) {
      glBindFramebuffer(GL_FRAMEBUFFER, m.shadow_fbos[layer]);
      glClear(GL_DEPTH_BUFFER_BIT);
      glUniformMatrix4fv(m.depth_u_view_projection, 1, GL_FALSE, glm::value_ptr(m.shadow_passes[layer]));
      for (const Impl::Draw& d : m.draws) {
        if (!d.cast_shadows) continue;
        glUniformMatrix4fv(m.depth_u_model, 1, GL_FALSE, glm::value_ptr(d.model));
        glBindVertexArray(d.mesh->vao);
        glDrawElements(GL_TRIANGLES, d.mesh->count, GL_UNSIGNED_INT, nullptr);
      }
    }
    glViewport(0, 0, m.width, m.height);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo);  // 0: OSMesa's buffer
  glClearColor(m.clear.r, m.clear.g, m.clear.b, m.clear.a);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const Impl::Program* current = nullptr;
  for (const Impl::Draw& d : m.draws) {
    const Impl::Program& p = *d.program;
    if (&p != current) {
      glUseProgram(p.id);
      current = &p;
    }
    glUniformMatrix4fv(p.u_model, 1, GL_FALSE, glm::value_ptr(d.model));
    glUniformMatrix3fv(p.u_normal_matrix, 1, GL_FALSE, glm::value_ptr(d.normal_matrix));
    glUniform3fv(p.u_albedo, 1, glm::value_ptr(d.material.albedo));
    glUniform3fv(p.u_f0, 1, glm::value_ptr(d.material.f0));
    glUniform1f(p.u_metallic, d.material.metallic);
    glUniform1f(p.u_alpha, d.material.alpha);
    glUniform1f(p.u_k, d.material.k);
    glUniform1f(p.u_ao, d.material.ao);
    glUniform3fv(p.u_emissive, 1, glm::value_ptr(d.material.emissive));
    if (p.u_roughness >= 0) glUniform1f(p.u_roughness, d.material.roughness);
    if (p.u_receive_shadows >= 0) glUniform1i(p.u_receive_shadows, d.receive_shadows ? 1 : 0);
    if (d.texture != 0) {
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, d.texture);
      glBindSampler(0, d.sampler);
    }
    glBindVertexArray(d.mesh->vao);
    glDrawElements(GL_TRIANGLES, d.mesh->count, GL_UNSIGNED_INT, nullptr);
  }
  if (m.background) {  // after the objects, at the far plane: depth test ≤, no depth write
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    glUseProgram(m.background_program);
    glBindVertexArray(m.background_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
  }
  if (m.fbo) {  // the resolve: a box filter of the samples into the single-sampled buffer
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m.fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, m.width, m.height, 0, 0, m.width, m.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  glFinish();
}

std::string LlvmpipeRenderer::renderer_name() const {
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return s ? s : "?";
}

std::string LlvmpipeRenderer::anisotropy_extension() const { return impl_->anisotropy_extension; }
float LlvmpipeRenderer::max_anisotropy() const { return impl_->max_anisotropy; }

}  // namespace softpbr::bench
