// Parameters of a run moved in place between steps, as offsets from the
// values they had when held: what a filter that estimates them beside the
// state (augmented states, docs/estimation.md) corrects and differences.
// The model is always set to base + sum_j offset_j direction_j, so that an
// offset put back restores the values to the bit, and two parameters that
// move one body (a mass that moves its inertia, and the inertia) add up.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "monohydra/core/model.hpp"
#include "monohydra/core/sensitivities.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh {

class HeldParameters {
 public:
  // Each a parameter as the sensitivities take it (the host's
  // parameter_direction.cpp makes them from paths); `sim` outlives this.
  // Throws std::invalid_argument naming an initial coordinate (start()
  // alone reads it), a body out of range or an option its component does
  // not change in place.
  HeldParameters(Simulation& sim, std::vector<ParameterDirection> parameters);

  Eigen::Index size() const { return static_cast<Eigen::Index>(params_.size()); }
  const std::vector<ParameterDirection>& parameters() const { return params_; }
  // Each parameter's value now, in the path's units: its value when held
  // plus its offset.
  Eigen::VectorXd values() const;
  const Eigen::VectorXd& offsets() const { return offsets_; }
  // The model at these offsets. Throws std::invalid_argument (naming the
  // path) for a value the model refuses (a mass at or below 0, a value
  // outside a component's range); the offsets stay as they were.
  void set(const Eigen::VectorXd& offsets);

 private:
  void apply(const Eigen::VectorXd& offsets);
  Simulation& sim_;
  std::vector<ParameterDirection> params_;
  Eigen::VectorXd offsets_;
  std::vector<int> bodies_;  // the bodies any parameter moves
  std::vector<Body> body_base_;
  Eigen::Vector3d gravity_base_ = Eigen::Vector3d::Zero();
  bool moves_gravity_ = false;
  std::vector<int> handles_;         // per parameter: its option's handle, or -1
  std::vector<double> option_base_;  // per parameter: its option's value when held
};

}  // namespace mh
