// libFuzzer target: the environment cache's entries (pbr::Environment::from_bytes, what
// load_environment reads back from `--env-cache` folders).
//
// An entry carries the key of what it was made from and a checksum of its bytes, so a
// mutated input would mostly stop at those two checks. The harness makes them pass: it
// passes the input's own key (bytes 8–15) and rewrites the trailing checksum (FNV-1a 64
// over everything before it), so the mutations reach the sizes, the level count and the
// texels. A std::invalid_argument naming the entry is a fine outcome; anything else is a
// finding, as is an environment whose maps disagree with its size or hold a value that is
// negative or not finite (from_bytes promises neither happens).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz_support.h"

#include "softpbr/pbr/environment.h"

namespace {
[[noreturn]] void finding(const char* what) { softpbr::fuzz::finding("fuzz_envcache", what); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size);
  std::uint64_t key = 0;
  if (bytes.size() >= 24) {
    for (int i = 0; i < 8; ++i) key |= static_cast<std::uint64_t>(bytes[8 + static_cast<std::size_t>(i)]) << (8 * i);
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (std::size_t i = 0; i + 8 < bytes.size(); ++i) h = (h ^ bytes[i]) * 0x100000001b3ull;
    for (int i = 0; i < 8; ++i) bytes[bytes.size() - 8 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(h >> (8 * i));
  }
  const std::string name = "fuzz.spenv";
  std::shared_ptr<const softpbr::pbr::Environment> env;
  try {
    env = softpbr::pbr::Environment::from_bytes(bytes, name, key);
  } catch (const std::invalid_argument& e) {
    if (std::string(e.what()).rfind(name + ": ", 0) != 0) finding("an error that does not name the entry");
    return 0;
  } catch (...) {
    finding("an exception other than std::invalid_argument");
  }
  if (!env) finding("no environment and no error");
  for (int i = 0; i < softpbr::pbr::Environment::kLevels; ++i) {
    const auto& level = env->level(i);
    if (level.width() != softpbr::pbr::Environment::level_side(env->size(), i) + 2 || level.height() != level.width())
      finding("a level's size disagrees with the map's");
    for (float v : level.texels_f())
      if (!std::isfinite(v) || v < 0.0f) finding("a level holds a value that is negative or not finite");
  }
  if (env->irradiance().width() != softpbr::pbr::kIrradianceSize + 2) finding("the irradiance map's size is wrong");
  return 0;
}
