// The llvmpipe side of the comparison (see llvmpipe.h).
#include "llvmpipe.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/glext.h>

#include <map>
#include <stdexcept>

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "softpbr/pbr/shading.h"

namespace softpbr::bench {

namespace {

constexpr int kMaxLights = 8;

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;
out vec3 v_world;
out vec3 v_normal;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  gl_Position = u_view_projection * world;
}
)";

// pbr/shading.h's shade() with Reinhard and gamma; names as there.
const char* kFragmentShader = R"(#version 330 core
in vec3 v_world;
in vec3 v_normal;
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
vec3 brdf(vec3 n, vec3 l, vec3 v) {
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
  vec3 F = F_Schlick(u_f0, VoH);
  vec3 specular = F * ((a2 * NoL) / (4.0 * kPi * d * d * g_v * g_l * max(NoL, kMinNoV)));
  vec3 kD = max(vec3(1.0) - F, vec3(0.0)) * (1.0 - u_metallic);
  return kD * u_albedo * (1.0 / kPi) + specular;
}
void main() {
  vec3 v = normalize_or(u_eye - v_world, vec3(0.0, 0.0, 1.0));
  vec3 n = normalize_or(v_normal, v);
  vec3 lo = vec3(0.0);
  for (int i = 0; i < u_light_count; ++i) {
    vec3 d = u_light_position[i] - v_world;
    float dist2 = max(dot(d, d), 1e-8);
    float inv_dist = 1.0 / sqrt(dist2);
    vec3 l = d * inv_dist;
    float NoL = dot(n, l);
    if (NoL > 0.0) lo += brdf(n, l, v) * (u_light_radiance[i] * (inv_dist * inv_dist)) * NoL;
  }
  vec3 c = u_ambient * u_albedo * u_ao + lo + u_emissive;
  c = c / (vec3(1.0) + c);  // Reinhard
  o_color = vec4(pow(c, vec3(u_inv_gamma)), 1.0);
}
)";

GLuint compile(GLenum type, const char* source) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
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

}  // namespace

struct LlvmpipeRenderer::Impl {
  OSMesaContext context = nullptr;
  int width = 0, height = 0;
  GLuint program = 0;
  struct GpuMesh {
    GLuint vao = 0, vbo = 0, ebo = 0;
    GLsizei count = 0;
  };
  std::map<const pbr::Mesh*, GpuMesh> meshes;
  struct Draw {
    const GpuMesh* mesh;
    glm::mat4 model;
    glm::mat3 normal_matrix;
    pbr::ShadingMaterial material;
  };
  std::vector<Draw> draws;
  glm::vec4 clear{0, 0, 0, 1};
  GLint u_model = -1, u_normal_matrix = -1, u_albedo = -1, u_f0 = -1, u_metallic = -1, u_alpha = -1, u_k = -1,
        u_ao = -1, u_emissive = -1;
};

LlvmpipeRenderer::LlvmpipeRenderer(int width, int height) : impl_(std::make_unique<Impl>()) {
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
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader), fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  impl_->program = glCreateProgram();
  glAttachShader(impl_->program, vs);
  glAttachShader(impl_->program, fs);
  glLinkProgram(impl_->program);
  GLint ok = 0;
  glGetProgramiv(impl_->program, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("llvmpipe: GLSL link error");
  glUseProgram(impl_->program);
  const GLuint p = impl_->program;
  impl_->u_model = glGetUniformLocation(p, "u_model");
  impl_->u_normal_matrix = glGetUniformLocation(p, "u_normal_matrix");
  impl_->u_albedo = glGetUniformLocation(p, "u_albedo");
  impl_->u_f0 = glGetUniformLocation(p, "u_f0");
  impl_->u_metallic = glGetUniformLocation(p, "u_metallic");
  impl_->u_alpha = glGetUniformLocation(p, "u_alpha");
  impl_->u_k = glGetUniformLocation(p, "u_k");
  impl_->u_ao = glGetUniformLocation(p, "u_ao");
  impl_->u_emissive = glGetUniformLocation(p, "u_emissive");
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
  if (impl_->program) glDeleteProgram(impl_->program);
  if (impl_->context) OSMesaDestroyContext(impl_->context);
}

void LlvmpipeRenderer::load(const pbr::Scene& scene, const pbr::OutputSettings& output) {
  if (output.tone_map != pbr::ToneMap::Reinhard || output.exposure != 0.0f || !(output.gamma > 0.0f))
    throw std::invalid_argument("llvmpipe: only Reinhard with a gamma curve and exposure 0");
  if (scene.lights.size() > kMaxLights) throw std::invalid_argument("llvmpipe: at most 8 lights");
  Impl& m = *impl_;
  const GLuint p = m.program;
  const glm::mat4 vp =
      scene.camera.projection(static_cast<float>(m.width) / static_cast<float>(m.height)) * scene.camera.view();
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
    const std::string idx = "[" + std::to_string(i) + "]";
    glUniform3fv(glGetUniformLocation(p, ("u_light_position" + idx).c_str()), 1, glm::value_ptr(l.position));
    glUniform3fv(glGetUniformLocation(p, ("u_light_radiance" + idx).c_str()), 1, glm::value_ptr(radiance));
  }
  m.clear = scene.background;
  m.draws.clear();
  for (const pbr::Object& o : scene.objects) {
    auto [it, fresh] = m.meshes.try_emplace(o.mesh.get());
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
      g.count = static_cast<GLsizei>(o.mesh->indices.size());
    }
    m.draws.push_back({&g, o.transform, glm::transpose(glm::inverse(glm::mat3(o.transform))),
                       pbr::prepare_material(o.material)});
  }
  if (glGetError() != GL_NO_ERROR) throw std::runtime_error("llvmpipe: GL error while loading the scene");
}

void LlvmpipeRenderer::render() {
  Impl& m = *impl_;
  glClearColor(m.clear.r, m.clear.g, m.clear.b, m.clear.a);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  for (const Impl::Draw& d : m.draws) {
    glUniformMatrix4fv(m.u_model, 1, GL_FALSE, glm::value_ptr(d.model));
    glUniformMatrix3fv(m.u_normal_matrix, 1, GL_FALSE, glm::value_ptr(d.normal_matrix));
    glUniform3fv(m.u_albedo, 1, glm::value_ptr(d.material.albedo));
    glUniform3fv(m.u_f0, 1, glm::value_ptr(d.material.f0));
    glUniform1f(m.u_metallic, d.material.metallic);
    glUniform1f(m.u_alpha, d.material.alpha);
    glUniform1f(m.u_k, d.material.k);
    glUniform1f(m.u_ao, d.material.ao);
    glUniform3fv(m.u_emissive, 1, glm::value_ptr(d.material.emissive));
    glBindVertexArray(d.mesh->vao);
    glDrawElements(GL_TRIANGLES, d.mesh->count, GL_UNSIGNED_INT, nullptr);
  }
  glFinish();
}

std::string LlvmpipeRenderer::renderer_name() const {
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return s ? s : "?";
}

}  // namespace softpbr::bench
