// Coordinate partitioning (Sect. 2.2): Gaussian elimination with full pivoting
// on the constraint Jacobian Phi_z (m x N) chooses r = rank(Phi_z) dependent
// coordinates z^d (the pivot columns) and r independent constraint rows (the
// pivot rows); the N - r columns where no pivot appears are the independent
// coordinates z^i, the degrees of freedom f of Eqs. (13)-(17).
#pragma once

#include <string>
#include <vector>

#include "eigen.hpp"

namespace mh::double_step {

// Indices are 0-based and ascending in each list.
struct Partition {
  std::vector<int> rows;         // r constraint rows used (all m unless redundant)
  std::vector<int> dependent;    // r coordinates z^d: the pivot columns
  std::vector<int> independent;  // N - r coordinates z^i
  bool operator==(const Partition& o) const {
    return rows == o.rows && dependent == o.dependent && independent == o.independent;
  }
  bool operator!=(const Partition& o) const { return !(*this == o); }
};

// A pivot is taken as zero (the row is redundant, the configuration singular)
// when it is below this fraction of the largest pivot. Far below any
// re-partition threshold and far above the round-off of an assembled Phi_z
// (whose exact rank deficiencies leave pivots near 1e-16 of the largest).
constexpr double kRankThreshold = 1e-8;

// Full-pivoting LU of phi_z (into `lu`, which must be sized m x N: compute()
// then reuses its storage). Returns the numerical rank.
int factor_full_pivoting(const Eigen::Ref<const Eigen::MatrixXd>& phi_z,
                         Eigen::FullPivLU<Eigen::MatrixXd>& lu);

// The partition given by the first r pivots of a factored `lu` (r <= its
// rank). `out`'s lists must already have sizes r, r and N - r: they are
// overwritten in place, so this does not allocate.
void partition_from_pivots(const Eigen::FullPivLU<Eigen::MatrixXd>& lu, int r, Partition& out);

// The partition with the given independent coordinates (N - r of them,
// ascending): the other r are dependent, and the r rows kept are the pivot
// rows of full pivoting on Phi_z's dependent columns (m x r). Returns the pivot
// ratio of that block, 0 when it is singular (the choice is then unusable).
double partition_with_independent(const Eigen::Ref<const Eigen::MatrixXd>& phi_z,
                                  const std::vector<int>& independent, Partition& out);

// Sizes `p`'s lists for r pivots among N coordinates.
void size_partition(Partition& p, int N, int r);

// The reciprocal condition estimate used to decide re-partitioning: the ratio
// of the smallest to the largest pivot of a full-pivoting LU of a square
// matrix (1 for an orthogonal-like block, 0 when singular). Cheap and
// allocation-free, unlike Eigen's rcond() estimators.
double pivot_ratio(const Eigen::FullPivLU<Eigen::MatrixXd>& lu);

// "z3" or "z2, z5": the named coordinates.
std::string coordinate_list(const std::vector<int>& indices, const std::vector<std::string>& names);
// "5" or "5, 6": 1-based row numbers of the rows of 0..m-1 not in `rows`.
std::string dropped_rows(const std::vector<int>& rows, int m);

}  // namespace mh::double_step
