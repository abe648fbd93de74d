// Image-based lighting: prefiltering an environment (see environment.h and
// docs/design.md, "Image-based lighting").
#include "softpbr/pbr/environment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <list>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"

namespace softpbr::pbr {

namespace {

constexpr double kPi = dmath::kPi;
constexpr double kLn2 = 0.693147180559945309417232121458176568;

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw std::invalid_argument(name + ": " + what);
}

bool is_pow2(int n) { return n > 0 && (n & (n - 1)) == 0; }

// Runs fn(i) for i in [0, count) on the pool, or in order without one. Each i writes its
// own outputs, so the result does not depend on the split.
template <class Fn>
void for_each_index(raster::ThreadPool* pool, std::size_t count, Fn&& fn) {
  if (pool != nullptr && pool->size() > 1 && count > 1) pool->parallel_for(count, fn);
  else
    for (std::size_t i = 0; i < count; ++i) fn(i);
}

// An octahedral map of side `size` with a one-texel border: (size + 2)² RGB texels in
// double while it is built.
struct OctMap {
  int size = 0;
  std::vector<glm::dvec3> texels;  // (size + 2)², row-major, border included

  explicit OctMap(int s) : size(s), texels(static_cast<std::size_t>(s + 2) * static_cast<std::size_t>(s + 2)) {}
  int full() const { return size + 2; }
  glm::dvec3& at(int px, int py) { return texels[static_cast<std::size_t>(py) * static_cast<std::size_t>(full()) + static_cast<std::size_t>(px)]; }
  const glm::dvec3& at(int px, int py) const {
    return texels[static_cast<std::size_t>(py) * static_cast<std::size_t>(full()) + static_cast<std::size_t>(px)];
  }
  // Interior texel (x, y), x, y in [0, size).
  glm::dvec3& interior(int x, int y) { return at(x + 1, y + 1); }
  const glm::dvec3& interior(int x, int y) const { return at(x + 1, y + 1); }

  // The border continues the sphere across the square's edges: the map folds along each
  // edge's midpoint ((1 + e, v) is (1 − e, −v) in [−1, 1]²), and the corners (all −Y) take
  // the opposite corner.
  void fill_border() {
    const int s = size;
    for (int i = 0; i < s; ++i) {
      at(0, i + 1) = interior(0, s - 1 - i);          // left column
      at(s + 1, i + 1) = interior(s - 1, s - 1 - i);  // right column
      at(i + 1, 0) = interior(s - 1 - i, 0);          // top row
      at(i + 1, s + 1) = interior(s - 1 - i, s - 1);  // bottom row
    }
    at(0, 0) = interior(s - 1, s - 1);
    at(s + 1, 0) = interior(0, s - 1);
    at(0, s + 1) = interior(s - 1, 0);
    at(s + 1, s + 1) = interior(0, 0);
  }

  // Bilinear lookup at octahedral coordinates uv in [0, 1]².
  glm::dvec3 bilinear(const glm::dvec2& uv) const {
    const double cx = uv.x * size + 0.5, cy = uv.y * size + 0.5;
    int x0 = static_cast<int>(std::floor(cx)), y0 = static_cast<int>(std::floor(cy));
    x0 = std::clamp(x0, 0, size);
    y0 = std::clamp(y0, 0, size);
    const double fx = std::clamp(cx - x0, 0.0, 1.0), fy = std::clamp(cy - y0, 0.0, 1.0);
    const glm::dvec3 top = at(x0, y0) * (1.0 - fx) + at(x0 + 1, y0) * fx;
    const glm::dvec3 bottom = at(x0, y0 + 1) * (1.0 - fx) + at(x0 + 1, y0 + 1) * fx;
    return top * (1.0 - fy) + bottom * fy;
  }

  // The next mip: 2×2 box of the interior.
  OctMap half() const {
    OctMap m(std::max(1, size / 2));
    if (size == 1) {
      m.interior(0, 0) = interior(0, 0);
    } else {
      for (int y = 0; y < m.size; ++y)
        for (int x = 0; x < m.size; ++x)
          m.interior(x, y) = ((interior(2 * x, 2 * y) + interior(2 * x + 1, 2 * y)) +
                              (interior(2 * x, 2 * y + 1) + interior(2 * x + 1, 2 * y + 1))) *
                             0.25;
    }
    m.fill_border();
    return m;
  }

