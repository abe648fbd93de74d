// The tile kernels of MaskedShadowDepthShader<TexturedUv0PbrShader>, the shadow maps' pass of
// alpha-masked and blended casters drawn with UV set 0 alone (see scene_kernels.h, shadows.h).
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::MaskedShadowDepthShader<::softpbr::pbr::TexturedUv0PbrShader>);
