// The tile kernels of LayeredPbrShader, the shader of materials with the extensions' layers (see scene_kernels.h):
// its entry and its kernels for 1 sample a pixel.
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::LayeredPbrShader);
SOFTPBR_PBR_TILE_KERNELS(, 1, ::softpbr::pbr::LayeredPbrShader);
