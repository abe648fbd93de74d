// The tile kernels of GBufferShader, the occlusion's depth and normal pass (see scene_kernels.h, occlusion.h).
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::GBufferShader);
