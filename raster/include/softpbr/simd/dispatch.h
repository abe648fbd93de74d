// softpbr/simd/dispatch.h — runs the copy of a kernel compiled for an instruction set.
//
// A kernel source compiled per target (softpbr/simd/foreach_target.h) defines a function
// f in the namespaces baseline, avx2 and avx512 (x86-64; baseline alone elsewhere).
// In the scope that holds those namespaces,
//   SOFTPBR_DISPATCH(isa, f)(args...)              a function
//   SOFTPBR_DISPATCH(isa, f<W, Shader>)(args...)   an instantiation of a template
// calls the copy for `isa`, which the CPU must support (simd::supported(isa); callers
// choose isa once, e.g. the Renderer at construction from simd::cpu_isa()). Like
// Highway's HWY_DYNAMIC_DISPATCH: one indirect call per kernel call, never per pixel.
#pragma once

#include "softpbr/simd/isa.h"

namespace softpbr::simd::detail {

template <class Fn>
constexpr Fn choose(Isa isa, Fn baseline, Fn avx2, Fn avx512) {
  switch (isa) {
    case Isa::Avx512: return avx512;
    case Isa::Avx2: return avx2;
    default: return baseline;
  }
}
template <class Fn>
constexpr Fn choose(Isa, Fn baseline) {
  return baseline;
}

}  // namespace softpbr::simd::detail

#if SOFTPBR_SIMD_X86_TARGETS
#define SOFTPBR_DISPATCH(isa, ...) \
  (::softpbr::simd::detail::choose((isa), &baseline::__VA_ARGS__, &avx2::__VA_ARGS__, &avx512::__VA_ARGS__))
#else
#define SOFTPBR_DISPATCH(isa, ...) (::softpbr::simd::detail::choose((isa), &baseline::__VA_ARGS__))
#endif
