// The pixel-data check of image views (see image.h).
#include "softpbr/image/image.h"

#include <stdexcept>
#include <string>

namespace softpbr::image {

namespace {
template <class Sample>
void check(const ImageView<Sample>& image, std::string_view what) {
  if (image.width < 0 || image.height < 0 ||
      image.rgba.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4)
    throw std::invalid_argument(std::string(what) + ": image size " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " and pixel data (" + std::to_string(image.rgba.size()) +
                                " samples) disagree");
}
}  // namespace

void check_pixels(const ImageView8& image, std::string_view what) { check(image, what); }
void check_pixels(const ImageViewF& image, std::string_view what) { check(image, what); }

}  // namespace softpbr::image
