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

// octahedral_encode, inlined into the prefilter's sample loop (the same operations).
inline glm::dvec2 encode(const glm::dvec3& d) {
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
  glm::vec3 lf;   // l in float, as the sample loop reads it
  double weight;  // n·l
  int lod0;       // the source mip below the filtered lod, and the blend to the next
  double frac;
};

// The GGX lobe of α (roughness²) as `count` samples for filtered importance sampling of a
// source whose level 0 has side `source_size` (and `mips` levels).
std::vector<LobeSample> lobe(double alpha, std::uint32_t count, int source_size, int mips) {
  const double a2 = alpha * alpha;
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
    // Křivánek & Colbert: the mip whose texels cover the sample's solid angle, without a
    // bias toward coarser mips (half a level blurred the narrow lobes: a near-mirror lost
    // 9% of a small sun's peak, test_environment's Monte Carlo case).
    double lod = 0.5 * (dmath::log(sample_solid_angle / texel_solid_angle) / kLn2);
    lod = std::clamp(lod, 0.0, static_cast<double>(mips - 1));
    const int lod0 = std::min(static_cast<int>(std::floor(lod)), mips - 1);
    samples.push_back({l, glm::vec3(l), l.z, lod0, lod - lod0});
  }
  return samples;
}

// The source chain as the sample loop reads it: float RGBA texels (16 bytes, a quarter of
// the double texels' cache footprint), border included.
struct SourceLevel {
  int size = 0;
  std::vector<glm::vec4> texels;  // (size + 2)², row-major

  explicit SourceLevel(const OctMap& m) : size(m.size), texels(m.texels.size()) {
    for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = glm::vec4(glm::vec3(m.texels[i]), 0.0f);
  }
  // OctMap::bilinear in float: uv in [0, 1]² (an encoded direction), so the texel
  // coordinate is ≥ 0.5 and truncation is floor.
  glm::vec3 bilinear(float u, float v) const {
    const float fs = static_cast<float>(size);
    const float cx = u * fs + 0.5f, cy = v * fs + 0.5f;
    const int x0 = std::min(static_cast<int>(cx), size), y0 = std::min(static_cast<int>(cy), size);
    const float fx = std::min(cx - static_cast<float>(x0), 1.0f), fy = std::min(cy - static_cast<float>(y0), 1.0f);
    const std::size_t full = static_cast<std::size_t>(size) + 2;
    const glm::vec4* r0 = &texels[static_cast<std::size_t>(y0) * full + static_cast<std::size_t>(x0)];
    const glm::vec4* r1 = r0 + full;
    const glm::vec4 top = r0[0] * (1.0f - fx) + r0[1] * fx;
    const glm::vec4 bottom = r1[0] * (1.0f - fx) + r1[1] * fx;
    return glm::vec3(top * (1.0f - fy) + bottom * fy);
  }
};

