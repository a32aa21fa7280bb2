// Phi, Phi_z and Phi_z_dot zd of a model's cut joints at (z, zd) in one call,
// for the constraint tests (constraints_test, constraint_derivatives_test).
#pragma once

#include <Eigen/Core>

#include "monohydra/core/constraints.hpp"
#include "monohydra/core/data.hpp"
#include "monohydra/core/kinematics.hpp"
#include "monohydra/core/model.hpp"

namespace mh::test {

struct ConstraintEval {
  Eigen::VectorXd phi, phi_dot;
  Eigen::MatrixXd phi_z;
};

inline ConstraintEval evaluate(const Model& model, Constraints& cs, const Eigen::VectorXd& z,
                               const Eigen::VectorXd& zd) {
  Data data(model);
  forward_kinematics(model, data, z, zd);
  ConstraintEval e{Eigen::VectorXd(cs.size()), Eigen::VectorXd(cs.size()),
                   Eigen::MatrixXd(cs.size(), model.num_coordinates())};
  evaluate_constraints(model, data, cs, e.phi, e.phi_z, e.phi_dot);
  return e;
}

}  // namespace mh::test
