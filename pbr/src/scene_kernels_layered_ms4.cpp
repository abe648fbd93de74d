// The tile kernels of LayeredPbrShader for 4 samples a pixel (see scene_kernels.h).
#include "scene_kernels.h"

SOFTPBR_PBR_TILE_KERNELS(, 4, ::softpbr::pbr::LayeredPbrShader);
