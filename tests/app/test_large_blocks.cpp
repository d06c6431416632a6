// The ewis program's operator new (apps/ewis/large_blocks.cpp), linked into this test as into the program:
// large blocks are mapped on their own and their memory leaves the process when freed; alignment requests hold.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <memory>
#include <new>
#include <vector>

namespace {

std::size_t resident_bytes() {
  std::ifstream f("/proc/self/statm");
  std::size_t size = 0, resident = 0;
  f >> size >> resident;
  return resident * 4096;
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kReplaced = false;  // AddressSanitizer brings its own operator new
#else
constexpr bool kReplaced = true;
#endif

}  // namespace

TEST(LargeBlocks, LargeVectorsAreMappedApartAndGiveTheirMemoryBack) {
  if (!kReplaced) GTEST_SKIP() << "operator new is AddressSanitizer's in this build";
  const std::size_t before = resident_bytes();
  {
    std::vector<std::uint32_t> big(16u << 20);  // 64 MiB, touched by the zero-fill
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.data()) % (2u << 20), 64u);
    for (std::size_t i = 0; i < big.size(); i += 1024) big[i] = static_cast<std::uint32_t>(i);
    EXPECT_EQ(big[5 << 20], 5u << 20);
    EXPECT_GT(resident_bytes(), before + (60u << 20));
  }
  EXPECT_LT(resident_bytes(), before + (8u << 20)) << "freed, the 64 MiB left the process";
}

TEST(LargeBlocks, SmallBlocksAndAlignmentRequests) {
  struct alignas(64) Line {
    char bytes[64];
  };
  struct alignas(4096) Page {
    char bytes[4096];
  };
  for (int i = 0; i < 50; ++i) {
    auto small = std::make_unique<int>(i);
    EXPECT_EQ(*small, i);
    auto line = std::make_unique<Line>();
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(line.get()) % 64, 0u);
    auto page = std::make_unique<Page>();
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(page.get()) % 4096, 0u);
  }
  std::vector<Page> pages(600);  // 2.4 MB of 4096-aligned pages: over-aligned and large
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(pages.data()) % 4096, 0u);
  std::vector<Line> lines(40000);  // 2.5 MB of 64-aligned lines: the mapping's offset keeps 64
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(lines.data()) % 64, 0u);
}

TEST(LargeBlocks, ImpossibleRequestsFailAsTheStandardSays) {
  const std::size_t huge = std::size_t{1} << 62;
  EXPECT_EQ(::operator new(huge, std::nothrow), nullptr);
  EXPECT_THROW(::operator delete(::operator new(huge)), std::bad_alloc);
  ::operator delete(nullptr);  // no-op
}
