// Initial assembly of closed loops: the model's z0 are given to a few decimals
// (the quick-return's angles to 0.01 deg), so the loops are closed by Newton
// before any formulation sees them, and every formulation starts from the same
// consistent state. The bodies listed under assembly.fixed keep their
// coordinates; the others move by the least-squares (minimum-norm) correction,
// which also copes with redundant constraints.
#include <Eigen/QR>
#include <cmath>

#include "engine.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {

void Simulation::Engine::assemble_loops() {
  z0 = model.initial_coordinates();
  zd0 = model.initial_rates();
  forward_kinematics(model, data, z0, zd0);
  constraints = build_constraints(model, data);
  m = constraints.size();
  phi.setZero(m);
  phi_dot_zd.setZero(m);
  phi_z.setZero(m, N);
  if (m == 0) return;

  std::vector<int> free_cols;
  for (int j = 0; j < N; ++j) {
    bool fixed = false;
    for (int f : model.assembly_fixed) fixed = fixed || f == j;
    if (!fixed) free_cols.push_back(j);
  }
  const int nf = static_cast<int>(free_cols.size());
  Eigen::MatrixXd A(m, nf);
  const auto free_part = [&](const Eigen::MatrixXd& Pz) {
    for (int c = 0; c < nf; ++c) A.col(c) = Pz.col(free_cols[static_cast<size_t>(c)]);
  };
  const double scale = std::max(1.0, settings.tol_position);
  double residual = 0.0;
  bool closed = false;
  for (int it = 0; it < 50 && !closed; ++it) {
    forward_kinematics(model, data, z0, zd0);
    evaluate_constraints(model, data, constraints, phi, phi_z, phi_dot_zd);
    constraints_valid = false;  // at kinematics of its own, not kept
    residual = phi.lpNorm<Eigen::Infinity>();
    if (residual <= 1e-13 * scale) {
      closed = true;
      break;
    }
    // Every body fixed: nothing can move, and an m x 0 matrix must not reach the QR.
    if (nf == 0) break;
    free_part(phi_z);
    const Eigen::VectorXd dz = A.completeOrthogonalDecomposition().solve(-phi);
    for (int c = 0; c < nf; ++c) z0[free_cols[static_cast<size_t>(c)]] += dz[c];
  }
  if (!closed && nf == 0)
    throw InputError(file->assembly_mark, "assembly.fixed",
                     "lists every body, so nothing can move to close the loops: the constraint "
                     "residual is " +
                         std::to_string(residual) +
                         " (leave at least one body of each loop out of assembly.fixed)");
  if (!closed)
    throw InputError(SourceMark{file->path, 0, 0}, "cut_joints",
                     "the loops cannot be closed from the given z0: the constraint residual "
                     "stays at " +
                         std::to_string(residual) +
                         " after 50 Newton iterations (check the cut joints' points and the "
                         "initial coordinates)");
  // Consistent rates: remove the part of zd0 that violates Phi_z zd = 0.
  const Eigen::VectorXd vel = phi_z * zd0;
  if (nf == 0) {
    const double rate_residual = vel.lpNorm<Eigen::Infinity>();
    if (rate_residual > 1e-10 * std::max(1.0, zd0.lpNorm<Eigen::Infinity>()))
      throw InputError(file->assembly_mark, "assembly.fixed",
                       "lists every body, so nothing can move to make the initial rates "
                       "consistent with the loops: Phi_z zd0 is " +
                           std::to_string(rate_residual) +
                           " (leave at least one body of each loop out of assembly.fixed)");
    return;
  }
  free_part(phi_z);
  const Eigen::VectorXd correction = A.completeOrthogonalDecomposition().solve(-vel);
  for (int c = 0; c < nf; ++c) zd0[free_cols[static_cast<size_t>(c)]] += correction[c];
}

}  // namespace mh
