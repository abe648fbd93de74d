// softpbr/raster/detail/rast-inl.h — the tile kernel: coverage, depth, interpolation and
// shading, compiled once per target (rast.h includes it through
// softpbr/simd/foreach_target.h; no include guard, no header included here).
//
// One thread owns a tile at a time; inside it the triangles of a draw run in submission
// order. Each triangle is walked in 2×2 quads aligned to even pixel coordinates (tiles
// have even sizes, so a quad never straddles two tiles). Every value a pixel gets — edge
// functions, depth, varyings, derivatives — is the value of the triangle's plane
// equations at that pixel alone, so it cannot depend on where a tile or span starts: the
// floating-point ones are computed there, never accumulated along a span; only the exact
// 64-bit edge functions are stepped from quad to quad (integer sums, the same values).
//
// kMs is the target's samples a pixel (1, 4, 8). With MSAA a pixel is covered when one of
// its samples is (the same edge functions at the sample positions); depth is tested and
// written per sample, the pixel is shaded once (at its centre) and its colour written and
// blended into the covered samples that passed (docs/design.md, MSAA).

namespace softpbr::raster::detail::SOFTPBR_TARGET_NS {

inline bool depth_passes(DepthTest test, float z, float stored) {
  switch (test) {
    case DepthTest::Less: return z < stored;
    case DepthTest::LessEqual: return z <= stored;
    default: return true;
  }
}

inline glm::vec4 blend(Blend mode, glm::vec4 src, glm::vec4 dst) {
  if (mode == Blend::Replace) return src;
  const float k = 1.0f - src.a;  // premultiplied "over"
  return {src.r + dst.r * k, src.g + dst.g * k, src.b + dst.b * k, src.a + dst.a * k};
}

// Alpha to coverage (DrawState::alpha_to_coverage): the samples of kMs that `alpha` keeps,
// sample s when alpha ≥ alpha_ref + ((s + 0.5) / kMs − 0.5) (the offset exact in float;
// for kMs = 1 it is 0, the alpha test). NaN keeps none.
template <int kMs>
inline unsigned alpha_coverage(float alpha, float alpha_ref) {
  unsigned mask = 0;
  for (int s = 0; s < kMs; ++s) {
    constexpr float kInv = 1.0f / static_cast<float>(kMs);
    const float offset = (static_cast<float>(s) + 0.5f) * kInv - 0.5f;
    if (alpha >= alpha_ref + offset) mask |= 1u << s;
  }
  return mask;
}

// MSAA: writes a pixel's colour `src` into its samples in `mask` (bit s: sample s) — for an
// alpha-tested draw, those whose depth `sample_depth` still passes (it writes them too):
// the stored depth of sample s is depth_at[4 · s] (its quad's, target.h depth_index).
template <int kMs>
inline void write_samples(const DrawState& state, const glm::vec4& src, unsigned mask, const float* sample_depth,
                          std::size_t idx, float* depth_at, const TargetPixels& target) {
  if (state.alpha_test) {
    glm::vec4 c = src;
    if (state.alpha_to_coverage) {
      mask &= alpha_coverage<kMs>(src.a, state.alpha_ref);
      c.a = 1.0f;
    } else if (!(src.a >= state.alpha_ref)) {
      return;
    }
    for (int s = 0; s < kMs; ++s) {
      if (!(mask & (1u << s))) continue;
      const std::size_t i = static_cast<std::size_t>(s) * target.plane + idx;
      float& stored = depth_at[4 * s];
      if (!depth_passes(state.depth_test, sample_depth[s], stored)) continue;
      if (state.depth_write) stored = sample_depth[s];
      target.colors[i] = blend(state.blend, c, target.colors[i]);
    }
    return;
  }
  if (state.blend == Blend::Replace) {
    // No branch on the mask (along edges it changes from pixel to pixel, and was
    // mispredicted): every sample is stored, an uncovered one keeping its own bits.
#if SOFTPBR_TARGET_AVX512
    // AVX-512: a masked store each, all four floats or none (no load).
    const simd::native_t<float, 4> value = simd::SOFTPBR_TARGET_NS::load_vector<4>(&src.r);
    for (int s = 0; s < kMs; ++s) {
      glm::vec4* const sample = target.colors + static_cast<std::size_t>(s) * target.plane + idx;
      simd::SOFTPBR_TARGET_NS::store_masked<4>(&sample->r, 0xFu * (mask >> s & 1u), value);
    }
#else
    // Elsewhere: the stored colour read back and selected against the new one.
    using I4 = simd::native_t<std::int32_t, 4>;
    I4 bits;
    __builtin_memcpy(&bits, &src, sizeof bits);
    for (int s = 0; s < kMs; ++s) {
      glm::vec4* const sample = target.colors + static_cast<std::size_t>(s) * target.plane + idx;
      I4 old;
      __builtin_memcpy(&old, sample, sizeof old);
      const I4 covered = I4{} - static_cast<std::int32_t>(mask >> s & 1u);  // all ones or zeros
      const I4 value = (bits & covered) | (old & ~covered);
      __builtin_memcpy(sample, &value, sizeof value);
    }
#endif
    return;
  }
  for (unsigned m = mask; m != 0; m &= m - 1) {
    const std::size_t i = static_cast<std::size_t>(std::countr_zero(m)) * target.plane + idx;
    target.colors[i] = blend(Blend::Over, src, target.colors[i]);
  }
}

// MSAA: a quad's samples are tested as "sample lanes" k = 4·s + j (sample s of pixel j; the
// masks' bit order, transpose_4x4_bits in rast.h), kLanes at once — four samples with
// AVX-512, two with AVX2, one with SSE/NEON: a float vector of the target's width for
// depth, its 64-bit edge values in kPieces vectors of kPiece lanes (the widest each target
// holds in registers; GCC builds wider generic vectors, and broadcasts into them, through
// the stack).
struct SampleGroup {
  static constexpr int kPiece = SOFTPBR_TARGET_AVX512 ? 8 : 4;
  static constexpr int kLanes = SOFTPBR_TARGET_AVX512 ? 16 : SOFTPBR_TARGET_AVX ? 8 : 4;
  static constexpr int kSamples = kLanes / 4;
  static constexpr int kPieces = kLanes / kPiece;
  using Piece = simd::native_t<std::int64_t, kPiece>;
  using Depths = simd::Lanes<kLanes, SOFTPBR_ISA>;
  using Floats = typename simd::detail::Native<kLanes>::f;

