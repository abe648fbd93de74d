// tests/softpbr_test_paths.h — where the test suites find the source tree, their goldens and
// their scratch folders: SOFTPBR_SOURCE_DIR, SOFTPBR_BINARY_DIR, SOFTPBR_GOLDEN_DIR and
// SOFTPBR_GOLDEN_OUTPUT_DIR, each a `const char[]` naming an absolute folder.
//
// tests/CMakeLists.txt forces this header into every test file (-include) and generates the
// one file that defines the folders (softpbr_test_paths.cpp, from softpbr_test_paths.cpp.in).
// They are not compile definitions: a definition holding an absolute path makes every test
// file's compilation differ between two clones of the repository, so ccache could share
// none of them between the clones and build folders of a machine (docs/design.md, Tests and
// CI). Being arrays, not string literals, they cannot be pasted to a literal: write
// fs::path(SOFTPBR_SOURCE_DIR) / "name".
#pragma once

namespace softpbr::test_paths {
extern const char source_dir[];
extern const char binary_dir[];
extern const char golden_dir[];
extern const char golden_output_dir[];
}  // namespace softpbr::test_paths

#define SOFTPBR_SOURCE_DIR (::softpbr::test_paths::source_dir)
#define SOFTPBR_BINARY_DIR (::softpbr::test_paths::binary_dir)
// CHECK_RENDER_MATCHES / CHECK_IMAGE_MATCHES (softpbr/golden/doctest_checks.h) read these two.
#define SOFTPBR_GOLDEN_DIR (::softpbr::test_paths::golden_dir)
#define SOFTPBR_GOLDEN_OUTPUT_DIR (::softpbr::test_paths::golden_output_dir)
