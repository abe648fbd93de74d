// The tile kernels of TexturedUv0PbrShader for 4 samples a pixel (see scene_kernels.h).
#include "scene_kernels.h"

SOFTPBR_PBR_TILE_KERNELS(, 4, ::softpbr::pbr::TexturedUv0PbrShader);