  std::shared_ptr<const raster::Texture> texture() const {
    std::vector<float> rgba(texels.size() * 4);
    for (std::size_t i = 0; i < texels.size(); ++i) {
      rgba[4 * i + 0] = static_cast<float>(texels[i].x);
      rgba[4 * i + 1] = static_cast<float>(texels[i].y);
      rgba[4 * i + 2] = static_cast<float>(texels[i].z);
      rgba[4 * i + 3] = 1.0f;
    }
    return std::make_shared<const raster::Texture>(image::ImageViewF(full(), full(), rgba),
                                                   raster::TextureOptions{.mipmaps = false});
  }
};

// The equirectangular image as doubles, with bilinear lookups (u wraps, v clamps).
struct Equirect {
  int width, height;
  const float* rgba;

  glm::dvec3 texel(int x, int y) const {
    x = ((x % width) + width) % width;
    y = std::clamp(y, 0, height - 1);
    const float* p = rgba + (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4;
    return {p[0], p[1], p[2]};
  }
  glm::dvec3 bilinear(const glm::dvec2& uv) const {
    const double cx = uv.x * width - 0.5, cy = uv.y * height - 0.5;
    const double fx0 = std::floor(cx), fy0 = std::floor(cy);
    const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
    const double fx = cx - fx0, fy = cy - fy0;
    const glm::dvec3 top = texel(x0, y0) * (1.0 - fx) + texel(x0 + 1, y0) * fx;
    const glm::dvec3 bottom = texel(x0, y0 + 1) * (1.0 - fx) + texel(x0 + 1, y0 + 1) * fx;
    return top * (1.0 - fy) + bottom * fy;
  }
};

// Level 0: the octahedral resampling of the equirectangular image, 2×2 samples a texel
// (the image's texels are about as large as the map's, and a small sun must keep its energy).
OctMap resample(const Equirect& src, int size, raster::ThreadPool* pool) {
  OctMap m(size);
  constexpr int kSub = 2;
  for_each_index(pool, static_cast<std::size_t>(size), [&](std::size_t row) {
    const int y = static_cast<int>(row);
    for (int x = 0; x < size; ++x) {
      glm::dvec3 sum(0.0);
      for (int sy = 0; sy < kSub; ++sy)
        for (int sx = 0; sx < kSub; ++sx) {
          const glm::dvec2 uv((x + (sx + 0.5) / kSub) / size, (y + (sy + 0.5) / kSub) / size);
          sum += src.bilinear(equirect_uv(octahedral_decode(uv)));
        }
      m.interior(x, y) = sum * (1.0 / (kSub * kSub));
    }
  });
  m.fill_border();
  return m;
}

// The radical inverse of i in base 2 (van der Corput), the Hammersley set's second coordinate.
double radical_inverse(std::uint32_t i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x55555555u) << 1) | ((i & 0xAAAAAAAAu) >> 1);
  i = ((i & 0x33333333u) << 2) | ((i & 0xCCCCCCCCu) >> 2);
  i = ((i & 0x0F0F0F0Fu) << 4) | ((i & 0xF0F0F0F0u) >> 4);
  i = ((i & 0x00FF00FFu) << 8) | ((i & 0xFF00FF00u) >> 8);
  return static_cast<double>(i) * (1.0 / 4294967296.0);
}

// A GGX-distributed half vector in the frame where n = +Z: cos θ and the unit H.
glm::dvec3 ggx_half_vector(std::uint32_t j, std::uint32_t count, double a2) {
  const double xi1 = static_cast<double>(j) / count, xi2 = radical_inverse(j);
  const double cos_theta = std::sqrt((1.0 - xi1) / (1.0 + (a2 - 1.0) * xi1));
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * kPi * xi2;
  return {sin_theta * dmath::cos(phi), sin_theta * dmath::sin(phi), cos_theta};
}

