// benchmarks/memory.h — heap accounting for the benchmarks: linking memory.cpp replaces
// the global operator new/delete with counting versions (bytes as glibc's
// malloc_usable_size reports them), so a benchmark can report the peak heap a frame
// needs beyond what existed before it (the meshes, the scene).
#pragma once

#include <cstddef>

namespace softpbr::bench {

// Bytes currently allocated through operator new.
std::size_t heap_in_use();
// Highest heap_in_use() since the last reset_heap_peak().
std::size_t heap_peak();
// Starts a new peak measurement at the current use.
void reset_heap_peak();

}  // namespace softpbr::bench
