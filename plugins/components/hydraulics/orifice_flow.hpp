// The semi-empirical orifice law that the throttle (Eq. 24) and the
// directional control valve (Eq. 26) share: flow proportional to
// g(dp) = sgn(dp) sqrt|dp|, made linear (laminar) below a transition pressure
// so that the law is continuous and has a finite slope at dp = 0 (Sect. 3.1:
// "less than 2 bar ... linear relation").
#pragma once

#include <cmath>

namespace hyd {

class OrificeFlow {
 public:
  // transition_pressure p_tr > 0 (Pa).
  explicit OrificeFlow(double transition_pressure = 2e5)
      : p_tr_(transition_pressure), sqrt_p_tr_(std::sqrt(transition_pressure)) {}

  // g(dp) (sqrt(Pa)): sgn(dp) sqrt|dp| for |dp| >= p_tr, sqrt(p_tr) dp / p_tr
  // below; the two agree at |dp| = p_tr.
  double g(double dp) const {
    if (std::abs(dp) >= p_tr_) return std::copysign(std::sqrt(std::abs(dp)), dp);
    return sqrt_p_tr_ * dp / p_tr_;
  }
  // dg/d(dp) (1/sqrt(Pa)): 1 / (2 sqrt|dp|) turbulent, 1 / sqrt(p_tr) laminar.
  double slope(double dp) const {
    if (std::abs(dp) >= p_tr_) return 0.5 / std::sqrt(std::abs(dp));
    return 1.0 / sqrt_p_tr_;
  }
  double transition_pressure() const { return p_tr_; }

 private:
  double p_tr_;
  double sqrt_p_tr_;
};

}  // namespace hyd
