#pragma once
// Large temporary arrays of plain values (sort keys, offsets) that a step fills itself: no zero-fill, and from
// 1 MiB on they are mapped on their own with transparent huge pages requested (madvise), so the first touch
// costs one fault per 2 MiB instead of one per 4 KiB. On the 2-core VMs we run on, those faults were most of a
// 1.3 M-point voxel grid's time (110 ms -> 55 ms on its first call; filter.md).
#include <cstddef>
#include <type_traits>
#include <utility>

namespace ewis {

// Gives the heap's free pages back to the operating system (glibc's malloc_trim; a no-op elsewhere). For after
// a step that made many small, short-lived allocations among long-lived ones (Assimp's import): freed, they
// stay in the process's resident memory otherwise (30 MB after a 5.6 MB OBJ).
void return_free_heap_to_os();

// Frees a container's memory now. (`v = {}` does not: for a std::vector it is the initializer-list
// assignment, which clears but keeps the capacity.)
template <class T>
void release_memory(T& v) {
  v = T();
}

// Maps `bytes` (rounded up to 4 KiB pages) of zeroed memory on its own, starting on a 2 MiB boundary; with
// `huge_pages`, transparent huge pages are requested for its whole 2 MiB frames. Throws std::bad_alloc. Freed with
// unmap_aligned(p, bytes) (the same bytes).
void* map_aligned(std::size_t bytes, bool huge_pages);
void unmap_aligned(void* p, std::size_t bytes) noexcept;

// Asks for transparent huge pages on the 2 MiB-aligned part of [data, data + bytes) not touched yet (a large
// std::vector just reserved or resized without initialisation): its first touch then faults once per 2 MiB. A
// hint only; small ranges are left alone.
void prefer_huge_pages(const void* data, std::size_t bytes);

namespace scratch_detail {
void* allocate(std::size_t bytes);  // never null: throws std::bad_alloc
void release(void* p, std::size_t bytes) noexcept;
}  // namespace scratch_detail

template <class T>
class ScratchArray {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

 public:
  ScratchArray() = default;
  explicit ScratchArray(std::size_t n) : data_(n ? static_cast<T*>(scratch_detail::allocate(n * sizeof(T))) : nullptr), size_(n) {}
  ScratchArray(const ScratchArray&) = delete;
  ScratchArray& operator=(const ScratchArray&) = delete;
  ScratchArray(ScratchArray&& o) noexcept : data_(std::exchange(o.data_, nullptr)), size_(std::exchange(o.size_, 0)) {}
  ScratchArray& operator=(ScratchArray&& o) noexcept {
    swap(o);
    return *this;
  }
  ~ScratchArray() { scratch_detail::release(data_, size_ * sizeof(T)); }

  void swap(ScratchArray& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(size_, o.size_);
  }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace ewis
