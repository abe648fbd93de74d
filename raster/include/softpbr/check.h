// softpbr/check.h — SOFTPBR_DCHECK: internal invariants, checked in Debug builds.
//
// For what the code itself guarantees (a tile's origin is even, a packet never holds more
// lanes than it has, a binned list covers every entry), not for bad input: input errors
// are exceptions at the API boundary with the file and line or JSON pointer
// (docs/design.md, "Errors"). As pbrt's DCHECK and Mesa's assert: on in Debug builds (no
// NDEBUG; .ci/matrix's ASan+UBSan configuration runs the whole suite so), compiled out in
// Release, where the condition is not evaluated. A failed check prints the condition and
// where it is, then aborts.
#pragma once

#include <cstdio>
#include <cstdlib>

namespace softpbr::detail {
[[noreturn]] inline void check_failed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: internal check failed: %s\n", file, line, condition);
  std::abort();
}
}  // namespace softpbr::detail

#if defined(NDEBUG)
#define SOFTPBR_DCHECK(condition) static_cast<void>(sizeof(static_cast<bool>(condition)))
#else
#define SOFTPBR_DCHECK(condition) \
  ((condition) ? static_cast<void>(0) : ::softpbr::detail::check_failed(#condition, __FILE__, __LINE__))
#endif
