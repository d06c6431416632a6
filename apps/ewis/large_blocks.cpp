// The ewis program's operator new/delete (a replacement for the whole process, DESIGN.md "Memory"): blocks of
// 1 MiB and more are mapped on their own, 2 MiB-aligned, from 4 MiB with transparent huge pages requested
// (as core/scratch.hpp does), and unmapped as soon as they are freed; smaller ones come from malloc as before.
// Why: glibc keeps freed large blocks in its heap once its mmap threshold has grown, and the fragments stay
// resident: `ewis inspect` on the 1.27 M-point demo scan peaked at 82 MB of resident memory for a 46 MB heap.
// With this, the resident peak follows the live heap (issue 8: under 4x the points), and a block's first touch
// faults once per 2 MiB instead of once per 4 KiB (glibc's own mmap threshold at 1 MiB made inspect 15% slower).
// Not under AddressSanitizer, which brings its own operator new.
#if !defined(__SANITIZE_ADDRESS__)
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

#include "ewis/core/scratch.hpp"

namespace {

constexpr std::size_t kLarge = std::size_t{1} << 20;
constexpr std::size_t kFrame = std::size_t{2} << 20;  // mapped blocks start on a 2 MiB boundary
constexpr std::size_t kHugeFrom = std::size_t{4} << 20;  // smaller blocks keep 4 KiB pages (less rounding up)
constexpr std::size_t kHeader = 64;                   // the caller's block starts this far into the mapping
constexpr std::uint64_t kMagic = 0x6577697362696721ull;

struct Header {
  std::uint64_t magic;
  std::size_t mapped;       // bytes mapped (header included)
  std::uintptr_t check;     // ~address of the header
};

void* allocate(std::size_t n) {
  if (n >= kLarge) {
    if (n > SIZE_MAX - kHeader) throw std::bad_alloc();
    const std::size_t mapped = n + kHeader;
    auto* h = static_cast<Header*>(ewis::map_aligned(mapped, mapped >= kHugeFrom));
    *h = {kMagic, mapped, ~reinterpret_cast<std::uintptr_t>(h)};
    return reinterpret_cast<char*>(h) + kHeader;
  }
  for (;;) {
    if (void* p = std::malloc(n ? n : 1)) return p;
    std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

// A mapped block is the only kind whose address lies kHeader past a 2 MiB boundary with the header's magic and
// check in front (malloc's blocks sit 16 bytes into a page when mapped, and inside glibc's heaps, where the 64
// bytes in front are always mapped, otherwise).
bool is_mapped(void* p) {
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  if (a % kFrame != kHeader) return false;
  const auto* h = reinterpret_cast<const Header*>(a - kHeader);
  return h->magic == kMagic && h->check == ~reinterpret_cast<std::uintptr_t>(h);
}

void release(void* p) noexcept {
  if (!p) return;
  if (is_mapped(p)) {
    auto* h = reinterpret_cast<Header*>(static_cast<char*>(p) - kHeader);
    const std::size_t mapped = h->mapped;
    h->magic = 0;
    ewis::unmap_aligned(h, mapped);
    return;
  }
  std::free(p);
}

void* allocate_aligned(std::size_t n, std::align_val_t al) {
  const std::size_t align = static_cast<std::size_t>(al);
  if (align <= alignof(std::max_align_t)) return allocate(n);  // malloc's alignment covers it
  if (n >= kLarge && align <= kHeader) return allocate(n);     // so does the mapping's 64
  const std::size_t rounded = (n + align - 1) / align * align;
  if (void* p = std::aligned_alloc(align, rounded ? rounded : align)) return p;
  throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t n, std::align_val_t al) { return allocate_aligned(n, al); }
void* operator new[](std::size_t n, std::align_val_t al) { return allocate_aligned(n, al); }
void* operator new(std::size_t n, std::align_val_t al, const std::nothrow_t&) noexcept {
  try {
    return allocate_aligned(n, al);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, std::align_val_t al, const std::nothrow_t&) noexcept {
  try {
    return allocate_aligned(n, al);
  } catch (...) {
    return nullptr;
  }
}

void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }
#endif