// A level prefiltered from the source chain with the GGX lobe of α: per texel, the samples
// turned into its frame, encoded, read (two mips blended) and summed with their weights in
// double, in the samples' order.
OctMap prefilter(const std::vector<SourceLevel>& source, int size, double alpha, std::uint32_t count,
                 raster::ThreadPool* pool) {
  const std::vector<LobeSample> samples = lobe(alpha, count, source[0].size, static_cast<int>(source.size()));
  double weight = 0.0;  // the same for every texel
  for (const LobeSample& s : samples) weight += s.weight;
  OctMap m(size);
  for_each_index(pool, static_cast<std::size_t>(size), [&](std::size_t row) {
    const int y = static_cast<int>(row);
    for (int x = 0; x < size; ++x) {
      const glm::dvec3 nd = octahedral_decode({(x + 0.5) / size, (y + 0.5) / size});
      glm::dvec3 td, bd;
      frame(nd, td, bd);
      const glm::vec3 n(nd), t(td), b(bd);
      glm::dvec3 sum(0.0);
      for (const LobeSample& s : samples) {
        // The sample's direction and its octahedral coordinates in float (a direction to
        // 1e-7; the weights and the sum stay in double).
        const glm::vec3 l = t * s.lf.x + b * s.lf.y + n * s.lf.z;
        const float l1 = std::fabs(l.x) + std::fabs(l.y) + std::fabs(l.z);
        const float inv = 1.0f / l1;  // > 0: l is a unit vector's rotation
        float px = l.x * inv, pz = l.z * inv;
        if (l.y < 0.0f) {
          const float fx = (1.0f - std::fabs(pz)) * (px < 0.0f ? -1.0f : 1.0f);
          const float fz = (1.0f - std::fabs(px)) * (pz < 0.0f ? -1.0f : 1.0f);
          px = fx, pz = fz;
        }
        const float u = px * 0.5f + 0.5f, v = pz * 0.5f + 0.5f;
        glm::vec3 c = source[static_cast<std::size_t>(s.lod0)].bilinear(u, v);
        if (s.frac > 0.0) {
          const auto f = static_cast<float>(s.frac);
          c = c * (1.0f - f) + source[static_cast<std::size_t>(s.lod0) + 1].bilinear(u, v) * f;
        }
        sum += glm::dvec3(c) * s.weight;
      }
      m.interior(x, y) = weight > 0.0 ? sum / weight : glm::dvec3(0.0);
    }
  });
  m.fill_border();
  return m;
}

// The irradiance map: for each texel's direction n, (1/π) ∫ L(ω) max(0, n·ω) dω, summed over
// cells of the equirectangular image (at most kCellsX × kCellsY; each the solid-angle
// weighted sum of the texels whose centres fall in it, at its centre direction): exact
// for the map up to the cells' size (2.8°, where the clamped cosine is smooth). Rows of
// the output are split over the pool; every sum runs in a fixed order.
OctMap irradiance_map(const Equirect& src, raster::ThreadPool* pool) {
  constexpr int kCellsX = 128, kCellsY = 64;
  const int cw = std::min(kCellsX, src.width), ch = std::min(kCellsY, src.height);
  struct Cell {
    glm::dvec3 dir;
    glm::dvec3 power;  // Σ L Ω over its texels
  };
  std::vector<Cell> cells(static_cast<std::size_t>(cw) * static_cast<std::size_t>(ch));
  for (int y = 0; y < src.height; ++y) {
    const double solid_angle = (2.0 * kPi / src.width) *
                               (dmath::cos(kPi * y / src.height) - dmath::cos(kPi * (y + 1) / src.height));
    const auto cy = static_cast<std::size_t>(static_cast<std::int64_t>(y) * ch / src.height);
    for (int x = 0; x < src.width; ++x) {
      const auto cx = static_cast<std::size_t>(static_cast<std::int64_t>(x) * cw / src.width);
      cells[cy * static_cast<std::size_t>(cw) + cx].power += src.texel(x, y) * solid_angle;
    }
  }
  for (int y = 0; y < ch; ++y) {
    // The cell's centre: the middle of the texel rows and columns it holds.
    const int y0 = (y * src.height + ch - 1) / ch, y1 = ((y + 1) * src.height + ch - 1) / ch;
    const double theta = kPi * (0.5 * (y0 + y1)) / src.height;
    const double st = dmath::sin(theta), ct = dmath::cos(theta);
    for (int x = 0; x < cw; ++x) {
      const int x0 = (x * src.width + cw - 1) / cw, x1 = ((x + 1) * src.width + cw - 1) / cw;
      const double phi = 2.0 * kPi * (0.5 * (x0 + x1) / src.width - 0.5);
      cells[static_cast<std::size_t>(y) * static_cast<std::size_t>(cw) + static_cast<std::size_t>(x)].dir =
          glm::dvec3(st * dmath::sin(phi), ct, -st * dmath::cos(phi));
    }
  }
  OctMap m(kIrradianceSize);
  for_each_index(pool, static_cast<std::size_t>(kIrradianceSize), [&](std::size_t row) {
    const int y = static_cast<int>(row);
    for (int x = 0; x < kIrradianceSize; ++x) {
      const glm::dvec3 n = octahedral_decode({(x + 0.5) / kIrradianceSize, (y + 0.5) / kIrradianceSize});
      glm::dvec3 sum(0.0);
      for (const Cell& c : cells) {
        const double cosine = n.x * c.dir.x + n.y * c.dir.y + n.z * c.dir.z;
        if (cosine > 0.0) sum += c.power * cosine;
      }
      m.interior(x, y) = sum * (1.0 / kPi);
    }
  });
  m.fill_border();
  return m;
}

