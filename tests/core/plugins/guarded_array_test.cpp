// The arrays the host hands plugins to write (core/src/plugins/guarded_array.hpp):
// the array is its size alone, and a write past its end changes the guard.
#include "../../../core/src/plugins/guarded_array.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace mh {
namespace {

TEST(GuardedArray, AnArrayWrittenWithinItsSizeKeepsItsGuard) {
  GuardedArray a;
  EXPECT_TRUE(a.intact());  // empty: only the guard
  a.assign(6, 1.5);
  EXPECT_EQ(a.size(), 6u);
  EXPECT_EQ(a.end() - a.begin(), 6);
  EXPECT_TRUE(std::all_of(a.begin(), a.end(), [](double v) { return v == 1.5; }));
  std::fill(a.begin(), a.end(), -2.0);
  for (size_t i = 0; i < a.size(); ++i) a[i] = std::nan("");  // any value, NaN too
  EXPECT_TRUE(a.intact());
}

TEST(GuardedArray, AWriteOneOrFourPastTheEndChangesTheGuard) {
  for (size_t past = 0; past < GuardedArray::kGuardWords; ++past) {
    GuardedArray a;
    a.resize(9);
    a.data()[9 + past] = 0.0;
    EXPECT_FALSE(a.intact()) << past;
    a.arm();
    EXPECT_TRUE(a.intact()) << past;
  }
}

// The guard's words are NaNs with a payload of their own: a plugin that
// writes a NaN past the end (the commonest NaN, or any computed one) is seen.
TEST(GuardedArray, ANanWrittenPastTheEndIsSeen) {
  GuardedArray a;
  a.resize(3);
  a.data()[3] = std::nan("");
  EXPECT_FALSE(a.intact());
}

TEST(GuardedArray, ResizingKeepsTheGuardPastTheNewEnd) {
  GuardedArray a;
  a.resize(4);
  a.resize(12);
  EXPECT_TRUE(a.intact());
  a.resize(2);
  EXPECT_TRUE(a.intact());
  a.data()[2] = 1.0;
  EXPECT_FALSE(a.intact());
}

}  // namespace
}  // namespace mh
