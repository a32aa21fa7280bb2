// Every shipped linear solver (linear_solver.cpp) against KLU, the default:
// the same solutions to round-off on sparse systems whose values change from
// one factorization to the next, and a singular matrix reported, not solved.
#include "monohydra/core/linear_solver.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace mh {
namespace {

constexpr LinearSolverKind kAll[] = {LinearSolverKind::klu, LinearSolverKind::umfpack,
                                     LinearSolverKind::dense, LinearSolverKind::automatic};

std::vector<double> values_of(const SparsePattern& p, const Eigen::MatrixXd& A) {
  std::vector<double> v(static_cast<size_t>(p.nonzeros()));
  for (int c = 0; c < p.size(); ++c)
    for (int k = p.column_start()[c]; k < p.column_start()[c + 1]; ++k)
      v[static_cast<size_t>(k)] = A(p.row_index()[k], c);
  return v;
}

// A tangent-like pattern: a dense mechanical block coupled to a sparse chain.
SparsePattern tangent_like(int dense, int chain) {
  std::vector<std::pair<int, int>> e;
  for (int r = 0; r < dense; ++r)
    for (int c = 0; c < dense; ++c) e.emplace_back(r, c);
  const int n = dense + chain;
  for (int i = dense; i + 1 < n; ++i) {
    e.emplace_back(i, i + 1);
    e.emplace_back(i + 1, i);
  }
  e.emplace_back(0, n - 1);
  e.emplace_back(n - 1, 0);
  return SparsePattern(n, e);
}

TEST(LinearSolver, EverySolverGivesKlusSolutionsAcrossRefactorizations) {
  const SparsePattern p = tangent_like(6, 10);
  const int n = p.size();
  auto klu = make_linear_solver(p, LinearSolverKind::klu);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (LinearSolverKind kind : kAll) {
    auto solver = make_linear_solver(p, kind);
    for (int trial = 0; trial < 6; ++trial) {
      Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
      for (int c = 0; c < n; ++c)
        for (int k = p.column_start()[c]; k < p.column_start()[c + 1]; ++k)
          A(p.row_index()[k], c) = u(rng);
      A.diagonal().array() += 3.0 + trial;  // values change between factorizations
      const auto v = values_of(p, A);
      ASSERT_TRUE(klu->factor(v.data())) << klu->error();
      ASSERT_TRUE(solver->factor(v.data())) << to_string(kind) << ": " << solver->error();
      const Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(n, [&] { return u(rng); });
      Eigen::VectorXd x_klu = b, x = b;
      klu->solve(x_klu.data());
      solver->solve(x.data());
      EXPECT_LT((A * x - b).norm(), 1e-13 * b.norm()) << to_string(kind);
      EXPECT_LT((x - x_klu).norm(), 1e-12 * x_klu.norm()) << to_string(kind);
    }
  }
}

TEST(LinearSolver, EverySolverReportsASingularMatrixInsteadOfSolvingIt) {
  const SparsePattern p(3, {{0, 1}, {1, 0}});
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 3);
  A(0, 0) = 1.0;
  A(1, 1) = 2.0;  // row and column 2 are all zero
  const auto v = values_of(p, A);
  for (LinearSolverKind kind : kAll) {
    auto solver = make_linear_solver(p, kind);
    EXPECT_FALSE(solver->factor(v.data())) << to_string(kind);
    EXPECT_NE(solver->error().find("singular"), std::string::npos)
        << to_string(kind) << ": " << solver->error();
  }
}

TEST(LinearSolver, ASolverRecoversAfterASingularMatrix) {
  const SparsePattern p(2, {{0, 1}, {1, 0}});
  for (LinearSolverKind kind : kAll) {
    auto solver = make_linear_solver(p, kind);
    const std::vector<double> singular{1.0, 2.0, 2.0, 4.0};  // columns (1,2), (2,4)
    EXPECT_FALSE(solver->factor(singular.data())) << to_string(kind);
    const std::vector<double> regular{2.0, 1.0, 1.0, 3.0};
    ASSERT_TRUE(solver->factor(regular.data())) << to_string(kind) << ": " << solver->error();
    double b[2] = {3.0, 4.0};  // A (1, 1) = (3, 4)
    solver->solve(b);
    EXPECT_NEAR(b[0], 1.0, 1e-15) << to_string(kind);
    EXPECT_NEAR(b[1], 1.0, 1e-15) << to_string(kind);
  }
}

// auto: dense LU where more than half the entries are in the pattern (a
// chain's tangent), KLU where it is sparse (a tree's); the other kinds as named.
TEST(LinearSolver, AutoTakesDenseLuForADensePatternAndKluForASparseOne) {
  EXPECT_EQ(resolve_linear_solver(tangent_like(6, 0), LinearSolverKind::automatic),
            LinearSolverKind::dense);
  EXPECT_EQ(resolve_linear_solver(tangent_like(3, 30), LinearSolverKind::automatic),
            LinearSolverKind::klu);
  for (LinearSolverKind kind :
       {LinearSolverKind::klu, LinearSolverKind::umfpack, LinearSolverKind::dense})
    EXPECT_EQ(resolve_linear_solver(tangent_like(6, 0), kind), kind);
}

TEST(LinearSolver, AKluSolverLikeAnotherOfItsPatternSolvesAsItsOwnAnalysisDoes) {
  const SparsePattern p = tangent_like(6, 10);
  const int n = p.size();
  const auto first = make_linear_solver(p, LinearSolverKind::klu);
  const auto alone = make_linear_solver(p, LinearSolverKind::klu);
  const auto shared = make_linear_solver(p, LinearSolverKind::klu, first.get());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int round = 0; round < 3; ++round) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
    for (int c = 0; c < n; ++c)
      for (int k = p.column_start()[c]; k < p.column_start()[c + 1]; ++k)
        A(p.row_index()[k], c) = u(rng);
    A.diagonal().array() += 8.0;
    const std::vector<double> v = values_of(p, A);
    ASSERT_TRUE(alone->factor(v.data()));
    ASSERT_TRUE(shared->factor(v.data()));
    Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(n, [&] { return u(rng); });
    Eigen::VectorXd x_alone = b, x_shared = b;
    alone->solve(x_alone.data());
    shared->solve(x_shared.data());
    // The same ordering, so the same arithmetic: equal to the bit.
    EXPECT_EQ(x_alone, x_shared) << "round " << round;
    EXPECT_LT((A * x_shared - b).norm(), 1e-12 * b.norm());
  }
  // Another pattern is analysed anew, and solves its own matrix.
  const SparsePattern q = tangent_like(3, 5);
  const auto other = make_linear_solver(q, LinearSolverKind::klu, first.get());
  Eigen::MatrixXd B = Eigen::MatrixXd::Identity(q.size(), q.size()) * 2.0;
  const std::vector<double> w = values_of(q, B);
  ASSERT_TRUE(other->factor(w.data()));
  Eigen::VectorXd c = Eigen::VectorXd::Ones(q.size());
  other->solve(c.data());
  EXPECT_TRUE(c.isApprox(Eigen::VectorXd::Constant(q.size(), 0.5)));
}

}  // namespace
}  // namespace mh