// GGX samples a texel for level i (i ≥ 1) from options.samples, the count at α = 0.05.
std::uint32_t level_samples(int samples, int i) {
  static constexpr int kScale[kEnvironmentLevels] = {0, -2, -1, 0, 1, 2, 3, 3};  // log2 of the factor
  const int k = kScale[i];
  const int n = k < 0 ? samples >> -k : samples << k;
  return static_cast<std::uint32_t>(std::max(n, 8));
}

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

int Environment::level_side(int size, int i) {
  if (i == 0) return size;
  const double want = 8.0 / static_cast<double>(kEnvironmentLevelAlpha[i]);
  int side = 32;
  while (side < size && side * 2 <= want) side *= 2;  // the largest power of two ≤ `want`, in [32, size]
  return std::min(side, size);
}

glm::dvec2 octahedral_encode(const glm::dvec3& d) { return encode(d); }

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
  irradiance_ = irradiance_map(src, pool).texture();

  std::vector<OctMap> chain;
  chain.push_back(resample(src, size_, pool));
  while (chain.back().size > 1) chain.push_back(chain.back().half());

  levels_.push_back(chain[0].texture());
  const std::vector<SourceLevel> source(chain.begin(), chain.end());
  for (int i = 1; i < kLevels; ++i)
    levels_.push_back(prefilter(source, level_side(size_, i), static_cast<double>(kEnvironmentLevelAlpha[i]),
                                level_samples(options.samples, i), pool)
                          .texture());
}

std::size_t Environment::bytes() const {
  std::size_t n = irradiance_->texel_bytes();
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
    // A 128² level 0: the studio's sharpest edges are smoothsteps 6° wide (texels of 1.6°
    // hold them; at 256² the 8-bit image of WaterBottle at 1080p differs by at most 1 level
    // in 0.5% of its values), a third of the prefiltering work of 256².
    return std::make_shared<const Environment>(image::ImageViewF(im), "studio (built in)", EnvironmentOptions{.size = 128},
                                               pool);
  }();
  return s;
}

// --- Serialization. ---

namespace {
// Version 2: the key, the irradiance map instead of SH coefficients, 8 levels, RGB texels,
// a checksum. A file of another version is ignored and replaced (load_environment).
constexpr char kMagic[8] = {'S', 'P', 'E', 'N', 'V', '0', '0', '2'};

std::uint64_t fnv1a(std::span<const std::uint8_t> bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::uint8_t b : bytes) h = (h ^ b) * 0x100000001b3ull;
  return h;
}

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_u64(std::vector<std::uint8_t>& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_texture(std::vector<std::uint8_t>& out, const raster::Texture& t) {
  put_u32(out, static_cast<std::uint32_t>(t.width()));
  const std::span<const float> texels = t.texels_f();
  for (std::size_t i = 0; i < texels.size(); ++i) {
    if (i % 4 == 3) continue;  // RGB: alpha is 1
    std::uint32_t v;
    std::memcpy(&v, &texels[i], 4);
    put_u32(out, v);
  }
}

struct Reader {
  std::span<const std::uint8_t> bytes;
  std::size_t at = 0;
  const std::string& name;
  std::uint64_t bits(int n) {
    if (bytes.size() - at < static_cast<std::size_t>(n)) fail(name, "the environment cache file is truncated");
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(bytes[at + static_cast<std::size_t>(i)]) << (8 * i);
    at += static_cast<std::size_t>(n);
    return v;
  }
  std::uint32_t u32() { return static_cast<std::uint32_t>(bits(4)); }
  // A square RGB texture of side `full`, each value finite and ≥ 0.
  std::shared_ptr<const raster::Texture> texture(std::uint32_t full) {
    if (u32() != full) fail(name, "bad map size in the environment cache file");
    const std::size_t n = static_cast<std::size_t>(full) * full;
    if ((bytes.size() - at) / 12 < n) fail(name, "the environment cache file is truncated");
    std::vector<float> rgba(n * 4, 1.0f);
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = u32();
        float f;
        std::memcpy(&f, &v, 4);
        if (!std::isfinite(f) || f < 0.0f) fail(name, "a value in the environment cache file is negative or not finite");
        rgba[4 * i + static_cast<std::size_t>(c)] = f;
      }
    return std::make_shared<const raster::Texture>(
        image::ImageViewF(static_cast<int>(full), static_cast<int>(full), rgba), raster::TextureOptions{.mipmaps = false});
  }
};
}  // namespace

