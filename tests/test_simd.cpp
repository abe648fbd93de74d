// softpbr/simd: every lane operation gives, on every compiled target (baseline, AVX2,
// AVX-512 where the CPU has them) and at 4, 8 and 16 lanes, the bits the same operation
// gives on one float; dispatch picks the copy asked for. The operations on plain vectors
// (mask bits, stores, gathers, table lookups, byte permutes) also in their AVX-512 VBMI
// copy where the CPU has VBMI.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "softpbr/simd/dispatch.h"
#include "softpbr/simd/simd.h"

namespace simd = softpbr::simd;

namespace simd_test {
constexpr int kOps = 15;
constexpr std::uint32_t kTable[8] = {3, 1, 4, 1, 5, 9, 2, 6};
}  // namespace simd_test

#define SOFTPBR_TARGET_FILE "simd_ops-inl.h"
#define SOFTPBR_TARGET_ALSO_VBMI
#include "softpbr/simd/foreach_target.h"

namespace simd_test {
namespace {

// The operations of lane_ops on one lane, with floats.
void scalar_ops(const float* a_in, const float* b_in, int lane, int n, float* out) {
  const float a = a_in[lane], b = b_in[lane];
  float r[kOps];
  r[0] = a + b;
  r[1] = a - b;
  r[2] = a * b;
  r[3] = a / b;
  r[4] = -a;
  r[5] = simd::sqrt(a);
  r[6] = simd::min(a, b);
  r[7] = simd::max(a, b);
  r[8] = simd::clamp(a, -1.0f, 1.0f);
  r[9] = simd::select(a < b, a, b);
  r[10] = simd::select(simd::both(a <= b, b >= 0.0f), 1.0f, 0.0f);
  r[11] = simd::select(!(a > b), a * 2.0f, b);
  bool any = false;
  for (int i = 0; i < n; ++i) any = any || a_in[i] > b_in[i];
  r[12] = any ? 1.0f : 0.0f;
  const auto record = [&](int c) { return a_in[(4 * lane + c) % n] + static_cast<float>(4 * lane + c); };
  r[13] = record(0) + record(1) * 2.0f + record(2) * 4.0f - record(3);
  r[14] = static_cast<float>(kTable[std::bit_cast<std::uint32_t>(a_in[0]) & 7u]);
  for (int k = 0; k < kOps; ++k) out[k * n + lane] = r[k];
}

template <int N>
void run_lane_ops(simd::Isa isa, const float* a, const float* b, float* out) {
  SOFTPBR_DISPATCH(isa, lane_ops<N>)(a, b, out);
}

std::vector<simd::Isa> supported_isas() {
  std::vector<simd::Isa> isas;
  for (simd::Isa isa : {simd::Isa::Baseline, simd::Isa::Avx2, simd::Isa::Avx512})
    if (simd::supported(isa)) isas.push_back(isa);
  return isas;
}

template <int N>
void check_width(const std::vector<float>& values, std::mt19937& rng) {
  std::uniform_int_distribution<std::size_t> pick(0, values.size() - 1);
  std::size_t compared = 0, equal = 0;
  for (int round = 0; round < 400; ++round) {
    float a[N], b[N];
    for (int i = 0; i < N; ++i) a[i] = values[pick(rng)], b[i] = values[pick(rng)];
    float want[kOps * N];
    for (int i = 0; i < N; ++i) scalar_ops(a, b, i, N, want);
    for (simd::Isa isa : supported_isas()) {
      float got[kOps * N];
      run_lane_ops<N>(isa, a, b, got);
      for (int k = 0; k < kOps; ++k)
        for (int i = 0; i < N; ++i) {
          const std::uint32_t g = std::bit_cast<std::uint32_t>(got[k * N + i]);
          const std::uint32_t w = std::bit_cast<std::uint32_t>(want[k * N + i]);
          // NaN results compare as NaN (their payload is not part of the contract).
          ++compared;
          if (g == w || (std::isnan(got[k * N + i]) && std::isnan(want[k * N + i]))) {
            ++equal;
          } else {
            CAPTURE(std::string(simd::isa_name(isa)));
            CAPTURE(N);
            CAPTURE(k);
            CAPTURE(a[i]);
            CAPTURE(b[i]);
            CHECK(g == w);
          }
        }
    }
  }
  CHECK(compared == 400u * kOps * N * supported_isas().size());
  CHECK(equal == compared);
}

}  // namespace
}  // namespace simd_test

