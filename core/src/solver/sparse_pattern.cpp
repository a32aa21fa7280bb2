#include "monohydra/core/sparse_pattern.hpp"

#include <algorithm>
#include <stdexcept>

namespace mh {

SparsePattern::SparsePattern(int n, std::vector<std::pair<int, int>> entries) : n_(n) {
  for (int i = 0; i < n; ++i) entries.emplace_back(i, i);
  for (const auto& [row, col] : entries) {
    if (row < 0 || row >= n || col < 0 || col >= n)
      throw std::invalid_argument("SparsePattern: entry outside the " + std::to_string(n) + " x " +
                                  std::to_string(n) + " matrix");
  }
  // Sort by column, then row, and drop repeats: KLU wants sorted, unique rows.
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second < b.second : a.first < b.first;
  });
  entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
  column_start_.assign(static_cast<size_t>(n) + 1, 0);
  row_index_.reserve(entries.size());
  for (const auto& [row, col] : entries) {
    ++column_start_[static_cast<size_t>(col) + 1];
    row_index_.push_back(row);
  }
  for (int c = 0; c < n; ++c) column_start_[c + 1] += column_start_[c];
}

int SparsePattern::slot(int row, int col) const {
  const auto begin = row_index_.begin() + column_start_[col];
  const auto end = row_index_.begin() + column_start_[col + 1];
  const auto it = std::lower_bound(begin, end, row);
  return (it != end && *it == row) ? static_cast<int>(it - row_index_.begin()) : -1;
}

std::vector<std::vector<int>> SparsePattern::column_groups() const {
  std::vector<std::vector<int>> groups;
  std::vector<std::vector<char>> rows_used;  // per group: rows already claimed
  for (int c = 0; c < n_; ++c) {
    size_t g = 0;
    for (; g < groups.size(); ++g) {
      bool clash = false;
      for (int k = column_start_[c]; k < column_start_[c + 1] && !clash; ++k)
        clash = rows_used[g][row_index_[k]] != 0;
      if (!clash) break;
    }
    if (g == groups.size()) {
      groups.emplace_back();
      rows_used.emplace_back(static_cast<size_t>(n_), 0);
    }
    groups[g].push_back(c);
    for (int k = column_start_[c]; k < column_start_[c + 1]; ++k) rows_used[g][row_index_[k]] = 1;
  }
  return groups;
}

}  // namespace mh