// An orthonormal frame (t, b, n) for unit n without branches on n's direction (Duff et al.
// 2017, "Building an orthonormal basis, revisited").
void frame(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
  const double sign = n.z < 0.0 ? -1.0 : 1.0;
  const double a = -1.0 / (sign + n.z);
  const double c = n.x * n.y * a;
  t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

struct LobeSample {
  glm::dvec3 l;   // in the frame n = v = +Z
  double weight;  // n·l
  int lod0;       // the source mip below the filtered lod, and the blend to the next
  double frac;
};

// The GGX lobe of roughness `roughness` as `count` samples for filtered importance
// sampling of a source whose level 0 has side `source_size` (and `mips` levels).
std::vector<LobeSample> lobe(double roughness, std::uint32_t count, int source_size, int mips) {
  const double alpha = roughness * roughness, a2 = alpha * alpha;
  const double texel_solid_angle = 4.0 * kPi / (static_cast<double>(source_size) * source_size);
  std::vector<LobeSample> samples;
  samples.reserve(count);
  for (std::uint32_t j = 0; j < count; ++j) {
    const glm::dvec3 h = ggx_half_vector(j, count, a2);
    // l = reflect(−v, h) with v = n = +Z.
    const glm::dvec3 l(2.0 * h.z * h.x, 2.0 * h.z * h.y, 2.0 * h.z * h.z - 1.0);
    if (!(l.z > 0.0)) continue;
    // pdf(l) = D(h) (n·h) / (4 (v·h)) = D(h) / 4, with v = n.
    const double d = h.z * h.z * (a2 - 1.0) + 1.0;
    const double D = a2 / (kPi * d * d);
    const double pdf = D / 4.0;
    const double sample_solid_angle = 1.0 / (count * pdf);
    // Křivánek & Colbert: the mip whose texels cover the sample's solid angle, one level
    // coarser (their bias of 1) for a smooth result.
    double lod = 0.5 * (dmath::log(sample_solid_angle / texel_solid_angle) / kLn2) + 0.5;
    lod = std::clamp(lod, 0.0, static_cast<double>(mips - 1));
    const int lod0 = std::min(static_cast<int>(std::floor(lod)), mips - 1);
    samples.push_back({l, l.z, lod0, lod - lod0});
  }
  return samples;
}

// A level prefiltered from the source chain.
OctMap prefilter(const std::vector<OctMap>& source, int size, double roughness, std::uint32_t count,
                 raster::ThreadPool* pool) {
  const std::vector<LobeSample> samples = lobe(roughness, count, source[0].size, static_cast<int>(source.size()));
  OctMap m(size);
  for_each_index(pool, static_cast<std::size_t>(size), [&](std::size_t row) {
    const int y = static_cast<int>(row);
    for (int x = 0; x < size; ++x) {
      const glm::dvec3 n = octahedral_decode({(x + 0.5) / size, (y + 0.5) / size});
      glm::dvec3 t, b;
      frame(n, t, b);
      glm::dvec3 sum(0.0);
      double weight = 0.0;
      for (const LobeSample& s : samples) {
        const glm::dvec3 l = t * s.l.x + b * s.l.y + n * s.l.z;
        const glm::dvec2 uv = octahedral_encode(l);
        glm::dvec3 c = source[static_cast<std::size_t>(s.lod0)].bilinear(uv);
        if (s.frac > 0.0) c = c * (1.0 - s.frac) + source[static_cast<std::size_t>(s.lod0) + 1].bilinear(uv) * s.frac;
        sum += c * s.weight;
        weight += s.weight;
      }
      m.interior(x, y) = weight > 0.0 ? sum / weight : glm::dvec3(0.0);
    }
  });
  m.fill_border();
  return m;
}

// The irradiance coefficients by integration over the equirectangular texels, each with
// its exact solid angle (2π / W)(cos θ₀ − cos θ₁); rows summed in order.
std::array<glm::vec3, Environment::kShCount> project_irradiance(const Equirect& src, raster::ThreadPool* pool) {
  using Row = std::array<glm::dvec3, Environment::kShCount>;
  std::vector<Row> rows(static_cast<std::size_t>(src.height));
  std::vector<double> sin_phi(static_cast<std::size_t>(src.width)), cos_phi(static_cast<std::size_t>(src.width));
  for (int x = 0; x < src.width; ++x) {
    const double phi = 2.0 * kPi * ((x + 0.5) / src.width - 0.5);
    sin_phi[static_cast<std::size_t>(x)] = dmath::sin(phi);
    cos_phi[static_cast<std::size_t>(x)] = dmath::cos(phi);
  }
  for_each_index(pool, static_cast<std::size_t>(src.height), [&](std::size_t row) {
    const int y = static_cast<int>(row);
    const double theta = kPi * (y + 0.5) / src.height;
    const double solid_angle = (2.0 * kPi / src.width) *
                               (dmath::cos(kPi * y / src.height) - dmath::cos(kPi * (y + 1) / src.height));
    const double st = dmath::sin(theta), ct = dmath::cos(theta);
    Row acc{};
    for (int x = 0; x < src.width; ++x) {
      const glm::dvec3 d(st * sin_phi[static_cast<std::size_t>(x)], ct, -st * cos_phi[static_cast<std::size_t>(x)]);
      const std::array<double, Environment::kShCount> y_lm = sh_basis(d);
      const glm::dvec3 l = src.texel(x, y) * solid_angle;
      for (int i = 0; i < Environment::kShCount; ++i) acc[static_cast<std::size_t>(i)] += l * y_lm[static_cast<std::size_t>(i)];
    }
    rows[row] = acc;
  });
  Row total{};
  for (const Row& r : rows)
    for (int i = 0; i < Environment::kShCount; ++i) total[static_cast<std::size_t>(i)] += r[static_cast<std::size_t>(i)];
  // Convolution with the clamped cosine (Â₀ = π, Â₁ = 2π/3, Â₂ = π/4) over π, and each
  // basis function's constant, so that the shader evaluates the bare polynomials.
  const double k0 = 0.5 * std::sqrt(1.0 / kPi), k1 = std::sqrt(3.0 / (4.0 * kPi)), k2 = 0.5 * std::sqrt(15.0 / kPi);
  const double k20 = 0.25 * std::sqrt(5.0 / kPi), k22 = 0.25 * std::sqrt(15.0 / kPi);
  const double scale[Environment::kShCount] = {k0,
                                               k1 * 2.0 / 3.0,
                                               k1 * 2.0 / 3.0,
                                               k1 * 2.0 / 3.0,
                                               k2 * 0.25,
                                               k2 * 0.25,
                                               k20 * 0.25,
                                               k2 * 0.25,
                                               k22 * 0.25};
  std::array<glm::vec3, Environment::kShCount> c{};
  for (int i = 0; i < Environment::kShCount; ++i) c[static_cast<std::size_t>(i)] = glm::vec3(total[static_cast<std::size_t>(i)] * scale[i]);
  return c;
}

// Side of prefiltered level i: level 0 is the map; level 1 (roughness 0.2, a lobe about
// 10° across) a quarter of it, each next level half the last, at least 32 (a smaller map's
// bilinear diamonds show on rough spheres) and at most the map.
int level_side(int size, int i) { return i == 0 ? size : std::min(size, std::max(32, size >> (i + 1))); }

int default_size(int width, int height) {
  const double texels = static_cast<double>(width) * height;
  int s = 8;
  while (s < 1024 && static_cast<double>(s) * 2 * s * 2 <= texels) s *= 2;
  return s;
}

}  // namespace

