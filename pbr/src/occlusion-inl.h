// compute_occlusion's lanes kernels (see occlusion.cpp), compiled once per target
// (occlusion.cpp includes this file through softpbr/simd/foreach_target.h; no include
// guard, no header included here): N pixels of a row at a time, each lane computing
// exactly occlusion_at's and blur_at's operations for its pixel, in the same order — the
// same IEEE single-precision operations (+ − × ÷ sqrt, comparisons), a skipped sample being
// a lane left out of the sum instead of a `continue` — so every pixel has the bits of the
// scalar code (test_occlusion renders with 1 lane against every width and dispatch).

namespace softpbr::pbr::detail {
namespace {
namespace SOFTPBR_TARGET_NS {

template <int N>
using OccLanes = simd::Lanes<N, SOFTPBR_ISA>;
template <int N>
using OccMask = simd::LaneMask<N, SOFTPBR_ISA>;
template <int N>
using OccInt = typename simd::detail::Native<N>::i;

// Lanes i = 0 … N−1 of `base + i`, as floats (exact: |base + i| < 2^24).
template <int N>
inline OccLanes<N> lane_index_floats(int base) {
  OccInt<N> i;
  for (int k = 0; k < N; ++k) i[k] = base + k;
  return OccLanes<N>(__builtin_convertvector(i, typename OccLanes<N>::native));
}

// occlusion_at for the N pixels x0 … x0 + N − 1 of row y (x0 a multiple of 4, so lane k's
// rotation is column k & 3's), into raw[0 … N).
template <int N>
inline void occlusion_lanes(const Frame& f, int x0, int y, float radius, float strength, float* raw) {
  using L = OccLanes<N>;
  using M = OccMask<N>;
  using I = OccInt<N>;
  using Native = typename L::native;
  const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(f.w);
  L gx, gy, gz, gw;
  simd::load_deinterleave4<N>(&f.g[row + static_cast<std::size_t>(x0)].x, gx, gy, gz, gw);
  const M valid = gw > L(0.0f);
  if (!simd::any(valid)) {
    L(1.0f).store(raw);
    return;
  }
  // P = f.point(x, y, g.w).
  const L xf = lane_index_floats<N>(x0);
  const float yf = static_cast<float>(y);
  const L nx = (xf + 0.5f) * f.sx - 1.0f;
  const float ny = 1.0f - (yf + 0.5f) * f.sy;
  const L wv_p = f.ortho ? L(1.0f) : gw;
  const L Px = nx * wv_p * f.inv_p00, Py = ny * wv_p * f.inv_p11, Pz = -gw;
  const L Nx = gx, Ny = gy, Nz = gz;
  const L sign = simd::select(Nz >= L(0.0f), L(1.0f), L(-1.0f));
  const L a = -1.0f / (sign + Nz);
  const L b = Nx * Ny * a;
  const L Tx = 1.0f + sign * Nx * Nx * a, Ty = sign * b, Tz = -sign * Nx;
  const L Bx = b, By = sign + Ny * Ny * a, Bz = -Ny;
  // The rotations of this row's four columns, repeated across the lanes.
  alignas(64) float rc[N], rs[N];
  for (int k = 0; k < N; ++k) {
    const float* rot = kRotation[(y & 3) * 4 + ((x0 + k) & 3)];
    rc[k] = rot[0];
    rs[k] = rot[1];
  }
  const L rot0 = L::load(rc), rot1 = L::load(rs);
  const float r2 = radius * radius, inv_r2 = 1.0f / r2;
  const float fw = static_cast<float>(f.w), fh = static_cast<float>(f.h);
  I xi;
  for (int k = 0; k < N; ++k) xi[k] = x0 + k;
  L sum(0.0f);
  for (const auto& k : kKernel) {
    const L kx = (rot0 * k[0] - rot1 * k[1]) * radius;
    const L ky = (rot1 * k[0] + rot0 * k[1]) * radius;
    const float kz = k[2] * radius;
    const L Sx = Px + Tx * kx + Bx * ky + Nx * kz;
    const L Sy = Py + Ty * kx + By * ky + Ny * kz;
    const L Sz = Pz + Tz * kx + Bz * ky + Nz * kz;
    const L wv = f.ortho ? L(1.0f) : -Sz;
    M ok = valid & (wv > L(0.0f));
    const L inv_w = 1.0f / wv;
    const L px = (Sx * inv_w * f.p00 + 1.0f) * f.half_w;
    const L py = (1.0f - Sy * inv_w * f.p11) * f.half_h;
    ok = ok & (px >= L(0.0f)) & (px < L(fw)) & (py >= L(0.0f)) & (py < L(fh));
    if (!simd::any(ok)) continue;
    // The sample's pixel (lanes outside the frame read pixel (0, 0), then are left out).
    const I qx = __builtin_convertvector(simd::select(ok, px, L(0.0f)).v, I);
    const I qy = __builtin_convertvector(simd::select(ok, py, L(0.0f)).v, I);
    ok = ok & M(~((qx == xi) & (qy == I{} + y)));
    alignas(64) float dq_lanes[N];
    for (int k2 = 0; k2 < N; ++k2)
      dq_lanes[k2] = f.g[static_cast<std::size_t>(qy[k2]) * static_cast<std::size_t>(f.w) +
                         static_cast<std::size_t>(qx[k2])]
                         .w;
    const L dq = L::load(dq_lanes);
    ok = ok & (dq > L(0.0f));
    // v = f.point(qx, qy, dq) − P.
    const L qnx = (L(__builtin_convertvector(qx, Native)) + 0.5f) * f.sx - 1.0f;
    const L qny = 1.0f - (L(__builtin_convertvector(qy, Native)) + 0.5f) * f.sy;
    const L wq = f.ortho ? L(1.0f) : dq;
    const L vx = qnx * wq * f.inv_p00 - Px;
    const L vy = qny * wq * f.inv_p11 - Py;
    const L vz = -dq - Pz;
    const L vv = vx * vx + vy * vy + vz * vz;
    ok = ok & (vv < L(r2)) & (vv > L(0.0f));
    const L cosine = (vx * Nx + vy * Ny + vz * Nz) / simd::sqrt(vv);
    const L term = (cosine - kBias) * (1.0f - vv * inv_r2);
    ok = ok & (term > L(0.0f));
    sum = simd::select(ok, sum + term, sum);
  }
  const float scale = 1.0f / (static_cast<float>(kSamples) * (1.0f - kBias));
  const L ao = 1.0f - strength * sum * scale;
  // std::clamp(ao, 0, 1): ao < 0 ? 0 : (1 < ao ? 1 : ao).
  const L clamped = simd::select(ao < L(0.0f), L(0.0f), simd::select(L(1.0f) < ao, L(1.0f), ao));
  simd::select(valid, clamped, L(1.0f)).store(raw);
}

template <int N>
void occlusion_rows(const Frame& f, int y0, int y1, float radius, float strength, float* raw) {
  for (int y = y0; y < y1; ++y) {
    float* out = raw + static_cast<std::size_t>(y) * static_cast<std::size_t>(f.w);
    int x = 0;
    for (; x + N <= f.w; x += N) occlusion_lanes<N>(f, x, y, radius, strength, out + x);
    for (; x < f.w; ++x) out[x] = occlusion_at(f, x, y, radius, strength);
  }
}

// blur_at for the N pixels x0 … x0 + N − 1 of row y, all of whose 4×4 neighbourhoods lie
// within the row range 0 … w − 1 (2 ≤ x0, x0 + N ≤ w − 1).
template <int N>
inline void blur_lanes(const Frame& f, const float* raw, float depth_tolerance, int x0, int y, float* out) {
  using L = OccLanes<N>;
  using M = OccMask<N>;
  const std::size_t w = static_cast<std::size_t>(f.w);
  const std::size_t i = static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x0);
  L cx, cy, cz, cw;
  simd::load_deinterleave4<N>(&f.g[i].x, cx, cy, cz, cw);
  const M valid = cw > L(0.0f);
  if (!simd::any(valid)) return;  // out keeps 1
  L sum(0.0f), n(0.0f);
  for (int dy = -2; dy <= 1; ++dy) {
    const int yy = y + dy;
    if (yy < 0 || yy >= f.h) continue;
    for (int dx = -2; dx <= 1; ++dx) {
      const std::size_t j = static_cast<std::size_t>(yy) * w + static_cast<std::size_t>(x0 + dx);
      L qx, qy, qz, qw;
      simd::load_deinterleave4<N>(&f.g[j].x, qx, qy, qz, qw);
      const L dd = qw - cw;
      const M ok = (qw > L(0.0f)) & (simd::max(dd, -dd) <= L(depth_tolerance)) &
                   (qx * cx + qy * cy + qz * cz >= L(kBlurNormal));
      sum = simd::select(ok, sum + L::load(raw + j), sum);
      n = simd::select(ok, n + 1.0f, n);
    }
  }
  simd::select(valid, sum / n, L::load(out)).store(out);
}

template <int N>
void blur_rows(const Frame& f, const float* raw, float depth_tolerance, int y0, int y1, float* out) {
  for (int y = y0; y < y1; ++y) {
    float* row = out + static_cast<std::size_t>(y) * static_cast<std::size_t>(f.w);
    int x = 0;
    for (; x < 2 && x < f.w; ++x) blur_at(f, raw, depth_tolerance, x, y, row);
    for (; x + N <= f.w - 1; x += N) blur_lanes<N>(f, raw, depth_tolerance, x, y, row + x);
    for (; x < f.w; ++x) blur_at(f, raw, depth_tolerance, x, y, row);
  }
}

}  // namespace SOFTPBR_TARGET_NS
}  // namespace
}  // namespace softpbr::pbr::detail
