// The tile kernels of TexturedPbrShader, the textured, alpha-tested, blended, double-sided and unlit objects' shader (see scene_kernels.h).
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::TexturedPbrShader);