TEST_CASE("simd: every lane operation on every compiled target and width gives the bits of the float operation") {
  std::vector<float> values = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 2.0f, 3.0f, 1e-3f, -7.25f,
                               std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                               std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::denorm_min(),
                               std::numeric_limits<float>::min(), std::numeric_limits<float>::max(), 1e30f};
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> uniform(-4.0f, 4.0f);
  for (int i = 0; i < 200; ++i) values.push_back(uniform(rng));
  simd_test::check_width<4>(values, rng);
  simd_test::check_width<8>(values, rng);
  simd_test::check_width<16>(values, rng);
}

namespace simd_test {
namespace {
using Kernel = void (*)(const float*, const float*, float*);
Kernel chosen(simd::Isa isa) { return SOFTPBR_DISPATCH(isa, lane_ops<4>); }
}  // namespace
}  // namespace simd_test

TEST_CASE("simd: SOFTPBR_MAX_ISA lowers the instruction set the kernels run, never raises it") {
  using simd::Isa;
  CHECK(simd::capped_isa(Isa::Avx512, nullptr) == Isa::Avx512);
  CHECK(simd::capped_isa(Isa::Avx512, "avx2") == Isa::Avx2);
  CHECK(simd::capped_isa(Isa::Avx512, "baseline") == Isa::Baseline);
  CHECK(simd::capped_isa(Isa::Avx2, "baseline") == Isa::Baseline);
  CHECK(simd::capped_isa(Isa::Avx2, "avx2") == Isa::Avx2);
  CHECK(simd::capped_isa(Isa::Avx2, "avx512") == Isa::Avx2);
  CHECK(simd::capped_isa(Isa::Baseline, "avx2") == Isa::Baseline);
  CHECK(simd::capped_isa(Isa::Avx512, "AVX2") == Isa::Avx512);  // names are lower case
  CHECK(simd::capped_isa(Isa::Avx512, "") == Isa::Avx512);
  // This process: ctest's matrix_suites_avx2 runs the matrix suites with the cap set, and
  // there cpu_isa(), which the renderer and every dispatch read, must not be AVX-512.
  const char* cap = std::getenv("SOFTPBR_MAX_ISA");
  if (cap != nullptr && std::string(cap) == "avx2") CHECK(simd::cpu_isa() != Isa::Avx512);
  if (cap != nullptr && std::string(cap) == "baseline") CHECK(simd::cpu_isa() == Isa::Baseline);
}

TEST_CASE("simd: dispatch calls the copy of the kernel compiled for the instruction set asked for") {
  using simd::Isa;
  using simd_test::chosen;
  CHECK(simd::supported(Isa::Baseline));
  CHECK(simd::supported(simd::cpu_isa()));
  CHECK(simd::isa_name(Isa::Baseline) == "baseline");
  CHECK((chosen(Isa::Baseline) == &simd_test::baseline::lane_ops<4>));
#if SOFTPBR_SIMD_X86_TARGETS
  CHECK((chosen(Isa::Avx2) == &simd_test::avx2::lane_ops<4>));
  CHECK((chosen(Isa::Avx512) == &simd_test::avx512::lane_ops<4>));
  CHECK((chosen(Isa::Avx2) != chosen(Isa::Baseline)));
#else
  // Only the baseline copy is compiled (another architecture, or an unoptimized build):
  // every Isa falls back to it.
  CHECK((chosen(Isa::Avx2) == &simd_test::baseline::lane_ops<4>));
  CHECK((chosen(Isa::Avx512) == &simd_test::baseline::lane_ops<4>));
#endif
#if !SOFTPBR_SIMD_X86
  CHECK(!simd::supported(Isa::Avx2));
  CHECK(!simd::supported(Isa::Avx512));
#endif
}

