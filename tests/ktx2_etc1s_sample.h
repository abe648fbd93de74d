// The ETC1S texture the KTX2 suites share (test_ktx2_etc1s.cpp, test_ktx2_reference.cpp):
// 10×6 texels (3×2 blocks, the last column and row overhanging), four endpoints — one at
// each end of the colour range with the largest modifiers, so that the sums clamp — and four
// selectors, optionally with an alpha slice of other blocks. Written by etc1s_writer.h.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "etc1s_writer.h"
#include "ktx2_writer.h"

namespace ktx2_test {

struct Etc1sSample {
  int width = 10, height = 6, bw = 3, bh = 2;
  std::vector<Etc1sEndpointSpec> endpoints;
  std::vector<std::array<std::uint8_t, 4>> selectors;
  std::vector<Etc1sBlock> colour, alpha;
  Etc1sData data;
  std::size_t tables_bytes = 0;  // the global data's last part: the slice tables

  void rewrite() {
    data = write_etc1s(endpoints, selectors, bw, bh, colour, alpha);
    tables_bytes = static_cast<std::size_t>(data.sgd[12]) | (static_cast<std::size_t>(data.sgd[13]) << 8);
  }
  std::vector<std::uint8_t> file() const {
    Ktx2Spec s;
    s.vk_format = 0;
    s.color_model = 163;
    s.transfer = 2;
    s.scheme = 1;
    s.samples = alpha.empty() ? 1 : 2;
    s.width = width;
    s.height = height;
    s.sgd = data.sgd;
    s.levels.push_back(data.level);
    return write_ktx2(s);
  }
};

inline Etc1sSample etc1s_sample(bool with_alpha) {
  Etc1sSample s;
  s.endpoints = {{31, 0, 16, 7}, {3, 17, 29, 2}, {0, 31, 8, 5}, {12, 12, 12, 0}};
  s.selectors = {{0x1B, 0xE4, 0x00, 0xFF}, {0x55, 0xAA, 0x0F, 0xF0}, {0x27, 0x72, 0x8D, 0xD8}, {0xE1, 0x1E, 0x36, 0x63}};
  s.colour = {{0, 0}, {1, 2}, {2, 1}, {3, 3}, {1, 0}, {0, 2}};
  if (with_alpha) s.alpha = {{2, 3}, {3, 1}, {0, 0}, {1, 2}, {2, 2}, {3, 0}};
  s.rewrite();
  return s;
}

}  // namespace ktx2_test
