// The lane operations of softpbr/simd on N lanes, as a kernel compiled once per target
// (test_simd.cpp includes it through softpbr/simd/foreach_target.h; no include guard, no
// header included here): what a new kernel looks like, with no dispatch of its own.

namespace simd_test::SOFTPBR_TARGET_NS {

namespace lanes = softpbr::simd::SOFTPBR_TARGET_NS;

// For lanes a[0..N), b[0..N): out[k·N + i] = operation k of (a[i], b[i]), kOps operations.
template <int N>
SOFTPBR_KERNEL void lane_ops(const float* a_in, const float* b_in, float* out) {
  namespace simd = softpbr::simd;
  using V = lanes::Vec<N>;
  const V a = V::load(a_in), b = V::load(b_in);
  V r[kOps];
  float x[4 * N];
  r[0] = a + b;
  r[1] = a - b;
  r[2] = a * b;
  r[3] = a / b;
  r[4] = -a;
  r[5] = simd::sqrt(a);
  r[6] = simd::min(a, b);
  r[7] = simd::max(a, b);
  r[8] = simd::clamp(a, V(-1.0f), V(1.0f));
  r[9] = simd::select(a < b, a, b);
  r[10] = simd::select(simd::both(a <= b, b >= V(0.0f)), V(1.0f), V(0.0f));
  r[11] = simd::select(!(a > b), a * V(2.0f), b);
  r[12] = V(simd::any(a > b) ? 1.0f : 0.0f);
  for (int i = 0; i < 4 * N; ++i) x[i] = a_in[i % N] + static_cast<float>(i);  // records of four floats
  V c0, c1, c2, c3;
  simd::load_deinterleave4<N>(x, c0, c1, c2, c3);
  r[13] = c0 + c1 * V(2.0f) + c2 * V(4.0f) - c3;
  r[14] = V(static_cast<float>(lanes::gather<N>(kTable, simd::bits_of(a) & 7u)[0]));
  for (int k = 0; k < kOps; ++k) r[k].store(out + k * N);
}

// The mask helpers: out[0] = sign_bits(e), out[1] = mask_bits(a < b) for lanes a[0..4),
// b[0..4), and out[2 + m] = mask_bits(mask_from_bits(m)) for every m in [0, 16).
SOFTPBR_KERNEL inline void mask_ops(const std::int64_t* e_in, const float* a_in, const float* b_in, unsigned* out) {
  using V = lanes::Vec<4>;
  softpbr::simd::native_t<std::int64_t, 4> e;
  __builtin_memcpy(&e, e_in, sizeof e);
  out[0] = lanes::sign_bits(e);
  out[1] = lanes::mask_bits(V::load(a_in) < V::load(b_in));
  for (unsigned m = 0; m < 16; ++m) out[2 + m] = lanes::mask_bits(lanes::mask_from_bits(m));
}

// out[4i + c] = channel c of lane i after store_interleave4 of a, b, −a, a·b (lanes
// a[0..N), b[0..N)).
template <int N>
SOFTPBR_KERNEL void interleave_ops(const float* a_in, const float* b_in, float* out) {
  using V = lanes::Vec<N>;
  const V a = V::load(a_in), b = V::load(b_in);
  softpbr::simd::store_interleave4<N>(a, b, -a, a * b, out);
}

// out = first_lanes<N>(n) ? a : b, lane by lane.
template <int N>
SOFTPBR_KERNEL void first_lanes_ops(int n, const float* a_in, const float* b_in, float* out) {
  using V = lanes::Vec<N>;
  softpbr::simd::select(lanes::first_lanes<N>(n), V::load(a_in), V::load(b_in)).store(out);
}

// Lane i of out's four vectors (out[c·N + i]) from the record at records[i], by
// load_deinterleave4 from pointers; then out[4N + i] = the fraction split_whole(x) returns
// for x[i], and whole[i] its whole part.
template <int N>
SOFTPBR_KERNEL void record_ops(const float* const* records, const float* x, std::uint32_t* whole, float* out) {
  using V = lanes::Vec<N>;
  V c[4];
  softpbr::simd::load_deinterleave4<N>(records, c[0], c[1], c[2], c[3]);
  for (int k = 0; k < 4; ++k) c[k].store(out + k * N);
  softpbr::simd::split_whole(V::load(x), whole).store(out + 4 * N);
}

// out[i] = to_float_below_2p51 of the four 64-bit integers in[0..4).
SOFTPBR_KERNEL inline void to_float_ops(const std::int64_t* in, float* out) {
  softpbr::simd::native_t<std::int64_t, 4> v;
  __builtin_memcpy(&v, in, sizeof v);
  const softpbr::simd::native_t<float, 4> f = lanes::to_float_below_2p51(v);
  __builtin_memcpy(out, &f, sizeof f);
}

// out[4m + k] = lane k of compress4(x, m) for every mask m in [0, 16).
SOFTPBR_KERNEL inline void compress_ops(const float* x_in, float* out) {
  softpbr::simd::native_t<float, 4> x;
  __builtin_memcpy(&x, x_in, sizeof x);
  for (unsigned m = 0; m < 16; ++m) {
    const softpbr::simd::native_t<float, 4> c = lanes::compress4(x, m);
    __builtin_memcpy(out + 4 * m, &c, sizeof c);
  }
}

// The mask tests on plain vectors and on LaneMask, N lanes: out[0] = mask_bits(a < b),
// out[1] = any_lane, out[2] = all_lanes of it; out[3], out[4]: any_lane, all_lanes of the
// LaneMask of the same comparison.
template <int N>
SOFTPBR_KERNEL void lane_mask_ops(const float* a_in, const float* b_in, unsigned* out) {
  using V = lanes::Vec<N>;
  const V a = V::load(a_in), b = V::load(b_in);
  const softpbr::simd::native_t<std::int32_t, N> less = a.v < b.v;
  out[0] = lanes::mask_bits(less);
  out[1] = lanes::any_lane(less);
  out[2] = lanes::all_lanes(less);
  out[3] = lanes::any_lane(a < b);
  out[4] = lanes::all_lanes(a < b);
}

// store_masked of v = load_vector(v_in) (N floats) to masked[0..N) with `bits`, and
// store_vector of v to whole + 1 (not a vector's alignment).
template <int N>
SOFTPBR_KERNEL void store_ops(const float* v_in, unsigned bits, float* masked, float* whole) {
  const auto v = lanes::load_vector<N>(v_in);
  lanes::store_masked<N>(masked, bits, v);
  lanes::store_vector<N>(whole + 1, v);
}

// out[0..16): gather_words(words, index); out[16..32), out[32..48): gather_word_pairs'
// first and second (index[0..16)).
SOFTPBR_KERNEL inline void gather_ops(const std::uint8_t* words, const std::int32_t* index_in, std::int32_t* out) {
  softpbr::simd::native_t<std::int32_t, 16> index;
  softpbr::simd::bits512_t first, second;
  __builtin_memcpy(&index, index_in, sizeof index);
  const softpbr::simd::bits512_t w = lanes::gather_words(words, index);
  lanes::gather_word_pairs(words, index, first, second);
  __builtin_memcpy(out, &w, sizeof w);
  __builtin_memcpy(out + 16, &first, sizeof first);
  __builtin_memcpy(out + 32, &second, sizeof second);
}

// floats[0..16) = lookup_floats256(float_table, code); bytes[0..64) =
// lookup_bytes256(byte_table, index), bytes[64..128) = permute_bytes(a, index, b),
// bytes[128..192) = blend_bytes(bits, a, b), then unpack_lo8, unpack_hi8, unpack_lo16,
// unpack_hi16 of a and b (64 bytes each), then load_bits512(index_in + 1).
SOFTPBR_KERNEL inline void byte_ops(const float* float_table, const std::int32_t* code_in,
                                    const std::uint8_t* byte_table, const std::uint8_t* index_in,
                                    const std::uint8_t* a_in, const std::uint8_t* b_in, std::uint64_t bits,
                                    float* floats, std::uint8_t* bytes) {
  using B = softpbr::simd::bits512_t;
  softpbr::simd::native_t<std::int32_t, 16> code;
  __builtin_memcpy(&code, code_in, sizeof code);
  const B index = lanes::load_bits512(index_in), a = lanes::load_bits512(a_in), b = lanes::load_bits512(b_in);
  const softpbr::simd::native_t<float, 16> f = lanes::lookup_floats256(float_table, code);
  __builtin_memcpy(floats, &f, sizeof f);
  const B r[8] = {lanes::lookup_bytes256(byte_table, index), lanes::permute_bytes(a, index, b),
                  lanes::blend_bytes(bits, a, b),      lanes::unpack_lo8(a, b),
                  lanes::unpack_hi8(a, b),             lanes::unpack_lo16(a, b),
                  lanes::unpack_hi16(a, b),            lanes::load_bits512(index_in + 1)};
  __builtin_memcpy(bytes, r, sizeof r);
}

}  // namespace simd_test::SOFTPBR_TARGET_NS
