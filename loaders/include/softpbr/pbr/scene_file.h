// softpbr/pbr/scene_file.h — moved to softpbr/loaders/scene_file.h (softpbr::loaders, the
// readers of files). This forwarding header keeps #include <softpbr/pbr/scene_file.h> compiling
// for one release and goes away in the next: include <softpbr/loaders/scene_file.h> and link
// softpbr::loaders. The names stay in namespace softpbr::pbr (format_bytes now in
// softpbr/loaders/format_bytes.h).
#pragma once

#include "softpbr/loaders/format_bytes.h"
#include "softpbr/loaders/scene_file.h"
