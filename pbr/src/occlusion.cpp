// Screen-space ambient occlusion of the environment's light (see occlusion.h).
//
// Per pixel: the view-space point P and unit normal N of the surface it sees (from the
// depth and normal buffer), and kSamples points S = P + R · (T, B, N) · rot(k) in the
// hemisphere above the surface (a fixed kernel, turned about N by one of 16 angles picked
// by the pixel's place in a 4×4 pattern: Crytek's rotation, Mittring 2007). Each S is
// projected to its pixel, whose surface point Q is read back; it occludes P by the
// estimator of McGuire et al. 2011 ("The Alchemy Screen-Space Ambient Obscurance
// Algorithm") in cosine form: with v = Q − P,
//   term = max(0, v·N / |v| − β) · max(0, 1 − |v|² / R²)
// — how far above P's tangent plane Q rises, faded to 0 at the radius (the range check:
// a surface far in front of P, a silhouette, casts no halo). Q on P's own plane gives
// v·N ≈ 0 < β: an open plane is not occluded, whatever the view. The factor is
// 1 − strength · Σ term / (kSamples (1 − β)), clamped to [0, 1]; then a 4×4 box blur over
// the pixels whose depth and normal are P's (a bilateral blur), which averages the 16
// rotations into 16 × kSamples directions. Only IEEE basic operations (sqrt, division),
// each pixel's in a fixed order, and the build's -ffp-contract=off: the same bits on every
// machine and for any thread count.
#include "occlusion.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>

#include "softpbr/simd/dispatch.h"
#include "softpbr/simd/simd.h"

namespace softpbr::pbr::detail {

namespace {

constexpr int kSamples = 12;
// The kernel: a golden-angle spiral over the cosine-weighted hemisphere (elevation at least
// 0.15 rad-ish: z ≥ 0.15 before scaling), the k-th point scaled to 0.15 + 0.85 (k/12)²
// of the radius, so samples crowd near P where contact shadows are.
constexpr float kKernel[kSamples][3] = {
    {0.031823521f, 0.000000000f, 0.152620246f},   {-0.045260289f, 0.041462133f, 0.162398324f},
    {0.008105541f, -0.092358458f, 0.180731793f},  {0.080323110f, 0.104767273f, 0.205730656f},
    {-0.179437766f, -0.031740014f, 0.235249302f}, {0.207069075f, -0.131720396f, 0.266792776f},
    {-0.083922030f, 0.312185770f, 0.297364253f},  {-0.192311137f, -0.370283392f, 0.323196563f},
    {0.496568410f, 0.181345987f, 0.339226271f},   {-0.608835896f, 0.251318607f, 0.337889031f},
    {0.342645095f, -0.732212666f, 0.305553607f},  {0.292982446f, 0.934074205f, 0.204124145f},
};
// The rotations (cos, sin) of the 4×4 pattern, row by row: angles k · 22.5° in an
// interleaved order (neighbours differ by about half a turn).
constexpr float kRotation[16][2] = {
    {1.000000000f, 0.000000000f},   {-1.000000000f, 0.000000000f},  {0.707106781f, 0.707106781f},
    {-0.707106781f, -0.707106781f}, {0.000000000f, -1.000000000f},  {0.000000000f, 1.000000000f},
    {0.707106781f, -0.707106781f},  {-0.707106781f, 0.707106781f},  {0.382683432f, 0.923879533f},
    {-0.382683432f, -0.923879533f}, {0.923879533f, 0.382683432f},   {-0.923879533f, -0.382683432f},
    {0.923879533f, -0.382683432f},  {-0.923879533f, 0.382683432f},  {0.382683432f, -0.923879533f},
    {-0.382683432f, 0.923879533f},
};
// β: the cosine above the tangent plane below which a point does not occlude (float error
// of a point on P's own plane, and tessellated curved surfaces, stay under it).
constexpr float kBias = 0.1f;
// The blur's neighbours: depth within this fraction of the radius, normals within
// acos(0.8) ≈ 37°.
constexpr float kBlurDepth = 0.25f;
constexpr float kBlurNormal = 0.8f;

struct Frame {
  const glm::vec4* g;
  int w, h;
  bool ortho;
  float inv_p00, inv_p11, p00, p11;
  float sx, sy;  // 2 / width, 2 / height
  float half_w, half_h;  // width / 2, height / 2

