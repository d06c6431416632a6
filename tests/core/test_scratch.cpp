#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <vector>

#include "ewis/core/scratch.hpp"

namespace ewis {

// Small (malloc) and large (mapped, 2 MiB-aligned) arrays hold what is written, survive moves, and free cleanly
// (ASan checks the release paths in the sanitizer build).
TEST(ScratchArray, HoldsValuesAcrossSizesAndMoves) {
  for (std::size_t n : {std::size_t{1}, std::size_t{1000}, std::size_t{131072}, std::size_t{3'000'001}}) {
    ScratchArray<std::uint64_t> a(n);
    ASSERT_EQ(a.size(), n);
    std::iota(a.begin(), a.end(), std::uint64_t{7});
    ScratchArray<std::uint64_t> b(std::move(a));
    EXPECT_EQ(a.size(), 0u);
    ASSERT_EQ(b.size(), n);
    EXPECT_EQ(b[0], 7u);
    EXPECT_EQ(b[n - 1], 7u + n - 1);
    if (n * sizeof(std::uint64_t) >= (std::size_t{1} << 20)) {
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % (std::size_t{2} << 20), 0u);
    }
    ScratchArray<std::uint64_t> c;
    c = std::move(b);
    EXPECT_EQ(c[n / 2], 7u + n / 2);
  }
  ScratchArray<float> empty(0);
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_EQ(empty.data(), nullptr);
}

// The advice is a hint on the aligned interior only: any range (empty, tiny, unaligned, large) is safe and the
// memory keeps its contents.
TEST(ScratchArray, HugePageAdviceKeepsContents) {
  std::vector<std::uint32_t> v;
  v.reserve(3'000'000);
  prefer_huge_pages(v.data(), 3'000'000 * sizeof(std::uint32_t));
  v.resize(3'000'000);
  std::iota(v.begin(), v.end(), 0u);
  prefer_huge_pages(v.data() + 1, 17);
  prefer_huge_pages(nullptr, 0);
  EXPECT_EQ(v[2'999'999], 2'999'999u);
  EXPECT_EQ(v[12345], 12345u);
}

}  // namespace ewis
