// Forward sensitivities of a run with respect to parameters of its model:
// d(state)/d(p) carried along with the run by differentiating the discrete
// step (docs/identification.md). A parameter is named by its path, as
// `--set` names it; the host translates it into how it moves the values the
// engine can change in place (this struct), the core differentiates the
// step along that direction.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "monohydra/core/model.hpp"

namespace mh {

struct ParameterDirection {
  std::string path;    // e.g. "bodies/body3/mass", "gravity/1"
  double value = 0.0;  // its value in the model, in the file's units
  // d(value in the engine)/d(path's value): what a unit change of the
  // path's value moves. Mass in kg, centre of mass in m, inertia in kg m^2,
  // gravity in m/s^2 (a mass in a file whose shapes derive the inertia from
  // it moves both).
  struct BodyChange {
    int body = 0;
    double mass = 0.0;
    Eigen::Vector3d com = Eigen::Vector3d::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    // Of the body's linear inertial parameters instead: `com` moves the
    // first moment m c (kg m) and `inertia` the inertia about the body's
    // origin (kg m^2). A load added at a point moves these linearly where
    // the centre of mass and the inertia about it move as 1/(m + load)
    // (bodies/NAME/payload/mass).
    bool about_origin = false;
  };
  std::vector<BodyChange> bodies;
  // An initial coordinate or rate (bodies/NAME/z0, bodies/NAME/zd0): what a
  // unit change moves in the model's z0 and zd0 (rad or m, rad/s or m/s)
  // before the loops are closed. It acts through start() alone, and needs a
  // formulation that reads the initial state there
  // (MH_EXT_INITIAL_STATE_AT_START).
  struct InitialChange {
    int coordinate = 0;
    double z0 = 0.0;
    double zd0 = 0.0;
  };
  std::vector<InitialChange> initial;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  // A component's option that it offers as a parameter (monohydra/
  // parameters.h): the instance's name and the option's key; a unit change
  // of the path's value moves it by `option` (1: the file writes it in SI).
  std::string subsystem, key;
  double option = 0.0;
  // The step of the value the engine's directional differences take (0: a
  // millionth of the value, or of 1 where it is 0).
  double step = 0.0;
};

// Body `b` moved by `amount` along `change` (its mass, centre of mass and
// inertia about it; about_origin: through the linear parameters).
void move_body(Body& b, const ParameterDirection::BodyChange& change, double amount);

}  // namespace mh
