// softpbr/simd/foreach_target.h — compiles one kernel source once per target.
//
//   #define SOFTPBR_TARGET_FILE "softpbr/raster/detail/rast-inl.h"
//   #include "softpbr/simd/foreach_target.h"
//
// includes SOFTPBR_TARGET_FILE once for every target of softpbr/simd/isa.h (Baseline,
// then Avx2 and Avx512 on x86-64), each time with every function it defines compiled for
// that target (`#pragma GCC target` / `#pragma clang attribute`), and with
//   SOFTPBR_TARGET_NS      the target's namespace name: baseline, avx2, avx512
//   SOFTPBR_ISA            its simd::Isa value
//   SOFTPBR_TARGET_AVX     1 when 256-bit vector instructions are available, else 0
//   SOFTPBR_TARGET_AVX512  1 when AVX-512 F/DQ/VL/BW are available, else 0
//   SOFTPBR_TARGET_VBMI    1 in the AVX-512 VBMI copy (below), else 0
// The target file puts its definitions in a namespace named SOFTPBR_TARGET_NS (or in
// specializations for SOFTPBR_ISA), so the copies do not collide, and includes no header
// itself (a header included there would be compiled for one target only). Dispatch picks
// a copy at run time (softpbr/simd/dispatch.h). This is the scheme of Highway's
// foreach_target.h, without its per-target vector API: softpbr's lane types have fixed
// widths (4, 8, 16 on every target), which its width-equivalence tests need.
//
// With `#define SOFTPBR_TARGET_ALSO_VBMI` before the include, the file is included once more
// after AVX-512: namespace avx512vbmi, SOFTPBR_ISA Avx512, SOFTPBR_TARGET_VBMI 1, compiled
// with AVX-512 VBMI too (byte permutes across a 512-bit register). Not a dispatch target
// (isa.h: cpu_has_avx512_vbmi()): the caller picks that copy within Avx512 (texture.cpp's
// lane kernel); simd.h compiles the plain-vector lane operations this way, so that copy's
// byte permutes are VBMI's.
//
// No include guard: it is meant to be included many times.
#ifndef SOFTPBR_TARGET_FILE
#error "define SOFTPBR_TARGET_FILE before including softpbr/simd/foreach_target.h"
#endif

#include "softpbr/simd/isa.h"

// Whether the build's own flags already include AVX-512 F/DQ/VL/BW (e.g. -march=native).
#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512VL__) && defined(__AVX512BW__)
#define SOFTPBR_BUILD_AVX512 1
#else
#define SOFTPBR_BUILD_AVX512 0
#endif

// Each copy: the macros above set, then detail/one_target.h, which turns the target's
// features (SOFTPBR_TARGET_FEATURES, none for the baseline) on around the include of
// SOFTPBR_TARGET_FILE and undefines them all again.

// --- Baseline: the build's own flags. ---
#define SOFTPBR_TARGET_NS baseline
#define SOFTPBR_ISA ::softpbr::simd::Isa::Baseline
#if defined(__AVX__)
#define SOFTPBR_TARGET_AVX 1
#else
#define SOFTPBR_TARGET_AVX 0
#endif
#define SOFTPBR_TARGET_AVX512 SOFTPBR_BUILD_AVX512
#define SOFTPBR_TARGET_VBMI 0
#include "softpbr/simd/detail/one_target.h"

#if SOFTPBR_SIMD_X86_TARGETS
// --- AVX2 (no FMA: -ffp-contract=off forbids contraction, and no target enables it). ---
#define SOFTPBR_TARGET_FEATURES "avx2,avx,popcnt"
#define SOFTPBR_TARGET_NS avx2
#define SOFTPBR_ISA ::softpbr::simd::Isa::Avx2
#define SOFTPBR_TARGET_AVX 1
#define SOFTPBR_TARGET_AVX512 SOFTPBR_BUILD_AVX512
#define SOFTPBR_TARGET_VBMI 0
#include "softpbr/simd/detail/one_target.h"

// --- AVX-512 F, DQ, VL, BW. ---
#define SOFTPBR_TARGET_FEATURES "avx512f,avx512dq,avx512vl,avx512bw,avx2,avx,popcnt"
#define SOFTPBR_TARGET_NS avx512
#define SOFTPBR_ISA ::softpbr::simd::Isa::Avx512
#define SOFTPBR_TARGET_AVX 1
#define SOFTPBR_TARGET_AVX512 1
#define SOFTPBR_TARGET_VBMI 0
#include "softpbr/simd/detail/one_target.h"

#if defined(SOFTPBR_TARGET_ALSO_VBMI)
// --- AVX-512 with VBMI, for the files that ask for it. ---
#define SOFTPBR_TARGET_FEATURES "avx512f,avx512dq,avx512vl,avx512bw,avx512vbmi,avx2,avx,popcnt"
#define SOFTPBR_TARGET_NS avx512vbmi
#define SOFTPBR_ISA ::softpbr::simd::Isa::Avx512
#define SOFTPBR_TARGET_AVX 1
#define SOFTPBR_TARGET_AVX512 1
#define SOFTPBR_TARGET_VBMI 1
#include "softpbr/simd/detail/one_target.h"
#endif  // SOFTPBR_TARGET_ALSO_VBMI
#endif  // SOFTPBR_SIMD_X86_TARGETS

#undef SOFTPBR_BUILD_AVX512
#undef SOFTPBR_TARGET_FILE
#undef SOFTPBR_TARGET_ALSO_VBMI
