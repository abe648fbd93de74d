// Internal to softpbr_image: ownership of the pixels stb_image returns.
#pragma once

#include <memory>

#include <stb_image.h>

namespace softpbr::image::detail {

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};
template <class T>
using StbPixels = std::unique_ptr<T, StbFree>;

}  // namespace softpbr::image::detail