namespace simd_test {
namespace {
using MaskKernel = void (*)(const std::int64_t*, const float*, const float*, unsigned*);
MaskKernel mask_kernel(simd::Isa isa) { return SOFTPBR_DISPATCH(isa, mask_ops); }
}  // namespace
}  // namespace simd_test

namespace simd_test {
namespace {
template <int N>
void check_interleave(std::mt19937& rng) {
  std::uniform_real_distribution<float> uniform(-4.0f, 4.0f);
  float a[N], b[N], out[4 * N];
  for (int i = 0; i < N; ++i) a[i] = uniform(rng), b[i] = uniform(rng);
  for (simd::Isa isa : supported_isas()) {
    CAPTURE(std::string(simd::isa_name(isa)));
    CAPTURE(N);
    SOFTPBR_DISPATCH(isa, interleave_ops<N>)(a, b, out);
    int wrong = 0;
    for (int i = 0; i < N; ++i) {
      const float want[4] = {a[i], b[i], -a[i], a[i] * b[i]};
      for (int c = 0; c < 4; ++c) wrong += std::bit_cast<std::uint32_t>(out[4 * i + c]) != std::bit_cast<std::uint32_t>(want[c]);
    }
    CHECK(wrong == 0);
  }
}
}  // namespace
}  // namespace simd_test

namespace simd_test {
namespace {
template <int N>
void check_first_lanes() {
  float a[N], b[N], out[N];
  for (int i = 0; i < N; ++i) a[i] = static_cast<float>(i + 1), b[i] = -static_cast<float>(i + 1);
  for (simd::Isa isa : supported_isas()) {
    CAPTURE(std::string(simd::isa_name(isa)));
    CAPTURE(N);
    for (int n = 0; n <= N; ++n) {
      CAPTURE(n);
      SOFTPBR_DISPATCH(isa, first_lanes_ops<N>)(n, a, b, out);
      int wrong = 0;
      for (int i = 0; i < N; ++i) wrong += out[i] != (i < n ? a[i] : b[i]);
      CHECK(wrong == 0);
    }
  }
}
}  // namespace
}  // namespace simd_test

TEST_CASE("simd: first_lanes(n) selects the first n lanes, at 4, 8 and 16 lanes on every target") {
  simd_test::check_first_lanes<4>();
  simd_test::check_first_lanes<8>();
  simd_test::check_first_lanes<16>();
}

namespace simd_test {
namespace {
// Records scattered over an array, in a shuffled order, read into lanes by pointer; and
// texel coordinates in [0, 2^24) split into whole and fraction as a static_cast does.
template <int N>
void check_records(std::mt19937& rng) {
  std::uniform_real_distribution<float> uniform(-4.0f, 4.0f);
  std::vector<float> pool(4 * 64);
  for (float& v : pool) v = uniform(rng);
  std::uniform_int_distribution<int> which(0, 63);
  std::uniform_real_distribution<float> coordinate(0.0f, 16777215.0f);
  const float* records[N];
  float x[N];
  for (int i = 0; i < N; ++i) {
    records[i] = pool.data() + 4 * which(rng);
    x[i] = i % 2 == 0 ? coordinate(rng) : uniform(rng) * uniform(rng) + 16.0f;
  }
  x[0] = 0.0f;
  x[N - 1] = 16777215.0f;
  for (simd::Isa isa : supported_isas()) {
    CAPTURE(std::string(simd::isa_name(isa)));
    CAPTURE(N);
    float out[5 * N];
    std::uint32_t whole[N];
    SOFTPBR_DISPATCH(isa, record_ops<N>)(records, x, whole, out);
    int wrong = 0;
    for (int i = 0; i < N; ++i) {
      for (int c = 0; c < 4; ++c) wrong += std::bit_cast<std::uint32_t>(out[c * N + i]) != std::bit_cast<std::uint32_t>(records[i][c]);
      const int w = static_cast<int>(x[i]);
      wrong += whole[i] != static_cast<std::uint32_t>(w);
      wrong += std::bit_cast<std::uint32_t>(out[4 * N + i]) != std::bit_cast<std::uint32_t>(x[i] - static_cast<float>(w));
    }
    CHECK(wrong == 0);
  }
}
}  // namespace
}  // namespace simd_test

