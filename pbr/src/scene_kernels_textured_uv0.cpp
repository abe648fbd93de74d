// The tile kernels of TexturedUv0PbrShader, the textured shader with UV set 0 only (see scene_kernels.h).
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::TexturedUv0PbrShader);
