// softpbr/raster/raster.h — everything of softpbr::raster in one include.
#pragma once

#include "softpbr/raster/color.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/shader.h"
#include "softpbr/raster/target.h"
#include "softpbr/raster/texture.h"
