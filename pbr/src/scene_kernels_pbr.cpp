// The tile kernels of PbrShader, the untextured objects' shader (see scene_kernels.h):
// its entry and its kernels for 1 sample a pixel.
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::PbrShader);
SOFTPBR_PBR_TILE_KERNELS(, 1, ::softpbr::pbr::PbrShader);