void validate(const EnvironmentOptions& o) {
  if (o.size != 0 && (!is_pow2(o.size) || o.size < 8 || o.size > 2048))
    throw std::invalid_argument("environment size " + std::to_string(o.size) +
                                " is not 0 or a power of two in [8, 2048]");
  if (o.samples < 8 || o.samples > 4096)
    throw std::invalid_argument("environment samples " + std::to_string(o.samples) + " is outside [8, 4096]");
}

std::array<double, Environment::kShCount> sh_basis(const glm::dvec3& d) {
  const double k0 = 0.5 * std::sqrt(1.0 / kPi), k1 = std::sqrt(3.0 / (4.0 * kPi)), k2 = 0.5 * std::sqrt(15.0 / kPi);
  const double k20 = 0.25 * std::sqrt(5.0 / kPi), k22 = 0.25 * std::sqrt(15.0 / kPi);
  return {k0,
          k1 * d.y,
          k1 * d.z,
          k1 * d.x,
          k2 * d.x * d.y,
          k2 * d.y * d.z,
          k20 * (3.0 * d.z * d.z - 1.0),
          k2 * d.x * d.z,
          k22 * (d.x * d.x - d.y * d.y)};
}

glm::dvec2 octahedral_encode(const glm::dvec3& d) {
  const double l1 = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
  const double inv = 1.0 / (l1 > 0.0 ? l1 : 1.0);
  double px = d.x * inv, pz = d.z * inv;
  if (d.y < 0.0) {
    const double fx = (1.0 - std::fabs(pz)) * (px < 0.0 ? -1.0 : 1.0);
    const double fz = (1.0 - std::fabs(px)) * (pz < 0.0 ? -1.0 : 1.0);
    px = fx, pz = fz;
  }
  return {px * 0.5 + 0.5, pz * 0.5 + 0.5};
}