  // The view-space point seen at pixel (x, y) (its centre) at depth d.
  glm::vec3 point(int x, int y, float d) const {
    const float nx = (static_cast<float>(x) + 0.5f) * sx - 1.0f;
    const float ny = 1.0f - (static_cast<float>(y) + 0.5f) * sy;
    const float wv = ortho ? 1.0f : d;
    return {nx * wv * inv_p00, ny * wv * inv_p11, -d};
  }
};

float occlusion_at(const Frame& f, int x, int y, float radius, float strength) {
  const glm::vec4 g = f.g[static_cast<std::size_t>(y) * static_cast<std::size_t>(f.w) + static_cast<std::size_t>(x)];
  if (!(g.w > 0.0f)) return 1.0f;
  const glm::vec3 P = f.point(x, y, g.w);
  const glm::vec3 N(g.x, g.y, g.z);
  // An orthonormal basis around N (Duff et al. 2017, "Building an Orthonormal Basis,
  // Revisited"): branchless but for the sign.
  const float sign = N.z >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (sign + N.z);
  const float b = N.x * N.y * a;
  const glm::vec3 T(1.0f + sign * N.x * N.x * a, sign * b, -sign * N.x);
  const glm::vec3 B(b, sign + N.y * N.y * a, -N.y);
  const float* rot = kRotation[(y & 3) * 4 + (x & 3)];
  const float r2 = radius * radius, inv_r2 = 1.0f / r2;
  float sum = 0.0f;
  for (const auto& k : kKernel) {
    const float kx = (rot[0] * k[0] - rot[1] * k[1]) * radius;
    const float ky = (rot[1] * k[0] + rot[0] * k[1]) * radius;
    const float kz = k[2] * radius;
    const glm::vec3 S = P + T * kx + B * ky + N * kz;
    const float wv = f.ortho ? 1.0f : -S.z;
    if (!(wv > 0.0f)) continue;  // behind the eye
    const float inv_w = 1.0f / wv;  // one division a sample
    const float px = (S.x * inv_w * f.p00 + 1.0f) * f.half_w;
    const float py = (1.0f - S.y * inv_w * f.p11) * f.half_h;
    if (!(px >= 0.0f && px < static_cast<float>(f.w) && py >= 0.0f && py < static_cast<float>(f.h))) continue;
    const int qx = static_cast<int>(px), qy = static_cast<int>(py);
    if (qx == x && qy == y) continue;
    const float dq = f.g[static_cast<std::size_t>(qy) * static_cast<std::size_t>(f.w) + static_cast<std::size_t>(qx)].w;
    if (!(dq > 0.0f)) continue;  // nothing there
    const glm::vec3 v = f.point(qx, qy, dq) - P;
    const float vv = v.x * v.x + v.y * v.y + v.z * v.z;
    if (!(vv < r2) || !(vv > 0.0f)) continue;
    const float cosine = (v.x * N.x + v.y * N.y + v.z * N.z) / std::sqrt(vv);
    const float term = (cosine - kBias) * (1.0f - vv * inv_r2);
    if (term > 0.0f) sum = sum + term;
  }
  const float ao = 1.0f - strength * sum * (1.0f / (static_cast<float>(kSamples) * (1.0f - kBias)));
  return std::clamp(ao, 0.0f, 1.0f);
}

// The blurred factor of pixel (x, y) into row[x] (left as it is, 1, where no surface is):
// the mean of the raw factors of the pixels x − 2 … x + 1, y − 2 … y + 1 (one of each
// rotation) on P's surface — depth within kBlurDepth · R, normal within kBlurNormal.
void blur_at(const Frame& f, const float* raw, float depth_tolerance, int x, int y, float* row) {
  const int w = f.w, h = f.h;
  const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
  const glm::vec4 c = f.g[i];
  if (!(c.w > 0.0f)) return;  // 1
  float sum = 0.0f, n = 0.0f;
  for (int dy = -2; dy <= 1; ++dy) {
    const int yy = y + dy;
    if (yy < 0 || yy >= h) continue;
    for (int dx = -2; dx <= 1; ++dx) {
      const int xx = x + dx;
      if (xx < 0 || xx >= w) continue;
      const std::size_t j = static_cast<std::size_t>(yy) * static_cast<std::size_t>(w) + static_cast<std::size_t>(xx);
      const glm::vec4 q = f.g[j];
      if (!(q.w > 0.0f)) continue;
      const float dd = q.w - c.w;
      if (!(std::max(dd, -dd) <= depth_tolerance)) continue;
      if (!(q.x * c.x + q.y * c.y + q.z * c.z >= kBlurNormal)) continue;
      sum = sum + raw[j];
      n = n + 1.0f;
    }
  }
  row[x] = sum / n;  // n ≥ 1: the pixel itself
}

}  // namespace
}  // namespace softpbr::pbr::detail

