// softpbr/golden/doctest_checks.h — golden-image checks for doctest test suites.
//
//   CHECK_IMAGE_MATCHES(image, "goldens/name.png");                 // exact
//   CHECK_IMAGE_MATCHES_WITHIN(image, "goldens/name.png",
//                              softpbr::golden::Tolerance{2, 10});  // ≤ 10 pixels off by > 2
//   CHECK_RENDER_MATCHES(target, displayed_image8, "goldens/name"); // name.hash + name.png
//   REQUIRE_… forms stop the test case on failure.
// `image` is a raster::Image8, golden::ImageF or raster::Target; see golden.h for what each
// check compares and writes. The tolerance is the macro's last argument, so a braced
// Tolerance{2, 10} needs no extra parentheses.
//
// Configuration, read where the macro is used:
//   SOFTPBR_GOLDEN_DIR         compile definition (a string literal): relative golden paths
//                              resolve against it; the environment variable of the same name
//                              overrides it; neither: the working directory.
//   SOFTPBR_GOLDEN_OUTPUT_DIR  compile definition: where failure images go; the environment
//                              variable SOFTPBR_GOLDEN_OUTPUT overrides it; neither:
//                              ./golden-output.
//   SOFTPBR_GOLDEN_UPDATE_COMMAND  compile definition: the command failure messages suggest
//                              for accepting a change (default "SOFTPBR_UPDATE_GOLDENS=1 ctest").
//   SOFTPBR_UPDATE_GOLDENS=1   environment: rewrite the goldens that fail instead of failing.
#pragma once

#include <doctest/doctest.h>

#include "softpbr/golden/golden.h"

#ifndef SOFTPBR_GOLDEN_DIR
#define SOFTPBR_GOLDEN_DIR ""
#endif
#ifndef SOFTPBR_GOLDEN_OUTPUT_DIR
#define SOFTPBR_GOLDEN_OUTPUT_DIR ""
#endif
#ifndef SOFTPBR_GOLDEN_UPDATE_COMMAND
#define SOFTPBR_GOLDEN_UPDATE_COMMAND "SOFTPBR_UPDATE_GOLDENS=1 ctest"
#endif

// The options at the point of use (macros, not an inline function, so translation units
// with different compile definitions do not break the one-definition rule).
#define SOFTPBR_GOLDEN_OPTIONS()                                                                  \
  ::softpbr::golden::options_from_environment(::softpbr::golden::Options{                        \
      SOFTPBR_GOLDEN_DIR, SOFTPBR_GOLDEN_OUTPUT_DIR, false, SOFTPBR_GOLDEN_UPDATE_COMMAND})

// Reports a MatchResult through doctest: the check fails with the result's message, and an
// update is logged as a MESSAGE.
#define SOFTPBR_GOLDEN_REPORT(LEVEL, match_call)                                                  \
  do {                                                                                            \
    const ::softpbr::golden::MatchResult softpbr_golden_result_ = match_call;                     \
    if (softpbr_golden_result_.updated) DOCTEST_MESSAGE(softpbr_golden_result_.message);           \
    const bool image_matches_golden = softpbr_golden_result_.passed;                              \
    DOCTEST_##LEVEL##_MESSAGE(image_matches_golden, softpbr_golden_result_.message);              \
  } while (false)

#define CHECK_IMAGE_MATCHES(image_, golden_path_)                                                        \
  SOFTPBR_GOLDEN_REPORT(CHECK, ::softpbr::golden::match_golden((image_), (golden_path_),                \
                                   ::softpbr::golden::Tolerance{}, SOFTPBR_GOLDEN_OPTIONS()))
#define REQUIRE_IMAGE_MATCHES(image_, golden_path_)                                                      \
  SOFTPBR_GOLDEN_REPORT(REQUIRE, ::softpbr::golden::match_golden((image_), (golden_path_),              \
                                     ::softpbr::golden::Tolerance{}, SOFTPBR_GOLDEN_OPTIONS()))
#define CHECK_IMAGE_MATCHES_WITHIN(image_, golden_path_, ...)                                      \
  SOFTPBR_GOLDEN_REPORT(CHECK, ::softpbr::golden::match_golden((image_), (golden_path_), (__VA_ARGS__),   \
                                                               SOFTPBR_GOLDEN_OPTIONS()))
#define REQUIRE_IMAGE_MATCHES_WITHIN(image_, golden_path_, ...)                                    \
  SOFTPBR_GOLDEN_REPORT(REQUIRE, ::softpbr::golden::match_golden((image_), (golden_path_), (__VA_ARGS__), \
                                                                 SOFTPBR_GOLDEN_OPTIONS()))
#define CHECK_RENDER_MATCHES(target_, image_, golden_stem_)                                          \
  SOFTPBR_GOLDEN_REPORT(CHECK, ::softpbr::golden::match_render((target_), (image_), (golden_stem_), \
                                                               SOFTPBR_GOLDEN_OPTIONS()))
#define REQUIRE_RENDER_MATCHES(target_, image_, golden_stem_)                                        \
  SOFTPBR_GOLDEN_REPORT(REQUIRE, ::softpbr::golden::match_render((target_), (image_), (golden_stem_), \
                                                                 SOFTPBR_GOLDEN_OPTIONS()))
