// The tile kernels of LayeredPbrShader for 8 samples a pixel (see scene_kernels.h).
#include "scene_kernels.h"

SOFTPBR_PBR_TILE_KERNELS(, 8, ::softpbr::pbr::LayeredPbrShader);
