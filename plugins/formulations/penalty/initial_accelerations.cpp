// The acceleration-level augmented Lagrangian iteration at t0 (see the header).
#include "initial_accelerations.hpp"

#include <algorithm>

#include "constraint_terms.hpp"

namespace mh_penalty {

AccelerationSolve solve_initial_accelerations(const Eigen::Map<const Eigen::MatrixXd>& M,
                                              const Eigen::Map<const Eigen::VectorXd>& Q,
                                              const Eigen::Map<const Eigen::MatrixXd>& phi_z,
                                              const Eigen::Map<const Eigen::VectorXd>& phi_dot_zd,
                                              double alpha, Eigen::VectorXd& zdd,
                                              Eigen::VectorXd& lambda) {
  constexpr int kMaxIterations = 50;
  // The violation is a difference of terms of size |Phi_z| |zdd| and
  // |Phidot_z zd|; round-off keeps it from going much below 1e-13 of them.
  constexpr double kViolationBound = 1e-10;
  // The last correction of zdd, relative to zdd: see below.
  constexpr double kCorrectionBound = 1e-12;
  AccelerationSolve out;
  const Eigen::Index N = M.rows();
  const Eigen::Index m = phi_z.rows();

  Eigen::MatrixXd A = M;
  add_penalty_matrix(A, phi_z, alpha);
  // LDLT (pivoted): with alpha = 1e11 the matrix is positive definite but its
  // condition number reaches ~1e13.
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
  // N = 0 (a model of subsystems only): nothing to factor, no minimum pivot.
  if (A.rows() > 0 &&
      (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0.0))) {
    out.positive_definite = false;
    return out;
  }

  // The iteration in increment form: each pass solves for the change of zdd
  // from the residuals of M' zdd + Phi_z^T lambda = Q' and of the constraint
  // accelerations, which keeps the right-hand side small (alpha times a
  // vanishing violation) instead of subtracting two terms of size alpha.
  // Algebraically it is the classic update written in the header. It is also
  // iterative refinement: with alpha = 1e11 one solve with the matrix above
  // leaves a round-off error of about 1e-16 cond ~ 1e-5 (relative) in the
  // free directions of zdd, where Phi_z zdd is blind to it; the next pass sees
  // it in the residual of M' zdd + Phi_z^T lambda = Q' and removes it. So the
  // iteration stops when the violation is small AND the last correction is.
  zdd.setZero(N);
  Eigen::VectorXd c = phi_dot_zd;  // Phi_z zdd + Phidot_z zd at zdd = 0
  Eigen::VectorXd rhs(N), delta(N);
  for (out.iterations = 0; out.iterations < kMaxIterations;) {
    rhs = Q;
    rhs.noalias() -= M * zdd;
    add_constraint_forces(rhs, phi_z, lambda, -1.0);
    add_constraint_forces(rhs, phi_z, c, -alpha);
    delta = ldlt.solve(rhs);
    zdd += delta;
    c = phi_dot_zd;
    c.noalias() += phi_z * zdd;
    lambda += alpha * c;
    ++out.iterations;
    if (m == 0) {  // M' zdd = Q', well conditioned: one solve, exactly open-loop's
      out.converged = true;
      break;
    }
    const double scale =
        phi_z.cwiseAbs().rowwise().sum().maxCoeff() * zdd.lpNorm<Eigen::Infinity>() +
        phi_dot_zd.lpNorm<Eigen::Infinity>();
    out.bound = kViolationBound * std::max(1.0, scale);
    out.violation = c.lpNorm<Eigen::Infinity>();
    out.correction = delta.lpNorm<Eigen::Infinity>();
    if (out.violation <= out.bound &&
        out.correction <= kCorrectionBound * std::max(1.0, zdd.lpNorm<Eigen::Infinity>())) {
      out.converged = true;
      break;
    }
  }
  return out;
}

}  // namespace mh_penalty
