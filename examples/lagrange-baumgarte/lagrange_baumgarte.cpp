// lagrange-baumgarte: the classic index-1 formulation the paper's references
// compare against, as an example third-party formulation plugin built against
// the installed SDK alone. Its Newton unknowns are the N joint coordinates z
// (second order) AND the m Lagrange multipliers lambda (algebraic): a
// formulation's unknowns need not be coordinates. Residual rows:
//
//   M' zdd + Phi_z^T lambda - Q' = 0                                   (N rows)
//   Phi_z zdd + Phidot_z zd + 2 alpha Phi_z zd + beta^2 Phi = 0         (m rows)
//
// i.e. the constraint accelerations with Baumgarte's stabilization: the
// violation obeys Phi'' + 2 alpha Phi' + beta^2 Phi = 0 instead of Phi'' = 0,
// so position and velocity drift decay rather than grow linearly or
// quadratically, but they are never removed (no projections): the loop stays
// open by what the integrator's error feeds in. Redundant constraints make
// the multipliers non-unique and the Newton matrix singular (use penalty).
//
// The tangent is analytic, from the host's mech_derivatives: with
// A = Phi_z zdd + Phidot_z zd and d(Phi_z zd)/dz = Phidot_z = (1/2) dA/dzd,
//   d/dz:   [K + d(Phi_z^T lambda)/dz ; dA/dz + alpha dA/dzd + beta^2 Phi_z]
//   d/dzd:  [C ; dA/dzd + 2 alpha Phi_z]      d/dzdd: [M' ; Phi_z]
//   d/dlambda: [Phi_z^T ; 0]
// Options: alpha, beta (1/s, default 10), tolerance (of z, default the
// model's), multiplier_tolerance (N or N m, default 1e-3), tangent
// (analytic | differences). Outputs: lambda1..lambda_m, phi_dot_norm.
#include <Eigen/Core>
#include <Eigen/LU>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "monohydra/cpp/formulation_plugin.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/state.hpp"
#include "monohydra/monohydra.h"

namespace lagrange_baumgarte {
namespace {

using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd>;
using ConstVectorMap = Eigen::Map<const Eigen::VectorXd>;
using MatrixMap = Eigen::Map<Eigen::MatrixXd>;
using VectorMap = Eigen::Map<Eigen::VectorXd>;

struct State {
  const mh_host* host = nullptr;
  const mh_mechanism_service* mech = nullptr;  // found once, at create
  double alpha = 10.0;                         // Baumgarte damping (1/s)
  double beta = 10.0;                          // Baumgarte stiffness (1/s)
  double tol = 1e-7;                           // Newton tolerance of z (rad or m)
  double lambda_tol = 1e-3;
  bool analytic_tangent = true;
  int N = 0, m = 0;
  double t0 = 0.0;
  Eigen::VectorXd z, zd, zdd, lambda;  // accepted
  // M' and Phi_z of the last residual call: the tangent is taken there.
  Eigen::MatrixXd M_last, phi_z_last;
  std::vector<std::string> output_names;
  std::vector<int32_t> lambda_out;
  int32_t phi_dot_out = -1;
  Eigen::VectorXd phi_dot;  // m: Phi_z zd at the accepted state
  double phi_dot_norm = 0.0;

