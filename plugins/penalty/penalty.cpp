// The penalty-based semirecursive formulation (Sect. 2.3 and Sect. 4): the
// index-3 augmented Lagrangian with mass-orthogonal projections of Cuadrado
// et al. [9, 10] in relative joint coordinates. All N coordinates z_{k+1} are
// the Newton unknowns; the trapezoidal rule ties zd and zdd to them (Eqs.
// 32-34); the residual is Eq. (39),
//
//   r = dt^2/4 (M' zdd + Phi_z^T alpha Phi + Phi_z^T lambda - Q'),
//
// the multipliers are updated after every Newton update (Eq. 19), and the
// converged velocities and accelerations are projected (Eqs. 20-21,
// projections.hpp). This file holds the instance, its ops, the factory and
// the entry symbol.
#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "constraint_terms.hpp"
#include "initial_accelerations.hpp"
#include "monohydra/cpp/formulation_plugin.hpp"
#include "monohydra/monohydra.h"
#include "projections.hpp"

namespace mh_penalty {
namespace {

using VectorMap = Eigen::Map<Eigen::VectorXd>;

struct Penalty {
  const mh_host* host = nullptr;
  // Options (setup).
  double alpha = 1e11;      // penalty factor, one for every constraint (Eq. 18)
  double tol = 1e-7;        // Newton tolerance on every z_i (rad or m)
  bool projections = true;  // Eqs. (20)-(21)
  // Sizes.
  int N = 0;  // coordinates = Newton unknowns
  int m = 0;  // constraint rows
  double dt = 0.0;
  // Accepted at t_k (velocities and accelerations as projected).
  Eigen::VectorXd z, zd, zdd;
  Eigen::VectorXd lambda_k;  // multipliers at t_k: lambda_{k+1}^(0) (Eq. 19)
  // The step being solved.
  Eigen::VectorXd lambda;            // lambda_{k+1}^(h), Eq. (19)
  Eigen::VectorXd zd_hat, zdd_hat;   // Eq. (34)
  Eigen::VectorXd zd_it, zdd_it;     // Eq. (33) at the iterate
  Eigen::VectorXd multiplier_force;  // alpha Phi + lambda (m)
  // M' and Phi_z of the last residual call and the x they belong to: accept()
  // reuses them for the projections when it is called at that same x (the
  // host's converged iterate is the x of its last residual call).
  Eigen::VectorXd x_last;
  Eigen::MatrixXd M_last, phi_z_last;
  bool last_valid = false;
  // accept()'s results before they are committed.
  Eigen::VectorXd zd_prime, zdd_prime, zd_new, zdd_new;
  Projector projector;
};

Penalty& self(const mh_formulation* f) {
  return *static_cast<Penalty*>(f->plugin_data);
}

void log(const Penalty& s, mh_log_level level, const std::string& msg) {
  s.host->log(s.host, level, msg.c_str());
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// Runs an op; no exception crosses the C boundary.
template <class Body>
mh_status guarded(const mh_formulation* f, const char* op, Body&& body) noexcept {
  try {
    return body(self(f));
  } catch (const std::exception& e) {
    try {
      log(self(f), MH_LOG_ERROR, std::string(op) + ": " + e.what());
    } catch (...) {
    }
  } catch (...) {
    try {
      log(self(f), MH_LOG_ERROR, std::string(op) + ": unknown exception");
    } catch (...) {
    }
  }
  return MH_ERROR;
}

#ifdef EIGEN_RUNTIME_NO_MALLOC
// Debug aid: in a build with -DEIGEN_RUNTIME_NO_MALLOC, an Eigen heap
// allocation inside the time step's ops fails an assertion.
struct NoMalloc {
  NoMalloc() { Eigen::internal::set_is_malloc_allowed(false); }
  ~NoMalloc() { Eigen::internal::set_is_malloc_allowed(true); }
};
#else
struct NoMalloc {};
#endif

mh_status evaluate(Penalty& s, uint32_t flags, double t, const double* z, const double* zd,
                   mh_mech_result& out) {
  const mh_mech_request rq{sizeof(mh_mech_request), flags, t, z, zd};
  out = mh_mech_result{};
  out.struct_size = sizeof(mh_mech_result);
  return s.host->evaluate_mechanics(s.host, &rq, &out);
}

mh_status setup(const mh_formulation* f, uint32_t* num_unknowns) {
  return guarded(f, "setup", [&](Penalty& s) {
    mh_mech_info info{};
    info.struct_size = sizeof(info);
    if (s.host->mech_info(s.host, &info) != MH_OK) {
      log(s, MH_LOG_ERROR, "setup: the host gave no mechanism information");
      return MH_ERROR;
    }
    s.N = static_cast<int>(info.num_coordinates);
    s.m = static_cast<int>(info.num_constraints);
    s.dt = info.dt;
    s.tol = info.position_tolerance;
    if (s.host->option_number(s.host, "alpha", 0, s.alpha, &s.alpha) != MH_OK) return MH_ERROR;
    if (!(s.alpha > 0.0)) return s.host->option_error(s.host, "alpha", "a positive number");
    if (s.host->option_number(s.host, "tolerance", 0, s.tol, &s.tol) != MH_OK) return MH_ERROR;
    if (!(s.tol > 0.0)) return s.host->option_error(s.host, "tolerance", "a positive number");
    double projections = 1.0;
    if (s.host->option_number(s.host, "projections", 0, projections, &projections) != MH_OK)
      return MH_ERROR;
    if (projections != 0.0 && projections != 1.0)
      return s.host->option_error(s.host, "projections", "1 (on) or 0 (off)");
    s.projections = projections == 1.0;

    const Eigen::Index N = s.N, m = s.m;
    for (Eigen::VectorXd* v : {&s.z, &s.zd, &s.zdd, &s.zd_hat, &s.zdd_hat, &s.zd_it, &s.zdd_it,
                               &s.x_last, &s.zd_prime, &s.zdd_prime, &s.zd_new, &s.zdd_new})
      v->setZero(N);
    for (Eigen::VectorXd* v : {&s.lambda_k, &s.lambda, &s.multiplier_force}) v->setZero(m);
    s.M_last.setZero(N, N);
    s.phi_z_last.setZero(m, N);
    s.projector.resize(s.N, s.m);
    *num_unknowns = info.num_coordinates;
    return MH_OK;
  });
}

mh_status start(const mh_formulation* f, double t0, double dt, const double* z0, const double* zd0,
                double* abs_tolerance) {
  return guarded(f, "start", [&](Penalty& s) {
    if (!(dt > 0.0)) {
      log(s, MH_LOG_ERROR, "start: the time step must be positive");
      return MH_ERROR;
    }
    s.dt = dt;
    s.z = Eigen::Map<const Eigen::VectorXd>(z0, s.N);
    s.zd = Eigen::Map<const Eigen::VectorXd>(zd0, s.N);
    s.last_valid = false;
    mh_mech_result rs;
    const mh_status st =
        evaluate(s, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS, t0, s.z.data(), s.zd.data(), rs);
    if (st >= MH_DISCARD) return MH_ERROR;
    const ConstVectorMap phi(rs.phi, s.m);
    mh_status result = MH_OK;
    if (s.m > 0 && !(phi.lpNorm<Eigen::Infinity>() <= s.tol)) {
      log(s, MH_LOG_WARNING,
          "start: the initial coordinates violate the constraints by " +
              num(phi.lpNorm<Eigen::Infinity>()) + " (more than the tolerance " + num(s.tol) +
              "); the penalty forces will pull the loops closed in the first steps");
      result = MH_WARNING;
    }
    // Initial accelerations and multipliers: the acceleration-level augmented
    // Lagrangian problem, which tolerates redundant constraints.
    s.lambda.setZero(s.m);
    const AccelerationSolve a =
        solve_initial_accelerations(ConstMatrixMap(rs.M, s.N, s.N), ConstVectorMap(rs.Q, s.N),
                                    ConstMatrixMap(rs.phi_z, s.m, s.N),
                                    ConstVectorMap(rs.phi_dot_zd, s.m), s.alpha, s.zdd, s.lambda);
    if (!a.positive_definite) {
      log(s, MH_LOG_ERROR,
          "start: M' + Phi_z^T alpha Phi_z is not positive definite at the initial state (a "
          "massless body whose motion no constraint fixes?)");
      return MH_ERROR;
    }
    if (!a.converged) {
      log(s, MH_LOG_WARNING,
          "start: the initial accelerations did not settle in " + std::to_string(a.iterations) +
              " augmented Lagrangian iterations: constraint accelerations " + num(a.violation) +
              " (asked for " + num(a.bound) + "), last correction of zdd " + num(a.correction) +
              "; inconsistent constraints?");
      result = MH_WARNING;
    }
    if (!s.zdd.allFinite() || !s.lambda.allFinite()) {
      log(s, MH_LOG_ERROR, "start: the initial accelerations are not finite");
      return MH_ERROR;
    }
    s.lambda_k = s.lambda;
    for (int i = 0; i < s.N; ++i) abs_tolerance[i] = s.tol;
    log(s, MH_LOG_DEBUG,
        "start: alpha = " + num(s.alpha) + ", tolerance = " + num(s.tol) + ", projections " +
            (s.projections ? "on" : "off") + "; initial multipliers in " +
            std::to_string(a.iterations) + " iterations, constraint accelerations " +
            num(a.violation) + ", last correction of zdd " + num(a.correction));
    return result;
  });
}

mh_status predict(const mh_formulation* f, double, double* x) {
  return guarded(f, "predict", [&](Penalty& s) {
    [[maybe_unused]] const NoMalloc no_malloc;
    const double dt = s.dt;
    VectorMap(x, s.N) = s.z + dt * s.zd + (0.5 * dt * dt) * s.zdd;
    s.zd_hat = -((2.0 / dt) * s.z + s.zd);                               // Eq. (34)
    s.zdd_hat = -((4.0 / (dt * dt)) * s.z + (4.0 / dt) * s.zd + s.zdd);  // Eq. (34)
    s.lambda = s.lambda_k;  // lambda_{k+1}^(0) = lambda_k (Eq. 19's starting value)
    return MH_OK;
  });
}

mh_status residual(const mh_formulation* f, double t_next, const double* x, double* r) {
  return guarded(f, "residual", [&](Penalty& s) {
    [[maybe_unused]] const NoMalloc no_malloc;
    const double dt = s.dt;
    const ConstVectorMap xz(x, s.N);
    s.zd_it = (2.0 / dt) * xz + s.zd_hat;           // Eq. (33)
    s.zdd_it = (4.0 / (dt * dt)) * xz + s.zdd_hat;  // Eq. (33)
    mh_mech_result rs;
    s.last_valid = false;
    const mh_status st = evaluate(s, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS | MH_EVAL_SUBSYSTEMS,
                                  t_next, x, s.zd_it.data(), rs);
    if (st >= MH_DISCARD) return st;
    const ConstMatrixMap M(rs.M, s.N, s.N);
    const ConstVectorMap Q(rs.Q, s.N);
    const ConstVectorMap phi(rs.phi, s.m);
    const ConstMatrixMap phi_z(rs.phi_z, s.m, s.N);
    // Eqs. (36), (39): dt^2/4 (M' zdd + Phi_z^T (alpha Phi + lambda) - Q').
    s.multiplier_force = s.alpha * phi + s.lambda;
    VectorMap rr(r, s.N);
    rr.noalias() = M * s.zdd_it;
    add_constraint_forces(rr, phi_z, s.multiplier_force, 1.0);
    rr -= Q;
    rr *= 0.25 * dt * dt;
    if (s.projections && s.m > 0) {  // kept for the projections in accept()
      s.x_last = xz;
      s.M_last = M;
      s.phi_z_last = phi_z;
      s.last_valid = true;
    }
    return st;
  });
}

// No analytic tangent (the host's forward differences, Eq. 41, do it). The
// cheap path for later performance work: dr/dx ~= M' + dt/2 C + dt^2/4 K +
// dt^2/4 Phi_z^T alpha Phi_z, with C = -dQ'/dzd and K = -dQ'/dz (+ the
// derivatives of M' zdd and of Phi_z^T (alpha Phi + lambda) through Phi_z,
// usually dropped). Its dominant, exactly known part is
// M' + dt^2/4 Phi_z^T alpha Phi_z; the C and K of the hydraulic forces need the
// subsystems' Jacobians, which the host holds.

mh_status iteration_done(const mh_formulation* f, double t_next, const double* x) {
  return guarded(f, "iteration_done", [&](Penalty& s) {
    [[maybe_unused]] const NoMalloc no_malloc;
    const ConstVectorMap xz(x, s.N);
    s.zd_it = (2.0 / s.dt) * xz + s.zd_hat;  // Eq. (33); Phi itself does not depend on it
    mh_mech_result rs;
    const mh_status st = evaluate(s, MH_EVAL_CONSTRAINTS, t_next, x, s.zd_it.data(), rs);
    if (st >= MH_DISCARD) return st;
    const ConstVectorMap phi(rs.phi, s.m);
    if (!phi.allFinite()) {
      log(s, MH_LOG_ERROR, "iteration_done: the constraints Phi are not finite at the iterate");
      return MH_DISCARD;
    }
    s.lambda += s.alpha * phi;  // Eq. (19): lambda^(h+1) = lambda^(h) + alpha Phi^(h+1)
    return MH_OK;
  });
}

mh_status accept(const mh_formulation* f, double t_next, const double* x) {
  return guarded(f, "accept", [&](Penalty& s) {
    [[maybe_unused]] const NoMalloc no_malloc;
    const double dt = s.dt;
    const ConstVectorMap xz(x, s.N);
    s.zd_prime = (2.0 / dt) * xz + s.zd_hat;           // Eq. (33): zd'
    s.zdd_prime = (4.0 / (dt * dt)) * xz + s.zdd_hat;  // Eq. (33): zdd'
    if (s.projections && s.m > 0) {
      // W = M' (see projections.hpp). M' and Phi_z depend on z only: take them
      // from the last residual call when it was at this x.
      if (!s.last_valid || s.x_last != xz) {
        mh_mech_result rs;
        const mh_status st =
            evaluate(s, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS, t_next, x, s.zd_prime.data(), rs);
        if (st >= MH_DISCARD) return st;
        s.M_last = ConstMatrixMap(rs.M, s.N, s.N);
        s.phi_z_last = ConstMatrixMap(rs.phi_z, s.m, s.N);
        s.x_last = xz;
        s.last_valid = true;
      }
      if (!s.projector.factorize(ConstMatrixMap(s.M_last.data(), s.N, s.N),
                                 ConstMatrixMap(s.phi_z_last.data(), s.m, s.N), dt, s.alpha)) {
        log(s, MH_LOG_ERROR,
            "accept: W + dt^2/4 Phi_z^T alpha Phi_z is not positive definite; the projections "
            "(Eqs. 20-21) cannot be made");
        return MH_DISCARD;
      }
      s.projector.project_velocities(s.zd_prime, s.zd_new);  // Eq. (20)
      // Eq. (21) needs Phidot_z zd at the projected velocities.
      mh_mech_result rs;
      const mh_status st = evaluate(s, MH_EVAL_CONSTRAINTS, t_next, x, s.zd_new.data(), rs);
      if (st >= MH_DISCARD) return st;
      s.projector.project_accelerations(s.zdd_prime, ConstVectorMap(rs.phi_dot_zd, s.m),
                                        s.zdd_new);  // Eq. (21)
    } else {
      s.zd_new = s.zd_prime;
      s.zdd_new = s.zdd_prime;
    }
    if (!s.zd_new.allFinite() || !s.zdd_new.allFinite()) {
      log(s, MH_LOG_ERROR, "accept: the projected velocities or accelerations are not finite");
      return MH_DISCARD;
    }
    // Commit: the projected rates are the history of the next step's hats.
    s.z = xz;
    s.zd = s.zd_new;
    s.zdd = s.zdd_new;
    s.lambda_k = s.lambda;
    return MH_OK;
  });
}

mh_status coordinates(const mh_formulation* f, double* z, double* zd, double* zdd) {
  return guarded(f, "coordinates", [&](Penalty& s) {
    VectorMap(z, s.N) = s.z;
    VectorMap(zd, s.N) = s.zd;
    VectorMap(zdd, s.N) = s.zdd;
    return MH_OK;
  });
}

const void* get_extension(const mh_formulation*, const char*) {
  return nullptr;
}

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "penalty",
    "Penalty-based semirecursive formulation (index-3 augmented Lagrangian with projections)",
    "monohydra",
    "1.0.0",
    "Closed loops by cut joints: M' zdd + Phi_z^T (alpha Phi + lambda) = Q' (Eq. 18) with "
    "all relative coordinates as unknowns of the trapezoidal rule, multipliers updated per "
    "Newton iteration (Eq. 19) and mass-orthogonal projections of velocities and "
    "accelerations (Eqs. 20-21). Options: alpha, tolerance, projections."};

// The instance's operations; every instance gets a copy with its own state.
const mh_formulation kOps = [] {
  mh_formulation f{};
  f.struct_size = sizeof(mh_formulation);
  f.descriptor = &kDescriptor;
  f.setup = setup;
  f.start = start;
  f.predict = predict;
  f.residual = residual;
  f.tangent = nullptr;  // forward differences by the host, Eq. (41): see the note above
  f.iteration_done = iteration_done;
  f.accept = accept;
  f.coordinates = coordinates;
  f.destroy = monohydra::destroy_formulation<Penalty>;
  f.get_extension = get_extension;
  return f;
}();

const mh_formulation* create(const mh_host* host) {
  return monohydra::create_formulation<Penalty>(host, kOps);
}

}  // namespace
}  // namespace mh_penalty

MONOHYDRA_FORMULATION_PLUGIN(mh_penalty::kDescriptor, mh_penalty::create);