glm::dvec3 octahedral_decode(const glm::dvec2& uv) {
  double px = uv.x * 2.0 - 1.0, pz = uv.y * 2.0 - 1.0;
  const double y = 1.0 - std::fabs(px) - std::fabs(pz);
  if (y < 0.0) {
    const double fx = (1.0 - std::fabs(pz)) * (px < 0.0 ? -1.0 : 1.0);
    const double fz = (1.0 - std::fabs(px)) * (pz < 0.0 ? -1.0 : 1.0);
    px = fx, pz = fz;
  }
  const glm::dvec3 d(px, y, pz);
  return d / std::sqrt(glm::dot(d, d));
}

glm::dvec2 equirect_uv(const glm::dvec3& d) {
  const double u = 0.5 + dmath::atan2(d.x, -d.z) / (2.0 * kPi);
  const double v = dmath::atan2(std::sqrt(d.x * d.x + d.z * d.z), d.y) / kPi;
  return {u, v};
}

const raster::Sampler& Environment::level_sampler() {
  static const raster::Sampler s{raster::Wrap::ClampToEdge, raster::Wrap::ClampToEdge, raster::Filter::Linear,
                                 raster::Filter::Linear, raster::MipFilter::None};
  return s;
}

Environment::Environment(const image::ImageViewF& equirect, std::string name, const EnvironmentOptions& options,
                         raster::ThreadPool* pool)
    : name_(std::move(name)), options_(options) {
  try {
    validate(options);
  } catch (const std::invalid_argument& e) {
    fail(name_, e.what());
  }
  image::check_pixels(equirect, name_);
  if (equirect.width < 1 || equirect.height < 1) fail(name_, "the environment image is empty");
  for (std::size_t i = 0; i < equirect.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    const float v = equirect.rgba[i];
    if (!std::isfinite(v) || v < 0.0f) {
      const std::size_t p = i / 4;
      fail(name_, "pixel (" + std::to_string(p % static_cast<std::size_t>(equirect.width)) + ", " +
                      std::to_string(p / static_cast<std::size_t>(equirect.width)) +
                      ") is negative or not finite; an environment holds radiance");
    }
  }
  const Equirect src{equirect.width, equirect.height, equirect.rgba.data()};
  size_ = options.size != 0 ? options.size : default_size(equirect.width, equirect.height);
  sh_ = project_irradiance(src, pool);

  std::vector<OctMap> chain;
  chain.push_back(resample(src, size_, pool));
  while (chain.back().size > 1) chain.push_back(chain.back().half());

  levels_.push_back(chain[0].texture());
  for (int i = 1; i < kLevels; ++i) {
    const int s = level_side(size_, i);
    // Rougher lobes spread wider: twice the samples each level, up to 8× the first.
    const auto count = static_cast<std::uint32_t>(options.samples) << std::min(i - 1, 3);
    levels_.push_back(prefilter(chain, s, static_cast<double>(i) / (kLevels - 1), count, pool).texture());
  }
}

std::size_t Environment::bytes() const {
  std::size_t n = 0;
  for (const auto& l : levels_) n += l->texel_bytes();
  return n;
}

// --- The studio. ---

