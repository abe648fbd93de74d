// raster::Texture made with mip levels of its own (a KTX2 file's): the given levels kept as
// stored, the levels after them built from the last given exactly as a texture built from
// that level alone builds its chain, and levels of the wrong size refused.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "softpbr/raster/texture.h"

namespace raster = softpbr::raster;
namespace image = softpbr::image;

namespace {

image::Image8 filled(int w, int h, int salt) {
  std::vector<std::uint8_t> v(static_cast<std::size_t>(w) * h * 4);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<std::uint8_t>(i * 37 + salt * 101);
  return image::Image8(w, h, v);
}

std::vector<std::uint8_t> level_texels(const raster::Texture& t, int l) {
  const raster::Texture::Level& lv = t.level(l);
  const auto first = t.texels8().begin() + static_cast<std::ptrdiff_t>(lv.offset * 4);
  return {first, first + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(lv.width) * lv.height * 4)};
}

}  // namespace

TEST_CASE("texture levels: given levels are kept as stored and the rest built from the last given, as from that level alone") {
  for (const raster::ColorSpace space : {raster::ColorSpace::Srgb, raster::ColorSpace::Linear}) {
    const image::Image8 base = filled(12, 5, 0), level1 = filled(6, 2, 1);
    const raster::Texture t(image::Image8(base), std::vector<image::Image8>{level1}, space);
    REQUIRE(t.level_count() == 4);  // 12x5, 6x2, 3x1, 1x1
    CHECK(level_texels(t, 0) == std::vector<std::uint8_t>(base.rgba.begin(), base.rgba.end()));
    CHECK(level_texels(t, 1) == std::vector<std::uint8_t>(level1.rgba.begin(), level1.rgba.end()));
    const raster::Texture from_level1(image::ImageView8(level1), space);  // 6x2, 3x1, 1x1
    CHECK(level_texels(t, 2) == level_texels(from_level1, 1));
    CHECK(level_texels(t, 3) == level_texels(from_level1, 2));
    // No levels given: the chain built as by the other constructors.
    const raster::Texture none(image::Image8(base), std::vector<image::Image8>{}, space);
    const raster::Texture built(image::ImageView8(base), space);
    CHECK(std::equal(none.texels8().begin(), none.texels8().end(), built.texels8().begin(), built.texels8().end()));
  }
}

TEST_CASE("texture levels: a given level of the wrong size is refused, levels beyond the chain are ignored") {
  CHECK_THROWS_AS(raster::Texture(filled(8, 8, 0), std::vector<image::Image8>{filled(4, 3, 1)}, raster::ColorSpace::Srgb),
                  std::invalid_argument);
  const std::vector<image::Image8> many = {filled(2, 1, 1), filled(1, 1, 2), filled(1, 1, 3)};
  const raster::Texture t(filled(4, 2, 0), many, raster::ColorSpace::Linear);
  CHECK(t.level_count() == 3);
  CHECK(level_texels(t, 2) == std::vector<std::uint8_t>(many[1].rgba.begin(), many[1].rgba.end()));
}
