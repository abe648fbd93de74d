// Where a light's shadow map looks from (see shadows.h). The matrices are built in double
// from the light and the bounds (dmath for the cone's tangent) and rounded once to float:
// the same bits everywhere.
#include "shadows.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/vec3.hpp>

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr::detail {

namespace {

using D3 = glm::dvec3;

D3 to_d(const glm::vec3& v) { return {v.x, v.y, v.z}; }

// The eight corners of the bounds.
std::array<D3, 8> corners(const Bounds& b) {
  std::array<D3, 8> c;
  for (int i = 0; i < 8; ++i)
    c[static_cast<std::size_t>(i)] = D3((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y, (i & 4) ? b.max.z : b.min.z);
  return c;
}

// A camera's axes looking along unit f, as glm::lookAt builds them: u = f × up / |…|,
// v = u × f (so u × v = −f).
void look_axes(const D3& f, D3& u, D3& v) {
  const D3 up = std::abs(f.y) < 0.99 ? D3(0.0, 1.0, 0.0) : D3(1.0, 0.0, 0.0);
  const D3 c(f.y * up.z - f.z * up.y, f.z * up.x - f.x * up.z, f.x * up.y - f.y * up.x);
  u = c / std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
  v = D3(u.y * f.z - u.z * f.y, u.z * f.x - u.x * f.z, u.x * f.y - u.y * f.x);
}

double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Row k of the matrix: (axis · s, offset).
void set_row(double (&m)[4][4], int k, const D3& axis, double offset) {
  m[k][0] = axis.x;
  m[k][1] = axis.y;
  m[k][2] = axis.z;
  m[k][3] = offset;
}

// The matrix rows rounded to float, as glm's column-major matrix and as the map's rows.
glm::mat4 to_matrix(const double (&m)[4][4], float (*rows)[4]) {
  glm::mat4 out(0.0f);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const auto v = static_cast<float>(m[r][c]);
      out[c][r] = v;
      if (rows != nullptr) rows[r][c] = v;
    }
  return out;
}

// The scale that keeps kShadowBorder texels around a region of `size` texels.
double border_scale(int size) { return static_cast<double>(size) / static_cast<double>(size - 2 * kShadowBorder); }

// A perspective face's depth terms: clip z = a · d + b for view depth d, so that window
// depth is 0 at `near` and 1 at `far`.
void depth_terms(double near, double far, double& a, double& b) {
  a = (far + near) / (far - near);
  b = -2.0 * far * near / (far - near);
}

bool cube_setup(const D3& position, const Bounds& world, ShadowSetup& out) {
  double far = 0.0;
  for (const D3& q : corners(world)) {
    const D3 d = q - position;
    far = std::max({far, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  }
  if (!(far > 0.0) || !std::isfinite(far)) return false;
  far *= 1.01;
  const double near = far * kShadowNearFraction;
  double a, b;
  depth_terms(near, far, a, b);
  const int size = kShadowCubeSize;
  const double scale = border_scale(size);  // tan 45° = 1, widened by the border
  ShadowMap& m = out.map;
  m.kind = ShadowMap::Kind::Cube;
  m.size = size;
  m.position = glm::vec3(position);
  m.scale = static_cast<float>(scale);
  m.a = static_cast<float>(a);
  m.b = static_cast<float>(b);
  m.texel = static_cast<float>(2.0 * scale / size);
  out.view_projection.clear();
  for (const CubeFaceAxes& face : kCubeFaces) {
    D3 major(0.0), u(0.0), v(0.0);
    major[face.major_axis] = face.major_sign;
    u[face.u_axis] = face.u_sign;
    v[face.v_axis] = face.v_sign;
    double rows[4][4];
    set_row(rows, 0, u / scale, -dot(u, position) / scale);
    set_row(rows, 1, v / scale, -dot(v, position) / scale);
    set_row(rows, 2, major * a, -a * dot(major, position) + b);
    set_row(rows, 3, major, -dot(major, position));
    out.view_projection.push_back(to_matrix(rows, nullptr));
  }
  return true;
}

}  // namespace

bool shadow_setup(const PreparedLight& light, const Bounds& world, ShadowSetup& out) {
  if (world.empty()) return false;
  const Light& l = light.light;
  const D3 f = to_d(light.unit_direction);
  const std::array<D3, 8> box = corners(world);
  if (l.type == LightType::Point || (l.type == LightType::Spot && l.outer_cone > kSpotMaxCone))
    return cube_setup(to_d(l.position), world, out);
  D3 u, v;
  look_axes(f, u, v);
  const int size = kShadowMapSize;
  const double border = border_scale(size);
  ShadowMap& m = out.map;
  m.size = size;
  double rows[4][4];
  if (l.type == LightType::Directional) {
    // The bounds' corners across the light (u, v) and along it (s): a square around their
    // extent, the depth range with a margin.
    constexpr double inf = std::numeric_limits<double>::infinity();
    double u0 = inf, u1 = -inf, v0 = inf, v1 = -inf, s0 = inf, s1 = -inf;
    for (const D3& q : box) {
      u0 = std::min(u0, dot(u, q)), u1 = std::max(u1, dot(u, q));
      v0 = std::min(v0, dot(v, q)), v1 = std::max(v1, dot(v, q));
      s0 = std::min(s0, dot(f, q)), s1 = std::max(s1, dot(f, q));
    }
    const double extent = std::max({u1 - u0, v1 - v0, s1 - s0, 1e-6});
    const double half = 0.5 * std::max(u1 - u0, v1 - v0) * border + 1e-6 * extent;
    const double cu = 0.5 * (u0 + u1), cv = 0.5 * (v0 + v1);
    const double margin = 0.01 * extent;
    s0 -= margin, s1 += margin;
    m.kind = ShadowMap::Kind::Orthographic;
    set_row(rows, 0, u / half, -cu / half);
    set_row(rows, 1, v / half, -cv / half);
    set_row(rows, 2, f * (2.0 / (s1 - s0)), -(s0 + s1) / (s1 - s0));
    set_row(rows, 3, D3(0.0), 1.0);
    m.texel = static_cast<float>(2.0 * half / size);
  } else {
    // A spot light: a perspective face along its axis over its outer cone, as far as the
    // farthest corner of the bounds.
    const D3 p = to_d(l.position);
    double far = 0.0;
    for (const D3& q : box) far = std::max(far, dot(f, q - p));
    if (!(far > 0.0) || !std::isfinite(far)) return false;
    far *= 1.01;
    const double near = far * kShadowNearFraction;
    double a, b;
    depth_terms(near, far, a, b);
    const double t = dmath::tan(static_cast<double>(l.outer_cone)) * border;
    m.kind = ShadowMap::Kind::Perspective;
    set_row(rows, 0, u / t, -dot(u, p) / t);
    set_row(rows, 1, v / t, -dot(v, p) / t);
    set_row(rows, 2, f * a, -a * dot(f, p) + b);
    set_row(rows, 3, f, -dot(f, p));
    m.texel = static_cast<float>(2.0 * t / size);
  }
  out.view_projection.assign(1, to_matrix(rows, m.rows));
  return true;
}

std::uint64_t shadow_map_bytes(const Light& light) {
  if (!light.shadows) return 0;
  const bool cube = light.type == LightType::Point || (light.type == LightType::Spot && light.outer_cone > kSpotMaxCone);
  const auto side = static_cast<std::uint64_t>(cube ? kShadowCubeSize : kShadowMapSize);
  return (cube ? 6u : 1u) * side * side * sizeof(float);
}

}  // namespace softpbr::pbr::detail