image::ImageF Environment::studio_image(int width, int height) {
  image::ImageF im;
  im.width = width;
  im.height = height;
  im.rgba.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
  // Softboxes: centre (azimuth from −Z toward +X, elevation), half sizes (degrees), radiance.
  struct Box {
    double azimuth, elevation, half_w, half_h, radiance;
  };
  const Box boxes[] = {
      {-135.0, 35.0, 22.0, 14.0, 16.0},  // key: front left, above
      {125.0, 20.0, 18.0, 12.0, 5.0},    // fill: front right
      {20.0, 40.0, 30.0, 8.0, 10.0},     // rim: behind, high
      {0.0, 90.0, 360.0, 14.0, 3.0},     // top: a wide panel around the zenith
  };
  auto smooth = [](double e0, double e1, double x) {
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
  };
  for (int y = 0; y < height; ++y) {
    const double elevation = 90.0 - 180.0 * (y + 0.5) / height;  // degrees
    // The walls: dim grey, brighter toward the ceiling; a darker floor; a soft horizon.
    const double up = smooth(-6.0, 6.0, elevation);
    const double wall = 0.12 + 0.18 * smooth(0.0, 90.0, elevation);
    const double floor_radiance = 0.05;
    const double base = floor_radiance + (wall - floor_radiance) * up;
    for (int x = 0; x < width; ++x) {
      const double azimuth = 360.0 * ((x + 0.5) / width - 0.5);
      double l = base;
      for (const Box& b : boxes) {
        double da = std::fabs(azimuth - b.azimuth);
        if (da > 180.0) da = 360.0 - da;
        const double de = std::fabs(elevation - b.elevation);
        const double wx = 1.0 - smooth(b.half_w - 3.0, b.half_w + 3.0, da);
        const double wy = 1.0 - smooth(b.half_h - 3.0, b.half_h + 3.0, de);
        l += b.radiance * wx * wy;
      }
      float* p = &im.rgba[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4];
      // A slightly warm white.
      p[0] = static_cast<float>(l * 1.0);
      p[1] = static_cast<float>(l * 0.98);
      p[2] = static_cast<float>(l * 0.95);
      p[3] = 1.0f;
    }
  }
  return im;
}

std::shared_ptr<const Environment> Environment::studio(raster::ThreadPool* pool) {
  static const std::shared_ptr<const Environment> s = [pool] {
    const image::ImageF im = studio_image();
    return std::make_shared<const Environment>(image::ImageViewF(im), "studio (built in)", EnvironmentOptions{}, pool);
  }();
  return s;
}

// --- Serialization. ---

namespace {
constexpr char kMagic[8] = {'S', 'P', 'E', 'N', 'V', '0', '0', '1'};

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_f32(std::vector<std::uint8_t>& out, float f) {
  std::uint32_t v;
  std::memcpy(&v, &f, 4);
  put_u32(out, v);
}
struct Reader {
  std::span<const std::uint8_t> bytes;
  std::size_t at = 0;
  const std::string& name;
  std::uint32_t u32() {
    if (bytes.size() - at < 4) fail(name, "the environment cache file is truncated");
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(bytes[at + static_cast<std::size_t>(i)]) << (8 * i);
    at += 4;
    return v;
  }
  float f32() {
    const std::uint32_t v = u32();
    float f;
    std::memcpy(&f, &v, 4);
    return f;
  }
};
}  // namespace

std::vector<std::uint8_t> Environment::to_bytes() const {
  std::vector<std::uint8_t> out(kMagic, kMagic + 8);
  put_u32(out, static_cast<std::uint32_t>(options_.size));
  put_u32(out, static_cast<std::uint32_t>(options_.samples));
  put_u32(out, static_cast<std::uint32_t>(size_));
  for (const glm::vec3& c : sh_) put_f32(out, c.x), put_f32(out, c.y), put_f32(out, c.z);
  put_u32(out, static_cast<std::uint32_t>(levels_.size()));
  for (const auto& l : levels_) {
    put_u32(out, static_cast<std::uint32_t>(l->width()));
    for (float f : l->texels_f()) put_f32(out, f);
  }
  return out;
}

