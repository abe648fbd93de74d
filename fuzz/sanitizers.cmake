# Sanitizer builds (see fuzz/README.md and .ci/fuzz). Included by the top-level
# CMakeLists.txt before any target, so the libraries are instrumented too.
#   SOFTPBR_BUILD_FUZZERS  libFuzzer targets; everything built with ASan + UBSan (clang only)
#   SOFTPBR_TSAN           everything built with ThreadSanitizer, plus softpbr_tsan_tests
# Each wants its own build folder; neither is for installing.
option(SOFTPBR_BUILD_FUZZERS "Build the libFuzzer targets in fuzz/ with ASan and UBSan (clang only)" OFF)
option(SOFTPBR_TSAN "Build with ThreadSanitizer and the concurrent-render test in fuzz/" OFF)

if(SOFTPBR_BUILD_FUZZERS AND SOFTPBR_TSAN)
  message(FATAL_ERROR "SOFTPBR_BUILD_FUZZERS and SOFTPBR_TSAN need separate build folders")
endif()
if(SOFTPBR_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "SOFTPBR_BUILD_FUZZERS needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++")
  endif()
  # fuzzer-no-link: coverage instrumentation everywhere; only the fuzz targets link the
  # libFuzzer main. UBSan aborts at the first report so the fuzzer records it as a crash
  # (float-divide-by-zero is not in -fsanitize=undefined: IEEE division is used on purpose).
  # -gline-tables-only: file and line in every stack trace, without the full debug info
  # that made these builds several minutes longer (the tile kernels are large).
  add_compile_options(-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=all
                      -fno-omit-frame-pointer -gline-tables-only)
  add_link_options(-fsanitize=address,undefined)
endif()
if(SOFTPBR_TSAN)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer -gline-tables-only)
  add_link_options(-fsanitize=thread)
endif()
