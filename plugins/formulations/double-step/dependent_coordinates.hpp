// The dependent coordinates z^d for given independent ones z^i: Newton-Raphson
// on the kept rows of the loop-closure equations Phi(z) = 0 (Sect. 4, the text
// after Eq. 34), Phi_z^d dz^d = -Phi, from the estimate
// z^d_{k+1} = z^d_k + zd^d_k dt + zdd^d_k dt^2 / 2 the caller puts in z.
#pragma once

#include "coordinate_partition.hpp"
#include "eigen.hpp"
#include "monohydra/monohydra.h"

namespace mh::double_step {

struct DependentSolveResult {
  enum class Outcome { converged, not_converged, singular, host_failed };
  Outcome outcome = Outcome::converged;
  int iterations = 0;        // Newton updates of z^d
  double residual = 0.0;     // max |Phi| over the kept rows at the last evaluation
  double increment = 0.0;    // max |dz^d| of the last update
  double pivot_ratio = 0.0;  // of Phi_z^d's partial-pivoting LU, when singular
  mh_status host_status = MH_OK;
};

class DependentCoordinates {
 public:
  // Sizes every buffer: m constraint rows of which r are kept, N coordinates.
  void resize(int m, int N, int r);

  // Solves the kept rows of Phi(z) = 0 for z[dependent], holding
  // z[independent], from the z[dependent] given; zd only feeds the host's
  // velocity term, unused here. Converged when the last increment is at most
  // `tolerance` in every coordinate; with Newton's quadratic convergence the
  // error left is then of order tolerance^2, i.e. round-off. An increment at
  // the round-off of z itself (64 ulps of the largest |z^d|) is not applied:
  // z is then returned exactly as evaluated. On convergence the
  // last evaluation was at the returned z, and phi_z_d(), phi_z_i() and lu()
  // hold Phi_z^d, Phi_z^i and the LU of Phi_z^d there.
  DependentSolveResult solve(const mh_host* host, const mh_mechanism_service& mech, double t,
                             const Partition& p, double tolerance, int max_iterations,
                             Eigen::VectorXd& z, const Eigen::VectorXd& zd);

  const Eigen::MatrixXd& phi_z_d() const { return phi_z_d_; }
  const Eigen::MatrixXd& phi_z_i() const { return phi_z_i_; }
  const Eigen::PartialPivLU<Eigen::MatrixXd>& lu() const { return lu_; }

 private:
  // Phi_z^d and Phi_z^i (kept rows) and Phi (kept rows) from the host's result.
  void gather(const mh_mech_result& rs, const Partition& p);
  // Factors Phi_z^d; false when a pivot vanishes. *ratio: min/max |pivot|.
  bool factor(double* ratio);

  int m_ = 0, N_ = 0;
  Eigen::MatrixXd phi_z_d_;  // r x r
  Eigen::MatrixXd phi_z_i_;  // r x f
  Eigen::VectorXd phi_;      // r
  Eigen::VectorXd dz_;       // r
  Eigen::VectorXd scratch_;  // r
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace mh::double_step
