// The fundamental earth-moving equation (Reece 1964; McKyes, Soil Cutting and
// Tillage, 1985, Ch. 4): the passive force a flat blade of width w at rake
// angle rho, cutting to depth d, needs to fail the soil wedge ahead of it on
// a plane at angle beta,
//   P = w (gamma d^2 N_gamma + c d N_c + q d N_q + c_a d N_a),
// P at the soil-metal friction angle delta from the blade's normal, the
// adhesion c_a w d / sin(rho) along the blade beside it. The N factors come
// from the wedge's equilibrium (weight, surcharge, cohesion on the failure
// plane, adhesion on the blade, the two resultants at phi and delta from
// their planes' normals), written with s = sin(rho + delta + beta + phi):
//   N_gamma = (cot rho + cot beta) sin(beta + phi) / (2 s)
//   N_q     = (cot rho + cot beta) sin(beta + phi) / s
//   N_c     = cos phi / (sin beta s)
//   N_a     = -cos(rho + beta + phi) / (sin rho s)
// (McKyes' forms with cos(rho + delta) + sin(rho + delta) cot(beta + phi) =
// s / sin(beta + phi)). The soil fails on the plane that needs the least
// force: beta minimises P over 0 < beta < pi - rho - delta - phi, where s > 0.
// Templated on the scalar so that the component's Jacobian is the same
// function's derivative; beta is found in doubles and held, exact by the
// envelope theorem (dP/dbeta = 0 there).
#pragma once

#include <boost/math/tools/minima.hpp>
#include <cmath>
#include <limits>

namespace earth {

// A soil, in SI: the Mohr-Coulomb parameters the equation reads.
struct Soil {
  double density = 0.0;             // kg/m^3
  double gravity = 9.81;            // m/s^2: gamma = density * gravity
  double cohesion = 0.0;            // c, Pa
  double friction_angle = 0.0;      // phi, rad
  double interface_friction = 0.0;  // delta (soil on metal), rad
  double adhesion = 0.0;            // c_a, Pa
  double surcharge = 0.0;           // q, Pa, on the surface ahead of the blade
};

template <class S>
struct EarthFactors {
  S gamma, cohesion, surcharge, adhesion;  // N_gamma, N_c, N_q, N_a
};

template <class S>
EarthFactors<S> earth_factors(const Soil& soil, const S& rake, double beta) {
  using std::cos;
  using std::sin;
  using std::tan;
  const double phi = soil.friction_angle;
  const S s = sin(rake + soil.interface_friction + beta + phi);
  const S cots = 1.0 / tan(rake) + 1.0 / std::tan(beta);
  EarthFactors<S> n;
  n.gamma = cots * std::sin(beta + phi) / (2.0 * s);
  n.surcharge = cots * std::sin(beta + phi) / s;
  n.cohesion = std::cos(phi) / (std::sin(beta) * s);
  n.adhesion = -cos(rake + beta + phi) / (sin(rake) * s);
  return n;
}

// P / w at depth d (m) for the failure angle beta: N/m.
template <class S>
S force_per_width(const Soil& soil, const S& depth, const S& rake, double beta) {
  const EarthFactors<S> n = earth_factors(soil, rake, beta);
  const double unit_weight = soil.density * soil.gravity;
  return depth * (unit_weight * depth * n.gamma + soil.cohesion * n.cohesion +
                  soil.surcharge * n.surcharge + soil.adhesion * n.adhesion);
}

// The failure angle that minimises P at this depth and rake: Brent's
// minimiser (golden sections and parabolic steps; Boost.Math) over the whole
// admissible range, to half of double's digits: beta to about 1e-8 rad,
// where P is flat to round-off (P grows without bound at both ends, cot
// beta at one and 1/s at the other).
inline double failure_angle(const Soil& soil, double depth, double rake) {
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kInside = 1e-6;  // rad kept from each end, where P is infinite
  const double top = kPi - rake - soil.interface_friction - soil.friction_angle - kInside;
  boost::uintmax_t iterations = 200;
  return boost::math::tools::brent_find_minima(
             [&](double beta) { return force_per_width(soil, depth, rake, beta); }, kInside, top,
             std::numeric_limits<double>::digits / 2, iterations)
      .first;
}

// Bearing capacity factors of a strip (Prandtl 1920, Reissner 1924): the
// pressure the soil bears under the edge's end as it is pushed along itself,
// q_b = c N_c + gamma d N_q, with N_q = exp(pi tan phi) tan^2(pi/4 + phi/2)
// and N_c = (N_q - 1) cot phi (its limit 2 + pi as phi -> 0).
struct BearingFactors {
  double cohesion = 0.0, depth = 0.0;  // N_c, N_q
};

inline BearingFactors bearing_factors(double phi) {
  constexpr double kPi = 3.14159265358979323846;
  BearingFactors b;
  const double t = std::tan(0.25 * kPi + 0.5 * phi);
  b.depth = std::exp(kPi * std::tan(phi)) * t * t;
  b.cohesion = phi > 1e-8 ? (b.depth - 1.0) / std::tan(phi) : 2.0 + kPi;
  return b;
}

}  // namespace earth
