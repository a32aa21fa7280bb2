// Newton-Raphson for the dependent coordinates (Sect. 4, after Eq. 34).
#include "dependent_coordinates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "host_calls.hpp"
#include "lu_substitution.hpp"

namespace mh::double_step {
namespace {
// An increment of z^d within this many ulps of the largest |z^d| (rad or m)
// is the round-off of Phi itself (positions of order the coordinates), not an
// error of the estimate: measured on the case studies, two thirds of the
// first increments from the estimate along R_z lie between 1e-15 and 1e-14.
constexpr double kRoundOffUlps = 64.0;
}  // namespace

void DependentCoordinates::resize(int m, int N, int r) {
  m_ = m;
  N_ = N;
  phi_z_d_.setZero(r, r);
  phi_z_i_.setZero(r, N - r);
  phi_.setZero(r);
  dz_.setZero(r);
  scratch_.setZero(r);
  // Sized once here: compute() on an r x r matrix then reuses the storage.
  lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(r);
}

void DependentCoordinates::gather(const mh_mech_result& rs, const Partition& p) {
  const Eigen::Map<const Eigen::MatrixXd> phi_z(rs.phi_z, m_, N_);  // column-major
  const int r = static_cast<int>(p.rows.size());
  const int f = static_cast<int>(p.independent.size());
  for (int a = 0; a < r; ++a) {
    const int row = p.rows[static_cast<size_t>(a)];
    phi_[a] = rs.phi[row];
    for (int k = 0; k < r; ++k) phi_z_d_(a, k) = phi_z(row, p.dependent[static_cast<size_t>(k)]);
    for (int k = 0; k < f; ++k) phi_z_i_(a, k) = phi_z(row, p.independent[static_cast<size_t>(k)]);
  }
}

bool DependentCoordinates::factor(double* ratio) {
  // Equal size: PartialPivLU::compute assigns into its existing r x r storage
  // and its permutation keeps its size, so nothing is allocated.
  lu_.compute(phi_z_d_);
  const auto& LU = lu_.matrixLU();
  double lo = std::abs(LU(0, 0)), hi = lo;
  for (Eigen::Index k = 1; k < LU.rows(); ++k) {
    lo = std::min(lo, std::abs(LU(k, k)));
    hi = std::max(hi, std::abs(LU(k, k)));
  }
  *ratio = (hi > 0.0 && std::isfinite(hi) && std::isfinite(lo)) ? lo / hi : 0.0;
  return *ratio > kRankThreshold;
}

DependentSolveResult DependentCoordinates::solve(const mh_host* host,
                                                 const mh_mechanism_service& mech, double t,
                                                 const Partition& p, double tolerance,
                                                 int max_iterations, Eigen::VectorXd& z,
                                                 const Eigen::VectorXd& zd) {
  DependentSolveResult out;
  const int r = static_cast<int>(p.rows.size());
  bool converged = false;
  for (;;) {
    mh_mech_result rs{};
    // Phi and Phi_z only: the velocity term is of no use until z converges.
    out.host_status = evaluate(host, mech, MH_EVAL_CONSTRAINTS | MH_EVAL_POSITIONS_ONLY, t,
                               z.data(), zd.data(), rs);
    if (out.host_status >= MH_DISCARD) {
      out.outcome = DependentSolveResult::Outcome::host_failed;
      return out;
    }
    gather(rs, p);
    out.residual = phi_.lpNorm<Eigen::Infinity>();
    // The Jacobian is factored at every evaluation, the last one included:
    // Eqs. (13)-(15) need Phi_z^d at the solution itself, so that z^d, zd^d and
    // zdd^d are smooth functions of z^i for the host's difference tangent.
    if (!factor(&out.pivot_ratio) || !std::isfinite(out.residual)) {
      out.outcome = DependentSolveResult::Outcome::singular;
      return out;
    }
    if (converged) break;
    if (out.iterations >= max_iterations) {
      out.outcome = DependentSolveResult::Outcome::not_converged;
      return out;
    }
    dz_ = phi_;  // Phi_z^d dz^d = -Phi (the sign is applied below)
    lu_solve_in_place(lu_, dz_, scratch_);
    out.increment = dz_.lpNorm<Eigen::Infinity>();
    if (!dz_.allFinite()) {
      out.outcome = DependentSolveResult::Outcome::not_converged;
      return out;
    }
    // An increment at round-off (a start that was already the solution, as
    // the estimate along R_z is within a Newton iteration's last steps) is
    // not applied: z stands as evaluated, so Phi_z^d as factored is at z to
    // the last bit, and the host's kinematics at z stand for the dynamics
    // that follow (only the rates change: no new kinematics pass).
    double largest = 1.0;
    for (int k = 0; k < r; ++k)
      largest = std::max(largest, std::abs(z[p.dependent[static_cast<size_t>(k)]]));
    if (out.increment <= kRoundOffUlps * std::numeric_limits<double>::epsilon() * largest) break;
    for (int k = 0; k < r; ++k) z[p.dependent[static_cast<size_t>(k)]] -= dz_[k];
    ++out.iterations;
    converged = out.increment <= tolerance;
  }
  out.outcome = DependentSolveResult::Outcome::converged;
  return out;
}

}  // namespace mh::double_step
