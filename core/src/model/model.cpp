#include "monohydra/core/model.hpp"

namespace mh {

Eigen::VectorXd Model::initial_coordinates() const {
  Eigen::VectorXd z(num_coordinates());
  for (int j = 0; j < num_bodies(); ++j) z[j] = bodies[j].z0;
  return z;
}

Eigen::VectorXd Model::initial_rates() const {
  Eigen::VectorXd zd(num_coordinates());
  for (int j = 0; j < num_bodies(); ++j) zd[j] = bodies[j].zd0;
  return zd;
}

}  // namespace mh
