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
#include "solver/newton.hpp"

namespace mh {

void Simulation::Engine::assemble_loops() {
  cons.z0 = model.initial_coordinates();
  cons.zd0 = model.initial_rates();
  forward_kinematics(model, data, cons.z0, cons.zd0);
  cons.constraints = build_constraints(model, data);
  m = cons.constraints.size();
  cons.phi.setZero(m);
  cons.phi_dot_zd.setZero(m);
  cons.phi_z.setZero(m, N);
  close_loops();
}

void Simulation::Engine::close_loops() {
  cons.z0 = model.initial_coordinates();
  cons.zd0 = model.initial_rates();
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
  // Newton on Phi(z0) = 0 in the free coordinates, solved when |Phi| is
  // round-off; the minimum-norm increment of the least-squares problem.
  struct ClosureProblem final : NewtonProblem {
    Simulation::Engine& e;
    const std::vector<int>& free_cols;
    Eigen::MatrixXd& A;
    double bound;
    double residual_norm = 0.0;
    ClosureProblem(Simulation::Engine& engine, const std::vector<int>& cols, Eigen::MatrixXd& a,
                   double b)
        : e(engine), free_cols(cols), A(a), bound(b) {}
    void residual(Eigen::VectorXd& f) override {
      forward_kinematics(e.model, e.data, e.cons.z0, e.cons.zd0);
      evaluate_constraints(e.model, e.data, e.cons.constraints, e.cons.phi, e.cons.phi_z,
                           e.cons.phi_dot_zd);
      e.run.constraint_positions_valid = false;  // at kinematics of its own, not kept
      f = e.cons.phi;
      residual_norm = f.lpNorm<Eigen::Infinity>();
    }
    void setup() override {
      for (size_t c = 0; c < free_cols.size(); ++c)
        A.col(static_cast<Eigen::Index>(c)) = e.cons.phi_z.col(free_cols[c]);
    }
    void solve(const Eigen::VectorXd& f, Eigen::VectorXd& du) override {
      du = A.completeOrthogonalDecomposition().solve(-f);
    }
    void add(const Eigen::VectorXd& du) override {
      for (size_t c = 0; c < free_cols.size(); ++c)
        e.cons.z0[free_cols[c]] += du[static_cast<Eigen::Index>(c)];
    }
    void subtract(const Eigen::VectorXd& du) override {
      for (size_t c = 0; c < free_cols.size(); ++c)
        e.cons.z0[free_cols[c]] -= du[static_cast<Eigen::Index>(c)];
    }
    double measure(const Eigen::VectorXd& du, int& worst) override {
      Eigen::Index i = 0;
      const double size = du.size() > 0 ? du.cwiseAbs().maxCoeff(&i) : 0.0;
      worst = free_cols.empty() ? 0 : free_cols[static_cast<size_t>(i)];
      return size;
    }
    bool converged(double /*size*/) override { return false; }  // by the residual alone
    bool solved(const Eigen::VectorXd& /*f*/) override { return residual_norm <= bound; }
  };
  ClosureProblem problem(*this, free_cols, A, 1e-13 * scale);
  Eigen::VectorXd f(m), dz(nf);
  // Every body fixed: nothing can move, and an m x 0 matrix must not reach
  // the QR; the residual alone says whether the loops are closed.
  const NewtonOutcome out = newton_iterate(problem, nf == 0 ? 0 : 50, f, dz);
  const double residual = problem.residual_norm;
  const bool closed = out.end == NewtonOutcome::End::converged;
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
  const Eigen::VectorXd vel = cons.phi_z * cons.zd0;
  if (nf == 0) {
    const double rate_residual = vel.lpNorm<Eigen::Infinity>();
    if (rate_residual > 1e-10 * std::max(1.0, cons.zd0.lpNorm<Eigen::Infinity>()))
      throw InputError(file->assembly_mark, "assembly.fixed",
                       "lists every body, so nothing can move to make the initial rates "
                       "consistent with the loops: Phi_z zd0 is " +
                           std::to_string(rate_residual) +
                           " (leave at least one body of each loop out of assembly.fixed)");
    return;
  }
  free_part(cons.phi_z);
  const Eigen::VectorXd correction = A.completeOrthogonalDecomposition().solve(-vel);
  for (int c = 0; c < nf; ++c) cons.zd0[free_cols[static_cast<size_t>(c)]] += correction[c];
}

}  // namespace mh
