// The object tests/codegen/check_codegen.cmake disassembles (see probe-inl.h).
#include "softpbr/simd/simd.h"

#define SOFTPBR_TARGET_FILE "codegen/probe-inl.h"
#include "softpbr/simd/foreach_target.h"
