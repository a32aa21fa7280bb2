// M' x = y in O(N) (articulated_solve.hpp).
#include "monohydra/core/articulated_solve.hpp"

#include "monohydra/core/dynamics.hpp"

namespace mh {

ArticulatedWorkspace::ArticulatedWorkspace(const Model& model)
    : b(static_cast<size_t>(model.num_bodies()), Vector6d::Zero()),
      IA(static_cast<size_t>(model.num_bodies()), Matrix6d::Zero()),
      U(static_cast<size_t>(model.num_bodies()), Vector6d::Zero()),
      D(static_cast<size_t>(model.num_bodies()), 0.0),
      pA(static_cast<size_t>(model.num_bodies()), Vector6d::Zero()),
      A(static_cast<size_t>(model.num_bodies()), Vector6d::Zero()) {}

bool articulated_factor(const Model& model, const Data& data, ArticulatedWorkspace& ws) {
  const int n = model.num_bodies();
  for (int j = 0; j < n; ++j)
    ws.IA[static_cast<size_t>(j)] = body_mass_matrix(model, data, j);  // Eq. (9)
  // Children follow their parents: a backward sweep completes every subtree
  // before it is passed on.
  for (int j = n - 1; j >= 0; --j) {
    const auto k = static_cast<size_t>(j);
    const Vector6d& b = ws.b[k] = data.b[k];
    ws.U[k].noalias() = ws.IA[k] * b;
    ws.D[k] = b.dot(ws.U[k]);
    if (!(ws.D[k] > 0.0)) return false;
    const int p = model.bodies[k].parent;
    if (p == kGround) continue;
    ws.IA[static_cast<size_t>(p)] += ws.IA[k];
    ws.IA[static_cast<size_t>(p)].noalias() -= (ws.U[k] / ws.D[k]) * ws.U[k].transpose();
  }
  return true;
}

void articulated_solve(const Model& model, ArticulatedWorkspace& ws,
                       Eigen::Ref<Eigen::VectorXd> y) {
  const int n = model.num_bodies();
  for (int j = 0; j < n; ++j) ws.pA[static_cast<size_t>(j)].setZero();
  for (int j = n - 1; j >= 0; --j) {  // y_j - b_j^T pA_j, kept in y
    const auto k = static_cast<size_t>(j);
    y[j] -= ws.b[k].dot(ws.pA[k]);
    const int p = model.bodies[k].parent;
    if (p != kGround) ws.pA[static_cast<size_t>(p)] += ws.pA[k] + ws.U[k] * (y[j] / ws.D[k]);
  }
  for (int j = 0; j < n; ++j) {
    const auto k = static_cast<size_t>(j);
    const int p = model.bodies[k].parent;
    const Vector6d A_p = p == kGround ? Vector6d::Zero() : ws.A[static_cast<size_t>(p)];
    y[j] = (y[j] - ws.U[k].dot(A_p)) / ws.D[k];
    ws.A[k] = A_p + ws.b[k] * y[j];
  }
}

}  // namespace mh