TEST_CASE("simd: load_deinterleave4 from record pointers and split_whole, at 4, 8 and 16 lanes on every target") {
  std::mt19937 rng(9);
  for (int round = 0; round < 20; ++round) {
    simd_test::check_records<4>(rng);
    simd_test::check_records<8>(rng);
    simd_test::check_records<16>(rng);
  }
}

TEST_CASE("simd: store_interleave4 writes lane i's four values as record i at 4, 8 and 16 lanes on every target") {
  std::mt19937 rng(4);
  for (int round = 0; round < 20; ++round) {
    simd_test::check_interleave<4>(rng);
    simd_test::check_interleave<8>(rng);
    simd_test::check_interleave<16>(rng);
  }
}

namespace simd_test {
namespace {
using ToFloatKernel = void (*)(const std::int64_t*, float*);
ToFloatKernel to_float_kernel(simd::Isa isa) { return SOFTPBR_DISPATCH(isa, to_float_ops); }
}  // namespace
}  // namespace simd_test

TEST_CASE("simd: to_float_below_2p51 rounds 64-bit integers below 2^51 as a direct conversion does") {
  // Random magnitudes of every bit length up to 50 (the rasterizer's edge values), the
  // limits ±(2^51 − 1), and halfway cases between floats (ties to even) at several scales.
  std::mt19937_64 rng(7);
  std::vector<std::int64_t> values = {0, 1, -1, (std::int64_t{1} << 51) - 1, -((std::int64_t{1} << 51) - 1),
                                      (std::int64_t{1} << 24) + 1, (std::int64_t{1} << 24) + 3,
                                      -((std::int64_t{1} << 25) + 2), (std::int64_t{1} << 50) + (std::int64_t{1} << 26)};
  for (int bits = 1; bits <= 50; ++bits)
    for (int k = 0; k < 40; ++k) {
      const std::int64_t mag = static_cast<std::int64_t>(rng() >> (64 - bits));
      values.push_back(k % 2 ? -mag : mag);
      // A tie: a float's 24 bits, then a 1 and zeros below it.
      if (bits > 25) values.push_back(((mag >> (bits - 25)) | 1) << (bits - 25));
    }
  int checked = 0;
  for (std::size_t i = 0; i + 4 <= values.size(); i += 4) {
    for (simd::Isa isa : simd_test::supported_isas()) {
      float out[4];
      simd_test::to_float_kernel(isa)(&values[i], out);
      CAPTURE(std::string(simd::isa_name(isa)));
      for (int j = 0; j < 4; ++j) {
        CAPTURE(values[i + j]);
        CHECK(std::bit_cast<std::uint32_t>(out[j]) == std::bit_cast<std::uint32_t>(static_cast<float>(values[i + j])));
        ++checked;
      }
    }
  }
  CHECK(checked > 2000);
}

