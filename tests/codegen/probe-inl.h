// A 16-lane compare-and-select kernel compiled once per target (tests/codegen/probe.cpp
// includes it through softpbr/simd/foreach_target.h; no include guard, no header included
// here). tests/codegen/check_codegen.cmake disassembles its AVX-512 copy and fails when a
// lane compare comes out as scalar compares: GCC 12 compiled the lane operators, when they
// were friends defined in the class, without the region's target, and every 16-lane
// compare of the AVX-512 kernels became 16 vcomiss.

namespace codegen_probe::SOFTPBR_TARGET_NS {

using L16 = softpbr::simd::Lanes<16, SOFTPBR_ISA>;

// out = (b < a && b > 0.5) ? max(a·b, 1) : min(a − b, 2 − a)   — every lane operator kind.
__attribute__((noinline)) void compare_select16(const float* a_in, const float* b_in, float* out) {
  const L16 a = L16::load(a_in), b = L16::load(b_in);
  const auto m = (b < a) & !(b <= 0.5f);
  softpbr::simd::select(m, softpbr::simd::max(a * b, L16(1.0f)), softpbr::simd::min(a - b, 2.0f - a)).store(out);
}

}  // namespace codegen_probe::SOFTPBR_TARGET_NS
