// The linear test problems and their closed-form solutions.
#pragma once

#include <cmath>
#include <complex>

#include "driver.hpp"

namespace mh_test {

// m xdd + c xd + k x = F cos(W t), x(0) = 1, xd(0) = 0 (underdamped).
struct DampedOscillator {
  double m = 1.0, c = 0.4, k = 4.0, F = 1.0, W = 1.3;

  LinearProblem problem() const {
    const double F_ = F, W_ = W;
    return {{MH_UNKNOWN_SECOND_ORDER}, {m}, {c}, {k}, [F_, W_](double t, double* f) {
              f[0] = F_ * std::cos(W_ * t);
            }};
  }
  State initial() const { return {0.0, {1.0}, {0.0}, {(F - k * 1.0) / m}}; }
  // The closed form: particular Re(P e^{iWt}) plus the free damped response.
  double x(double t) const {
    const std::complex<double> P = F / std::complex<double>(k - m * W * W, c * W);
    const double xp0 = P.real(), vp0 = (std::complex<double>(0.0, W) * P).real();
    const double s = -c / (2.0 * m), wd = std::sqrt(k / m - s * s);
    const double A = 1.0 - xp0, B = (0.0 - vp0 - s * A) / wd;
    const double xp = (P * std::exp(std::complex<double>(0.0, W * t))).real();
    return xp + std::exp(s * t) * (A * std::cos(wd * t) + B * std::sin(wd * t));
  }
};

// y' = lambda y + sin(w t), y(0) = 1.
struct FirstOrder {
  double lambda = -2.0, w = 3.0;

  LinearProblem problem() const {
    const double l = lambda, w_ = w;
    return {{MH_UNKNOWN_FIRST_ORDER}, {0.0}, {1.0}, {-l}, [w_](double t, double* f) {
              f[0] = std::sin(w_ * t);
            }};
  }
  State initial() const { return {0.0, {1.0}, {lambda * 1.0}, {0.0}}; }
  double y(double t) const {
    const double d = w * w + lambda * lambda, A = -lambda / d, B = -w / d;
    return (1.0 - B) * std::exp(lambda * t) + A * std::sin(w * t) + B * std::cos(w * t);
  }
};

// The two above side by side plus an algebraic unknown z = x + y:
//   unknowns (x, y, z), rows: oscillator, first-order, z - x - y = 0.
struct Mixed {
  DampedOscillator osc;
  FirstOrder first;

  LinearProblem problem() const {
    const DampedOscillator o = osc;
    const FirstOrder q = first;
    return {{MH_UNKNOWN_SECOND_ORDER, MH_UNKNOWN_FIRST_ORDER, MH_UNKNOWN_ALGEBRAIC},
            {o.m, 0, 0, 0, 0, 0, 0, 0, 0},
            {o.c, 0, 0, 0, 1, 0, 0, 0, 0},
            {o.k, 0, 0, 0, -q.lambda, 0, -1, -1, 1},
            [o, q](double t, double* f) {
              f[0] = o.F * std::cos(o.W * t);
              f[1] = std::sin(q.w * t);
              f[2] = 0.0;
            }};
  }
  State initial() const {
    const State a = osc.initial(), b = first.initial();
    return {0.0, {a.x[0], b.x[0], a.x[0] + b.x[0]}, {a.xd[0], b.xd[0], 0.0}, {a.xdd[0], 0.0, 0.0}};
  }
};

}  // namespace mh_test