TEST_CASE("simd: sign_bits, mask_bits and mask_from_bits give lane i as bit i on every target") {
  std::mt19937_64 rng(99);
  const std::int64_t edge[] = {0, -1, 1, INT64_MIN, INT64_MAX, -(std::int64_t{1} << 40), std::int64_t{1} << 40};
  const float values[] = {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(),
                          std::numeric_limits<float>::infinity(), 2.5f};
  int checked = 0;
  for (int round = 0; round < 500; ++round) {
    std::int64_t e[4];
    float a[4], b[4];
    unsigned want_sign = 0, want_less = 0;
    for (int i = 0; i < 4; ++i) {
      e[i] = round % 2 ? edge[rng() % std::size(edge)] : static_cast<std::int64_t>(rng());
      a[i] = values[rng() % std::size(values)];
      b[i] = values[rng() % std::size(values)];
      want_sign |= e[i] < 0 ? 1u << i : 0u;
      want_less |= a[i] < b[i] ? 1u << i : 0u;
    }
    for (simd::Isa isa : simd_test::supported_isas()) {
      unsigned out[18];
      simd_test::mask_kernel(isa)(e, a, b, out);
      CAPTURE(std::string(simd::isa_name(isa)));
      CHECK(out[0] == want_sign);
      CHECK(out[1] == want_less);
      for (unsigned m = 0; m < 16; ++m) CHECK(out[2 + m] == m);
      ++checked;
    }
  }
  CHECK(checked == 500 * static_cast<int>(simd_test::supported_isas().size()));
}

namespace simd_test {
namespace {
using CompressKernel = void (*)(const float*, float*);
CompressKernel compress_kernel(simd::Isa isa) { return SOFTPBR_DISPATCH(isa, compress_ops); }
}  // namespace
}  // namespace simd_test

TEST_CASE("simd: compress4 moves the lanes of a mask's set bits to the front, in order and with their bits") {
  // Lanes with bits a conversion would change (−0, a signalling NaN's payload, a denormal).
  const float x[4] = {-0.0f, std::bit_cast<float>(0x7fa00001u), std::bit_cast<float>(0x00000003u), 1.5f};
  for (simd::Isa isa : simd_test::supported_isas()) {
    CAPTURE(std::string(simd::isa_name(isa)));
    float out[64];
    simd_test::compress_kernel(isa)(x, out);
    for (unsigned m = 0; m < 16; ++m) {
      CAPTURE(m);
      int k = 0;
      for (int i = 0; i < 4; ++i) {
        if (!(m & (1u << i))) continue;
        CHECK(std::bit_cast<std::uint32_t>(out[4 * m + k]) == std::bit_cast<std::uint32_t>(x[i]));
        ++k;
      }
      CHECK(k == std::popcount(m));
    }
  }
}