std::vector<std::uint8_t> Environment::to_bytes(std::uint64_t key) const {
  std::vector<std::uint8_t> out(kMagic, kMagic + 8);
  put_u64(out, key);
  put_u32(out, static_cast<std::uint32_t>(options_.size));
  put_u32(out, static_cast<std::uint32_t>(options_.samples));
  put_u32(out, static_cast<std::uint32_t>(size_));
  put_texture(out, *irradiance_);
  put_u32(out, static_cast<std::uint32_t>(levels_.size()));
  for (const auto& l : levels_) put_texture(out, *l);
  put_u64(out, fnv1a(out));
  return out;
}

std::shared_ptr<const Environment> Environment::from_bytes(std::span<const std::uint8_t> bytes, std::string name,
                                                           std::uint64_t key) {
  if (bytes.size() < 16 || std::memcmp(bytes.data(), kMagic, 8) != 0)
    fail(name, "not an environment cache file of this version");
  {
    Reader tail{bytes, bytes.size() - 8, name};
    if (tail.bits(8) != fnv1a(bytes.first(bytes.size() - 8)))
      fail(name, "the environment cache file is damaged (its checksum does not match)");
  }
  Reader r{bytes.first(bytes.size() - 8), 8, name};
  if (r.bits(8) != key) fail(name, "the environment cache file was made from another map");
  auto env = std::shared_ptr<Environment>(new Environment());
  env->name_ = name;  // a copy: the readers above hold a reference to `name`
  env->options_.size = static_cast<int>(r.u32());
  env->options_.samples = static_cast<int>(r.u32());
  try {
    validate(env->options_);
  } catch (const std::invalid_argument& e) {
    fail(env->name_, e.what());
  }
  env->size_ = static_cast<int>(r.u32());
  if (!is_pow2(env->size_) || env->size_ < 8 || env->size_ > 2048) fail(env->name_, "bad map size in the cache file");
  env->irradiance_ = r.texture(kIrradianceSize + 2);
  if (r.u32() != kLevels) fail(env->name_, "bad level count in the cache file");
  for (int i = 0; i < kLevels; ++i)
    env->levels_.push_back(r.texture(static_cast<std::uint32_t>(level_side(env->size_, i) + 2)));
  if (r.at != r.bytes.size()) fail(env->name_, "trailing bytes in the environment cache file");
  return env;
}

// --- Loading with the caches. ---

namespace {
struct CacheEntry {
  std::uint64_t hash;
  std::size_t length;
  EnvironmentOptions options;
  std::shared_ptr<const Environment> env;
};

// The largest cache file: a 2048 map's levels and irradiance map, RGB floats, and headers.
std::uint64_t max_cache_bytes() {
  std::uint64_t n = 4096 + 12ull * (kIrradianceSize + 2) * (kIrradianceSize + 2);
  for (int i = 0; i < kEnvironmentLevels; ++i) {
    const std::uint64_t full = static_cast<std::uint64_t>(Environment::level_side(2048, i)) + 2;
    n += 12 * full * full + 4;
  }
  return n;
}
}  // namespace

