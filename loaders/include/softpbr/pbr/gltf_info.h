// softpbr/pbr/gltf_info.h — moved to softpbr/loaders/gltf_info.h (softpbr::loaders, the readers
// of files). This forwarding header keeps #include <softpbr/pbr/gltf_info.h> compiling for one
// release and goes away in the next: include <softpbr/loaders/gltf_info.h> and link
// softpbr::loaders. The names stay in namespace softpbr::pbr (it also brings what the old header
// brought: gltf.h's, obj.h's and scene_file.h's names).
#pragma once

#include "softpbr/loaders/format_bytes.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/gltf_info.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/loaders/scene_file.h"
