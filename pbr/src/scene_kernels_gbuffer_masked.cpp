// The tile kernels of MaskedGBufferShader<TexturedPbrShader>, the occlusion's depth and normal
// pass of alpha-masked objects (see scene_kernels.h, occlusion.h).
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::MaskedGBufferShader<::softpbr::pbr::TexturedPbrShader>);
