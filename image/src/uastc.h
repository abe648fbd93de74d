// Internal to softpbr_image: UASTC (LDR 4×4) blocks decoded to 8-bit RGBA.
//
// Source: the Basis Universal "UASTC Texture Specification" (BinomialLLC/basis_universal
// wiki): a 128-bit block in one of 19 modes, each a 4×4 LDR subset of ASTC (KHR Data
// Format Specification 1.3, "ASTC Compressed Texture Image Formats") with a simpler bit
// layout — the mode as a prefix code, transcoding hints, the partition pattern as an index
// into a table of ASTC partition seeds, the endpoints' trits or quints packed as base-3 or
// base-5 numbers ahead of their low bits, then the weights. A texel's colour is ASTC's: the
// endpoints unquantized to 8 bits, widened to 16 by ×257, blended by the unquantized
// weight (0..64) with rounding, and the top 8 bits kept. Integer arithmetic throughout: the
// same bytes on every machine.
#pragma once

#include <cstdint>

namespace softpbr::image::detail {

// Decodes one 16-byte UASTC block into 16 RGBA texels (rows of 4, top row first; 64 bytes).
// Returns false for a block no encoder writes (the reserved mode, a partition index beyond
// its table); `rgba` is then unspecified.
bool decode_uastc_block(const std::uint8_t* block, std::uint8_t* rgba);

// The partition (0, 1 or 2) of texel (x, y) of a 4×4 block under ASTC's partition function
// (KHR Data Format Specification 1.3, §23.21 "Partition pattern generation"), exposed for tests.
int astc_partition(int seed, int x, int y, int partitions);

// ASTC's unquantization of a colour endpoint value (§23.12): `value` is the BISE index
// (trit or quint above the low bits) of range `range` (0..20), the result 0..255.
int astc_unquantize_endpoint(int range, int value);

}  // namespace softpbr::image::detail
