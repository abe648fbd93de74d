// The tile kernels of MaskedGBufferShader<TexturedUv0PbrShader>, the occlusion's depth and
// normal pass of alpha-masked objects drawn with UV set 0 alone (see scene_kernels.h, occlusion.h).
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::MaskedGBufferShader<::softpbr::pbr::TexturedUv0PbrShader>);