namespace simd_test {
namespace {

// Every copy of a kernel this CPU runs, with its target's name: the dispatch targets, and
// the AVX-512 VBMI copy where the CPU has VBMI.
template <class Fn>
struct Copy {
  std::string name;
  Fn fn;
};
template <class Fn>
std::vector<Copy<Fn>> copies_of([[maybe_unused]] Fn baseline, [[maybe_unused]] Fn avx2, [[maybe_unused]] Fn avx512,
                                [[maybe_unused]] Fn avx512vbmi) {
  std::vector<Copy<Fn>> copies = {{"baseline", baseline}};
#if SOFTPBR_SIMD_X86_TARGETS
  if (simd::supported(simd::Isa::Avx2)) copies.push_back({"avx2", avx2});
  if (simd::supported(simd::Isa::Avx512)) copies.push_back({"avx512", avx512});
  if (simd::cpu_has_avx512_vbmi()) copies.push_back({"avx512vbmi", avx512vbmi});
#endif
  return copies;
}
#if SOFTPBR_SIMD_X86_TARGETS
#define SIMD_TEST_COPIES(...)                                                                 \
  ::simd_test::copies_of(&::simd_test::baseline::__VA_ARGS__, &::simd_test::avx2::__VA_ARGS__, \
                         &::simd_test::avx512::__VA_ARGS__, &::simd_test::avx512vbmi::__VA_ARGS__)
#else
#define SIMD_TEST_COPIES(...)                                                                          \
  ::simd_test::copies_of(&::simd_test::baseline::__VA_ARGS__, &::simd_test::baseline::__VA_ARGS__, \
                         &::simd_test::baseline::__VA_ARGS__, &::simd_test::baseline::__VA_ARGS__)
#endif

template <int N>
void check_lane_masks(std::mt19937& rng) {
  const float values[] = {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), 2.5f};
  for (int round = 0; round < 200; ++round) {
    float a[N], b[N];
    for (int i = 0; i < N; ++i) {
      a[i] = values[rng() % std::size(values)];
      b[i] = values[rng() % std::size(values)];
      if (round % 4 == 0) a[i] = -2.0f, b[i] = 3.0f;  // every lane set
      if (round % 4 == 1) a[i] = 3.0f, b[i] = -2.0f;  // none
    }
    unsigned bits = 0;
    for (int i = 0; i < N; ++i) bits |= a[i] < b[i] ? 1u << i : 0u;
    const unsigned any = bits != 0, all = bits == (1u << N) - 1;
    for (const auto& copy : SIMD_TEST_COPIES(lane_mask_ops<N>)) {
      CAPTURE(copy.name);
      CAPTURE(N);
      unsigned out[5];
      copy.fn(a, b, out);
      CHECK(out[0] == bits);
      CHECK(out[1] == any);
      CHECK(out[2] == all);
      CHECK(out[3] == any);
      CHECK(out[4] == all);
    }
  }
}

template <int N>
void check_stores(std::mt19937& rng) {
  std::uniform_real_distribution<float> uniform(-4.0f, 4.0f);
  const float sentinel = -99.0f;
  for (int round = 0; round < 100; ++round) {
    float v_in[N + 1];  // read from v_in + 1: not a vector's alignment
    float* const v = v_in + 1;
    for (int i = 0; i < N; ++i) v[i] = uniform(rng);
    v[0] = -0.0f;
    const unsigned bits = round < 16 && N == 4 ? static_cast<unsigned>(round) : static_cast<unsigned>(rng()) & ((1u << N) - 1);
    for (const auto& copy : SIMD_TEST_COPIES(store_ops<N>)) {
      CAPTURE(copy.name);
      CAPTURE(N);
      CAPTURE(bits);
      float masked[N], whole[N + 2];
      for (float& x : masked) x = sentinel;
      for (float& x : whole) x = sentinel;
      copy.fn(v_in + 1, bits, masked, whole);
      int wrong = 0;
      for (int i = 0; i < N; ++i) {
        const float want = bits >> i & 1u ? v[i] : sentinel;
        wrong += std::bit_cast<std::uint32_t>(masked[i]) != std::bit_cast<std::uint32_t>(want);
        wrong += std::bit_cast<std::uint32_t>(whole[i + 1]) != std::bit_cast<std::uint32_t>(v[i]);
      }
      wrong += whole[0] != sentinel || whole[N + 1] != sentinel;
      CHECK(wrong == 0);
    }
  }
}

}  // namespace
}  // namespace simd_test

TEST_CASE("simd: mask_bits, any_lane and all_lanes of plain masks and LaneMasks at 4, 8 and 16 lanes on every target") {
  std::mt19937 rng(21);
  simd_test::check_lane_masks<4>(rng);
  simd_test::check_lane_masks<8>(rng);
  simd_test::check_lane_masks<16>(rng);
}

TEST_CASE("simd: load_vector, store_masked (the lanes of its bits, nothing else) and store_vector at any alignment") {
  std::mt19937 rng(22);
  simd_test::check_stores<4>(rng);
  simd_test::check_stores<8>(rng);
  simd_test::check_stores<16>(rng);
}

TEST_CASE("simd: gather_words and gather_word_pairs load each lane's words from an unaligned array on every target") {
  std::mt19937 rng(23);
  std::vector<std::uint8_t> storage(4 * 300 + 1);
  for (auto& x : storage) x = static_cast<std::uint8_t>(rng());
  const std::uint8_t* words = storage.data() + 1;  // not 4-byte aligned
  const auto word = [&](std::int32_t i) {
    std::int32_t w;
    std::memcpy(&w, words + 4 * static_cast<std::size_t>(i), 4);
    return w;
  };
  for (int round = 0; round < 100; ++round) {
    std::int32_t index[16];
    for (int i = 0; i < 16; ++i) index[i] = static_cast<std::int32_t>(rng() % 299);
    index[0] = 0;
    index[15] = 298;
    for (const auto& copy : SIMD_TEST_COPIES(gather_ops)) {
      CAPTURE(copy.name);
      std::int32_t out[48];
      copy.fn(words, index, out);
      int wrong = 0;
      for (int i = 0; i < 16; ++i) {
        wrong += out[i] != word(index[i]);
        wrong += out[16 + i] != word(index[i]);
        wrong += out[32 + i] != word(index[i] + 1);
      }
      CHECK(wrong == 0);
    }
  }
}

