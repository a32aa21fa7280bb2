// The sparsity pattern of the shared Newton tangent, analysed once per run
// (compressed sparse columns, sorted rows), and the column groups that forward
// differences may perturb together (Curtis-Powell-Reid).
#pragma once

#include <utility>
#include <vector>

namespace mh {

class SparsePattern {
 public:
  // n x n pattern holding every (row, col) in `entries` and the diagonal.
  SparsePattern(int n, std::vector<std::pair<int, int>> entries);

  int size() const { return n_; }
  int nonzeros() const { return static_cast<int>(row_index_.size()); }
  const std::vector<int>& column_start() const { return column_start_; }
  const std::vector<int>& row_index() const { return row_index_; }
  // Position of (row, col) in the value array, or -1 when not in the pattern.
  int slot(int row, int col) const;

  // Greedy grouping of columns so that no two columns of a group share a row:
  // one residual evaluation per group differentiates every column in it.
  std::vector<std::vector<int>> column_groups() const;

  bool operator==(const SparsePattern& other) const {
    return n_ == other.n_ && column_start_ == other.column_start_ && row_index_ == other.row_index_;
  }
  bool operator!=(const SparsePattern& other) const { return !(*this == other); }

 private:
  int n_;
  std::vector<int> column_start_;
  std::vector<int> row_index_;
};

}  // namespace mh
