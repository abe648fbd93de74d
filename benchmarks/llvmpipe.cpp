// The llvmpipe side of the comparison (see llvmpipe.h).
#include "llvmpipe.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/glext.h>

#include <algorithm>
#include <map>
#include <span>
#include <stdexcept>
#include <utility>

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "softpbr/pbr/shading.h"
#include "softpbr/raster/texture.h"

namespace softpbr::bench {

namespace {

constexpr int kMaxLights = 8;

// The shaders are compiled twice: as they are for PbrShader's objects, and with TEXTURED
// defined for TexturedPbrShader's (a base colour texture read through the mesh's uv).
const char* kVersion = "#version 330 core\n";
const char* kTexturedDefine = "#define TEXTURED 1\n";

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

// pbr/shading.h's shade() with Reinhard and gamma; names as there. TEXTURED: the base
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
uniform vec3 u_light_position[8];
uniform vec3 u_light_radiance[8];
uniform float u_inv_gamma;
const float kPi = 3.14159265358979323846;
const float kMinNoV = 1e-4;

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
    vec3 d = u_light_position[i] - v_world;
    float dist2 = max(dot(d, d), 1e-8);
    float inv_dist = 1.0 / sqrt(dist2);
    vec3 l = d * inv_dist;
    float NoL = dot(n, l);
    if (NoL > 0.0) lo += brdf(n, l, v, albedo, f0) * (u_light_radiance[i] * (inv_dist * inv_dist)) * NoL;
  }
  vec3 c = u_ambient * albedo * u_ao + lo + u_emissive;
  c = c / (vec3(1.0) + c);  // Reinhard
  o_color = vec4(pow(c, vec3(u_inv_gamma)), 1.0);
}
)";

GLuint compile(GLenum type, const char* source, bool textured) {
  const GLuint s = glCreateShader(type);
  const char* parts[] = {kVersion, textured ? kTexturedDefine : "", source};
  glShaderSource(s, 3, parts, nullptr);
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
  // One program per shader: PbrShader's equation, and the same with the base colour texture.
  struct Program {
    GLuint id = 0;
    GLint u_model = -1, u_normal_matrix = -1, u_albedo = -1, u_f0 = -1, u_metallic = -1, u_alpha = -1, u_k = -1,
          u_ao = -1, u_emissive = -1;
  };
  Program programs[2];  // [textured]
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
  };
  std::vector<Draw> draws;
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
  for (const bool textured : {false, true}) {
    const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader, textured);
    const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader, textured);
    Impl::Program& pr = impl_->programs[textured];
    pr.id = glCreateProgram();
    glAttachShader(pr.id, vs);
    glAttachShader(pr.id, fs);
    glLinkProgram(pr.id);
    GLint ok = 0;
    glGetProgramiv(pr.id, GL_LINK_STATUS, &ok);
    if (!ok) throw std::runtime_error("llvmpipe: GLSL link error");
    glDeleteShader(vs);
    glDeleteShader(fs);
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
    if (textured) {
      glUseProgram(p);
      glUniform1i(glGetUniformLocation(p, "u_base_color_texture"), 0);
    }
  }
  glUseProgram(impl_->programs[0].id);
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
  for (const Impl::Program& pr : impl_->programs)
    if (pr.id) glDeleteProgram(pr.id);
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
  if (output.tone_map != pbr::ToneMap::Reinhard || output.exposure != 0.0f || !(output.gamma > 0.0f))
    throw std::invalid_argument("llvmpipe: only Reinhard with a gamma curve and exposure 0");
  if (scene.lights.size() > kMaxLights) throw std::invalid_argument("llvmpipe: at most 8 lights");
  Impl& m = *impl_;
  const glm::mat4 vp =
      scene.camera.projection(static_cast<float>(m.width) / static_cast<float>(m.height)) * scene.camera.view();
  for (const Impl::Program& pr : m.programs) {
    const GLuint p = pr.id;
    glUseProgram(p);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_view_projection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform3fv(glGetUniformLocation(p, "u_eye"), 1, glm::value_ptr(scene.camera.position));
    glUniform3fv(glGetUniformLocation(p, "u_ambient"), 1, glm::value_ptr(scene.ambient));
    glUniform1f(glGetUniformLocation(p, "u_inv_gamma"), 1.0f / output.gamma);
    glUniform1i(glGetUniformLocation(p, "u_light_count"), static_cast<GLint>(scene.lights.size()));
    for (std::size_t i = 0; i < scene.lights.size(); ++i) {
      const pbr::Light& l = scene.lights[i];
      if (l.type != pbr::LightType::Point || l.range != 0.0f)
        throw std::invalid_argument("llvmpipe: point lights without range only");
      const glm::vec3 radiance = l.color * l.intensity;
      // Appended piece by piece: GCC 12 misreads "[" + std::to_string(i) (-Wrestrict).
      std::string idx = "[";
      idx += std::to_string(i);
      idx += "]";
      glUniform3fv(glGetUniformLocation(p, ("u_light_position" + idx).c_str()), 1, glm::value_ptr(l.position));
      glUniform3fv(glGetUniformLocation(p, ("u_light_radiance" + idx).c_str()), 1, glm::value_ptr(radiance));
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
    Impl::Draw d{&g, &m.programs[textured], 0, 0, o.transform, glm::transpose(glm::inverse(glm::mat3(o.transform))),
                 pbr::prepare_material(o.material)};
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
  if (m.fbo) glBindFramebuffer(GL_FRAMEBUFFER, m.fbo);
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
    if (d.texture != 0) {
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, d.texture);
      glBindSampler(0, d.sampler);
    }
    glBindVertexArray(d.mesh->vao);
    glDrawElements(GL_TRIANGLES, d.mesh->count, GL_UNSIGNED_INT, nullptr);
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
