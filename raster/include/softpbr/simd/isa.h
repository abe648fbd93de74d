// softpbr/simd/isa.h — the instruction sets kernels are compiled for, and which one runs.
//
// A kernel is one source compiled once per target (softpbr/simd/foreach_target.h) and
// chosen once at run time (softpbr/simd/dispatch.h). The targets:
//   Baseline — the build's own flags (x86-64 baseline is SSE2; on AArch64, NEON);
//   Avx2     — x86-64 with AVX2 (and AVX, POPCNT), whatever the build targets;
//   Avx512   — x86-64 with AVX-512 F, DQ, VL and BW.
// No target enables FMA, and the project compiles with -ffp-contract=off, so every target
// performs the same IEEE operations: the same bits (docs/design.md, "Determinism").
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string_view>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SOFTPBR_SIMD_X86 1
#else
#define SOFTPBR_SIMD_X86 0
#endif

// 1 where kernels are also compiled for AVX2 and AVX-512: x86-64 with GCC or Clang, in
// optimized builds. Unoptimized code (-O0, Debug) is not inlined across the per-target
// regions, and a call between functions compiled for different vector ABIs (a 32-byte
// lane vector passed in a ymm register, or in memory) corrupts the values: there every Isa
// runs the baseline copy of a kernel (SOFTPBR_DISPATCH falls back to it), with the same
// bits. cpu_isa() still reports the CPU, so the choice of lanes does not depend on it.
#if SOFTPBR_SIMD_X86 && defined(__OPTIMIZE__)
#define SOFTPBR_SIMD_X86_TARGETS 1
#else
#define SOFTPBR_SIMD_X86_TARGETS 0
#endif

namespace softpbr::simd {

enum class Isa : std::uint8_t { Baseline, Avx2, Avx512 };

// `found` lowered to the instruction set named by `cap` (SOFTPBR_MAX_ISA's value, or null)
// where that is narrower: "baseline", "avx2"; anything else leaves `found` as it is. Never
// raises it.
inline Isa capped_isa(Isa found, const char* cap) {
  const std::string_view name = cap != nullptr ? cap : "";
  if (name == "baseline") return Isa::Baseline;
  if (name == "avx2" && found == Isa::Avx512) return Isa::Avx2;
  return found;
}

// The widest instruction set of this CPU (and OS) that a dispatched kernel can use
// (Baseline off x86-64), capped by the environment's SOFTPBR_MAX_ISA (capped_isa): the
// AVX2 kernels benchmarked and tested on an AVX-512 CPU. The bits are the same either
// way. Decided once, on first call.
inline Isa cpu_isa() {
#if SOFTPBR_SIMD_X86
  static const Isa isa = [] {
    __builtin_cpu_init();
    Isa found = Isa::Baseline;
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw"))
      found = Isa::Avx512;
    else if (__builtin_cpu_supports("avx2"))
      found = Isa::Avx2;
    return capped_isa(found, std::getenv("SOFTPBR_MAX_ISA"));
  }();
  return isa;
#else
  return Isa::Baseline;
#endif
}

// Whether this CPU has AVX-512 VBMI (byte permutes across a 512-bit register: Ice Lake,
// Zen 4 and later; not Skylake-X or Cascade Lake). Not a target of its own: a kernel
// that gains from it (the texture lane kernel's table lookups) compiles an extra copy
// and picks it at run time within Avx512. Decided once, on first call.
inline bool cpu_has_avx512_vbmi() {
#if SOFTPBR_SIMD_X86
  static const bool vbmi = [] {
    __builtin_cpu_init();
    return cpu_isa() == Isa::Avx512 && __builtin_cpu_supports("avx512vbmi");
  }();
  return vbmi;
#else
  return false;
#endif
}

// Whether a kernel compiled for `isa` may run here.
inline bool supported(Isa isa) { return static_cast<int>(isa) <= static_cast<int>(cpu_isa()); }

inline std::string_view isa_name(Isa isa) {
  switch (isa) {
    case Isa::Avx2: return "avx2";
    case Isa::Avx512: return "avx512";
    default: return "baseline";
  }
}

}  // namespace softpbr::simd

// Marks the entry point of a kernel compiled per target: every call inside it is inlined
// (GCC and Clang's flatten), so code written outside the target region — a user's shader
// template, glm — runs in the target's instruction set with its lane operations inlined.
#define SOFTPBR_KERNEL __attribute__((flatten))