std::shared_ptr<const Environment> Environment::from_bytes(std::span<const std::uint8_t> bytes, std::string name) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0)
    fail(name, "not an environment cache file of this version");
  Reader r{bytes, 8, name};
  auto env = std::shared_ptr<Environment>(new Environment());
  env->name_ = std::move(name);
  env->options_.size = static_cast<int>(r.u32());
  env->options_.samples = static_cast<int>(r.u32());
  try {
    validate(env->options_);
  } catch (const std::invalid_argument& e) {
    fail(env->name_, e.what());
  }
  env->size_ = static_cast<int>(r.u32());
  if (!is_pow2(env->size_) || env->size_ < 8 || env->size_ > 2048) fail(env->name_, "bad map size in the cache file");
  for (glm::vec3& c : env->sh_) {
    c.x = r.f32();
    c.y = r.f32();
    c.z = r.f32();
  }
  if (r.u32() != kLevels) fail(env->name_, "bad level count in the cache file");
  for (int i = 0; i < kLevels; ++i) {
    const std::uint32_t full = r.u32();
    const std::uint32_t expect = static_cast<std::uint32_t>(level_side(env->size_, i) + 2);
    if (full != expect) fail(env->name_, "bad level size in the cache file");
    const std::size_t n = static_cast<std::size_t>(full) * full * 4;
    if ((bytes.size() - r.at) / 4 < n) fail(env->name_, "the environment cache file is truncated");
    std::vector<float> rgba(n);
    for (float& f : rgba) f = r.f32();
    env->levels_.push_back(std::make_shared<const raster::Texture>(
        image::ImageViewF(static_cast<int>(full), static_cast<int>(full), rgba), raster::TextureOptions{.mipmaps = false}));
  }
  if (r.at != bytes.size()) fail(env->name_, "trailing bytes in the environment cache file");
  return env;
}

// --- Loading with the caches. ---

namespace {
std::uint64_t fnv1a(std::span<const std::uint8_t> bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::uint8_t b : bytes) h = (h ^ b) * 0x100000001b3ull;
  return h;
}

struct CacheEntry {
  std::uint64_t hash;
  std::size_t length;
  EnvironmentOptions options;
  std::shared_ptr<const Environment> env;
};
}  // namespace

std::shared_ptr<const Environment> load_environment(const std::filesystem::path& path, const EnvironmentOptions& options,
                                                    raster::ThreadPool* pool, const std::filesystem::path& cache_dir,
                                                    const image::Limits& limits) {
  const std::string name = path.string();
  try {
    validate(options);
  } catch (const std::invalid_argument& e) {
    fail(name, e.what());
  }
  const std::vector<std::uint8_t> bytes = image::read_file(path, limits);
  const std::uint64_t hash = fnv1a(bytes);
  std::filesystem::path cached;
  if (!cache_dir.empty()) {
    char key[64];
    std::snprintf(key, sizeof key, "%016llx-%zu-s%d-n%d.spenv", static_cast<unsigned long long>(hash), bytes.size(),
                  options.size, options.samples);
    cached = cache_dir / key;
  }
  // The on-disk cache gets every environment loaded with it, including one found in
  // memory (loaded earlier without a cache folder, or with another one).
  const auto store = [&](const Environment& env, bool replace) {
    std::error_code ec;
    if (cached.empty() || (!replace && std::filesystem::is_regular_file(cached, ec))) return;
    std::filesystem::create_directories(cache_dir, ec);
    if (ec) throw std::runtime_error(cache_dir.string() + ": cannot create the environment cache: " + ec.message());
    image::write_file_atomic(cached, env.to_bytes());
  };
  // In memory: the last few environments, by content and options.
  static std::mutex mutex;
  static std::list<CacheEntry> recent;
  constexpr std::size_t kKeep = 4;
  std::shared_ptr<const Environment> env;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (auto it = recent.begin(); it != recent.end(); ++it)
      if (it->hash == hash && it->length == bytes.size() && it->options == options) {
        recent.splice(recent.begin(), recent, it);
        env = recent.front().env;
        break;
      }
  }
  if (env) {
    store(*env, false);
    return env;
  }
  if (!cached.empty()) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(cached, ec)) {
      try {
        env = Environment::from_bytes(image::read_file(cached), name);
      } catch (const std::exception&) {
        env = nullptr;  // unreadable or stale: prefiltered again and replaced below
      }
    }
  }
  if (!env) {
    const image::ImageF im = image::load_imagef(bytes, name, limits);
    env = std::make_shared<const Environment>(image::ImageViewF(im), name, options, pool);
    store(*env, true);  // replaces a stale file
  }
  const std::lock_guard<std::mutex> lock(mutex);
  recent.push_front({hash, bytes.size(), options, env});
  if (recent.size() > kKeep) recent.pop_back();
  return env;
}

// --- The split-sum table. ---