  // A quad's four lanes (pixel centres) repeated over a piece's samples.
  // (A preprocessor choice: `if constexpr` discards nothing outside a template.)
  static Piece repeat_quad(simd::native_t<std::int64_t, 4> e) {
#if SOFTPBR_TARGET_AVX512
    return __builtin_shufflevector(e, e, 0, 1, 2, 3, 0, 1, 2, 3);
#else
    return e;
#endif
  }
  // A piece's lanes from its samples' values, each repeated over the sample's four pixels.
  static Piece repeat_samples(const std::int64_t* sample_values) {
    using I4 = simd::native_t<std::int64_t, 4>;
    const I4 a = I4{} + sample_values[0];
#if SOFTPBR_TARGET_AVX512
    return __builtin_shufflevector(a, I4{} + sample_values[1], 0, 1, 2, 3, 4, 5, 6, 7);
#else
    return a;
#endif
  }
  static unsigned sign_bits(Piece v) {
#if SOFTPBR_TARGET_AVX512
    return simd::SOFTPBR_TARGET_NS::sign_bits8(v);
#else
    return simd::SOFTPBR_TARGET_NS::sign_bits(v);
#endif
  }
  // Two vectors of n floats as one of 2n.
  static simd::native_t<float, 8> join(simd::native_t<float, 4> a, simd::native_t<float, 4> b) {
    return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
  }
  static typename simd::detail::Native<16>::f join(simd::native_t<float, 8> a, simd::native_t<float, 8> b) {
    return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  }
  // kLanes floats from the group's pieces, or from its samples' 4-float rows.
  template <int N>
  static Floats join_all(const simd::native_t<float, N>* parts) {
    if constexpr (N == kLanes) return parts[0];
    else if constexpr (2 * N == kLanes) return join(parts[0], parts[1]);
    else return join(join(parts[0], parts[1]), join(parts[2], parts[3]));
  }
};

// Covered pixels waiting for a packet shader (W lanes; W = 0, the scalar path, keeps one
// unused): the FragmentPacket the shader reads, filled lane by lane, so a full packet is
// shaded where it was written, without a copy.
struct NoPacketUniforms {};

// The shader's per-draw uniforms for packets of F (shader.h, PacketUniformsFor), if it has
// them and packets are shaded (W > 0).
template <int W, class F, class S>
inline auto packet_uniforms_of(const S& shader) {
  if constexpr (W > 0 && PacketUniformsFor<S, F>) return shader.template packet_uniforms<F>();
  else return NoPacketUniforms{};
}

template <int W, Shader S>
struct Packet {
  static constexpr int kW = W > 0 ? W : 1;
  using F = std::conditional_t<kW == 1, float, simd::Lanes<kW, SOFTPBR_ISA>>;
  static constexpr int kN = kVaryingCount<typename S::Varyings>;
  // Built once per draw and tile; flush_packet hands them to every packet.
  const decltype(packet_uniforms_of<W, F>(std::declval<const S&>())) uniforms;
  FragmentPacket<F, typename S::Varyings> p;
  // Varyings are interpolated kW lanes at a time, not per quad: a lane keeps its
  // perspective-correct weights of vertices 1 and 2 (b1, b2), and the lanes
  // [run_start, count) all come from one triangle, whose v0, v1 − v0 and v2 − v0 are kept
  // here until the run ends (finish_run: at the next triangle or when the packet is shaded).
  F b1, b2;
  F v0[kN > 0 ? kN : 1], d1[kN > 0 ? kN : 1], d2[kN > 0 ? kN : 1];  // broadcast once per triangle
  int run_start = 0;
  std::size_t index[kW];  // pixel index in the target
  // MSAA: the samples of each lane's pixel that are covered and passed the depth test (bit
  // s: sample s), and their depths and where its sample 0's is stored (alpha-tested draws
  // test and write them when flushing).
  std::uint8_t sample_mask[kW];
  float sample_depth[kW][kMaxSamples];
  float* depth_at[kW];
  int count = 0;
  ShadeCounts shaded;  // for the tile: flush_packet adds each packet (the scalar path each pixel)

