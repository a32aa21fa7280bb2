#include "monohydra/core/sparse_pattern.hpp"

#include <gtest/gtest.h>

#include <set>

namespace mh {
namespace {

TEST(SparsePattern, HoldsEveryEntryAndTheDiagonalOnceInSortedColumns) {
  const SparsePattern p(4, {{0, 1}, {3, 1}, {0, 1}, {2, 0}});
  EXPECT_EQ(p.nonzeros(), 4 + 3);  // diagonal + (0,1), (3,1), (2,0)
  EXPECT_GE(p.slot(2, 0), 0);
  EXPECT_GE(p.slot(3, 1), 0);
  EXPECT_EQ(p.slot(1, 0), -1);
  for (int c = 0; c < 4; ++c)
    for (int k = p.column_start()[c] + 1; k < p.column_start()[c + 1]; ++k)
      EXPECT_LT(p.row_index()[k - 1], p.row_index()[k]);
}

TEST(SparsePattern, ColumnGroupsNeverShareARowAndCoverEveryColumn) {
  // A block-diagonal pattern with one dense 3x3 block and five lone states.
  std::vector<std::pair<int, int>> e;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e.emplace_back(r, c);
  const SparsePattern p(8, e);
  const auto groups = p.column_groups();
  std::set<int> seen;
  for (const auto& g : groups) {
    std::set<int> rows;
    for (int c : g) {
      EXPECT_TRUE(seen.insert(c).second);
      for (int k = p.column_start()[c]; k < p.column_start()[c + 1]; ++k)
        EXPECT_TRUE(rows.insert(p.row_index()[k]).second) << "row shared within a group";
    }
  }
  EXPECT_EQ(seen.size(), 8u);
  EXPECT_EQ(groups.size(), 3u);  // the dense block needs 3; the diagonal rides along
}

TEST(SparsePattern, RejectsEntriesOutsideTheMatrix) {
  EXPECT_THROW(SparsePattern(2, {{2, 0}}), std::invalid_argument);
}

}  // namespace
}  // namespace mh
