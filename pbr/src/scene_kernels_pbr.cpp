// The tile kernels of PbrShader, the untextured objects' shader (see scene_kernels.h).
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::PbrShader);
