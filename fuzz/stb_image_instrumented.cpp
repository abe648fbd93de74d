// stb_image's implementation (from Debian's libstb-dev header), compiled into fuzz_image
// with the sanitizers and coverage instrumentation. Definitions in the executable take
// precedence over libstb.so's, so the decoder the fuzzer drives is this one.
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
