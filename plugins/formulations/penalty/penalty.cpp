// The penalty-based semirecursive formulation (Sect. 2.3 and Sect. 4): the
// index-3 augmented Lagrangian with mass-orthogonal projections of Cuadrado
// et al. [9, 10] in relative joint coordinates. All N coordinates z are
// second-order Newton unknowns; the host's integrator ties zd and zdd at the
// step's end to them (the trapezoidal rule, Eqs. 32-34, by default); the
// residual is Eq. (18), i.e. Eq. (39) without its dt^2/4 factor,
//
//   r = M' zdd + Phi_z^T (alpha Phi + lambda) - Q',
//
// the multipliers are updated after every Newton update (Eq. 19), and the
// converged velocities and accelerations are projected in place (Eqs. 20-21,
// projections.hpp). Outputs: the multipliers lambda1..lambda_m and the
// constraint velocity violation phi_dot_norm = ||Phi_z zd||. This file holds
// the instance, its ops, the factory and the entry symbol.
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "constraint_terms.hpp"
#include "initial_accelerations.hpp"
#include "monohydra/constrained.h"
#include "monohydra/cpp/formulation_plugin.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/state.hpp"
#include "monohydra/monohydra.h"
#include "projections.hpp"

namespace mh_penalty {
namespace {

using VectorMap = Eigen::Map<Eigen::VectorXd>;

struct Penalty {
  const mh_host* host = nullptr;
  const mh_mechanism_service* mech = nullptr;  // found once, at create
  // Options (setup).
  double alpha = 1e11;      // penalty factor, one for every constraint (Eq. 18)
  double tol = 1e-7;        // Newton tolerance on every z_i (rad or m)
  bool projections = true;  // Eqs. (20)-(21)
  // W of the projections: M' + C c_v/c_a + K/c_a (the paper's, needs the
  // host's mech_derivatives) or M' alone.
  bool tangent_projection_matrix = true;
  // Sizes and the initial time (setup, from mech_info).
  int N = 0;  // coordinates = Newton unknowns
  int m = 0;  // constraint rows
  double t0 = 0.0;
  // Accepted (velocities and accelerations as projected); z0, zd0 after setup.
  Eigen::VectorXd z, zd, zdd;
  Eigen::VectorXd lambda_k;  // multipliers at t_k: lambda_{k+1}^(0) (Eq. 19)
  // The step being solved.
  Eigen::VectorXd lambda;            // lambda_{k+1}^(h), Eq. (19)
  Eigen::VectorXd multiplier_force;  // alpha Phi + lambda (m)
  // M' and Phi_z of the last residual call and the x they belong to: accept()
  // reuses them for the projections and phi_dot_norm when it is called at that
  // same x (the host's converged iterate is the x of its last residual call).
  Eigen::VectorXd x_last;
  Eigen::MatrixXd M_last, phi_z_last;
  Eigen::MatrixXd W;  // the projections' W (N x N)
  bool last_valid = false;
  // accept()'s rates: the integrator's zd', zdd' and the projected ones,
  // before they are committed and written back.
  Eigen::VectorXd zd_prime, zdd_prime, zd_new, zdd_new;
  Projector projector;
  // Outputs: their names (the host may keep the pointers), indices and the
  // values at the accepted state, cached by start and accept.
  std::vector<std::string> output_names;  // lambda1..lambda_m
  std::vector<int32_t> lambda_out;        // m
  int32_t phi_dot_out = -1;
  Eigen::VectorXd phi_dot;  // m: Phi_z zd at the accepted state
  double phi_dot_norm = 0.0;

