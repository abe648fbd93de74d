// softpbr/loaders/format_bytes.h — byte counts as the loaders' and the command's messages
// write them ("over the memory limit of 4.0 GiB").
#pragma once

#include <cstdint>
#include <string>

namespace softpbr::pbr {

// "1.5 GiB", "12.0 MiB", "640 B": for messages.
std::string format_bytes(std::uint64_t bytes);

}  // namespace softpbr::pbr
