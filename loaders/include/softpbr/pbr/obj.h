// softpbr/pbr/obj.h — moved to softpbr/loaders/obj.h (softpbr::loaders, the readers of files).
// This forwarding header keeps #include <softpbr/pbr/obj.h> compiling for one release and goes
// away in the next: include <softpbr/loaders/obj.h> and link softpbr::loaders. The names stay in
// namespace softpbr::pbr.
#pragma once

#include "softpbr/loaders/obj.h"
