// A minimum-pressure (cavitation) limit for a fluid volume: the free gas and
// vapour a real oil releases when it is pulled towards its vapour pressure.
// A fixed amount of gas, alpha V at the reference pressure p_ref, follows
// Boyle's law in the pressure above the limit p_min (x = p - p_min):
//   V_g(p) = alpha V x_r / q(x),   x_r = p_ref - p_min
//   q(x)   = (x + sqrt(x^2 + 4 eps^2)) / 2,  eps = 1e-4 x_r
// q is x with a smooth positive floor (q -> x above a few eps, q > 0 for
// every x, so the law is defined wherever Newton looks). The volume's row
// gains the gas's share of the storage,
//   row += C_g(p) dp/dt,   C_g = -dV_g/dp = alpha V x_r q'(x) / q(x)^2 > 0,
// which grows without bound as p falls to p_min (the gas swells to 1e4
// alpha V there), so a chamber pulled by its load lets the gas take the volume
// and its pressure stays at or just above p_min instead of going negative.
// Above the limit it is a small extra compliance: alpha x_r / p^2 per unit
// volume (1e-3 * 1e5 / 1e12 = 1e-10 1/Pa at 1 MPa, beside 1/B_oil = 6.7e-10).
#pragma once

#include <cmath>
#include <limits>
#include <string>

#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/host.h"

namespace hyd {

class GasRelease {
 public:
  GasRelease() = default;  // off: no storage added

  bool on() const { return on_; }
  double minimum_pressure() const { return p_min_; }

  // The same limit for a volume of `volume` (m^3).
  GasRelease for_volume(double volume) const {
    GasRelease g = *this;
    g.gas_ = alpha_ * volume * x_r_;
    return g;
  }

  // C_g(p) (m^3/Pa) and dC_g/dp (m^3/Pa^2). With r = sqrt(x^2 + 4 eps^2),
  // q' = q / r, so C_g = alpha V x_r / (q r) and dC_g/dp = -2 alpha V x_r / r^3;
  // q is computed as 2 eps^2 / (r - x) below the limit, where x + r cancels.
  double capacitance(double p) const {
    const double x = p - p_min_, r = std::sqrt(x * x + 4.0 * eps2_);
    return gas_ / (floor(x, r) * r);
  }
  double capacitance_slope(double p) const {
    const double x = p - p_min_, r = std::sqrt(x * x + 4.0 * eps2_);
    return -2.0 * gas_ / (r * r * r);
  }
  // V_g(p) (m^3), for the docs and the tests.
  double gas_volume(double p) const {
    const double x = p - p_min_;
    return gas_ / floor(x, std::sqrt(x * x + 4.0 * eps2_));
  }

  // Reads minimum_pressure (turns the limit on), gas_fraction and
  // gas_reference_pressure. Without minimum_pressure the limit is off and the
  // other two are refused.
  mh_status read(const mh_host* h) {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    double p_min = kNaN, alpha = kNaN, p_ref = kNaN;
    if (monohydra::options(h).option_number(h, "minimum_pressure", 0, kNaN, &p_min) != MH_OK ||
        monohydra::options(h).option_number(h, "gas_fraction", 0, kNaN, &alpha) != MH_OK ||
        monohydra::options(h).option_number(h, "gas_reference_pressure", 0, kNaN, &p_ref) != MH_OK)
      return MH_ERROR;
    if (std::isnan(p_min)) {
      const char* alone = "minimum_pressure beside it (the cavitation limit is off without it)";
      if (!std::isnan(alpha)) return monohydra::options(h).option_error(h, "gas_fraction", alone);
      if (!std::isnan(p_ref))
        return monohydra::options(h).option_error(h, "gas_reference_pressure", alone);
      return MH_OK;
    }
    if (std::isnan(alpha)) alpha = 1e-3;
    if (std::isnan(p_ref)) p_ref = 1e5;
    if (!(alpha > 0.0 && alpha < 1.0))
      return monohydra::options(h).option_error(
          h, "gas_fraction", "a free-gas volume fraction in (0, 1) at gas_reference_pressure");
    if (!(p_ref > p_min))
      return monohydra::options(h).option_error(
          h, "gas_reference_pressure",
          ("a reference pressure above minimum_pressure = " + short_number(p_min) + " Pa").c_str());
    on_ = true;
    p_min_ = p_min;
    alpha_ = alpha;
    x_r_ = p_ref - p_min;
    eps2_ = 1e-8 * x_r_ * x_r_;  // eps = 1e-4 x_r
    return MH_OK;
  }

 private:
  // q(x) = (x + r) / 2 = 2 eps^2 / (r - x), whichever does not cancel.
  double floor(double x, double r) const {
    return x >= 0.0 ? 0.5 * (x + r) : 2.0 * eps2_ / (r - x);
  }

  bool on_ = false;
  double p_min_ = 0.0, alpha_ = 0.0, x_r_ = 1.0, eps2_ = 1e-8;
  double gas_ = 0.0;  // alpha V x_r, m^3 Pa
};

}  // namespace hyd