  // What the next step reads (MH_EXT_STATE, monohydra/cpp/state.hpp): the
  // accepted state and what its outputs show.
  template <class Archive>
  void state(Archive& a) {
    a(z);
    a(zd);
    a(zdd);
    a(lambda);
    a(phi_dot);
    a(phi_dot_norm);
  }
};

void log(const State& s, mh_log_level level, const std::string& msg) {
  s.host->log(s.host, level, msg.c_str());
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

template <class Body>
mh_status guarded(const mh_formulation* f, const char* op, Body&& body) noexcept {
  return monohydra::guarded_op<State>(f, op, body);
}

mh_status evaluate(const State& s, uint32_t flags, double t, const double* z, const double* zd,
                   mh_mech_result& out) {
  const mh_mech_request rq{sizeof(mh_mech_request), flags, t, z, zd};
  out = mh_mech_result{};
  out.struct_size = sizeof(mh_mech_result);
  return s.mech->evaluate_mechanics(s.host, &rq, &out);
}

mh_status read_options(State& s) {
  const mh_host* h = s.host;
  if (monohydra::options(h).option_number(h, "alpha", 0, s.alpha, &s.alpha) != MH_OK)
    return MH_ERROR;
  if (!(s.alpha >= 0.0))
    return monohydra::options(h).option_error(h, "alpha", "a damping rate >= 0 (1/s)");
  if (monohydra::options(h).option_number(h, "beta", 0, s.beta, &s.beta) != MH_OK) return MH_ERROR;
  if (!(s.beta >= 0.0))
    return monohydra::options(h).option_error(h, "beta", "a stiffness rate >= 0 (1/s)");
  if (monohydra::options(h).option_number(h, "tolerance", 0, s.tol, &s.tol) != MH_OK)
    return MH_ERROR;
  if (!(s.tol > 0.0))
    return monohydra::options(h).option_error(h, "tolerance", "a positive number");
  if (monohydra::options(h).option_number(h, "multiplier_tolerance", 0, s.lambda_tol,
                                          &s.lambda_tol) != MH_OK)
    return MH_ERROR;
  if (!(s.lambda_tol > 0.0))
    return monohydra::options(h).option_error(h, "multiplier_tolerance",
                                              "a positive force (N or N m)");
  const char* tangent = "analytic";
  if (monohydra::options(h).option_string(h, "tangent", 0, tangent, &tangent) != MH_OK)
    return MH_ERROR;
  const std::string name = tangent != nullptr ? tangent : "";
  if (name != "analytic" && name != "differences")
    return monohydra::options(h).option_error(h, "tangent", "analytic or differences");
  s.analytic_tangent = name == "analytic";
  if (s.analytic_tangent && !monohydra::has_mech_derivatives(*s.mech)) {
    log(s, MH_LOG_ERROR,
        "setup: tangent: analytic needs the host service mech_derivatives, which this "
        "host does not give: use tangent: differences");
    return MH_ERROR;
  }
  return MH_OK;
}

mh_status setup(const mh_formulation* f) noexcept {
  return guarded(f, "setup", [&](State& s) {
    mh_mech_info info{};
    info.struct_size = sizeof(info);
    if (monohydra::mechanism(s.host).mech_info(s.host, &info) != MH_OK || info.z0 == nullptr ||
        info.zd0 == nullptr || info.coordinate_names == nullptr ||
        info.coordinate_is_angle == nullptr) {
      log(s, MH_LOG_ERROR, "setup: the host gave no mechanism information");
      return MH_ERROR;
    }
    s.N = static_cast<int>(info.num_coordinates);
    s.m = static_cast<int>(info.num_constraints);
    s.t0 = info.t0;
    s.tol = info.position_tolerance;
    if (read_options(s) != MH_OK) return MH_ERROR;
    s.z = ConstVectorMap(info.z0, s.N);
    s.zd = ConstVectorMap(info.zd0, s.N);
    s.zdd.setZero(s.N);
    s.lambda.setZero(s.m);
    s.phi_dot.setZero(s.m);
    s.M_last.setZero(s.N, s.N);
    s.phi_z_last.setZero(s.m, s.N);
    // Unknowns 0..N-1: the coordinates; N..N+m-1: the multipliers.
    for (int i = 0; i < s.N; ++i) {
      const mh_unknown_spec spec = monohydra::unknown_spec(
          info.coordinate_names[i], info.coordinate_is_angle[i] != 0 ? "rad" : "m",
          MH_UNKNOWN_SECOND_ORDER, s.tol);
      int32_t index = -1;
      if (monohydra::unknowns(s.host).add_unknown(s.host, &spec, &index) != MH_OK) return MH_ERROR;
    }
    for (int i = 1; i <= s.m; ++i) s.output_names.push_back("lambda" + std::to_string(i));
    for (int i = 0; i < s.m; ++i) {
      const mh_unknown_spec spec = monohydra::unknown_spec(
          s.output_names[static_cast<size_t>(i)].c_str(), "N", MH_UNKNOWN_ALGEBRAIC, s.lambda_tol);
      int32_t index = -1;
      if (monohydra::unknowns(s.host).add_unknown(s.host, &spec, &index) != MH_OK) return MH_ERROR;
    }
    s.lambda_out.assign(static_cast<size_t>(s.m), -1);
    for (int i = 0; i < s.m; ++i) {
      const mh_output_spec spec =
          monohydra::output_spec(s.output_names[static_cast<size_t>(i)].c_str(), "");
      if (monohydra::outputs(s.host).add_output(s.host, &spec,
                                                &s.lambda_out[static_cast<size_t>(i)]) != MH_OK)
        return MH_ERROR;
    }
    const mh_output_spec spec = monohydra::output_spec("phi_dot_norm", "1/s");
    return monohydra::outputs(s.host).add_output(s.host, &spec, &s.phi_dot_out);
  });
}

// The constraint rows' Baumgarte terms: Phidot_z zd + 2 alpha Phi_z zd + beta^2 Phi.
Eigen::VectorXd stabilized_terms(const State& s, const mh_mech_result& rs, const double* zd) {
  const ConstMatrixMap phi_z(rs.phi_z, s.m, s.N);
  const ConstVectorMap v(zd, s.N);
  return ConstVectorMap(rs.phi_dot_zd, s.m) + 2.0 * s.alpha * (phi_z * v) +
         s.beta * s.beta * ConstVectorMap(rs.phi, s.m);
}

// Consistent accelerations and multipliers at t0: the KKT system
//   [M' Phi_z^T; Phi_z 0] [zdd; lambda] = [Q'; -(Phidot_z zd + 2 alpha Phi_z zd + beta^2 Phi)].
mh_status start(const mh_formulation* f, const mh_unknown_buffers* out) noexcept {
  double* x0 = out->x;
  double* xd0 = out->xd;
  double* xdd0 = out->xdd;
  return guarded(f, "start", [&](State& s) {
    mh_mech_result rs;
    if (evaluate(s, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS, s.t0, s.z.data(), s.zd.data(), rs) >=
        MH_DISCARD)
      return MH_ERROR;
    const int n = s.N + s.m;
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd rhs(n);
    kkt.topLeftCorner(s.N, s.N) = ConstMatrixMap(rs.M, s.N, s.N);
    rhs.head(s.N) = ConstVectorMap(rs.Q, s.N);
    if (s.m > 0) {
      const ConstMatrixMap phi_z(rs.phi_z, s.m, s.N);
      kkt.topRightCorner(s.N, s.m) = phi_z.transpose();
      kkt.bottomLeftCorner(s.m, s.N) = phi_z;
      rhs.tail(s.m) = -stabilized_terms(s, rs, s.zd.data());
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(kkt);
    if (lu.rank() < n) {
      log(s, MH_LOG_ERROR,
          "start: [M' Phi_z^T; Phi_z 0] is singular (rank " + std::to_string(lu.rank()) + " of " +
              std::to_string(n) +
              "): redundant constraints make the Lagrange multipliers non-unique; use the "
              "penalty formulation for such mechanisms");
      return MH_ERROR;
    }
    const Eigen::VectorXd sol = lu.solve(rhs);
    s.zdd = sol.head(s.N);
    s.lambda = sol.tail(s.m);
    s.phi_dot_norm = s.m > 0 ? (ConstMatrixMap(rs.phi_z, s.m, s.N) * s.zd).norm() : 0.0;
    VectorMap(x0, n) << s.z, s.lambda;
    VectorMap(xd0, n) << s.zd, Eigen::VectorXd::Zero(s.m);
    VectorMap(xdd0, n) << s.zdd, Eigen::VectorXd::Zero(s.m);
    log(s, MH_LOG_DEBUG,
        "start: alpha = " + num(s.alpha) + " 1/s, beta = " + num(s.beta) + " 1/s, tangent " +
            (s.analytic_tangent ? "analytic" : "by differences"));
    return MH_OK;
  });
}

mh_status residual(const mh_formulation* f, const mh_unknown_values* at, double* r) noexcept {
  const double t = at->t;
  const double* x = at->x;
  const double* xd = at->xd;
  const double* xdd = at->xdd;
  return guarded(f, "residual", [&](State& s) {
    mh_mech_result rs;
    const mh_status st =
        evaluate(s, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS | MH_EVAL_SUBSYSTEMS, t, x, xd, rs);
    if (st >= MH_DISCARD) return st;
    const ConstMatrixMap M(rs.M, s.N, s.N);
    const ConstMatrixMap phi_z(rs.phi_z, s.m, s.N);
    const ConstVectorMap zdd(xdd, s.N);
    const ConstVectorMap lambda(x + s.N, s.m);
    VectorMap r1(r, s.N);
    r1.noalias() = M * zdd;
    r1.noalias() += phi_z.transpose() * lambda;
    r1 -= ConstVectorMap(rs.Q, s.N);
    if (s.m > 0) {
      VectorMap r2(r + s.N, s.m);
      r2.noalias() = phi_z * zdd;
      r2 += ConstVectorMap(rs.phi_dot_zd, s.m) + s.beta * s.beta * ConstVectorMap(rs.phi, s.m);
      r2.noalias() += (2.0 * s.alpha) * (phi_z * ConstVectorMap(xd, s.N));
    }
    s.M_last = M;
    s.phi_z_last = phi_z;
    return st;
  });
}

// Analytic blocks at the last residual call's arguments (see the top of the file).
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
  return guarded(f, "tangent", [&](State& s) {
    const int N = s.N, m = s.m, n = N + m;
    if (!s.analytic_tangent) {  // tangent: differences: no column given, the host differences
      for (int j = 0; j < n; ++j) column_given[j] = 0;
      return MH_OK;
    }
    mh_mech_derivatives_request rq{};
    rq.struct_size = sizeof(rq);
    rq.flags = MH_DERIV_DYNAMICS;
    if (s.m > 0) rq.flags |= MH_DERIV_CONSTRAINT_FORCES | MH_DERIV_CONSTRAINT_ACCELERATIONS;
    rq.t = t;
    rq.z = x;
    rq.zd = xd;
    rq.zdd = xdd;
    rq.v = x + s.N;  // lambda
    mh_mech_derivatives d{};
    d.struct_size = sizeof(d);
    const mh_status st = s.mech->mech_derivatives(s.host, &rq, &d);
    if (st >= MH_DISCARD) return st;
    MatrixMap dx(dr_dx, n, n), dxd(dr_dxd, n, n), dxdd(dr_dxdd, n, n);
    dx.topLeftCorner(N, N) = ConstMatrixMap(d.K, N, N);
    dxd.topLeftCorner(N, N) = ConstMatrixMap(d.C, N, N);
    dxdd.topLeftCorner(N, N) = s.M_last;
    if (m > 0) {
      const ConstMatrixMap dA_dz(d.dA_dz, m, N), dA_dzd(d.dA_dzd, m, N);
      dx.topLeftCorner(N, N) += ConstMatrixMap(d.dPhizT_v_dz, N, N);
      dx.topRightCorner(N, m) = s.phi_z_last.transpose();
      dx.bottomLeftCorner(m, N) = dA_dz + s.alpha * dA_dzd + s.beta * s.beta * s.phi_z_last;
      dxd.bottomLeftCorner(m, N) = dA_dzd + 2.0 * s.alpha * s.phi_z_last;
      dxdd.bottomLeftCorner(m, N) = s.phi_z_last;
    }
    for (int j = 0; j < n; ++j) column_given[j] = 1;
    return MH_OK;
  });
}

// No projections: the converged state is committed as the integrator left it.
mh_status accept(const mh_formulation* f, double t, const mh_step_coefficients*,
                 const mh_unknown_buffers* values, uint32_t*) noexcept {
  double* x = values->x;
  double* xd = values->xd;
  double* xdd = values->xdd;
  return guarded(f, "accept", [&](State& s) {
    s.z = ConstVectorMap(x, s.N);
    s.zd = ConstVectorMap(xd, s.N);
    s.zdd = ConstVectorMap(xdd, s.N);
    s.lambda = ConstVectorMap(x + s.N, s.m);
    if (s.m > 0) {
      mh_mech_result rs;
      const mh_status st = evaluate(s, MH_EVAL_CONSTRAINTS, t, x, xd, rs);
      if (st >= MH_DISCARD) return st;
      s.phi_dot.noalias() = ConstMatrixMap(rs.phi_z, s.m, s.N) * s.zd;  // no allocation
      s.phi_dot_norm = s.phi_dot.norm();
    }
    return MH_OK;
  });
}

mh_status coordinates(const mh_formulation* f, const mh_coordinate_buffers* out) noexcept {
  double* z = out->z;
  double* zd = out->zd;
  double* zdd = out->zdd;
  return guarded(f, "coordinates", [&](State& s) {
    VectorMap(z, s.N) = s.z;
    VectorMap(zd, s.N) = s.zd;
    VectorMap(zdd, s.N) = s.zdd;
    return MH_OK;
  });
}

mh_status write_outputs(const mh_formulation* f, double* outputs, uint32_t num_outputs) noexcept {
  return guarded(f, "write_outputs", [&](State& s) {
    const auto put = [&](int32_t index, double value) {
      if (index >= 0 && static_cast<uint32_t>(index) < num_outputs) outputs[index] = value;
    };
    for (int i = 0; i < s.m; ++i) put(s.lambda_out[static_cast<size_t>(i)], s.lambda[i]);
    put(s.phi_dot_out, s.phi_dot_norm);
    return MH_OK;
  });
}

// Its state saves and loads, so that a run can be snapshotted (state.h).
const void* get_extension(const mh_formulation*, const char* id) noexcept {
  if (id != nullptr && std::strcmp(id, MH_EXT_STATE) == 0)
    return monohydra::state_extension<mh_formulation, State>();
  return nullptr;
}

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "lagrange-baumgarte",
    "Lagrange multipliers with Baumgarte stabilization (index-1, example plugin)",
    "monohydra examples",
    "1.0.0",
    "Unknowns z (second order) and lambda (algebraic): M' zdd + Phi_z^T lambda = Q', Phi_z zdd "
    "+ Phidot_z zd + 2 alpha Phi_z zd + beta^2 Phi = 0; analytic tangent from mech_derivatives; "
    "no projections. Options: alpha, beta (1/s, default 10), tolerance, multiplier_tolerance "
    "(default 1e-3), tangent (analytic | differences). Outputs: lambda1..lambda_m, "
    "phi_dot_norm."};

const mh_formulation kOps = [] {
  mh_formulation f{};
  f.struct_size = sizeof(mh_formulation);
  f.descriptor = &kDescriptor;
  f.setup = setup;
  f.start = start;
  f.residual = residual;
  f.tangent = tangent;
  f.accept = accept;
  f.coordinates = coordinates;
  f.write_outputs = write_outputs;
  f.destroy = monohydra::destroy_formulation<State>;
  f.get_extension = get_extension;
  return f;
}();

const mh_formulation* create(const mh_host* host) {
  return monohydra::create_formulation<State>(host, kOps);
}

}  // namespace
}  // namespace lagrange_baumgarte

