#include "ewis/core/scratch.hpp"

#include <sys/mman.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <cstdint>
#include <cstdlib>
#include <new>

namespace ewis {

void return_free_heap_to_os() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

void prefer_huge_pages(const void* data, std::size_t bytes) {
#ifdef MADV_HUGEPAGE
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHuge - 1) / kHuge * kHuge, last = (begin + bytes) / kHuge * kHuge;
  if (data && last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)data, (void)bytes;
#endif
}

}  // namespace ewis

namespace ewis {
namespace {
constexpr std::size_t kPage = 4096;
constexpr std::size_t kHugePage = std::size_t{2} << 20;
std::size_t page_rounded(std::size_t bytes) { return (bytes + kPage - 1) / kPage * kPage; }
}  // namespace

void* map_aligned(std::size_t bytes, bool huge_pages) {
  // Map one huge page more than needed and unmap the slack on both sides, so the block starts on a 2 MiB
  // boundary and every whole frame of it can be a huge page.
  const std::size_t size = page_rounded(bytes);
  if (size < bytes || size > SIZE_MAX - kHugePage) throw std::bad_alloc();
  void* raw = mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) throw std::bad_alloc();
  const auto at = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t aligned = (at + kHugePage - 1) / kHugePage * kHugePage;
  if (aligned > at) munmap(raw, aligned - at);
  if (const std::size_t tail = at + size + kHugePage - (aligned + size)) munmap(reinterpret_cast<void*>(aligned + size), tail);
  void* p = reinterpret_cast<void*>(aligned);
#ifdef MADV_HUGEPAGE
  // a hint: without THP it is refused and 4 KiB pages are used
  if (huge_pages && size >= kHugePage) madvise(p, size / kHugePage * kHugePage, MADV_HUGEPAGE);
#else
  (void)huge_pages;
#endif
  return p;
}

void unmap_aligned(void* p, std::size_t bytes) noexcept {
  if (p) munmap(p, page_rounded(bytes));
}

}  // namespace ewis

namespace ewis::scratch_detail {
namespace {
constexpr std::size_t kMapFrom = std::size_t{1} << 20;
// whole 2 MiB frames, so that the array's last pages can be huge ones too
std::size_t mapped_size(std::size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }
}  // namespace

void* allocate(std::size_t bytes) {
  if (bytes < kMapFrom) {
    if (void* p = std::malloc(bytes)) return p;
    throw std::bad_alloc();
  }
  return map_aligned(mapped_size(bytes), true);
}

void release(void* p, std::size_t bytes) noexcept {
  if (!p) return;
  if (bytes < kMapFrom)
    std::free(p);
  else
    unmap_aligned(p, mapped_size(bytes));
}

}  // namespace ewis::scratch_detail
