// The open-loop formulation: a tree without cut joints, M' zdd = Q' (Eq. 12),
// with the trapezoidal rule written with z_{k+1} as the primary unknowns
// (Eqs. 32-34 on the full set z), residual Eq. (39) without constraints.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <new>
#include <string>

#include "monohydra/cpp/formulation_plugin.hpp"
#include "monohydra/monohydra.h"

namespace {

struct OpenLoop {
  const mh_host* host = nullptr;
  int N = 0;
  double dt = 0.0;
  double tol = 1e-7;
  Eigen::VectorXd z, zd, zdd;      // accepted at t_k
  Eigen::VectorXd z_hat, zdd_hat;  // Eq. (34)
  Eigen::VectorXd zd_it, zdd_it;   // at the iterate, Eq. (33)
};

OpenLoop& self(const mh_formulation* f) {
  return *static_cast<OpenLoop*>(f->plugin_data);
}

void log_error(const OpenLoop& s, const std::string& msg) {
  s.host->log(s.host, MH_LOG_ERROR, msg.c_str());
}

mh_status setup(const mh_formulation* f, uint32_t* num_unknowns) {
  OpenLoop& s = self(f);
  mh_mech_info info{};
  info.struct_size = sizeof(info);
  if (s.host->mech_info(s.host, &info) != MH_OK) return MH_ERROR;
  if (info.num_constraints != 0) {
    log_error(s, "the model has cut joints (" + std::to_string(info.num_constraints) +
                     " constraint rows); open-loop handles trees only: choose double-step or "
                     "penalty");
    return MH_ERROR;
  }
  s.N = static_cast<int>(info.num_coordinates);
  s.tol = info.position_tolerance;
  if (s.host->option_number(s.host, "tolerance", 0, s.tol, &s.tol) != MH_OK) return MH_ERROR;
  if (!(s.tol > 0.0)) return s.host->option_error(s.host, "tolerance", "a positive number");
  for (Eigen::VectorXd* v : {&s.z, &s.zd, &s.zdd, &s.z_hat, &s.zdd_hat, &s.zd_it, &s.zdd_it})
    v->setZero(s.N);
  *num_unknowns = static_cast<uint32_t>(s.N);
  return MH_OK;
}

// Accelerations from M' zdd = Q' at the given state.
mh_status accelerations(OpenLoop& s, double t, const Eigen::VectorXd& z, const Eigen::VectorXd& zd,
                        Eigen::VectorXd& zdd) {
  mh_mech_request rq{sizeof(rq), MH_EVAL_DYNAMICS, t, z.data(), zd.data()};
  mh_mech_result rs{};
  rs.struct_size = sizeof(rs);
  if (s.host->evaluate_mechanics(s.host, &rq, &rs) >= MH_DISCARD) return MH_ERROR;
  const Eigen::Map<const Eigen::MatrixXd> M(rs.M, s.N, s.N);
  const Eigen::Map<const Eigen::VectorXd> Q(rs.Q, s.N);
  Eigen::LDLT<Eigen::MatrixXd> ldlt(M);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
    log_error(s, "the mass matrix M' is singular at the initial state (a massless body?)");
    return MH_ERROR;
  }
  zdd = ldlt.solve(Q);
  return MH_OK;
}

mh_status start(const mh_formulation* f, double t0, double dt, const double* z0, const double* zd0,
                double* abs_tolerance) {
  OpenLoop& s = self(f);
  s.dt = dt;
  s.z = Eigen::Map<const Eigen::VectorXd>(z0, s.N);
  s.zd = Eigen::Map<const Eigen::VectorXd>(zd0, s.N);
  for (int i = 0; i < s.N; ++i) abs_tolerance[i] = s.tol;
  return accelerations(s, t0, s.z, s.zd, s.zdd);
}

mh_status predict(const mh_formulation* f, double, double* x) {
  OpenLoop& s = self(f);
  const double dt = s.dt;
  Eigen::Map<Eigen::VectorXd>(x, s.N) = s.z + dt * s.zd + 0.5 * dt * dt * s.zdd;
  s.z_hat = -((2.0 / dt) * s.z + s.zd);                                // Eq. (34)
  s.zdd_hat = -((4.0 / (dt * dt)) * s.z + (4.0 / dt) * s.zd + s.zdd);  // Eq. (34)
  return MH_OK;
}

mh_status residual(const mh_formulation* f, double t_next, const double* x, double* r) {
  OpenLoop& s = self(f);
  const double dt = s.dt;
  const Eigen::Map<const Eigen::VectorXd> z(x, s.N);
  s.zd_it = (2.0 / dt) * z + s.z_hat;            // Eq. (33)
  s.zdd_it = (4.0 / (dt * dt)) * z + s.zdd_hat;  // Eq. (33)
  mh_mech_request rq{sizeof(rq), MH_EVAL_DYNAMICS | MH_EVAL_SUBSYSTEMS, t_next, x, s.zd_it.data()};
  mh_mech_result rs{};
  rs.struct_size = sizeof(rs);
  const mh_status st = s.host->evaluate_mechanics(s.host, &rq, &rs);
  if (st >= MH_DISCARD) return st;
  const Eigen::Map<const Eigen::MatrixXd> M(rs.M, s.N, s.N);
  const Eigen::Map<const Eigen::VectorXd> Q(rs.Q, s.N);
  // Eq. (39) without constraints: dt^2/4 (M' zdd - Q').
  Eigen::Map<Eigen::VectorXd>(r, s.N).noalias() = (0.25 * dt * dt) * (M * s.zdd_it - Q);
  return MH_OK;
}

mh_status accept(const mh_formulation* f, double, const double* x) {
  OpenLoop& s = self(f);
  const double dt = s.dt;
  s.z = Eigen::Map<const Eigen::VectorXd>(x, s.N);
  s.zd = (2.0 / dt) * s.z + s.z_hat;
  s.zdd = (4.0 / (dt * dt)) * s.z + s.zdd_hat;
  return MH_OK;
}

mh_status coordinates(const mh_formulation* f, double* z, double* zd, double* zdd) {
  const OpenLoop& s = self(f);
  Eigen::Map<Eigen::VectorXd>(z, s.N) = s.z;
  Eigen::Map<Eigen::VectorXd>(zd, s.N) = s.zd;
  Eigen::Map<Eigen::VectorXd>(zdd, s.N) = s.zdd;
  return MH_OK;
}

const void* get_extension(const mh_formulation*, const char*) {
  return nullptr;
}

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "open-loop",
    "Open-loop semirecursive formulation",
    "monohydra",
    "1.0.0",
    "Trees of revolute and prismatic joints without cut joints: M' zdd = Q' (Eq. 12) under "
    "the trapezoidal rule with positions as primary unknowns."};

// The instance's operations; every instance gets a copy with its own state.
const mh_formulation kOps = [] {
  mh_formulation f{};
  f.struct_size = sizeof(mh_formulation);
  f.descriptor = &kDescriptor;
  f.setup = setup;
  f.start = start;
  f.predict = predict;
  f.residual = residual;
  f.tangent = nullptr;  // forward differences by the host
  f.iteration_done = nullptr;
  f.accept = accept;
  f.coordinates = coordinates;
  f.destroy = monohydra::destroy_formulation<OpenLoop>;
  f.get_extension = get_extension;
  return f;
}();

const mh_formulation* create(const mh_host* host) {
  return monohydra::create_formulation<OpenLoop>(host, kOps);
}

}  // namespace

MONOHYDRA_FORMULATION_PLUGIN(kDescriptor, create);