  explicit Packet(const S& shader) : uniforms(packet_uniforms_of<W, F>(shader)) {
    // Derivatives the shader does not read stay zero.
    for (auto& d : p.ddx) d = F(0.0f);
    for (auto& d : p.ddy) d = F(0.0f);
    p.front_facing = true;
  }
};

// Lane `lane` of a packet's lane vector, written through its bytes (a float or simd::Lanes).
template <class F>
inline void put_lane(F& lanes, int lane, float x) {
  __builtin_memcpy(reinterpret_cast<char*>(&lanes) + static_cast<std::size_t>(lane) * sizeof(float), &x, sizeof x);
}
template <class F>
inline float get_lane(const F& lanes, int lane) {
  float x;
  __builtin_memcpy(&x, reinterpret_cast<const char*>(&lanes) + static_cast<std::size_t>(lane) * sizeof(float),
                   sizeof x);
  return x;
}
// Lanes [lane, lane + 4) at once (lane + 4 ≤ W).
template <class F>
inline void put_4_lanes(F& lanes, int lane, const float* x) {
  __builtin_memcpy(reinterpret_cast<char*>(&lanes) + static_cast<std::size_t>(lane) * sizeof(float), x,
                   4 * sizeof(float));
}

// Interpolates the varyings of the run's lanes [b.run_start, end) from their weights,
// v0 + b1·(v1 − v0) + b2·(v2 − v0): the operations raster_triangle would do per quad, in
// the same order, on the packet's width. Lanes below run_start keep their values; lanes
// from end on may change (they are written later, or are padding).
template <int W, class S>
inline void finish_run(Packet<W, S>& b, int end) {
  constexpr int kN = Packet<W, S>::kN;
  if (end <= b.run_start) return;
  const auto value = [&](int k) { return b.v0[k] + b.b1 * b.d1[k] + b.b2 * b.d2[k]; };
  if constexpr (W > 1) {
    if (b.run_start > 0) {
      const auto earlier = simd::SOFTPBR_TARGET_NS::first_lanes<W>(b.run_start);
      for (int k = 0; k < kN; ++k) b.p.v[k] = simd::select(earlier, b.p.v[k], value(k));
      b.run_start = end;
      return;
    }
  }
  for (int k = 0; k < kN; ++k) b.p.v[k] = value(k);
  b.run_start = end;
}

// Shades the buffered lanes with fragment_packet<Lanes<W>> (or <float> for W = 1), writes
// them. Depth was written when the lanes passed the depth test (see raster_triangle);
// colour is written here in lane order, so a pixel that two buffered triangles cover ends
// up blended in submission order.
template <int W, int kMs, class S>
void flush_packet(const S& shader, Packet<W, S>& b, const DrawState& state, const TargetPixels& target) {
  glm::vec4* const colors = target.colors;
  float* const depths = target.depths;
  using F = typename Packet<W, S>::F;
  SOFTPBR_DCHECK(b.count >= 0 && b.count <= W);
  if (b.count == 0) return;
  b.shaded.invocations += static_cast<std::uint64_t>(b.count);
  b.shaded.calls += 1;
  FragmentPacket<F, typename S::Varyings>& p = b.p;
  if constexpr (W > 1) {
    for (int lane = b.count; lane < W; ++lane) {  // pad with copies of lane 0: finite, discarded
      put_lane(b.b1, lane, get_lane(b.b1, 0));
      put_lane(b.b2, lane, get_lane(b.b2, 0));
      for (const int k : kDerivativeIndices<S>) {
        put_lane(p.ddx[k], lane, get_lane(p.ddx[k], 0));
        put_lane(p.ddy[k], lane, get_lane(p.ddy[k], 0));
      }
      put_lane(p.pos_x, lane, get_lane(p.pos_x, 0));
      put_lane(p.pos_y, lane, get_lane(p.pos_y, 0));
      put_lane(p.depth, lane, get_lane(p.depth, 0));
    }
  }
  finish_run(b, W);  // the padding too: lane 0's weights on the last triangle, finite
  const Color<F> c = [&] {
    if constexpr (PacketUniformsFor<S, F>) return shader.template fragment_packet<F>(p, b.uniforms);
    else return shader.template fragment_packet<F>(p);
  }();
  // Lane i's colour as out[4i .. 4i + 3], RGBA: a whole pixel per 16-byte copy.
  alignas(64) float out[4 * W];
  if constexpr (W == 1) {
    out[0] = c.r, out[1] = c.g, out[2] = c.b, out[3] = c.a;
  } else {
    simd::store_interleave4<W>(c.r, c.g, c.b, c.a, out);
  }
  [[maybe_unused]] const auto color = [&](int lane) {
    glm::vec4 v;
    __builtin_memcpy(&v, out + 4 * lane, sizeof v);
    return v;
  };
  if constexpr (kMs > 1) {
    for (int lane = 0; lane < b.count; ++lane)
      write_samples<kMs>(state, color(lane), b.sample_mask[lane], b.sample_depth[lane], b.index[lane],
                         state.alpha_test ? b.depth_at[lane] : nullptr, target);  // set for alpha tests only
  } else if (state.alpha_test) {  // the blend mode decided once per packet: replacing does not read the target
    // Lanes in submission order, each tested against the depths the lanes before it wrote.
    for (int lane = 0; lane < b.count; ++lane) {
      if (!(out[4 * lane + 3] >= state.alpha_ref)) continue;
      const std::size_t idx = b.index[lane];
      const float z = get_lane(p.depth, lane);
      if (!depth_passes(state.depth_test, z, depths[idx])) continue;
      if (state.depth_write) depths[idx] = z;
      if constexpr (!kDepthOnly<S>) {
        glm::vec4 c = color(lane);
        if (state.alpha_to_coverage) c.a = 1.0f;  // one sample: the alpha test, then alpha to one
        colors[idx] = blend(state.blend, c, colors[idx]);
      }
    }
  } else if constexpr (kDepthOnly<S>) {
    // Never reached: a depth-only draw without the alpha test fills no packet.
  } else if (state.blend == Blend::Replace) {
    for (int lane = 0; lane < b.count; ++lane) colors[b.index[lane]] = color(lane);
  } else {
    for (int lane = 0; lane < b.count; ++lane) {
      const std::size_t idx = b.index[lane];
      colors[idx] = blend(state.blend, color(lane), colors[idx]);
    }
  }
  b.count = 0;
  b.run_start = 0;
}

// Walking a row of quads only where the triangle may be. Edge i is
// e(x, y) = a·x + b·y + c in fixed point; over the two pixel squares of a quad row
// ([X, X + 2 px] × [Y, Y + 2 px], which hold every pixel centre and MSAA sample of the
// quads) it is largest at a corner. With r = max over the row's two y of b·y + c, a quad
// at X can hold a point with e ≥ 0 only if a·X + r ≥ −2 px·a (a > 0) or a·X + r ≥ 0
// (a < 0). The crossing −r/a is found in double through a reciprocal of a, and the bound
// widened by a pixel each way: the error of two roundings on |r/a| < 2^51 is far below a
// pixel, so no quad with a covered sample is skipped, and the exact per-lane test still
// decides every pixel. The walk visits the same covered quads in the same order: the
// same bits, fewer empty quads.
inline constexpr int kMinClippedSpan = 8;  // pixels between a triangle's first and last quad

struct RowSpanEdges {
  double inv_a[3];  // 1 / a (0 when a = 0)
};

inline RowSpanEdges row_span_edges(const Triangle& t) {
  RowSpanEdges r{};
  for (int i = 0; i < 3; ++i) r.inv_a[i] = t.a[i] != 0 ? 1.0 / static_cast<double>(t.a[i]) : 0.0;
  return r;
}

// Narrows [qx_first, qx_last] (even quad x, inclusive) to the quads of row qy that may
// hold a covered sample; false when none may.
inline bool span_of_row(const Triangle& t, const RowSpanEdges& edges, int qy, int& qx_first, int& qx_last) {
  constexpr std::int64_t kStep = kSubpixelScale;
  const std::int64_t y_top = std::int64_t{qy} * kStep, y_bottom = y_top + 2 * kStep;
  // Pixel bounds, kept within a few pixels of the walk so that the conversions stay small.
  double lo = qx_first - 4, hi = qx_last + 4;
  for (int i = 0; i < 3; ++i) {
    const std::int64_t a = t.a[i], b = t.b[i];
    const std::int64_t r = b * (b > 0 ? y_bottom : y_top) + t.c[i];
    if (a == 0) {
      if (r < 0) return false;
      continue;
    }
    // The edge crosses zero at x = −r/a (fixed point), in pixels:
    const double cross = -static_cast<double>(r) * edges.inv_a[i] * (1.0 / kStep);
    if (a > 0) lo = std::max(lo, cross - 3.0);  // X ≥ cross − 2 px, less a pixel of margin
    else hi = std::min(hi, cross + 1.0);        // X ≤ cross, plus a pixel of margin
  }
  if (!(lo <= hi)) return false;
  const int first = std::max(qx_first, static_cast<int>(std::floor(lo)) & ~1);
  const int last = std::min(qx_last, static_cast<int>(std::floor(hi)));
  if (first > last) return false;
  qx_first = first;
  qx_last = last;
  return true;
}

// W = 0: the shader's scalar fragment(); W ≥ 1: packets of W lanes through fragment_packet.
// Packets fill across the triangles of a tile (one facing per packet): small triangles
// still shade full packets. `packet` carries the lanes waiting from earlier triangles.
template <int W, int kMs, Shader S>
void raster_triangle(const S& shader, const DrawGeometry& geometry, const TriangleChunk& chunk,
                     const Triangle& t, const TileRect& tile, const TargetPixels& target, Packet<W, S>& packet) {
  using V = typename S::Varyings;
  constexpr int kN = kVaryingCount<V>;
  constexpr std::int64_t kStep = kSubpixelScale;  // one pixel in fixed point
  constexpr std::int64_t kHalf = kSubpixelScale / 2;

  // Quads cover [x0, x1] × [y0, y1]; tile origins are even, so x0, y0 stay inside it.
  SOFTPBR_DCHECK(tile.x0 % 2 == 0 && tile.y0 % 2 == 0);
  const int x0 = std::max(t.min_x, tile.x0) & ~1;
  const int y0 = std::max(t.min_y, tile.y0) & ~1;
  const int x1 = std::min(t.max_x, tile.x1 - 1);
  const int y1 = std::min(t.max_y, tile.y1 - 1);
  if (x0 > x1 || y0 > y1) return;

  // Varyings as v0 + λ1·(v1 − v0) + λ2·(v2 − v0), with perspective-correct λ: each term
  // broadcast to a quad's four lanes once per triangle, not once per quad (for the scalar
  // path, and for the varyings whose derivatives a packet shader reads; packets take the
  // rest from finish_run).
  const float* p0 = geometry.varyings(chunk, t.vertex[0]);
  const float* p1 = geometry.varyings(chunk, t.vertex[1]);
  const float* p2 = geometry.varyings(chunk, t.vertex[2]);
  using V4 = simd::Lanes<4, SOFTPBR_ISA>;
  V4 v0[kN > 0 ? kN : 1], d1[kN > 0 ? kN : 1], d2[kN > 0 ? kN : 1];
  for (int k = 0; k < kN; ++k) {
    v0[k] = V4(p0[k]);
    d1[k] = V4(p1[k] - p0[k]);
    d2[k] = V4(p2[k] - p0[k]);
  }

  const DrawState& state = geometry.state;
  // Copied out of the state: the kernel's stores (depths, packet lanes) would otherwise
  // make the compiler reload them for every lane.
  const DepthTest depth_test = state.depth_test;
  const bool depth_write = state.depth_write;
  // An alpha-tested draw writes depth after shading (flush_packet), not here.
  const bool early_depth_write = depth_write && !state.alpha_test;
  const int width = target.width;
  const std::size_t origin = target.origin;  // the index of pixel (0, 0) (TargetPixels)
  glm::vec4* colors = target.colors;
  float* depths = target.depths;
  if constexpr (W > 0) {
    if (packet.p.front_facing != t.front_facing) {
      flush_packet<W, kMs>(shader, packet, state, target);
      packet.p.front_facing = t.front_facing;
    }
    // The lanes of earlier triangles are interpolated; this one's run begins.
    finish_run(packet, packet.count);
    for (int k = 0; k < kN; ++k) {
      packet.v0[k] = typename Packet<W, S>::F(p0[k]);
      packet.d1[k] = typename Packet<W, S>::F(p1[k] - p0[k]);
      packet.d2[k] = typename Packet<W, S>::F(p2[k] - p0[k]);
    }
  }

  // The edge functions of a quad's four lanes as one vector of 64-bit integers per edge:
  // the lane-0 value plus these steps, kept in registers.
  using I64x4 = simd::native_t<std::int64_t, 4>;
  const auto lane_step = [&](int i) {
    const std::int64_t a = t.a[i], b = t.b[i];
    return I64x4{0, a * kStep, b * kStep, (a + b) * kStep};
  };
  // Three named values, not an array, so that they stay in registers.
  const I64x4 step0 = lane_step(0), step1 = lane_step(1), step2 = lane_step(2);
  // From one quad to the next along a row: two pixels.
  const I64x4 quad_step0 = I64x4{} + std::int64_t{t.a[0]} * (2 * kStep);
  const I64x4 quad_step1 = I64x4{} + std::int64_t{t.a[1]} * (2 * kStep);
  const I64x4 quad_step2 = I64x4{} + std::int64_t{t.a[2]} * (2 * kStep);
  const auto to_float = [](I64x4 e) { return simd::SOFTPBR_TARGET_NS::to_float_below_2p51(e); };
  // MSAA: the sample lanes of group g (SampleGroup: samples g·kSamples …) run as its
  // pieces; group_edge[g][i][p] holds edge i at piece p's sample lanes minus its value at
  // the lane's pixel centre, i.e. the sample's offset (1/16 pixel, 16 fixed-point units),
  // added to the quad's centre values repeated (repeat_quad); group_weight[g][i − 1][p] the
  // same for edges 1 and 2 with their bias added, the unbiased values the depth plane
  // takes. Exact integers, so a sample's values are those of its own plane equation,
  // whichever way the sum is grouped.
  using G = SampleGroup;
  constexpr int kSamples = kMs > 1 ? kMs : 1;
  constexpr int kGroups = kMs > 1 ? kMs / G::kSamples : 1;
  [[maybe_unused]] typename G::Piece group_edge[kGroups][3][G::kPieces], group_weight[kGroups][2][G::kPieces];
  if constexpr (kMs > 1) {
    const SampleOffset* offsets = kMs == 4 ? kSamplePattern4 : kSamplePattern8;
    std::int64_t offset[3][kSamples], weight[2][kSamples];
    for (int s = 0; s < kMs; ++s) {
      for (int i = 0; i < 3; ++i)
        offset[i][s] = std::int64_t{t.a[i]} * (offsets[s].x * 16) + std::int64_t{t.b[i]} * (offsets[s].y * 16);
      weight[0][s] = offset[1][s] + t.bias[1];
      weight[1][s] = offset[2][s] + t.bias[2];
    }
    constexpr int kPieceSamples = G::kPiece / 4;
    for (int g = 0; g < kGroups; ++g)
      for (int p = 0; p < G::kPieces; ++p) {
        const int s = g * G::kSamples + p * kPieceSamples;
        for (int i = 0; i < 3; ++i) group_edge[g][i][p] = G::repeat_samples(&offset[i][s]);
        for (int i = 0; i < 2; ++i) group_weight[g][i][p] = G::repeat_samples(&weight[i][s]);
      }
  }
  // A row of quads is walked only over the quads where every edge function can be ≥ 0
  // (span_of_row): the others would find no sample inside. Worth its three divisions per
  // triangle when the triangle spans a few quads across the tile.
  const bool clip_rows = x1 - x0 >= kMinClippedSpan;
  const RowSpanEdges span_edges = clip_rows ? row_span_edges(t) : RowSpanEdges{};
  // MSAA: a quad's 4 · kMs depths are consecutive (target.h, depth_index), its samples'
  // rows of four at [4 · s]; quads_per_row of them a row.
  [[maybe_unused]] const std::size_t quads_per_row = static_cast<std::size_t>(target.width + 1) / 2;
  for (int qy = y0; qy <= y1; qy += 2) {
    const std::int64_t sy = qy * kStep + kHalf;
    [[maybe_unused]] const std::size_t row_quads = static_cast<std::size_t>((qy - target.y0) >> 1) * quads_per_row;
    // Lanes 2 and 3 (the quad's lower row) exist only inside the tile.
    const unsigned rows = qy + 1 < tile.y1 ? 0xFu : 0x3u;
    const std::int64_t row0 = t.b[0] * sy + t.c[0], row1 = t.b[1] * sy + t.c[1], row2 = t.b[2] * sy + t.c[2];
    int qx_first = x0, qx_last = x1;
    if (clip_rows && !span_of_row(t, span_edges, qy, qx_first, qx_last)) continue;
    // The edge values of the row's first quad, then stepped a quad at a time: integer
    // additions, exact, so each quad gets the values its own plane equation gives.
    const std::int64_t sx_first = qx_first * kStep + kHalf;
    I64x4 e0 = (I64x4{} + (t.a[0] * sx_first + row0)) + step0;
    I64x4 e1 = (I64x4{} + (t.a[1] * sx_first + row1)) + step1;
    I64x4 e2 = (I64x4{} + (t.a[2] * sx_first + row2)) + step2;
    for (int qx = qx_first; qx <= qx_last; qx += 2, e0 += quad_step0, e1 += quad_step1, e2 += quad_step2) {
      // Lanes: 0 = (qx, qy), 1 = (qx+1, qy), 2 = (qx, qy+1), 3 = (qx+1, qy+1).
      const int lane_x[4] = {qx, qx + 1, qx, qx + 1};
      const int lane_y[4] = {qy, qy, qy + 1, qy + 1};
      // Lane j's pixel in the target's arrays (TargetPixels: y · width + x − origin).
      // Arithmetic on j, not the arrays: the append below indexes by a table entry.
      const std::size_t quad_index = static_cast<std::size_t>(qy) * width + qx - origin;  // lane 0's, (qx, qy)
      const auto pixel_index = [&](int j) {
        return quad_index + static_cast<std::size_t>(j >> 1) * width + static_cast<std::size_t>(j & 1);
      };
      // A lane is inside when all three edge values are non-negative: the sign bit of
      // their OR is clear.
      const unsigned in_tile = rows & (qx + 1 < tile.x1 ? 0xFu : 0x5u);
      unsigned mask;
      // MSAA: covered[g] has bit 4·s + j when sample g·kSamples + s of lane j is inside.
      [[maybe_unused]] unsigned covered[kGroups];
      if constexpr (kMs == 1) {
        mask = ~simd::SOFTPBR_TARGET_NS::sign_bits(e0 | e1 | e2) & in_tile;
      } else {
        constexpr unsigned kEvery = 0x1111u & ((1u << G::kLanes) - 1);  // lane 0 of each sample
        unsigned any = 0;
        for (int g = 0; g < kGroups; ++g) {
          unsigned outside = 0;
          for (int p = 0; p < G::kPieces; ++p)
            outside |= G::sign_bits((G::repeat_quad(e0) + group_edge[g][0][p]) |
                                    (G::repeat_quad(e1) + group_edge[g][1][p]) |
                                    (G::repeat_quad(e2) + group_edge[g][2][p]))
                       << (G::kPiece * p);
          covered[g] = ~outside & (in_tile * kEvery);
          any |= covered[g];
        }
        if (any == 0) continue;  // before the fold to pixels: a shorter wait for the branch
        mask = pixels_of_sample_lanes(any);
      }
      if (mask == 0) continue;

      // Unbiased edge values as floats: the screen-space barycentric weights × 2·area,
      // each rounded once (to_float_below_2p51: edge values stay below 2^50).
      // From here the four lanes run as one simd::Vec<4>, each lane the same IEEE
      // operations in the same order as one pixel would take alone.
      const V4 w0(to_float(e0 + static_cast<std::int64_t>(t.bias[0])));
      const V4 w1(to_float(e1 + static_cast<std::int64_t>(t.bias[1])));
      const V4 w2(to_float(e2 + static_cast<std::int64_t>(t.bias[2])));

      // Early depth test (shaders cannot change depth): a passing pixel's depth is written
      // now, so later triangles test against it even while its colour waits in a packet —
      // unless the draw's alpha test may still discard it.
      alignas(16) float z[4];
      const V4 zq = simd::clamp(V4(t.z0) + w1 * V4(t.inv_area) * V4(t.dz1) + w2 * V4(t.inv_area) * V4(t.dz2),
                                V4(0.0f), V4(1.0f));
      zq.store(z);
      // A quad wholly inside the tile (every quad but those on an odd image edge) tests
      // its four depths (a sample's, with MSAA) as one vector: two 2-float rows loaded,
      // compared, and written back with the passing lanes replaced (the others keep their
      // own bits; the tile has one writer).
      const bool whole_quad = in_tile == 0xFu;
      const auto test_quad = [&](float* plane_depths, V4 zv, unsigned lanes) {
        alignas(16) float stored[4];
        __builtin_memcpy(stored, plane_depths + quad_index, 2 * sizeof(float));
        __builtin_memcpy(stored + 2, plane_depths + quad_index + width, 2 * sizeof(float));
        const V4 old = V4::load(stored);
        if (depth_test == DepthTest::Less) lanes &= simd::SOFTPBR_TARGET_NS::mask_bits(zv < old);
        else if (depth_test == DepthTest::LessEqual) lanes &= simd::SOFTPBR_TARGET_NS::mask_bits(zv <= old);
        if (early_depth_write) {  // also when none passed (no branch on it): the same bits
          simd::select(simd::SOFTPBR_TARGET_NS::mask_from_bits(lanes), zv, old).store(stored);
          __builtin_memcpy(plane_depths + quad_index, stored, 2 * sizeof(float));
          __builtin_memcpy(plane_depths + quad_index + width, stored + 2, 2 * sizeof(float));
        }
        return lanes;
      };
      // MSAA: depth per sample from the same plane equation at the sample, tested and
      // written per sample; lane_samples[j] keeps the samples of lane j that passed.
      alignas(64) float sample_z[kSamples][4];  // [s][j]: group g's sample lanes at [g·kSamples]
      unsigned lane_samples[4] = {0, 0, 0, 0};
      [[maybe_unused]] float* const quad_depths =
          kMs == 1 ? depths : depths + (row_quads + static_cast<std::size_t>((qx - target.x0) >> 1)) * (4 * kSamples);
      if constexpr (kMs == 1) {
        if (whole_quad) {
          mask = test_quad(depths, zq, mask);
        } else {
          for (int j = 0; j < 4; ++j) {
            if (!(mask & (1u << j))) continue;
            const std::size_t idx = pixel_index(j);
            if (!depth_passes(depth_test, z[j], depths[idx])) mask &= ~(1u << j);
            else if (early_depth_write) depths[idx] = z[j];
          }
        }
      } else {
        mask = 0;
        for (int g = 0; g < kGroups; ++g) {
          if (covered[g] == 0) continue;
          // The group's depths, as the 4-lane form computes a pixel centre's.
          const auto weights = [&](I64x4 e, int i) {
            simd::native_t<float, G::kPiece> parts[G::kPieces];
            for (int p = 0; p < G::kPieces; ++p)
              parts[p] = simd::SOFTPBR_TARGET_NS::to_float_below_2p51_n<G::kPiece>(G::repeat_quad(e) +
                                                                                   group_weight[g][i][p]);
            return typename G::Depths(G::join_all<G::kPiece>(parts));
          };
          using D = typename G::Depths;
          const D l1 = weights(e1, 0) * D(t.inv_area);
          const D l2 = weights(e2, 1) * D(t.inv_area);
          const D sz = simd::clamp(D(t.z0) + l1 * D(t.dz1) + l2 * D(t.dz2), D(0.0f), D(1.0f));
          sz.store(sample_z[g * G::kSamples]);
          unsigned passed;  // bit 4·s + j: sample g·kSamples + s of lane j passed
          if (whole_quad) {
            // The group's samples' 2×2 depths are consecutive in their quad: one vector,
            // compared at once and written back with the passing lanes replaced (the
            // others keep their own bits; the tile has one writer).
            float* const group_depths = quad_depths + g * G::kLanes;
            const D old = D::load(group_depths);
            passed = covered[g];
            if (depth_test == DepthTest::Less) passed &= simd::SOFTPBR_TARGET_NS::mask_bits(sz < old);
            else if (depth_test == DepthTest::LessEqual) passed &= simd::SOFTPBR_TARGET_NS::mask_bits(sz <= old);
            if (early_depth_write)  // also when none passed (no branch on it): the same bits
              simd::select(simd::SOFTPBR_TARGET_NS::mask_from_bits<G::kLanes>(passed), sz, old).store(group_depths);
          } else {
            passed = 0;
            for (unsigned b = covered[g]; b != 0; b &= b - 1) {
              const int k = std::countr_zero(b);  // lane 4·s' + j of the group: sample g·kSamples + s'
              float& stored = quad_depths[g * G::kLanes + k];
              const int s = g * G::kSamples + k / 4, j = k % 4;
              if (!depth_passes(depth_test, sample_z[s][j], stored)) continue;
              if (early_depth_write) stored = sample_z[s][j];
              passed |= 1u << k;
            }
          }
          mask |= pixels_of_sample_lanes(passed);
          const unsigned by_pixel = transpose_4x4_bits(passed);  // pixel j's samples in nibble j
          for (int j = 0; j < 4; ++j) lane_samples[j] |= ((by_pixel >> (4 * j)) & 0xFu) << (G::kSamples * g);
        }
      }
      if (mask == 0) continue;
      // A depth-only draw (shader.h, kDepthOnly) has written its depths above: nothing is
      // shaded, unless its alpha test decides which depths to keep.
      if constexpr (kDepthOnly<S>) {
        if (!state.alpha_test) continue;
      }

      // Perspective-correct varyings at all four lanes (helper lanes feed derivatives):
      // b1, b2 are the perspective-correct weights of vertices 1 and 2; beyond the
      // horizon (s ≤ 0, helper lanes only) they are 0, i.e. the lane takes v0.
      // The scalar path (W = 0) interpolates every varying here; packets interpolate at
      // their width from the weights (finish_run), and here only the varyings whose
      // derivatives the shader reads.
      alignas(16) float values[kN > 0 ? kN : 1][4];  // [varying][lane]
      alignas(16) float weight1[4], weight2[4];
      {
        const V4 a0 = w0 * V4(t.inv_w[0]);
        const V4 a1 = w1 * V4(t.inv_w[1]);
        const V4 a2 = w2 * V4(t.inv_w[2]);
        const V4 sum = a0 + a1 + a2;
        const auto ahead = sum > V4(0.0f);
        const V4 rs = V4(1.0f) / simd::select(ahead, sum, V4(1.0f));
        const V4 b1 = simd::select(ahead, a1 * rs, V4(0.0f));
        const V4 b2 = simd::select(ahead, a2 * rs, V4(0.0f));
        if constexpr (W == 0) {
          for (int k = 0; k < kN; ++k) (v0[k] + b1 * d1[k] + b2 * d2[k]).store(values[k]);
        } else {
          b1.store(weight1);
          b2.store(weight2);
          for (const int k : kDerivativeIndices<S>) (v0[k] + b1 * d1[k] + b2 * d2[k]).store(values[k]);
        }
      }
      // Coarse derivatives of the varyings the shader reads them of (zero for the others).
      float ddx[kN > 0 ? kN : 1] = {}, ddy[kN > 0 ? kN : 1] = {};
      for (const int k : kDerivativeIndices<S>) {
        ddx[k] = values[k][1] - values[k][0];
        ddy[k] = values[k][2] - values[k][0];
      }
      if constexpr (W == 0) {
        const V vddx = varyings_from_floats<V>(ddx);
        const V vddy = varyings_from_floats<V>(ddy);
        for (int j = 0; j < 4; ++j) {
          if (!(mask & (1u << j))) continue;
          float lane_values[kN > 0 ? kN : 1];
          for (int k = 0; k < kN; ++k) lane_values[k] = values[k][j];
          const Fragment<V> f{varyings_from_floats<V>(lane_values),
                              vddx,
                              vddy,
                              {static_cast<float>(lane_x[j]) + 0.5f, static_cast<float>(lane_y[j]) + 0.5f},
                              z[j],
                              t.front_facing};
          const glm::vec4 src = shader.fragment(f);
          packet.shaded.invocations += 1;
          packet.shaded.calls += 1;
          const std::size_t idx = pixel_index(j);
          if constexpr (kMs > 1) {
            float zs[kMs];
            for (int s = 0; s < kMs; ++s) zs[s] = sample_z[s][j];
            write_samples<kMs>(state, src, lane_samples[j], zs, idx, quad_depths + j, target);
          } else {
            [[maybe_unused]] glm::vec4 c = src;
            if (state.alpha_test) {
              if (!(src.a >= state.alpha_ref)) continue;
              if (depth_write) depths[idx] = z[j];
              if (state.alpha_to_coverage) c.a = 1.0f;  // one sample: the alpha test, then alpha to one
            }
            if constexpr (!kDepthOnly<S>) colors[idx] = blend(state.blend, c, colors[idx]);
          }
        }
      } else {
        FragmentPacket<typename Packet<W, S>::F, V>& p = packet.p;
        float px[4], py[4];  // the lanes' pixel centres
        for (int j = 0; j < 4; ++j) {
          px[j] = static_cast<float>(lane_x[j]) + 0.5f;
          py[j] = static_cast<float>(lane_y[j]) + 0.5f;
        }
        // What a lane keeps besides the shader's inputs: its pixel and, with MSAA, samples.
        const auto keep = [&](int lane, int j) {
          packet.index[lane] = pixel_index(j);
          if constexpr (kMs > 1) {
            packet.sample_mask[lane] = static_cast<std::uint8_t>(lane_samples[j]);
            if (state.alpha_test) {
              for (int s = 0; s < kMs; ++s) packet.sample_depth[lane][s] = sample_z[s][j];
              packet.depth_at[lane] = quad_depths + j;
            }
          }
        };
        if constexpr (W >= 4) {
          if (packet.count + 4 <= W) {
            // The quad's covered lanes into consecutive lanes from `count`, in their order:
            // per row one permutation that moves them to the front (simd compress4; the
            // identity for a whole quad) and one 4-float store. The lanes past the covered
            // ones are written too, and written again by the next quad or the padding. No
            // branch on the mask: along edges, and at MSAA on small triangles in most
            // quads, the covered lanes change from quad to quad, and the branches of a
            // per-lane append (or one for whole quads) were mispredicted.
            const int lane = packet.count;
            packet.count += std::popcount(mask);
            const auto put_covered = [&](auto& lanes, const float* x) {
              simd::native_t<float, 4> v;
              __builtin_memcpy(&v, x, sizeof v);
              v = simd::SOFTPBR_TARGET_NS::compress4(v, mask);
              float covered_lanes[4];
              __builtin_memcpy(covered_lanes, &v, sizeof v);
              put_4_lanes(lanes, lane, covered_lanes);
            };
            put_covered(packet.b1, weight1);
            put_covered(packet.b2, weight2);
            for (const int k : kDerivativeIndices<S>) {
              const float dx[4] = {ddx[k], ddx[k], ddx[k], ddx[k]};
              const float dy[4] = {ddy[k], ddy[k], ddy[k], ddy[k]};
              put_4_lanes(p.ddx[k], lane, dx);
              put_4_lanes(p.ddy[k], lane, dy);
            }
            put_covered(p.pos_x, px);
            put_covered(p.pos_y, py);
            put_covered(p.depth, z);
            const std::int32_t* const order = simd::detail::kCompress4[mask];
            for (int k = 0; k < 4; ++k) keep(lane + k, order[k]);
            if (packet.count == W) flush_packet<W, kMs>(shader, packet, state, target);
            continue;
          }
        }
        for (int j = 0; j < 4; ++j) {
          if (!(mask & (1u << j))) continue;
          SOFTPBR_DCHECK(packet.count < W);
          const int lane = packet.count++;
          put_lane(packet.b1, lane, weight1[j]);
          put_lane(packet.b2, lane, weight2[j]);
          for (const int k : kDerivativeIndices<S>) {
            put_lane(p.ddx[k], lane, ddx[k]);
            put_lane(p.ddy[k], lane, ddy[k]);
          }
          put_lane(p.pos_x, lane, px[j]);
          put_lane(p.pos_y, lane, py[j]);
          put_lane(p.depth, lane, z[j]);
          keep(lane, j);
          if (packet.count == W) flush_packet<W, kMs>(shader, packet, state, target);
        }
      }
    }
  }
}

// Rasterizes one draw's triangles that touch tile `tile` (rectangle `rect`) into `target`,
// W lanes at a time (W = 0: scalar fragment(), one pixel at a time), kMs samples a pixel.
template <int W, int kMs, Shader S>
SOFTPBR_KERNEL ShadeCounts raster_tile(const S& shader, const DrawGeometry& geometry, std::size_t tile,
                                       const TileRect& rect, const TargetPixels& target) {
  Packet<W, S> packet(shader);
  for (const TriangleChunk& chunk : geometry.chunks)
    for (const std::uint32_t i : chunk.tile(tile))
      raster_triangle<W, kMs>(shader, geometry, chunk, chunk.triangles[i], rect, target, packet);
  if constexpr (W > 0) flush_packet<W, kMs>(shader, packet, geometry.state, target);
  return packet.shaded;
}

}  // namespace softpbr::raster::detail::SOFTPBR_TARGET_NS