  // What a step reads of the last one (MH_EXT_STATE, monohydra/cpp/state.hpp).
  template <class Archive>
  void state(Archive& a) {
    a(z);
    a(zd);
    a(zdd);
    a(lambda_k);
    a(phi_dot);
    a(phi_dot_norm);
  }
  std::string state_loaded() {
    last_valid = false;  // M' and Phi_z of the last residual are another run's
    return "";
  }
};

void log(const Penalty& s, mh_log_level level, const std::string& msg) {
  s.host->log(s.host, level, msg.c_str());
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

template <class Body>
mh_status guarded(const mh_formulation* f, const char* op, Body&& body) noexcept {
  return monohydra::guarded_op<Penalty>(f, op, std::forward<Body>(body));
}

mh_status evaluate(Penalty& s, uint32_t flags, double t, const double* z, const double* zd,
                   mh_mech_result& out) {
  const mh_mech_request rq{sizeof(mh_mech_request), flags, t, z, zd};
  out = mh_mech_result{};
  out.struct_size = sizeof(mh_mech_result);
  return s.mech->evaluate_mechanics(s.host, &rq, &out);
}

// phi_dot_norm = ||Phi_z zd|| (Phi_z at the accepted z, m x N).
void cache_phi_dot(Penalty& s, const ConstMatrixMap& phi_z, const Eigen::VectorXd& zd) {
  s.phi_dot.noalias() = phi_z.lazyProduct(zd);
  s.phi_dot_norm = s.phi_dot.norm();
}

mh_status declare_outputs(Penalty& s) {
  s.output_names.clear();
  for (int i = 1; i <= s.m; ++i) s.output_names.push_back("lambda" + std::to_string(i));
  s.lambda_out.assign(static_cast<size_t>(s.m), -1);
  for (int i = 0; i < s.m; ++i) {
    // Generalized constraint forces (N or N m, by the row's constraint).
    const mh_output_spec spec =
        monohydra::output_spec(s.output_names[static_cast<size_t>(i)].c_str(), "");
    if (monohydra::outputs(s.host).add_output(s.host, &spec,
                                              &s.lambda_out[static_cast<size_t>(i)]) != MH_OK)
      return MH_ERROR;
  }
  // The constraint velocity violation (rad/s or m/s by the row).
  const mh_output_spec spec = monohydra::output_spec("phi_dot_norm", "1/s");
  return monohydra::outputs(s.host).add_output(s.host, &spec, &s.phi_dot_out);
}

mh_status setup(const mh_formulation* f) noexcept {
  return guarded(f, "setup", [&](Penalty& s) {
    mh_mech_info info{};
    info.struct_size = sizeof(info);
    if (monohydra::mechanism(s.host).mech_info(s.host, &info) != MH_OK) {
      log(s, MH_LOG_ERROR, "setup: the host gave no mechanism information");
      return MH_ERROR;
    }
    if (info.z0 == nullptr || info.zd0 == nullptr || info.coordinate_names == nullptr ||
        info.coordinate_is_angle == nullptr) {
      log(s, MH_LOG_ERROR, "setup: the host gave no coordinate names or initial state");
      return MH_ERROR;
    }
    s.N = static_cast<int>(info.num_coordinates);
    s.m = static_cast<int>(info.num_constraints);
    s.t0 = info.t0;
    s.tol = info.position_tolerance;
    if (monohydra::options(s.host).option_number(s.host, "alpha", 0, s.alpha, &s.alpha) != MH_OK)
      return MH_ERROR;
    if (!(s.alpha > 0.0))
      return monohydra::options(s.host).option_error(s.host, "alpha", "a positive number");
    if (monohydra::options(s.host).option_number(s.host, "tolerance", 0, s.tol, &s.tol) != MH_OK)
      return MH_ERROR;
    if (!(s.tol > 0.0))
      return monohydra::options(s.host).option_error(s.host, "tolerance", "a positive number");
    double projections = 1.0;
    if (monohydra::options(s.host).option_number(s.host, "projections", 0, projections,
                                                 &projections) != MH_OK)
      return MH_ERROR;
    if (projections != 0.0 && projections != 1.0)
      return monohydra::options(s.host).option_error(s.host, "projections", "1 (on) or 0 (off)");
    s.projections = projections == 1.0;
    const char* matrix = "tangent";
    if (monohydra::options(s.host).option_string(s.host, "projection_matrix", 0, matrix, &matrix) !=
        MH_OK)
      return MH_ERROR;
    const std::string matrix_name = matrix != nullptr ? matrix : "";
    if (matrix_name != "tangent" && matrix_name != "mass")
      return monohydra::options(s.host).option_error(
          s.host, "projection_matrix",
          "tangent (W = M' + dt/2 C + dt^2/4 K, Eqs. 20-21) or mass "
          "(W = M')");
    s.tangent_projection_matrix = matrix_name == "tangent";
    if (s.tangent_projection_matrix && !monohydra::has_mech_derivatives(*s.mech)) {
      log(s, MH_LOG_ERROR,
          "setup: projection_matrix: tangent needs the host service mech_derivatives, which "
          "this host does not give: use projection_matrix: mass");
      return MH_ERROR;
    }

    const Eigen::Index N = s.N, m = s.m;
    for (Eigen::VectorXd* v : {&s.zdd, &s.x_last, &s.zd_prime, &s.zdd_prime, &s.zd_new, &s.zdd_new})
      v->setZero(N);
    for (Eigen::VectorXd* v : {&s.lambda_k, &s.lambda, &s.multiplier_force, &s.phi_dot})
      v->setZero(m);
    s.z = ConstVectorMap(info.z0, N);
    s.zd = ConstVectorMap(info.zd0, N);
    s.M_last.setZero(N, N);
    s.W.setZero(N, N);
    s.phi_z_last.setZero(m, N);
    s.projector.resize(s.N, s.m);
    // The unknowns: every z_i, second order, in the coordinates' order.
    for (int i = 0; i < s.N; ++i) {
      const mh_unknown_spec spec = monohydra::unknown_spec(
          info.coordinate_names[i], info.coordinate_is_angle[i] != 0 ? "rad" : "m",
          MH_UNKNOWN_SECOND_ORDER, s.tol);
      int32_t index = -1;
      if (monohydra::unknowns(s.host).add_unknown(s.host, &spec, &index) != MH_OK) return MH_ERROR;
    }
    return declare_outputs(s);
  });
}

mh_status start(const mh_formulation* f, const mh_unknown_buffers* out) noexcept {
  double* x0 = out->x;
  double* xd0 = out->xd;
  double* xdd0 = out->xdd;
  return guarded(f, "start", [&](Penalty& s) {
    s.last_valid = false;
    // The host's initial state now, not setup's copy of it
    // (MH_EXT_INITIAL_STATE_AT_START): an initial coordinate may be a parameter.
    mh_mech_info info{};
    info.struct_size = sizeof(info);
    if (monohydra::mechanism(s.host).mech_info(s.host, &info) != MH_OK || info.z0 == nullptr ||
        info.zd0 == nullptr) {
      log(s, MH_LOG_ERROR, "start: the host gave no assembled initial state (mech_info z0, zd0)");
      return MH_ERROR;
    }
    s.z = ConstVectorMap(info.z0, s.N);
    s.zd = ConstVectorMap(info.zd0, s.N);
    mh_mech_result rs;
    const mh_status st =
        evaluate(s, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS, s.t0, s.z.data(), s.zd.data(), rs);
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
    cache_phi_dot(s, ConstMatrixMap(rs.phi_z, s.m, s.N), s.zd);
    VectorMap(x0, s.N) = s.z;
    VectorMap(xd0, s.N) = s.zd;
    VectorMap(xdd0, s.N) = s.zdd;
    log(s, MH_LOG_DEBUG,
        "start: alpha = " + num(s.alpha) + ", tolerance = " + num(s.tol) + ", projections " +
            (s.projections ? "on" : "off") + "; initial multipliers in " +
            std::to_string(a.iterations) + " iterations, constraint accelerations " +
            num(a.violation) + ", last correction of zdd " + num(a.correction));
    return result;
  });
}

// A step begins from the accepted state: lambda_{k+1}^(0) = lambda_k (Eq. 19's start).
mh_status begin_step(const mh_formulation* f, const mh_step_begin*) noexcept {
  return guarded(f, "begin_step", [&](Penalty& s) {
    s.lambda = s.lambda_k;
    s.last_valid = false;
    return MH_OK;
  });
}

mh_status residual(const mh_formulation* f, const mh_unknown_values* at, double* r) noexcept {
  const double t = at->t;
  const double* x = at->x;
  const double* xd = at->xd;
  const double* xdd = at->xdd;
  return guarded(f, "residual", [&](Penalty& s) {
    mh_mech_result rs;
    s.last_valid = false;
    const mh_status st =
        evaluate(s, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS | MH_EVAL_SUBSYSTEMS, t, x, xd, rs);
    if (st >= MH_DISCARD) return st;
    const ConstMatrixMap M(rs.M, s.N, s.N);
    const ConstVectorMap Q(rs.Q, s.N);
    const ConstVectorMap phi(rs.phi, s.m);
    const ConstMatrixMap phi_z(rs.phi_z, s.m, s.N);
    // Eq. (18) (Eq. 39 without dt^2/4): M' zdd + Phi_z^T (alpha Phi + lambda) - Q'.
    s.multiplier_force = s.alpha * phi + s.lambda;
    VectorMap rr(r, s.N);
    rr.noalias() = M.lazyProduct(ConstVectorMap(xdd, s.N));
    add_constraint_forces(rr, phi_z, s.multiplier_force, 1.0);
    rr -= Q;
    // Kept for the tangent, and for the projections and phi_dot_norm in accept().
    s.x_last = ConstVectorMap(x, s.N);
    s.M_last = M;
    s.phi_z_last = phi_z;
    s.last_valid = true;
    return st;
  });
}

// The analytic tangent of Eq. (18) at the last residual call (the host's
// recursions, subsystem forces included):
//   dr/dz   = K + d(Phi_z^T v)/dz + alpha Phi_z^T Phi_z,  v = alpha Phi + lambda,
//   dr/dzd  = C,
//   dr/dzdd = M'.
// Without mech_derivatives the host differences every column (Eqs. 40-41).
mh_status tangent(const mh_formulation* f, const mh_unknown_values* at,
                  const mh_tangent_blocks* blocks) noexcept {
  const double t = at->t;
  const double* x = at->x;
  const double* xd = at->xd;
  const double* xdd = at->xdd;
  double* dr_dx = blocks->dr_dx;
  double* dr_dxd = blocks->dr_dxd;
  double* dr_dxdd = blocks->dr_dxdd;
  uint8_t* column_given = blocks->column_given;
  return guarded(f, "tangent", [&](Penalty& s) {
    if (!monohydra::has_mech_derivatives(*s.mech)) return MH_OK;
    if (!s.last_valid || s.x_last != ConstVectorMap(x, s.N)) {
      mh_mech_result rs;
      const mh_status st = evaluate(s, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS, t, x, xd, rs);
      if (st >= MH_DISCARD) return st;
      s.M_last = ConstMatrixMap(rs.M, s.N, s.N);
      s.phi_z_last = ConstMatrixMap(rs.phi_z, s.m, s.N);
      s.multiplier_force = s.alpha * ConstVectorMap(rs.phi, s.m) + s.lambda;
      s.x_last = ConstVectorMap(x, s.N);
      s.last_valid = true;
    }
    mh_mech_derivatives_request rq{};
    rq.struct_size = sizeof(rq);
    rq.flags = MH_DERIV_DYNAMICS | (s.m > 0 ? MH_DERIV_CONSTRAINT_FORCES : 0u);
    rq.t = t;
    rq.z = x;
    rq.zd = xd;
    rq.zdd = xdd;
    rq.v = s.multiplier_force.data();
    mh_mech_derivatives d{};
    d.struct_size = sizeof(d);
    const mh_status st = s.mech->mech_derivatives(s.host, &rq, &d);
    if (st >= MH_DISCARD) return st;
    Eigen::Map<Eigen::MatrixXd> Kt(dr_dx, s.N, s.N);
    Kt = ConstMatrixMap(d.K, s.N, s.N);
    if (s.m > 0) {
      Kt += ConstMatrixMap(d.dPhizT_v_dz, s.N, s.N);
      add_penalty_matrix(Kt, s.phi_z_last, s.alpha);
    }
    Eigen::Map<Eigen::MatrixXd>(dr_dxd, s.N, s.N) = ConstMatrixMap(d.C, s.N, s.N);
    Eigen::Map<Eigen::MatrixXd>(dr_dxdd, s.N, s.N) = s.M_last;
    std::fill(column_given, column_given + s.N, uint8_t{1});
    return MH_OK;
  });
}

// The unknowns are the coordinates (z = x, zd = xd) and the rows take Q' with
// the sign -1 (the host couples the subsystems to them analytically).
mh_status mechanics_map(const mh_formulation* f, const mh_mechanics_map* map) noexcept {
  double* dz_dx = map->dz_dx;
  double* dzd_dxd = map->dzd_dxd;
  double* dr_dQ = map->dr_dQ;
  return guarded(f, "mechanics_map", [&](Penalty& s) {
    for (int i = 0; i < s.N; ++i) {
      const size_t d = static_cast<size_t>(i) * static_cast<size_t>(s.N) + static_cast<size_t>(i);
      if (dz_dx != nullptr) dz_dx[d] = 1.0;
      if (dzd_dxd != nullptr) dzd_dxd[d] = 1.0;
      dr_dQ[d] = -1.0;
    }
    return MH_OK;
  });
}

mh_status iteration_done(const mh_formulation* f, const mh_unknown_values* at) noexcept {
  const double t = at->t;
  const double* x = at->x;
  const double* xd = at->xd;
  return guarded(f, "iteration_done", [&](Penalty& s) {
    mh_mech_result rs;
    const mh_status st = evaluate(s, MH_EVAL_CONSTRAINTS, t, x, xd, rs);  // Phi: of z only
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

// The step converged at x with the integrator's xd = zd', xdd = zdd': project
// them in place (Eqs. 20-21) and commit z, zd, zdd and lambda_k.
mh_status accept(const mh_formulation* f, double t, const mh_step_coefficients* c,
                 const mh_unknown_buffers* values, uint32_t*) noexcept {
  double* x = values->x;
  double* xd = values->xd;
  double* xdd = values->xdd;
  return guarded(f, "accept", [&](Penalty& s) {
    const ConstVectorMap xz(x, s.N);
    if (s.m > 0 && (!s.last_valid || s.x_last != xz)) {
      // M' and Phi_z depend on z only: from the last residual call when it was at x.
      mh_mech_result rs;
      const mh_status st = evaluate(s, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS, t, x, xd, rs);
      if (st >= MH_DISCARD) return st;
      s.M_last = ConstMatrixMap(rs.M, s.N, s.N);
      s.phi_z_last = ConstMatrixMap(rs.phi_z, s.m, s.N);
      s.x_last = xz;
      s.last_valid = true;
    }
    s.zd_prime = ConstVectorMap(xd, s.N);    // zd' of the integrator
    s.zdd_prime = ConstVectorMap(xdd, s.N);  // zdd'
    if (s.projections && s.m > 0) {
      // The paper's dt^2/4 is 1 / c_a, its dt/2 c_v / c_a (projections.hpp).
      if (c == nullptr || !(c->dxdd_dx_second > 0.0)) {
        log(s, MH_LOG_ERROR, "accept: the host gave no step coefficients for the projections");
        return MH_ERROR;
      }
      s.W = s.M_last;
      if (s.tangent_projection_matrix) {
        // W = M' + dt/2 C + dt^2/4 K at the converged z, zd', zdd' (Eqs. 20-21).
        mh_mech_derivatives_request rq{};
        rq.struct_size = sizeof(rq);
        rq.flags = MH_DERIV_DYNAMICS;
        rq.t = t;
        rq.z = x;
        rq.zd = xd;
        rq.zdd = xdd;
        mh_mech_derivatives d{};
        d.struct_size = sizeof(d);
        const mh_status st = s.mech->mech_derivatives(s.host, &rq, &d);
        if (st >= MH_DISCARD) return st;
        s.W += (c->dxd_dx_second / c->dxdd_dx_second) * ConstMatrixMap(d.C, s.N, s.N);
        s.W += (1.0 / c->dxdd_dx_second) * ConstMatrixMap(d.K, s.N, s.N);
      }
      if (!s.projector.factorize(ConstMatrixMap(s.W.data(), s.N, s.N),
                                 ConstMatrixMap(s.phi_z_last.data(), s.m, s.N),
                                 1.0 / c->dxdd_dx_second, s.alpha)) {
        log(s, MH_LOG_ERROR,
            "accept: W + dt^2/4 Phi_z^T alpha Phi_z is singular; the projections (Eqs. 20-21) "
            "cannot be made");
        return MH_DISCARD;
      }
      s.projector.project_velocities(s.zd_prime, s.zd_new);  // Eq. (20)
      // Eq. (21) needs Phidot_z zd at the projected velocities.
      mh_mech_result rs;
      const mh_status st = evaluate(s, MH_EVAL_CONSTRAINTS, t, x, s.zd_new.data(), rs);
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
    // Commit, and hand the projected rates back: the integrator's history.
    VectorMap(xd, s.N) = s.zd_new;
    VectorMap(xdd, s.N) = s.zdd_new;
    s.z = xz;
    s.zd = s.zd_new;
    s.zdd = s.zdd_new;
    s.lambda_k = s.lambda;
    if (s.m > 0) cache_phi_dot(s, ConstMatrixMap(s.phi_z_last.data(), s.m, s.N), s.zd);
    return MH_OK;
  });
}

mh_status coordinates(const mh_formulation* f, const mh_coordinate_buffers* out) noexcept {
  double* z = out->z;
  double* zd = out->zd;
  double* zdd = out->zdd;
  return guarded(f, "coordinates", [&](Penalty& s) {
    VectorMap(z, s.N) = s.z;
    VectorMap(zd, s.N) = s.zd;
    VectorMap(zdd, s.N) = s.zdd;
    return MH_OK;
  });
}

// The multipliers lambda_k and ||Phi_z zd|| at the accepted state, as cached.
mh_status write_outputs(const mh_formulation* f, double* outputs, uint32_t num_outputs) noexcept {
  return guarded(f, "write_outputs", [&](Penalty& s) {
    const auto put = [&](int32_t index, double value) {
      if (index >= 0 && static_cast<uint32_t>(index) < num_outputs) outputs[index] = value;
    };
    for (int i = 0; i < s.m; ++i) put(s.lambda_out[static_cast<size_t>(i)], s.lambda_k[i]);
    put(s.phi_dot_out, s.phi_dot_norm);
    return MH_OK;
  });
}

// The unknowns are the coordinates, coupled as the mechanics couple them
// (MH_EXT_COORDINATE_UNKNOWNS): the host's tangent is sparse for trees. Its
// state saves and loads (MH_EXT_STATE). A converged step holds Phi(z) = 0,
// the multipliers of Eq. (19) having made it so
// (MH_EXT_CONSTRAINED_AT_CONVERGENCE: a differentiated step is bordered by
// Phi_z).
const char kCoordinateUnknowns = 1;
const void* get_extension(const mh_formulation*, const char* id) noexcept {
  if (id == nullptr) return nullptr;
  if (std::strcmp(id, MH_EXT_COORDINATE_UNKNOWNS) == 0) return &kCoordinateUnknowns;
  if (std::strcmp(id, MH_EXT_CONSTRAINED_AT_CONVERGENCE) == 0) return &kCoordinateUnknowns;
  if (std::strcmp(id, MH_EXT_INITIAL_STATE_AT_START) == 0) return &kCoordinateUnknowns;
  if (std::strcmp(id, MH_EXT_STATE) == 0)
    return monohydra::state_extension<mh_formulation, Penalty>();
  return nullptr;
}

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "penalty",
    "Penalty-based semirecursive formulation (index-3 augmented Lagrangian with projections)",
    "monohydra",
    "2.0.0",
    "Closed loops by cut joints: M' zdd + Phi_z^T (alpha Phi + lambda) = Q' (Eq. 18) with "
    "all relative coordinates as second-order unknowns of the host's integrator, multipliers "
    "updated per Newton iteration (Eq. 19) and mass-orthogonal projections of velocities and "
    "accelerations (Eqs. 20-21). Options: alpha, tolerance, projections, projection_matrix "
    "(tangent: W = M' + dt/2 C + dt^2/4 K; mass: W = M'). Outputs: "
    "lambda1..lambda_m, phi_dot_norm."};

// The instance's operations; every instance gets a copy with its own state.
const mh_formulation kOps = [] {
  mh_formulation f{};
  f.struct_size = sizeof(mh_formulation);
  f.descriptor = &kDescriptor;
  f.setup = setup;
  f.start = start;
  f.begin_step = begin_step;
  f.residual = residual;
  f.tangent = tangent;
  f.iteration_done = iteration_done;
  f.accept = accept;
  f.coordinates = coordinates;
  f.write_outputs = write_outputs;
  f.destroy = monohydra::destroy_formulation<Penalty>;
  f.get_extension = get_extension;
  f.mechanics_map = mechanics_map;
  return f;
}();

const mh_formulation* create(const mh_host* host) {
  return monohydra::create_formulation<Penalty>(host, kOps);
}

}  // namespace
}  // namespace mh_penalty

MONOHYDRA_FORMULATION_PLUGIN(mh_penalty::kDescriptor, mh_penalty::create);
