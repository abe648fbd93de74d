// What the KTX2 suites check of a refused file (test_ktx2.cpp, test_ktx2_etc1s.cpp).
#pragma once

#include <doctest/doctest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "softpbr/image/ktx2.h"

namespace ktx2_test {

// image::load_ktx2 of `bytes` (named "t.ktx2") throws std::runtime_error whose one-line
// message starts with "t.ktx2: " and contains `what`.
inline void check_refused(const std::vector<std::uint8_t>& bytes, const std::string& what,
                          const softpbr::image::Limits& limits = {}) {
  try {
    softpbr::image::load_ktx2(bytes, "t.ktx2", limits);
    FAIL("no exception");
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(message.rfind("t.ktx2: ", 0) == 0);
    CHECK(message.find(what) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
}

}  // namespace ktx2_test