namespace lagrange_baumgarte {
// What `monohydra check lagrange_baumgarte.so` runs it on: the paper's
// four-bar linkage alone (its three beams and the cut joint at E), falling
// under gravity from the paper's initial angles, which close the loop.
constexpr const char* kExampleModel = R"(units: {length: m, mass: kg, time: s, angle: deg}
name: four-bar-linkage
planar: true
gravity: [0, -9.81, 0]
bodies:
  - {name: body1, parent: ground, joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]},
     mass: 225, shape: {type: beam, length: 9}, z0: 0}
  - {name: body2, parent: body1, joint: {type: revolute, at: [3, 0, 0], axis: [0, 0, 1]},
     mass: 35, shape: {type: beam, length: 1.4142135623730951}, z0: -135}
  - {name: body3, parent: body2,
     joint: {type: revolute, at: [1.4142135623730951, 0, 0], axis: [0, 0, 1]},
     mass: 50, shape: {type: beam, length: 2}, z0: -45}
cut_joints:
  - {name: E, type: revolute, a: {body: body3, at: [2, 0, 0]}, b: {body: ground, at: [0, -1, 0]}}
formulation: lagrange-baumgarte
solver: {dt: 0.001, t_end: 1}
)";
}  // namespace lagrange_baumgarte

MONOHYDRA_FORMULATION_PLUGIN_WITH_EXAMPLE(lagrange_baumgarte::kDescriptor,
                                          lagrange_baumgarte::create,
                                          lagrange_baumgarte::kExampleModel);
