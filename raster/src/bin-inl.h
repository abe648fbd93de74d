// Binning's index check, compiled once per target (bin.cpp includes it through
// softpbr/simd/foreach_target.h; no include guard, no header included here).

namespace softpbr::raster::detail::SOFTPBR_TARGET_NS {

// The largest of n indices (0 for none), without a branch per index: the loop vectorizes
// (unsigned max instructions from AVX2 on).
SOFTPBR_KERNEL std::uint32_t largest_of(const std::uint32_t* indices, std::size_t n) {
  std::uint32_t largest = 0;
  for (std::size_t i = 0; i < n; ++i) largest = largest < indices[i] ? indices[i] : largest;
  return largest;
}

}  // namespace softpbr::raster::detail::SOFTPBR_TARGET_NS
