// Choosing dependent and independent coordinates by full pivoting (Sect. 2.2).
#include "coordinate_partition.hpp"

#include <algorithm>
#include <cmath>

namespace mh::double_step {

int factor_full_pivoting(const Eigen::Ref<const Eigen::MatrixXd>& phi_z,
                         Eigen::FullPivLU<Eigen::MatrixXd>& lu) {
  // compute() copies phi_z into the LU's m x N storage: at equal size Eigen
  // resizes nothing, and the permutations and transpositions keep their sizes.
  lu.setThreshold(kRankThreshold);
  lu.compute(phi_z);
  return static_cast<int>(lu.rank());
}

void size_partition(Partition& p, int N, int r) {
  p.rows.assign(static_cast<size_t>(r), 0);
  p.dependent.assign(static_cast<size_t>(r), 0);
  p.independent.assign(static_cast<size_t>(N - r), 0);
}

void partition_from_pivots(const Eigen::FullPivLU<Eigen::MatrixXd>& lu, int r, Partition& out) {
  const auto& P = lu.permutationP().indices();  // row j of Phi_z is row P[j] of P Phi_z Q
  const auto& Q = lu.permutationQ().indices();  // column k of P Phi_z Q is column Q[k] of Phi_z
  const int m = static_cast<int>(P.size());
  const int N = static_cast<int>(Q.size());
  // Pivot k sits at row k and column k of P Phi_z Q: the first r are the
  // dependent columns and the kept rows.
  int kept = 0;
  for (int j = 0; j < m; ++j)
    if (P[j] < r) out.rows[static_cast<size_t>(kept++)] = j;
  for (int k = 0; k < r; ++k) out.dependent[static_cast<size_t>(k)] = Q[k];
  std::sort(out.dependent.begin(), out.dependent.end());
  int free = 0;
  for (int c = 0, d = 0; c < N; ++c) {
    if (d < r && out.dependent[static_cast<size_t>(d)] == c) {
      ++d;
      continue;
    }
    out.independent[static_cast<size_t>(free++)] = c;
  }
}

double partition_with_independent(const Eigen::Ref<const Eigen::MatrixXd>& phi_z,
                                  const std::vector<int>& independent, Partition& out) {
  const int m = static_cast<int>(phi_z.rows());
  const int N = static_cast<int>(phi_z.cols());
  const int r = N - static_cast<int>(independent.size());
  size_partition(out, N, r);
  out.independent = independent;
  std::sort(out.independent.begin(), out.independent.end());
  Eigen::MatrixXd dependent_columns(m, r);
  for (int c = 0, d = 0, k = 0; c < N; ++c) {
    if (k < N - r && out.independent[static_cast<size_t>(k)] == c) {
      ++k;
      continue;
    }
    out.dependent[static_cast<size_t>(d)] = c;
    dependent_columns.col(d++) = phi_z.col(c);
  }
  Eigen::FullPivLU<Eigen::MatrixXd> lu(m, r);
  if (factor_full_pivoting(dependent_columns, lu) < r) return 0.0;
  const auto& P = lu.permutationP().indices();
  for (int j = 0, kept = 0; j < m; ++j)
    if (P[j] < r) out.rows[static_cast<size_t>(kept++)] = j;
  const auto& LU = lu.matrixLU();
  double lo = std::abs(LU(0, 0));
  for (int k = 1; k < r; ++k) lo = std::min(lo, std::abs(LU(k, k)));
  return lo / std::abs(LU(0, 0));
}

double pivot_ratio(const Eigen::FullPivLU<Eigen::MatrixXd>& lu) {
  const auto& LU = lu.matrixLU();
  const Eigen::Index n = std::min(LU.rows(), LU.cols());
  if (n == 0) return 1.0;
  // Full pivoting takes the largest remaining entry each time, so |U_00| is
  // the largest pivot; the smallest need not be the last one, so scan.
  double lo = std::abs(LU(0, 0)), hi = lo;
  for (Eigen::Index k = 1; k < n; ++k) {
    lo = std::min(lo, std::abs(LU(k, k)));
    hi = std::max(hi, std::abs(LU(k, k)));
  }
  if (!(hi > 0.0) || !std::isfinite(lo) || !std::isfinite(hi)) return 0.0;
  return lo / hi;
}

std::string coordinate_list(const std::vector<int>& indices,
                            const std::vector<std::string>& names) {
  std::string out;
  for (int i : indices) {
    if (!out.empty()) out += ", ";
    out += names[static_cast<size_t>(i)];
  }
  return out;
}

std::string dropped_rows(const std::vector<int>& rows, int m) {
  std::string out;
  for (int j = 0; j < m; ++j) {
    if (std::find(rows.begin(), rows.end(), j) != rows.end()) continue;
    if (!out.empty()) out += ", ";
    out += std::to_string(j + 1);
  }
  return out;
}

}  // namespace mh::double_step
