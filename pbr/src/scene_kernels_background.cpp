// The tile kernels of BackgroundShader, the environment background's shader (see scene_kernels.h).
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::BackgroundShader);
