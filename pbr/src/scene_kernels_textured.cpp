// The tile kernels of TexturedPbrShader, the textured, alpha-tested, blended, double-sided and unlit objects' shader (see scene_kernels.h):
// its entry and its kernels for 1 sample a pixel.
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::TexturedPbrShader);
SOFTPBR_PBR_TILE_KERNELS(, 1, ::softpbr::pbr::TexturedPbrShader);
