#include "monohydra/core/klu_solver.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace mh {
namespace {

// Values of a dense matrix in the pattern's column-major layout.
std::vector<double> values_of(const SparsePattern& p, const Eigen::MatrixXd& A) {
  std::vector<double> v(static_cast<size_t>(p.nonzeros()));
  for (int c = 0; c < p.size(); ++c)
    for (int k = p.column_start()[c]; k < p.column_start()[c + 1]; ++k)
      v[static_cast<size_t>(k)] = A(p.row_index()[k], c);
  return v;
}

TEST(KluSolver, SolvesSparseSystemsToRoundOffAcrossRefactorizations) {
  const int n = 12;
  std::vector<std::pair<int, int>> e;
  for (int i = 0; i + 1 < n; ++i) {
    e.emplace_back(i, i + 1);
    e.emplace_back(i + 1, i);
  }
  e.emplace_back(0, n - 1);
  const SparsePattern p(n, e);
  KluSolver klu(p);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
    for (int c = 0; c < n; ++c)
      for (int k = p.column_start()[c]; k < p.column_start()[c + 1]; ++k)
        A(p.row_index()[k], c) = u(rng);
    A.diagonal().array() += 4.0;
    const auto v = values_of(p, A);
    ASSERT_TRUE(klu.factor(v.data())) << klu.error();
    Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(n, [&] { return u(rng); });
    Eigen::VectorXd x = b;
    klu.solve(x.data());
    EXPECT_LT((A * x - b).norm(), 1e-13 * b.norm());
  }
  EXPECT_EQ(klu.full_factorizations(), 1) << "later matrices reuse the first pivots";
}

TEST(KluSolver, ReportsASingularMatrixInsteadOfSolvingIt) {
  const SparsePattern p(3, {{0, 1}, {1, 0}});
  KluSolver klu(p);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 3);
  A(0, 0) = 1.0;
  A(1, 1) = 2.0;  // row and column 2 are all zero
  const auto v = values_of(p, A);
  EXPECT_FALSE(klu.factor(v.data()));
  EXPECT_NE(klu.error().find("singular"), std::string::npos) << klu.error();
}

}  // namespace
}  // namespace mh