namespace {
// The split-sum integrals for one n·v over the GGX half vectors of one roughness (`halfs`,
// ggx_half_vector(j, count, α²) for j = 0 … count − 1, which do not depend on n·v: the
// table computes them once per row and every texel of the row reuses them).
glm::dvec2 dfg_integrate(double NoV, double roughness, const std::vector<glm::dvec3>& halfs) {
  NoV = std::clamp(NoV, 1e-4, 1.0);
  const double alpha = roughness * roughness, k = alpha / 2.0;
  const glm::dvec3 v(std::sqrt(1.0 - NoV * NoV), 0.0, NoV);
  double a = 0.0, b = 0.0;
  for (const glm::dvec3& h : halfs) {
    const double VoH = glm::dot(v, h);
    const glm::dvec3 l = h * (2.0 * VoH) - v;
    const double NoL = l.z, NoH = h.z;
    if (!(NoL > 0.0) || !(VoH > 0.0)) continue;
    const double g = (NoV / (NoV * (1.0 - k) + k)) * (NoL / (NoL * (1.0 - k) + k));
    const double g_vis = g * VoH / (NoH * NoV);
    const double fc5 = (1.0 - VoH) * (1.0 - VoH) * (1.0 - VoH) * (1.0 - VoH) * (1.0 - VoH);
    a += (1.0 - fc5) * g_vis;
    b += fc5 * g_vis;
  }
  const auto count = static_cast<double>(static_cast<std::uint32_t>(halfs.size()));
  return {a / count, b / count};
}

std::vector<glm::dvec3> ggx_half_vectors(double roughness, int samples) {
  const double alpha = roughness * roughness, a2 = alpha * alpha;
  const auto count = static_cast<std::uint32_t>(samples);
  std::vector<glm::dvec3> halfs(count);
  for (std::uint32_t j = 0; j < count; ++j) halfs[j] = ggx_half_vector(j, count, a2);
  return halfs;
}
}  // namespace

glm::dvec2 dfg_reference(double NoV, double roughness, int samples) {
  return dfg_integrate(NoV, roughness, ggx_half_vectors(roughness, samples));
}

const raster::Texture& dfg_table() {
  static const raster::Texture table = [] {
    std::vector<float> rgba(static_cast<std::size_t>(kDfgSize) * kDfgSize * 4);
    for (int y = 0; y < kDfgSize; ++y) {
      const double roughness = (y + 0.5) / kDfgSize;
      const std::vector<glm::dvec3> halfs = ggx_half_vectors(roughness, kDfgSamples);
      for (int x = 0; x < kDfgSize; ++x) {
        const glm::dvec2 ab = dfg_integrate((x + 0.5) / kDfgSize, roughness, halfs);
        float* p = &rgba[(static_cast<std::size_t>(y) * kDfgSize + static_cast<std::size_t>(x)) * 4];
        p[0] = static_cast<float>(ab.x);
        p[1] = static_cast<float>(ab.y);
        p[2] = static_cast<float>(ab.x + ab.y);
        p[3] = 1.0f;
      }
    }
    return raster::Texture(image::ImageViewF(kDfgSize, kDfgSize, rgba), raster::TextureOptions{.mipmaps = false});
  }();
  return table;
}

PreparedEnvironment prepare_environment(const EnvironmentLighting& e) {
  if (!e.map) throw std::invalid_argument("environment: has no map");
  if (!std::isfinite(e.intensity) || e.intensity < 0.0f)
    throw std::invalid_argument("environment.intensity " + std::to_string(e.intensity) + " must be finite and ≥ 0");
  if (!std::isfinite(e.rotation)) throw std::invalid_argument("environment.rotation must be finite");
  PreparedEnvironment p;
  p.map = e.map.get();
  p.sh = p.map->irradiance_sh().data();
  for (int l = 0; l < kEnvironmentLevels; ++l) p.levels[static_cast<std::size_t>(l)] = &p.map->level(l);
  const double r = dmath::radians(static_cast<double>(e.rotation));
  p.cos_r = static_cast<float>(dmath::cos(r));
  p.sin_r = static_cast<float>(dmath::sin(r));
  p.intensity = e.intensity;
  p.multiscatter = e.multiscatter;
  return p;
}

}  // namespace softpbr::pbr
