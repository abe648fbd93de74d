// softpbr/simd/detail/one_target.h — one copy of foreach_target.h's target file: with
// SOFTPBR_TARGET_FEATURES defined (a GCC/Clang target string), every function the file
// defines is compiled with those features (`#pragma GCC target` in a push/pop, Clang's
// `#pragma clang attribute` push/pop); without it, with the build's own flags. Then the
// per-copy macros (SOFTPBR_TARGET_NS, SOFTPBR_ISA, SOFTPBR_TARGET_AVX, _AVX512, _VBMI,
// _FEATURES) are undefined for the next copy. Included by foreach_target.h only; no
// include guard.
// The argument is macro-expanded (SOFTPBR_TARGET_FEATURES becomes its string) before the
// inner macro stringizes it for _Pragma.
#define SOFTPBR_ONE_TARGET_PRAGMA_STRING(x) _Pragma(#x)
#define SOFTPBR_ONE_TARGET_PRAGMA(x) SOFTPBR_ONE_TARGET_PRAGMA_STRING(x)
#if defined(SOFTPBR_TARGET_FEATURES)
#if defined(__clang__)
SOFTPBR_ONE_TARGET_PRAGMA(clang attribute push(__attribute__((target(SOFTPBR_TARGET_FEATURES))), apply_to = function))
#else
#pragma GCC push_options
SOFTPBR_ONE_TARGET_PRAGMA(GCC target(SOFTPBR_TARGET_FEATURES))
#endif
#endif

#include SOFTPBR_TARGET_FILE

#if defined(SOFTPBR_TARGET_FEATURES)
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif
#undef SOFTPBR_ONE_TARGET_PRAGMA
#undef SOFTPBR_ONE_TARGET_PRAGMA_STRING
#undef SOFTPBR_TARGET_FEATURES
#undef SOFTPBR_TARGET_NS
#undef SOFTPBR_ISA
#undef SOFTPBR_TARGET_AVX
#undef SOFTPBR_TARGET_AVX512
#undef SOFTPBR_TARGET_VBMI
