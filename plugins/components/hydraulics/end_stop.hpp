// The stroke limits of a cylinder as stiff, damped contact (cylinder.cpp,
// options end_stop_*): past either end of the stroke the piston meets a stop
// that pushes back with
//   F = k delta + c w(delta) delta_dot,   w(delta) = smoothstep(delta / depth)
// delta >= 0 the penetration. The damping comes in over `depth` (w is C1, from
// 0 at first contact to 1 at depth), so the force is continuous at contact
// whatever the impact speed (a Kelvin-Voigt stop with a jump there would upset
// Newton). It stores k delta^2 / 2 and dissipates c w delta_dot^2 >= 0 exactly,
// so the energy balance closes; the price is that a stop leaving fast can pull
// briefly (c w delta_dot < -k delta), by at most c w |delta_dot|.
#pragma once

#include <cmath>

namespace hyd {

class EndStop {
 public:
  EndStop() = default;
  // Stops at strokes s_min and s_max (m); k > 0 (N/m), c >= 0 (N s/m), depth > 0 (m).
  EndStop(double s_min, double s_max, double k, double c, double depth)
      : on_(true), s_min_(s_min), s_max_(s_max), k_(k), c_(c), depth_(depth) {}

  bool on() const { return on_; }

  // The stops' force pushing the cylinder's ends apart (N) at stroke s and rate
  // sdot (> 0 at the lower stop, < 0 at the upper one, 0 between them), and
  // its derivatives in s and sdot (for an analytic point-force jacobian).
  double force(double s, double sdot, double* df_ds = nullptr, double* df_dsdot = nullptr) const {
    double f = 0.0, fs = 0.0, fv = 0.0;
    if (on_) {
      if (s < s_min_) contact(s_min_ - s, -sdot, f, fs, fv);  // delta = s_min - s: pushes apart
      if (s > s_max_) {                                       // delta = s - s_max: pulls together
        contact(s - s_max_, sdot, f, fs, fv);
        f = -f;
      }
    }
    if (df_ds != nullptr) *df_ds = fs;
    if (df_dsdot != nullptr) *df_dsdot = fv;
    return f;
  }

  // Stored k delta^2 / 2 (J) and dissipated c w delta_dot^2 (W) at (s, sdot).
  void energy(double s, double sdot, double& stored, double& dissipation) const {
    stored = 0.0;
    dissipation = 0.0;
    if (!on_) return;
    const double delta = s < s_min_ ? s_min_ - s : (s > s_max_ ? s - s_max_ : 0.0);
    if (delta <= 0.0) return;
    stored = 0.5 * k_ * delta * delta;
    dissipation = c_ * weight(delta) * sdot * sdot;
  }

 private:
  double weight(double delta) const {
    const double x = delta / depth_;
    return x >= 1.0 ? 1.0 : x * x * (3.0 - 2.0 * x);
  }
  double weight_slope(double delta) const {
    const double x = delta / depth_;
    return x >= 1.0 ? 0.0 : 6.0 * x * (1.0 - x) / depth_;
  }
  // F(delta, delta_dot) with dF/ds and dF/dsdot for delta = +-(s - s_stop),
  // written for the lower stop (delta = s_min - s, delta_dot = -sdot); the
  // upper one negates F, and with it both slopes come out right below.
  void contact(double delta, double delta_dot, double& f, double& fs, double& fv) const {
    const double w = weight(delta);
    f = k_ * delta + c_ * w * delta_dot;
    const double df_ddelta = k_ + c_ * weight_slope(delta) * delta_dot;
    const double df_ddelta_dot = c_ * w;
    // Lower stop: d delta/ds = -1, d delta_dot/dsdot = -1. Upper (F negated
    // by the caller): d delta/ds = +1, d delta_dot/dsdot = +1, so d(-F)/ds =
    // -df_ddelta: the same expressions.
    fs = -df_ddelta;
    fv = -df_ddelta_dot;
  }

  bool on_ = false;
  double s_min_ = 0.0, s_max_ = 0.0, k_ = 0.0, c_ = 0.0, depth_ = 1e-3;
};

}  // namespace hyd
