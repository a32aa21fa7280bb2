// Solves M' x = y (Eq. 12's mass matrix) in O(N) for a tree, without forming
// M': the articulated-body recursion in the semirecursive form. M' is
// R^T Mbar R with R_{jk} = b_k for k on body j's path to the ground (Eqs. 2,
// 12) and every b_k and Mbar_j expressed at the world origin, so the
// recursion needs no frame changes: a backward pass gathers each subtree's
// articulated inertia IA_j = Mbar_j + sum over children c of
// (IA_c - U_c U_c^T / D_c), U_c = IA_c b_c, D_c = b_c^T U_c; a second backward
// pass gathers the bias pA of y, and a forward pass gives x_j = (y_j - b_j^T
// pA_j - U_j^T A_parent) / D_j with A_j = A_parent + b_j x_j. Featherstone's
// articulated-body algorithm, written for M' alone (no velocity terms).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "monohydra/core/data.hpp"
#include "monohydra/core/model.hpp"

namespace mh {

// What articulated_factor leaves for articulated_solve, sized once from a Model.
struct ArticulatedWorkspace {
  explicit ArticulatedWorkspace(const Model& model);
  std::vector<Vector6d> b;   // the joints' b_j (Eq. 2) at the factorization
  std::vector<Matrix6d> IA;  // articulated inertia of each body's subtree
  std::vector<Vector6d> U;   // IA_j b_j
  std::vector<double> D;     // b_j^T IA_j b_j: the joint's articulated inertia
  std::vector<Vector6d> pA;  // bias of the right-hand side (articulated_solve)
  std::vector<Vector6d> A;   // the bodies' motion for x (articulated_solve)
};

// IA, U and D at the kinematics in `data` (forward_kinematics). Returns false
// when a joint's D is not positive (a massless subtree: M' singular).
bool articulated_factor(const Model& model, const Data& data, ArticulatedWorkspace& ws);

// y in, x = M'^-1 y out, with the factors of articulated_factor (at its
// kinematics, whatever data holds now).
void articulated_solve(const Model& model, ArticulatedWorkspace& ws, Eigen::Ref<Eigen::VectorXd> y);

}  // namespace mh