std::shared_ptr<const Environment> load_environment(const std::filesystem::path& path, const EnvironmentOptions& options,
                                                    raster::ThreadPool* pool, const std::filesystem::path& cache_dir,
                                                    const image::Limits& limits, std::vector<std::string>* warnings) {
  const std::string name = path.string();
  try {
    validate(options);
  } catch (const std::invalid_argument& e) {
    fail(name, e.what());
  }
  const std::vector<std::uint8_t> bytes = image::read_file(path, limits);
  const std::uint64_t hash = fnv1a(bytes);
  // What a cache entry must have been made from: these bytes, their length and the
  // options (the format's version is the file's magic).
  const std::uint64_t key = hash ^ (static_cast<std::uint64_t>(bytes.size()) * 0x9e3779b97f4a7c15ull) ^
                            (static_cast<std::uint64_t>(static_cast<std::uint32_t>(options.size)) << 32) ^
                            static_cast<std::uint64_t>(static_cast<std::uint32_t>(options.samples));
  std::filesystem::path cached;
  if (!cache_dir.empty()) {
    char file[64];
    std::snprintf(file, sizeof file, "%016llx-%zu-s%d-n%d.spenv", static_cast<unsigned long long>(hash), bytes.size(),
                  options.size, options.samples);
    cached = cache_dir / file;
  }
  // A cache is an optimisation: what cannot be read, made or written there is a warning
  // (once per call), and the render goes on.
  bool warned = false;
  const auto warn = [&](const std::string& what) {
    if (warned || warnings == nullptr) return;
    warned = true;
    warnings->push_back(what);
  };
  // The on-disk cache gets every environment loaded with it, including one found in
  // memory (loaded earlier without a cache folder, or with another one).
  const auto store = [&](const Environment& env, bool replace) {
    if (cached.empty()) return;
    std::error_code ec;
    if (!replace && std::filesystem::is_regular_file(cached, ec)) return;
    try {
      // An entry that is not a regular file (a link, a pipe, an empty folder) is removed
      // first: write_file_atomic replaces only files.
      const auto st = std::filesystem::symlink_status(cached, ec);
      if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st)) std::filesystem::remove(cached, ec);
      std::filesystem::create_directories(cache_dir, ec);
      if (ec) throw std::runtime_error(cache_dir.string() + ": cannot create it: " + ec.message());
      image::write_file_atomic(cached, env.to_bytes(key));
    } catch (const std::exception& e) {
      warn(std::string("environment cache not written (the render goes on): ") + e.what());
    }
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
  bool replace = false;
  if (!cached.empty()) {
    std::error_code ec;
    const auto status = std::filesystem::symlink_status(cached, ec);
    if (std::filesystem::exists(status)) {
      replace = true;
      try {
        image::Limits cache_limits;
        cache_limits.max_file_bytes = max_cache_bytes();
        env = Environment::from_bytes(image::read_file(cached, cache_limits), name, key);
        if (env->options() != options) throw std::invalid_argument("made with other options");
      } catch (const std::exception&) {
        env = nullptr;  // damaged, stale or not a file: prefiltered again and replaced below
      }
    }
  }
  if (!env) {
    const image::ImageF im = image::load_imagef(bytes, name, limits);
    env = std::make_shared<const Environment>(image::ImageViewF(im), name, options, pool);
    store(*env, replace);
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
  p.irradiance = &p.map->irradiance();
  for (int l = 0; l < kEnvironmentLevels; ++l) p.levels[static_cast<std::size_t>(l)] = &p.map->level(l);
  const double r = dmath::radians(static_cast<double>(e.rotation));
  p.cos_r = static_cast<float>(dmath::cos(r));
  p.sin_r = static_cast<float>(dmath::sin(r));
  p.intensity = e.intensity;
  p.multiscatter = e.multiscatter;
  return p;
}

}  // namespace softpbr::pbr
