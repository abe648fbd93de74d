// softpbr/image/memory.h — the allocator of large pixel buffers: images, textures and
// render targets.
//
// A buffer of 4 MiB or more is mapped on its own, aligned to 2 MiB, and advised for
// transparent huge pages (Linux, madvise(MADV_HUGEPAGE)); anything smaller, and every
// buffer on other systems or under AddressSanitizer (whose red zones only heap blocks
// have), comes from operator new as with std::allocator.
//
// Why: a buffer is first touched a page at a time, and each 4 KiB page fault is a trip
// into the kernel. On the virtual machines CI and batch renders run on it costs
// microseconds: the first touch of a 1080p 4× target (166 MB) took 0.47–0.62 s there,
// against 17–45 ms in 2 MiB pages (docs/design.md, "Memory"). The contents are the
// same either way: a vector value-initializes its elements as usual.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace softpbr::image {

namespace detail {
void* allocate_pixels(std::size_t bytes, std::size_t alignment);
void deallocate_pixels(void* p, std::size_t bytes, std::size_t alignment) noexcept;
}  // namespace detail

// Buffers of at least this many bytes are mapped in huge pages where the system allows.
inline constexpr std::size_t kHugePageBufferBytes = std::size_t{4} << 20;

// A stateless allocator: any two compare equal, so vectors move and swap their buffers.
template <class T>
struct PixelAllocator {
  using value_type = T;
  PixelAllocator() = default;
  template <class U>
  PixelAllocator(const PixelAllocator<U>&) noexcept {}  // NOLINT: implicit, as std::allocator
  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(detail::allocate_pixels(n * sizeof(T), alignof(T)));
  }
  void deallocate(T* p, std::size_t n) noexcept { detail::deallocate_pixels(p, n * sizeof(T), alignof(T)); }
  template <class U>
  bool operator==(const PixelAllocator<U>&) const noexcept { return true; }
};

// The storage of Image8, ImageF, raster::Texture and raster::Target: a std::vector in all
// but its allocator.
template <class T>
using PixelVector = std::vector<T, PixelAllocator<T>>;

}  // namespace softpbr::image
