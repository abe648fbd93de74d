// Large pixel buffers in transparent huge pages (see memory.h).
#include "softpbr/image/memory.h"

#include <cstdint>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#if defined(__SANITIZE_ADDRESS__)
#define SOFTPBR_PIXELS_FROM_HEAP 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SOFTPBR_PIXELS_FROM_HEAP 1
#endif
#endif
#if !defined(__linux__) || !defined(MADV_HUGEPAGE)
#define SOFTPBR_PIXELS_FROM_HEAP 1
#endif

namespace softpbr::image::detail {

#if !defined(SOFTPBR_PIXELS_FROM_HEAP)
namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;  // x86-64's and AArch64's (4 KiB granule) PMD size

bool mapped(std::size_t bytes) { return bytes >= kHugePageBufferBytes; }
std::size_t mapped_size(std::size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }
}  // namespace
#endif

void* allocate_pixels(std::size_t bytes, std::size_t alignment) {
#if !defined(SOFTPBR_PIXELS_FROM_HEAP)
  if (mapped(bytes)) {
    if (bytes > static_cast<std::size_t>(-1) - 2 * kHugePage) throw std::bad_alloc();
    const std::size_t size = mapped_size(bytes);
    // Map one huge page more than needed and unmap what lies outside the aligned range.
    void* raw = mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto start = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (start + kHugePage - 1) / kHugePage * kHugePage;
    if (aligned > start) munmap(raw, aligned - start);
    const std::size_t tail = start + size + kHugePage - (aligned + size);
    if (tail > 0) munmap(reinterpret_cast<void*>(aligned + size), tail);
    // Advice only: without it (THP off, an old kernel) the pages are 4 KiB, nothing else changes.
    madvise(reinterpret_cast<void*>(aligned), size, MADV_HUGEPAGE);
    return reinterpret_cast<void*>(aligned);
  }
#endif
  if (alignment > __STDCPP_DEFAULT_NEW_ALIGNMENT__) return ::operator new(bytes, std::align_val_t(alignment));
  return ::operator new(bytes);
}

void deallocate_pixels(void* p, std::size_t bytes, std::size_t alignment) noexcept {
#if !defined(SOFTPBR_PIXELS_FROM_HEAP)
  if (mapped(bytes)) {
    munmap(p, mapped_size(bytes));
    return;
  }
#endif
  if (alignment > __STDCPP_DEFAULT_NEW_ALIGNMENT__) ::operator delete(p, std::align_val_t(alignment));
  else ::operator delete(p);
}

}  // namespace softpbr::image::detail