TEST_CASE("simd: lookup_floats256, lookup_bytes256, permute_bytes, blend_bytes, the unpacks and load_bits512 on every target") {
  std::mt19937 rng(24);
  // A float table with bits a conversion would change (−0, a signalling NaN, a denormal).
  std::vector<float> float_table(256);
  for (int i = 0; i < 256; ++i) float_table[i] = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
  float_table[0] = -0.0f;
  float_table[1] = std::bit_cast<float>(0x7fa00001u);
  float_table[255] = std::bit_cast<float>(0x00000003u);
  std::vector<std::uint8_t> byte_storage(257);
  for (auto& x : byte_storage) x = static_cast<std::uint8_t>(rng());
  const std::uint8_t* byte_table = byte_storage.data() + 1;  // any alignment
  for (int round = 0; round < 100; ++round) {
    std::int32_t code[16];
    std::uint8_t index[65], a[64], b[64];
    for (auto& c : code) c = static_cast<std::int32_t>(rng());  // bits above 7 ignored
    index[64] = static_cast<std::uint8_t>(rng());
    for (int i = 0; i < 64; ++i) {
      index[i] = static_cast<std::uint8_t>(rng());
      a[i] = static_cast<std::uint8_t>(rng());
      b[i] = static_cast<std::uint8_t>(rng());
    }
    code[0] = 255;
    code[1] = 0;
    index[0] = 255;
    index[1] = 0;
    index[2] = 127;
    index[3] = 128;
    const std::uint64_t bits = (static_cast<std::uint64_t>(rng()) << 32) | rng();
    // What each operation gives, byte by byte.
    std::uint8_t want[8][64];
    std::memcpy(want[7], index + 1, 64);
    for (int i = 0; i < 64; ++i) {
      want[0][i] = byte_table[index[i]];
      want[1][i] = (index[i] & 64) ? b[index[i] & 63] : a[index[i] & 63];
      want[2][i] = (bits >> i & 1u) ? b[i] : a[i];
    }
    for (int block = 0; block < 64; block += 16)
      for (int i = 0; i < 8; ++i) {
        want[3][block + 2 * i] = a[block + i], want[3][block + 2 * i + 1] = b[block + i];
        want[4][block + 2 * i] = a[block + 8 + i], want[4][block + 2 * i + 1] = b[block + 8 + i];
      }
    for (int block = 0; block < 64; block += 16)
      for (int u = 0; u < 4; ++u)
        for (int e = 0; e < 2; ++e) {
          want[5][block + 4 * u + e] = a[block + 2 * u + e], want[5][block + 4 * u + 2 + e] = b[block + 2 * u + e];
          want[6][block + 4 * u + e] = a[block + 8 + 2 * u + e], want[6][block + 4 * u + 2 + e] = b[block + 8 + 2 * u + e];
        }
    for (const auto& copy : SIMD_TEST_COPIES(byte_ops)) {
      CAPTURE(copy.name);
      float floats[16];
      std::uint8_t bytes[8 * 64];
      copy.fn(float_table.data(), code, byte_table, index, a, b, bits, floats, bytes);
      int wrong = 0;
      for (int i = 0; i < 16; ++i)
        wrong += std::bit_cast<std::uint32_t>(floats[i]) != std::bit_cast<std::uint32_t>(float_table[code[i] & 255]);
      CHECK(wrong == 0);
      for (int op = 0; op < 8; ++op) {
        CAPTURE(op);
        CHECK(std::memcmp(bytes + 64 * op, want[op], 64) == 0);
      }
    }
  }
}
