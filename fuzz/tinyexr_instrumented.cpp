// tinyexr's implementation (from Debian's libtinyexr-dev header, zlib for ZIP as Debian
// builds it), compiled into fuzz_exr with the sanitizers and coverage instrumentation.
// Definitions in the executable take precedence over libtinyexr.so's.
#define TINYEXR_IMPLEMENTATION
#include <tinyexr.h>
