// Memory of large arrays (util/memory.h): huge-page alignment and contents kept through growth and copies.
#include "util/memory.h"

#include <gtest/gtest.h>

#include <cstdint>

using namespace whitted;

namespace {

// Large arrays sit 2 MiB-aligned (huge-page candidates) and keep their contents through growth and copies; small
// ones come 64-byte aligned from operator new.
TEST(HugePageAllocator, AlignsLargeBlocksAndKeepsContents) {
  using A = HugePageAllocator<uint32_t>;
  LargeVector<uint32_t> small(100, 7u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % 64, 0u);
  LargeVector<uint32_t> v;
  const std::size_t n = 3 * A::kMinBytes / sizeof(uint32_t) + 12345;  // grows through both kinds of block
  for (std::size_t i = 0; i < n; ++i) v.push_back(uint32_t(i * 2654435761u));
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % HugePages::kHuge, 0u);
  LargeVector<uint32_t> copy = v;
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(copy.data()) % HugePages::kHuge, 0u);
  ASSERT_EQ(copy.size(), n);
  for (std::size_t i = 0; i < n; i += 997) EXPECT_EQ(copy[i], uint32_t(i * 2654435761u));
  EXPECT_EQ(copy.back(), uint32_t((n - 1) * 2654435761u));
  v.shrink_to_fit();
  v.resize(10);
  v.shrink_to_fit();  // back to a small block
  EXPECT_EQ(v[9], uint32_t(9 * 2654435761u));
}

}  // namespace
