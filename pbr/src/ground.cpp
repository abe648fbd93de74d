// The shadow catcher under a scene's objects (see ground.h). Its opacity is built from the
// casters' depths with IEEE basic operations in a fixed order, row by row (a row is one
// thread's), so it is the same bits for any thread count, tile size and machine.
#include "ground.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "softpbr/image/image.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/shadow.h"
#include "shadows.h"

namespace softpbr::pbr::detail {

namespace {

constexpr std::size_t kSide = static_cast<std::size_t>(kGroundSize);

// Three box blurs of radius r along each row of the kSide × kSide `values` (zero beyond
// the square's edges), rows in parallel; a running sum in double over each row.
void blur_rows(std::vector<float>& values, int r, raster::ThreadPool& pool) {
  if (r <= 0) return;
  const double scale = 1.0 / static_cast<double>(2 * r + 1);
  const auto radius = static_cast<std::ptrdiff_t>(r);
  const auto n = static_cast<std::ptrdiff_t>(kSide);
  pool.parallel_for(kSide, [&](std::size_t row) {
    float* line = values.data() + row * kSide;
    std::vector<float> in(line, line + kSide);
    for (int pass = 0; pass < 3; ++pass) {
      double sum = 0.0;
      for (std::ptrdiff_t i = 0; i < std::min(radius, n); ++i) sum += static_cast<double>(in[static_cast<std::size_t>(i)]);
      for (std::ptrdiff_t i = 0; i < n; ++i) {
        if (i + radius < n) sum += static_cast<double>(in[static_cast<std::size_t>(i + radius)]);
        if (i - radius - 1 >= 0) sum -= static_cast<double>(in[static_cast<std::size_t>(i - radius - 1)]);
        // The running sum may round below zero where the row is empty again.
        line[static_cast<std::size_t>(i)] = static_cast<float>(std::max(sum * scale, 0.0));
      }
      std::copy(line, line + kSide, in.begin());
    }
  });
}

void transpose(std::vector<float>& values) {
  for (std::size_t y = 0; y < kSide; ++y)
    for (std::size_t x = y + 1; x < kSide; ++x) std::swap(values[y * kSide + x], values[x * kSide + y]);
}

// Both ways: rows, then columns (as rows of the transposed square).
void blur(std::vector<float>& values, int r, raster::ThreadPool& pool) {
  blur_rows(values, r, pool);
  transpose(values);
  blur_rows(values, r, pool);
  transpose(values);
}

int texels(double world, double texel) {
  const double t = std::ceil(world / texel);
  return static_cast<int>(std::clamp(t, 1.0, static_cast<double>(kGroundSize) / 8.0));
}

}  // namespace

bool ground_setup(const Bounds& world, const Ground& ground, const std::vector<GroundLight>& lights, GroundSetup& out) {
  if (world.empty()) return false;
  const glm::dvec3 lo(world.min), hi(world.max);
  const double width = std::max(hi.x - lo.x, hi.z - lo.z), height = hi.y - lo.y;
  if (!(width > 0.0) || !std::isfinite(width) || !std::isfinite(height)) return false;
  // The footprint, grown by the corners' shadows on the plane y = lo.y (within two widths
  // of its centre).
  const double cx = 0.5 * (lo.x + hi.x), cz = 0.5 * (lo.z + hi.z), cap = 2.0 * width;
  double x0 = lo.x, x1 = hi.x, z0 = lo.z, z1 = hi.z;
  for (const GroundLight& l : lights)
    for (int i = 0; i < 8; ++i) {
      const glm::dvec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
      glm::dvec3 p;
      if (l.directional) {
        const glm::dvec3 d(l.to_light);
        if (!(d.y > 0.0)) continue;
        p = c - d * ((c.y - lo.y) / d.y);
      } else {
        const glm::dvec3 q(l.position);
        if (!(q.y > c.y)) continue;  // the light is not above the corner: no shadow of it below
        p = q + (c - q) * ((q.y - lo.y) / (q.y - c.y));
      }
      if (!std::isfinite(p.x) || !std::isfinite(p.z)) continue;
      x0 = std::min(x0, std::max(p.x, cx - cap)), x1 = std::max(x1, std::min(p.x, cx + cap));
      z0 = std::min(z0, std::max(p.z, cz - cap)), z1 = std::max(z1, std::min(p.z, cz + cap));
    }
  const double footprint = std::max(x1 - x0, z1 - z0);
  // The contact shadow fades over the objects' height, at most their width (a tall thin
  // object's shadow is that of its foot), at least a twentieth of the width (a flat one).
  const double reach = std::clamp(height, 0.05 * width, width);
  // The blur of what is at `reach` spreads over softness · ½ width (three boxes: 3 radii);
  // the square holds the footprint and that spread on each side, and a few texels.
  const double softness = std::clamp(static_cast<double>(ground.softness), 0.0, 1.0);
  const double spread = 0.5 * width * softness;
  const double side = (footprint + 2.0 * spread) * static_cast<double>(kGroundSize) / static_cast<double>(kGroundSize - 8);
  const double texel = side / static_cast<double>(kGroundSize);
  out.y = static_cast<float>(lo.y);
  out.x0 = static_cast<float>(0.5 * (x0 + x1) - 0.5 * side);
  out.z0 = static_cast<float>(0.5 * (z0 + z1) - 0.5 * side);
  out.side = static_cast<float>(side);
  out.reach = static_cast<float>(reach);
  out.blur_far = texels(spread / 3.0, texel);
  out.blur_near = texels(0.01 * width, texel);
  // Clip x = 2 (x − x0) / side − 1, clip y = 1 − 2 (z − z0) / side (row 0 at z0), clip z =
  // 2 (y' − y) / reach − 1, w = 1.
  const auto sx = static_cast<double>(out.x0), sz = static_cast<double>(out.z0), y0 = static_cast<double>(out.y);
  const auto s = static_cast<double>(out.side), h = static_cast<double>(out.reach);
  glm::mat4 m(0.0f);
  m[0][0] = static_cast<float>(2.0 / s);
  m[3][0] = static_cast<float>(-2.0 * sx / s - 1.0);
  m[2][1] = static_cast<float>(-2.0 / s);
  m[3][1] = static_cast<float>(1.0 + 2.0 * sz / s);
  m[1][2] = static_cast<float>(2.0 / h);
  m[3][2] = static_cast<float>(-2.0 * y0 / h - 1.0);
  m[3][3] = 1.0f;
  out.view_projection = m;
  return true;
}

bool dominant_light(const PreparedEnvironment& e, DominantLight& out) {
  if (e.irradiance == nullptr || !(e.intensity > 0.0f)) return false;
  // The interior texels of the octahedral irradiance map (a one-texel border around them).
  const int n = kIrradianceSize;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  int best_x = 0, best_y = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const glm::vec4 c = e.irradiance->texel(0, x + 1, y + 1);
      const double l = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
      if (!std::isfinite(l)) return false;
      if (l > hi) hi = l, best_x = x, best_y = y;
      lo = std::min(lo, l);
    }
  if (!(hi > 0.0)) return false;
  const glm::dvec3 d = octahedral_decode(
      glm::dvec2((static_cast<double>(best_x) + 0.5) / n, (static_cast<double>(best_y) + 0.5) / n));
  // The environment's frame → world (to_environment's inverse rotation).
  const double c = e.cos_r, s = e.sin_r;
  const glm::dvec3 w(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
  if (!(w.y > 0.05)) return false;  // at or below the horizon: it throws no shadow on the ground
  out.to_light = glm::vec3(w);
  out.strength = static_cast<float>((hi - std::max(lo, 0.0)) / (hi + std::max(lo, 0.0)));
  return out.strength > 0.0f;
}

std::shared_ptr<const raster::Texture> ground_texture(const GroundSetup& setup, const Ground& ground,
                                                      std::span<const float> depths,
                                                      const std::vector<PreparedLight>& lights, const ShadowMap* sky,
                                                      const DominantLight& dominant, raster::ThreadPool& pool) {
  const float darkness = std::clamp(ground.darkness, 0.0f, 1.0f);
  // The contact shadow: opacity darkness · (1 − t) at height t · reach (three.js's contact
  // shadow's fade), split between what is near the ground (weight 1 − t, the near blur) and
  // what is high (t, the far blur).
  std::vector<float> near_part(kSide * kSide, 0.0f), far_part(kSide * kSide, 0.0f);
  pool.parallel_for(kSide, [&](std::size_t row) {
    for (std::size_t i = row * kSide; i < (row + 1) * kSide; ++i) {
      const float t = depths[i];
      if (!(t < 1.0f)) continue;  // nothing above this texel within reach
      const float u = 1.0f - std::max(t, 0.0f);
      const float o = darkness * u;
      near_part[i] = o * u;
      far_part[i] = o * (1.0f - u);
    }
  });
  blur(near_part, setup.blur_near, pool);
  blur(far_part, setup.blur_far, pool);
  const float texel = setup.side / static_cast<float>(kGroundSize);
  const auto centre = [&](std::size_t x, std::size_t row) {
    return simd::Vec3<float>(setup.x0 + (static_cast<float>(x) + 0.5f) * texel, setup.y,
                             setup.z0 + (static_cast<float>(row) + 0.5f) * texel);
  };
  const simd::Vec3<float> up(0.0f, 1.0f, 0.0f);

  // The environment's dominant light: its strength · darkness where its map says blocked.
  std::vector<float> sky_part;
  if (sky != nullptr) {
    sky_part.assign(kSide * kSide, 0.0f);
    const simd::Vec3<float> l(dominant.to_light.x, dominant.to_light.y, dominant.to_light.z);
    const float strength = darkness * std::clamp(dominant.strength, 0.0f, 1.0f);
    pool.parallel_for(kSide, [&](std::size_t row) {
      for (std::size_t x = 0; x < kSide; ++x)
        sky_part[row * kSide + x] =
            strength * (1.0f - shadow_visibility(*sky, centre(x, row), up, l, dominant.to_light.y));
    });
    blur(sky_part, setup.blur_near, pool);
  }

  // The lights: the share of their light on the ground (luminance · falloff · cos θ) that
  // their shadow maps block, at each texel's centre on the plane.
  bool any_map = false;
  for (const PreparedLight& l : lights) any_map = any_map || l.shadow != nullptr;
  image::PixelVector<std::uint8_t> rgba(kSide * kSide * 4, 0);
  pool.parallel_for(kSide, [&](std::size_t row) {
    for (std::size_t x = 0; x < kSide; ++x) {
      const std::size_t i = row * kSide + x;
      const float contact = std::min(near_part[i] + far_part[i], 1.0f);
      float blocked = 0.0f;
      if (any_map) {
        const simd::Vec3<float> p = centre(x, row);
        float total = 0.0f, shadowed = 0.0f;
        for (const PreparedLight& l : lights) {
          const LightSampleLanes<float> s = sample_light(l, p);
          const float cos_theta = s.to_light.y;
          if (!(cos_theta > 0.0f)) continue;
          const float w = (0.2126f * l.radiance.x + 0.7152f * l.radiance.y + 0.0722f * l.radiance.z) * s.falloff *
                          cos_theta;
          if (!(w > 0.0f)) continue;
          total += w;
          if (l.shadow != nullptr) shadowed += w * (1.0f - shadow_visibility(*l.shadow, p, up, s.to_light, cos_theta));
        }
        if (total > 0.0f) blocked = darkness * std::min(shadowed / total, 1.0f);
      }
      if (!sky_part.empty() && sky_part[i] > 0.0f) blocked = 1.0f - (1.0f - blocked) * (1.0f - sky_part[i]);
      // Where no light is blocked, the contact shadow exactly.
      const float opacity = blocked > 0.0f ? 1.0f - (1.0f - contact) * (1.0f - blocked) : contact;
      rgba[4 * i + 3] = static_cast<std::uint8_t>(std::clamp(opacity, 0.0f, 1.0f) * 255.0f + 0.5f);
    }
  });
  return std::make_shared<const raster::Texture>(image::Image8(kGroundSize, kGroundSize, std::move(rgba)),
                                                 raster::ColorSpace::Linear, raster::TextureOptions{}, &pool);
}

Object ground_object(const GroundSetup& setup, std::shared_ptr<const raster::Texture> texture) {
  auto mesh = std::make_shared<Mesh>();
  const float x0 = setup.x0, z0 = setup.z0, x1 = setup.x0 + setup.side, z1 = setup.z0 + setup.side;
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  // Texture row 0 at z0 (as the depths seen from below), column 0 at x0.
  mesh->vertices = {{{x0, setup.y, z0}, up, {0.0f, 0.0f}},
                    {{x0, setup.y, z1}, up, {0.0f, 1.0f}},
                    {{x1, setup.y, z1}, up, {1.0f, 1.0f}},
                    {{x1, setup.y, z0}, up, {1.0f, 0.0f}}};
  mesh->indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from above
  Object o;
  o.mesh = std::move(mesh);
  o.material.base_color = glm::vec3(0.0f);
  o.material.metallic = 0.0f;
  o.material.unlit = true;
  o.material.alpha_mode = AlphaMode::Blend;
  o.material.base_color_texture.texture = std::move(texture);
  o.material.base_color_texture.sampler.wrap_u = raster::Wrap::ClampToEdge;
  o.material.base_color_texture.sampler.wrap_v = raster::Wrap::ClampToEdge;
  o.cast_shadows = false;
  o.receive_shadows = false;
  return o;
}

std::uint64_t ground_bytes() {
  return raster::Target::depth_only_bytes(kGroundSize, kGroundSize) +
         static_cast<std::uint64_t>(raster::Texture::rgba8_chain_bytes(kGroundSize, kGroundSize)) +
         4 * kSide * kSide * sizeof(float) +
         static_cast<std::uint64_t>(kShadowMapSize) * static_cast<std::uint64_t>(kShadowMapSize) * sizeof(float);
}

}  // namespace softpbr::pbr::detail
