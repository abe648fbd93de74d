// The tile kernels of TexturedUv0PbrShader, the textured shader for one UV set without normal map or vertex colours (see scene_kernels.h):
// its entry and its kernels for 1 sample a pixel.
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::TexturedUv0PbrShader);
SOFTPBR_PBR_TILE_KERNELS(, 1, ::softpbr::pbr::TexturedUv0PbrShader);