// {baseline, avx2, avx512}::occlusion_rows<N>() and blur_rows<N>(): the same pixels N at
// a time (occlusion-inl.h).
#define SOFTPBR_TARGET_FILE "occlusion-inl.h"
#include "softpbr/simd/foreach_target.h"

namespace softpbr::pbr::detail {

void compute_occlusion(const raster::Target& gbuffer, const OcclusionSettings& s, raster::ThreadPool& pool,
                       std::vector<float>& out) {
  const int w = s.width, h = s.height;
  const std::size_t count = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  const Frame f{gbuffer.colors().data(),
                w,
                h,
                s.orthographic,
                1.0f / s.p00,
                1.0f / s.p11,
                s.p00,
                s.p11,
                2.0f / static_cast<float>(w),
                2.0f / static_cast<float>(h),
                0.5f * static_cast<float>(w),
                0.5f * static_cast<float>(h)};
  // Every raw factor is written below (no fill first: the pages are first touched by the
  // threads that compute them).
  const std::unique_ptr<float[]> raw_storage(new float[count]);
  float* const raw = raw_storage.get();
  out.assign(count, 1.0f);
  // Rows in bands of 8: fewer hand-outs of the pool, each band written by one thread.
  constexpr int kBand = 8;
  const auto bands = static_cast<std::size_t>((h + kBand - 1) / kBand);
  pool.parallel_for(bands, [&](std::size_t band) {
    const int y0 = static_cast<int>(band) * kBand, y1 = std::min(h, y0 + kBand);
    switch (s.lanes) {
      case 16: return SOFTPBR_DISPATCH(s.isa, occlusion_rows<16>)(f, y0, y1, s.radius, s.strength, raw);
      case 8: return SOFTPBR_DISPATCH(s.isa, occlusion_rows<8>)(f, y0, y1, s.radius, s.strength, raw);
      case 4: return SOFTPBR_DISPATCH(s.isa, occlusion_rows<4>)(f, y0, y1, s.radius, s.strength, raw);
      default:
        for (int y = y0; y < y1; ++y)
          for (int x = 0; x < w; ++x)
            raw[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] =
                occlusion_at(f, x, y, s.radius, s.strength);
    }
  });
  // The 4×4 blur (pixels x − 2 … x + 1, y − 2 … y + 1: one of each rotation), of the
  // neighbours on P's surface: depth within kBlurDepth · R, normal within kBlurNormal.
  const float depth_tolerance = kBlurDepth * s.radius;
  pool.parallel_for(bands, [&](std::size_t band) {
    const int y0 = static_cast<int>(band) * kBand, y1 = std::min(h, y0 + kBand);
    if (s.lanes <= 1) {
      for (int y = y0; y < y1; ++y) {
        float* row = out.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
        for (int x = 0; x < w; ++x) blur_at(f, raw, depth_tolerance, x, y, row);
      }
      return;
    }
    switch (s.lanes) {
      case 16: return SOFTPBR_DISPATCH(s.isa, blur_rows<16>)(f, raw, depth_tolerance, y0, y1, out.data());
      case 8: return SOFTPBR_DISPATCH(s.isa, blur_rows<8>)(f, raw, depth_tolerance, y0, y1, out.data());
      default: return SOFTPBR_DISPATCH(s.isa, blur_rows<4>)(f, raw, depth_tolerance, y0, y1, out.data());
    }
  });
}

}  // namespace softpbr::pbr::detail
