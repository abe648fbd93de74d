// ToneMapper's lanes kernels (see tonemap.cpp), compiled once per target (tonemap.cpp
// includes this file through softpbr/simd/foreach_target.h; no include guard, no header
// included here): the tone map and the codes of N pixels at a time.

namespace softpbr::pbr {
namespace {
namespace SOFTPBR_TARGET_NS {

// The codes of N values through the packed table, all in lanes: code_of for curves with at
// most one threshold per key.
template <int N>
inline simd::UintLanes<N> packed_codes(simd::Lanes<N, SOFTPBR_ISA> v, const Curve& c) {
  using U = simd::UintLanes<N>;
  using V = simd::Lanes<N, SOFTPBR_ISA>;
  const U bits = simd::bits_of(v) & 0x7fffffffu;  // −0 (t[0] = 0) looks up key 0 as +0
  U key = bits >> 16;
  const U lowest = U{} + c.packed_base, highest = U{} + kLastKey;
  key = key < lowest ? lowest : key;  // below t[0]: overridden with 0 below
  key = key > highest ? highest : key;
  const U entry = simd::SOFTPBR_TARGET_NS::gather<N>(c.packed, key - lowest);
  U code = (entry >> 17) - (U)((bits & 0xffffu) >= (entry & 0x1ffffu));  // a true comparison is −1
  code = (v < V(1.0f)).m ? code : U{} + 255u;
  return (v >= V(c.t0)).m ? code : U{};
}

// N pixels from `px` to 4N bytes at `out`.
template <int N, ToneMap kOp, int kSteps>
inline void encode_lanes(const glm::vec4* px, float scale, const Curve& curve, std::uint8_t* out) {
  using V = simd::Lanes<N, SOFTPBR_ISA>;
  V r, g, b, a;
  simd::load_deinterleave4<N>(&px[0].r, r, g, b, a);
  r *= V(scale);
  g *= V(scale);
  b *= V(scale);
  tone_map_operators::tone_map<kOp>(r, g, b);  // the same code as the scalar path
  // raster::unorm8(a) = a·255 + 0.5 truncated for 0 < a < 1, 0 at or below 0 (and NaN), 255
  // from 1: the same as truncating min(max(0, a), 1)·255 + 0.5 (0.5 → 0, 255.5 → 255; max
  // with 0 first turns NaN into 0), which every lane can convert.
  a = simd::min(simd::max(V(0.0f), a), V(1.0f)) * V(255.0f) + V(0.5f);
  if constexpr (kSteps == kPacked && std::endian::native == std::endian::little) {
    // Each pixel's four codes as one 32-bit lane, bytes r, g, b, a in memory order.
    const simd::UintLanes<N> rgba = packed_codes(r, curve) | packed_codes(g, curve) << 8 |
                                    packed_codes(b, curve) << 16 | simd::truncate_to_uint(a) << 24;
    std::memcpy(out, &rgba, 4 * N);
    return;
  }
  alignas(64) float ch[4][N];
  r.store(ch[0]);
  g.store(ch[1]);
  b.store(ch[2]);
  a.store(ch[3]);
  // The curve in locals: the byte stores below may alias anything to the compiler.
  const float* t = curve.t;
  const std::uint8_t* first = curve.first;
  const float t0 = curve.t0;
  const int steps = curve.steps;
  alignas(64) std::uint8_t bytes[4 * N];
  for (int i = 0; i < N; ++i) {
    bytes[4 * i + 0] = static_cast<std::uint8_t>(code_of<kSteps>(t, first, t0, steps, ch[0][i]));
    bytes[4 * i + 1] = static_cast<std::uint8_t>(code_of<kSteps>(t, first, t0, steps, ch[1][i]));
    bytes[4 * i + 2] = static_cast<std::uint8_t>(code_of<kSteps>(t, first, t0, steps, ch[2][i]));
    bytes[4 * i + 3] = static_cast<std::uint8_t>(static_cast<int>(ch[3][i]));
  }
  std::memcpy(out, bytes, sizeof bytes);
}

template <int N, ToneMap kOp, int kSteps>
inline void encode_rect_lanes(const Job& job) {
  const std::size_t width = static_cast<std::size_t>(job.target->width());
  const glm::vec4* colors = job.target->colors().data();
  const int n = job.x1 - job.x0;
  const int whole = n / N * N;
  // Runs of one colour (the background) are common: a set of N pixels all equal, bit for
  // bit, to the last such set reuses its bytes (no byte changes).
  glm::vec4 run[N];
  std::uint8_t run_bytes[4 * N];
  bool have_run = false;
  for (int y = job.y0; y < job.y1; ++y) {
    const std::size_t start = static_cast<std::size_t>(y) * width + static_cast<std::size_t>(job.x0);
    const glm::vec4* in = colors + start;
    std::uint8_t* out = job.image->rgba.data() + start * 4;
    for (int x = 0; x < whole; x += N) {
      if (have_run && simd::same_bytes<sizeof run>(in + x, run)) {
        std::memcpy(out + 4 * x, run_bytes, sizeof run_bytes);
        continue;
      }
      encode_lanes<N, kOp, kSteps>(in + x, job.scale, job.curve, out + 4 * x);
      if (simd::same_bytes<sizeof(glm::vec4) * (N - 1)>(in + x, in + x + 1)) {  // all N the same
        std::copy(in + x, in + x + N, run);
        std::memcpy(run_bytes, out + 4 * x, sizeof run_bytes);
        have_run = true;
      }
    }
    if (whole < n) {  // the last n − whole pixels, padded with zeros to a full set of lanes
      glm::vec4 rest[N] = {};
      std::uint8_t bytes[4 * N];
      std::copy(in + whole, in + n, rest);
      encode_lanes<N, kOp, kSteps>(rest, job.scale, job.curve, bytes);
      std::memcpy(out + 4 * whole, bytes, static_cast<std::size_t>(n - whole) * 4);
    }
  }
}

template <int N, int kSteps>
inline void encode_with_lanes(ToneMap op, const Job& job) {
  switch (op) {
    case ToneMap::None: return encode_rect_lanes<N, ToneMap::None, kSteps>(job);
    case ToneMap::Reinhard: return encode_rect_lanes<N, ToneMap::Reinhard, kSteps>(job);
    case ToneMap::Aces: return encode_rect_lanes<N, ToneMap::Aces, kSteps>(job);
    default: return encode_rect_lanes<N, ToneMap::Neutral, kSteps>(job);
  }
}
// The kernel: job's rectangle, N pixels at a time.
template <int N>
SOFTPBR_KERNEL void encode_with_lanes(ToneMap op, const Job& job) {
  SOFTPBR_DCHECK(0 <= job.x0 && job.x0 <= job.x1 && job.x1 <= job.target->width() && 0 <= job.y0 &&
                 job.y0 <= job.y1 && job.y1 <= job.target->height());
  if (job.curve.packed) return encode_with_lanes<N, kPacked>(op, job);
  switch (job.curve.steps) {
    case -1: return encode_with_lanes<N, -1>(op, job);
    case 1: return encode_with_lanes<N, 1>(op, job);  // sRGB, gamma 2.2 (see the tests)
    case 2: return encode_with_lanes<N, 2>(op, job);  // gamma 1
    default: return encode_with_lanes<N, 0>(op, job);
  }
}

// Resolve::ToneMapped of a multisampled row, N pixels at a time: exposure and the tone map
// per sample, then each channel's box mean (box_mean: pairwise in sample order); alpha is
// the mean of the linear alphas. The last pixels of a row run one at a time
// (resolve_tone_mapped_pixel; the 4-lane reference is resolve_tone_mapped_row, tonemap.cpp).
template <int N, ToneMap kOp, int kS>
inline void resolve_rows_lanes(const ResolveJob& job) {
  using V = simd::Lanes<N, SOFTPBR_ISA>;
  const raster::TargetPixels& pixels = *job.pixels;
  const std::size_t width = static_cast<std::size_t>(pixels.width);
  const glm::vec4* colors = pixels.colors;
  for (int y = job.y0; y < job.y1; ++y) {
    // Row indices relative to the pixels' origin (unsigned arithmetic: row + x − origin).
    const std::size_t row = static_cast<std::size_t>(y) * width - pixels.origin;
    glm::vec4* out = job.out + static_cast<std::size_t>(y - job.y0) * job.out_width;
    int x = job.x0;
    for (; x + N <= job.x1; x += N, out += N) {
      V r[kS], g[kS], b[kS], a[kS];
      for (int s = 0; s < kS; ++s) {
        simd::load_deinterleave4<N>(&colors[static_cast<std::size_t>(s) * pixels.plane + row + static_cast<std::size_t>(x)].r,
                                    r[s], g[s], b[s], a[s]);
        r[s] *= V(job.scale);
        g[s] *= V(job.scale);
        b[s] *= V(job.scale);
        tone_map_operators::tone_map<kOp>(r[s], g[s], b[s]);
      }
      simd::store_interleave4<N>(box_mean(r), box_mean(g), box_mean(b), box_mean(a), &out[0].r);
    }
    for (; x < job.x1; ++x, ++out)
      *out = resolve_tone_mapped_pixel<kOp, kS>(colors, pixels.plane, row + static_cast<std::size_t>(x), job.scale);
  }
}

// The kernel: job's rectangle of a 4- or 8-sample target, N pixels at a time.
template <int N>
SOFTPBR_KERNEL void resolve_with_lanes(ToneMap op, const ResolveJob& job) {
  const auto with_samples = [&]<ToneMap kOp>() {
    if (job.pixels->samples == 4) resolve_rows_lanes<N, kOp, 4>(job);
    else resolve_rows_lanes<N, kOp, 8>(job);
  };
  switch (op) {
    case ToneMap::None: return with_samples.template operator()<ToneMap::None>();
    case ToneMap::Reinhard: return with_samples.template operator()<ToneMap::Reinhard>();
    case ToneMap::Aces: return with_samples.template operator()<ToneMap::Aces>();
    default: return with_samples.template operator()<ToneMap::Neutral>();
  }
}

}  // namespace SOFTPBR_TARGET_NS
}  // namespace
}  // namespace softpbr::pbr
