// The tile kernels of MaskedShadowDepthShader<TexturedPbrShader>, the shadow maps' pass of
// alpha-masked and blended casters (see scene_kernels.h, shadows.h): 1 sample a pixel only.
#include "scene_kernels.h"

SOFTPBR_PBR_SCENE_KERNEL(::softpbr::pbr::detail::MaskedShadowDepthShader<::softpbr::pbr::TexturedPbrShader>);
