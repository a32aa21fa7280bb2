// Parameters moved in place as offsets (held_parameters.hpp).
#include "monohydra/core/held_parameters.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace mh {

HeldParameters::HeldParameters(Simulation& sim, std::vector<ParameterDirection> parameters)
    : sim_(sim), params_(std::move(parameters)), offsets_(Eigen::VectorXd::Zero(size())) {
  const Model& model = sim.model();
  for (const ParameterDirection& p : params_) {
    if (!p.initial.empty())
      throw std::invalid_argument(p.path +
                                  ": an initial coordinate acts through the start alone, not a "
                                  "value a running model can be corrected in");
    for (const ParameterDirection::BodyChange& b : p.bodies) {
      if (b.body < 0 || b.body >= model.num_bodies())
        throw std::invalid_argument(p.path + ": body " + std::to_string(b.body) +
                                    " is not one of the model's");
      if (std::find(bodies_.begin(), bodies_.end(), b.body) == bodies_.end()) {
        bodies_.push_back(b.body);
        body_base_.push_back(model.bodies[static_cast<size_t>(b.body)]);
      }
    }
    moves_gravity_ = moves_gravity_ || !p.gravity.isZero();
    if (p.subsystem.empty()) {
      handles_.push_back(-1);
      option_base_.push_back(0.0);
    } else {
      handles_.push_back(sim.component_parameter_handle(p.subsystem, p.key));
      option_base_.push_back(sim.component_parameter(p.subsystem, p.key));
    }
  }
  gravity_base_ = model.gravity;
}

Eigen::VectorXd HeldParameters::values() const {
  Eigen::VectorXd v(size());
  for (Eigen::Index j = 0; j < size(); ++j)
    v[j] = params_[static_cast<size_t>(j)].value + offsets_[j];
  return v;
}

void HeldParameters::apply(const Eigen::VectorXd& offsets) {
  for (size_t b = 0; b < bodies_.size(); ++b) {
    Body moved = body_base_[b];
    for (size_t j = 0; j < params_.size(); ++j)
      for (const ParameterDirection::BodyChange& c : params_[j].bodies)
        if (c.body == bodies_[b]) move_body(moved, c, offsets[static_cast<Eigen::Index>(j)]);
    sim_.set_body_inertia(bodies_[b], moved.mass, moved.com_B, moved.inertia_B);
  }
  if (moves_gravity_) {
    Eigen::Vector3d g = gravity_base_;
    for (size_t j = 0; j < params_.size(); ++j)
      g += offsets[static_cast<Eigen::Index>(j)] * params_[j].gravity;
    sim_.set_gravity(g);
  }
  for (size_t j = 0; j < params_.size(); ++j)
    if (handles_[j] >= 0)
      sim_.set_component_parameter(
          handles_[j], option_base_[j] + offsets[static_cast<Eigen::Index>(j)] * params_[j].option);
}

void HeldParameters::set(const Eigen::VectorXd& offsets) {
  if (offsets.size() != size())
    throw std::invalid_argument("held parameters: " + std::to_string(offsets.size()) +
                                " offsets for " + std::to_string(size()) + " parameters");
  try {
    apply(offsets);
  } catch (const std::invalid_argument& err) {
    apply(offsets_);  // as they were
    std::string paths;
    for (const ParameterDirection& p : params_) paths += (paths.empty() ? "" : ", ") + p.path;
    throw std::invalid_argument(paths + ": " + err.what());
  }
  offsets_ = offsets;
}

}  // namespace mh
