// tinyobjloader's implementation (from Debian's libtinyobjloader-dev header), compiled into
// fuzz_obj with the sanitizers and coverage instrumentation. Definitions in the executable
// take precedence over libtinyobjloader.so's, so the parser the fuzzer drives is this one.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
