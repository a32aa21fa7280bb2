// The open-loop formulation: a tree without cut joints, M' zdd = Q' (Eq. 12).
// All N joint coordinates z are second-order Newton unknowns; the host's
// integrator ties zd and zdd at the step's end to them (the trapezoidal rule,
// Eqs. 32-34, by default), and the residual is Eq. (39) without constraints
// and without its dt^2/4 factor: r = M'(z) zdd - Q'(z, zd), which a host with
// the inverse_dynamics service computes in O(N) without M' (a chain's M' is
// dense: N^2 to form, as much again to multiply). Its tangent is analytic
// (the host's mech_derivatives): dr/dz = K, dr/dzd = C, dr/dzdd = M', and
// M' and the tangent's blocks are copied on the mechanical block's pattern
// (sparsity.h, mechanical_pattern/1): O(N) for a tree of bounded depth.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "monohydra/constrained.h"
#include "monohydra/cpp/formulation_plugin.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/state.hpp"
#include "monohydra/inverse_dynamics.h"
#include "monohydra/monohydra.h"
#include "monohydra/sparsity.h"

namespace {

using ConstVectorMap = Eigen::Map<const Eigen::VectorXd>;
using VectorMap = Eigen::Map<Eigen::VectorXd>;

struct OpenLoop {
  const mh_host* host = nullptr;
  const mh_mechanism_service* mech = nullptr;  // found once, at create
  // The host's M' zdd - Q' in O(N) (inverse_dynamics.h), found at setup;
  // NULL: formed from evaluate_mechanics's M' and Q'.
  const mh_inverse_dynamics_service* inverse = nullptr;
  int N = 0;
  double t0 = 0.0;
  double tol = 1e-7;
  Eigen::VectorXd z, zd, zdd;  // accepted (z0, zd0 and their accelerations after start)
  // The mechanical pattern, asked for at the first residual (the host builds
  // it after setup); left empty by a host without the service: dense.
  bool pattern_asked = false;
  std::vector<int32_t> column_start, row_index;

  // What a step reads of the last one (MH_EXT_STATE, monohydra/cpp/state.hpp).
  template <class Archive>
  void state(Archive& a) {
    a(z);
    a(zd);
    a(zdd);
  }
};

void log_error(const OpenLoop& s, const std::string& msg) {
  s.host->log(s.host, MH_LOG_ERROR, msg.c_str());
}

mh_status setup(const mh_formulation* f) noexcept {
  return monohydra::guarded_op<OpenLoop>(f, "setup", [&](OpenLoop& s) {
    mh_mech_info info{};
    info.struct_size = sizeof(info);
    if (monohydra::mechanism(s.host).mech_info(s.host, &info) != MH_OK) return MH_ERROR;
    if (info.num_constraints != 0) {
      log_error(s, "the model has cut joints (" + std::to_string(info.num_constraints) +
                       " constraint rows); open-loop handles trees only: choose double-step or "
                       "penalty");
      return MH_ERROR;
    }
    if (info.z0 == nullptr || info.zd0 == nullptr || info.coordinate_names == nullptr ||
        info.coordinate_is_angle == nullptr) {
      log_error(s, "the host gave no coordinate names or initial state (mech_info)");
      return MH_ERROR;
    }
    s.N = static_cast<int>(info.num_coordinates);
    s.inverse = static_cast<const mh_inverse_dynamics_service*>(
        s.host->get_service(s.host, MH_SERVICE_INVERSE_DYNAMICS));
    s.t0 = info.t0;
    s.tol = info.position_tolerance;
    if (monohydra::options(s.host).option_number(s.host, "tolerance", 0, s.tol, &s.tol) != MH_OK)
      return MH_ERROR;
    if (!(s.tol > 0.0))
      return monohydra::options(s.host).option_error(s.host, "tolerance", "a positive number");
    s.z = ConstVectorMap(info.z0, s.N);
    s.zd = ConstVectorMap(info.zd0, s.N);
    s.zdd.setZero(s.N);
    // The unknowns: every z_i, second order, in the coordinates' order.
    for (int i = 0; i < s.N; ++i) {
      const mh_unknown_spec spec = monohydra::unknown_spec(
          info.coordinate_names[i], info.coordinate_is_angle[i] != 0 ? "rad" : "m",
          MH_UNKNOWN_SECOND_ORDER, s.tol);
      int32_t index = -1;
      if (monohydra::unknowns(s.host).add_unknown(s.host, &spec, &index) != MH_OK) return MH_ERROR;
    }
    return MH_OK;
  });
}

// x0 = z0, xd0 = zd0 and xdd0 from M' zdd = Q' (Eq. 12) at t0.
mh_status start(const mh_formulation* f, const mh_unknown_buffers* out) noexcept {
  double* x0 = out->x;
  double* xd0 = out->xd;
  double* xdd0 = out->xdd;
  return monohydra::guarded_op<OpenLoop>(f, "start", [&](OpenLoop& s) {
    // The host's initial state now, not setup's copy of it
    // (MH_EXT_INITIAL_STATE_AT_START): an initial coordinate may be a parameter.
    mh_mech_info info{};
    info.struct_size = sizeof(info);
    if (s.mech->mech_info(s.host, &info) != MH_OK || info.z0 == nullptr || info.zd0 == nullptr) {
      log_error(s, "start: the host gave no initial state (mech_info z0, zd0)");
      return MH_ERROR;
    }
    s.z = ConstVectorMap(info.z0, s.N);
    s.zd = ConstVectorMap(info.zd0, s.N);
    const mh_mech_request rq{sizeof(rq), MH_EVAL_DYNAMICS, s.t0, s.z.data(), s.zd.data()};
    mh_mech_result rs{};
    rs.struct_size = sizeof(rs);
    if (s.mech->evaluate_mechanics(s.host, &rq, &rs) >= MH_DISCARD) return MH_ERROR;
    const Eigen::Map<const Eigen::MatrixXd> M(rs.M, s.N, s.N);
    const ConstVectorMap Q(rs.Q, s.N);
    // LDLT (pivoted), as the penalty formulation's start: without cut joints
    // both give the same accelerations to the bit.
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(M);
    if (s.N > 0 && (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0))) {
      // (N = 0: a model of subsystems only, nothing to factor)
      log_error(s, "the mass matrix M' is singular at the initial state (a massless body?)");
      return MH_ERROR;
    }
    s.zdd = ldlt.solve(Q);  // Eq. (12)
    VectorMap(x0, s.N) = s.z;
    VectorMap(xd0, s.N) = s.zd;
    VectorMap(xdd0, s.N) = s.zdd;
    return MH_OK;
  });
}

// Copies the host's pattern once (the instance's own, whatever becomes of
// the host's arrays).
void ask_pattern(OpenLoop& s) {
  s.pattern_asked = true;
  const auto* service = static_cast<const mh_mechanical_pattern_service*>(
      s.host->get_service(s.host, MH_SERVICE_MECHANICAL_PATTERN));
  uint32_t columns = 0;
  const int32_t* start = nullptr;
  const int32_t* rows = nullptr;
  if (service == nullptr || service->mechanical_pattern(s.host, &columns, &start, &rows) != MH_OK ||
      columns != static_cast<uint32_t>(s.N))
    return;
  s.column_start.assign(start, start + s.N + 1);
  s.row_index.assign(rows, rows + start[s.N]);
}

// Eq. (12) as residual rows: r = M'(x) xdd - Q'(x, xd).
mh_status residual(const mh_formulation* f, const mh_unknown_values* at, double* r) noexcept {
  const double t = at->t;
  const double* x = at->x;
  const double* xd = at->xd;
  const double* xdd = at->xdd;
  return monohydra::guarded_op<OpenLoop>(f, "residual", [&](OpenLoop& s) {
    if (s.inverse != nullptr) {
      const mh_mech_request rq{sizeof(rq), MH_EVAL_SUBSYSTEMS, t, x, xd};
      return s.inverse->inverse_dynamics(s.host, &rq, xdd, r);
    }
    const mh_mech_request rq{sizeof(rq), MH_EVAL_DYNAMICS | MH_EVAL_SUBSYSTEMS, t, x, xd};
    mh_mech_result rs{};
    rs.struct_size = sizeof(rs);
    const mh_status st = s.mech->evaluate_mechanics(s.host, &rq, &rs);
    if (st >= MH_DISCARD) return st;
    const Eigen::Map<const Eigen::MatrixXd> M(rs.M, s.N, s.N);
    VectorMap rows(r, s.N);
    if (!s.pattern_asked) ask_pattern(s);
    if (s.row_index.empty()) {
      rows.noalias() = M * ConstVectorMap(xdd, s.N);
    } else {  // M' is zero off the pattern
      rows.setZero();
      for (int c = 0; c < s.N; ++c)
        for (int32_t k = s.column_start[static_cast<size_t>(c)];
             k < s.column_start[static_cast<size_t>(c) + 1]; ++k)
          rows[s.row_index[static_cast<size_t>(k)]] +=
              M(s.row_index[static_cast<size_t>(k)], c) * xdd[c];
    }
    rows -= ConstVectorMap(rs.Q, s.N);
    return st;
  });
}

// The analytic tangent at the iterate: dr/dz = K = d(M' zdd - Q')/dz,
// dr/dzd = C = -dQ'/dzd (the host's recursions, subsystem forces included),
// dr/dzdd = M' (one evaluate_mechanics). Without mech_derivatives the host
// differences every column.
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
  return monohydra::guarded_op<OpenLoop>(f, "tangent", [&](OpenLoop& s) {
    if (!monohydra::has_mech_derivatives(*s.mech)) return MH_OK;
    const mh_mech_request mrq{sizeof(mrq), MH_EVAL_DYNAMICS, t, x, xd};
    mh_mech_result rs{};
    rs.struct_size = sizeof(rs);
    const mh_status mst = s.mech->evaluate_mechanics(s.host, &mrq, &rs);
    if (mst >= MH_DISCARD) return mst;
    const Eigen::Map<const Eigen::MatrixXd> M(rs.M, s.N, s.N);
    if (!s.pattern_asked) ask_pattern(s);
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
    using MatrixMap = Eigen::Map<Eigen::MatrixXd>;
    using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd>;
    if (s.row_index.empty()) {
      MatrixMap(dr_dx, s.N, s.N) = ConstMatrixMap(d.K, s.N, s.N);
      MatrixMap(dr_dxd, s.N, s.N) = ConstMatrixMap(d.C, s.N, s.N);
      MatrixMap(dr_dxdd, s.N, s.N) = M;
    } else {  // the host reads the blocks on the pattern only
      for (int c = 0; c < s.N; ++c)
        for (int32_t k = s.column_start[static_cast<size_t>(c)];
             k < s.column_start[static_cast<size_t>(c) + 1]; ++k) {
          const int i = s.row_index[static_cast<size_t>(k)];
          const size_t e =
              static_cast<size_t>(c) * static_cast<size_t>(s.N) + static_cast<size_t>(i);
          dr_dx[e] = d.K[e];
          dr_dxd[e] = d.C[e];
          dr_dxdd[e] = M(i, c);
        }
    }
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
  return monohydra::guarded_op<OpenLoop>(f, "mechanics_map", [&](OpenLoop& s) {
    for (int i = 0; i < s.N; ++i) {
      const size_t d = static_cast<size_t>(i) * static_cast<size_t>(s.N) + static_cast<size_t>(i);
      if (dz_dx != nullptr) dz_dx[d] = 1.0;
      if (dzd_dxd != nullptr) dzd_dxd[d] = 1.0;
      dr_dQ[d] = -1.0;
    }
    return MH_OK;
  });
}

// The step converged: its z, zd, zdd are the accepted state (no correction).
mh_status accept(const mh_formulation* f, double, const mh_step_coefficients*,
                 const mh_unknown_buffers* values, uint32_t*) noexcept {
  double* x = values->x;
  double* xd = values->xd;
  double* xdd = values->xdd;
  return monohydra::guarded_op<OpenLoop>(f, "accept", [&](OpenLoop& s) {
    s.z = ConstVectorMap(x, s.N);
    s.zd = ConstVectorMap(xd, s.N);
    s.zdd = ConstVectorMap(xdd, s.N);
    return MH_OK;
  });
}

mh_status coordinates(const mh_formulation* f, const mh_coordinate_buffers* out) noexcept {
  double* z = out->z;
  double* zd = out->zd;
  double* zdd = out->zdd;
  return monohydra::guarded_op<OpenLoop>(f, "coordinates", [&](OpenLoop& s) {
    VectorMap(z, s.N) = s.z;
    VectorMap(zd, s.N) = s.zd;
    VectorMap(zdd, s.N) = s.zdd;
    return MH_OK;
  });
}

// The unknowns are the coordinates, coupled as the mechanics couple them
// (MH_EXT_COORDINATE_UNKNOWNS): the host's tangent is sparse for trees. The
// rows are Eq. (12) alone (MH_EXT_EQUATIONS_OF_MOTION): the host may solve
// Newton's system by the articulated-body recursion. Its state saves and
// loads (MH_EXT_STATE).
const char kCoordinateUnknowns = 1;
const void* get_extension(const mh_formulation*, const char* id) noexcept {
  if (id == nullptr) return nullptr;
  if (std::strcmp(id, MH_EXT_COORDINATE_UNKNOWNS) == 0) return &kCoordinateUnknowns;
  if (std::strcmp(id, MH_EXT_EQUATIONS_OF_MOTION) == 0) return &kCoordinateUnknowns;
  if (std::strcmp(id, MH_EXT_INITIAL_STATE_AT_START) == 0) return &kCoordinateUnknowns;
  if (std::strcmp(id, MH_EXT_STATE) == 0)
    return monohydra::state_extension<mh_formulation, OpenLoop>();
  return nullptr;
}

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "open-loop",
    "Open-loop semirecursive formulation",
    "monohydra",
    "2.0.0",
    "Trees of revolute and prismatic joints without cut joints: M' zdd = Q' (Eq. 12) with the "
    "joint coordinates as second-order unknowns of the host's integrator. Option: tolerance."};

// The instance's operations; every instance gets a copy with its own state.
const mh_formulation kOps = [] {
  mh_formulation f{};
  f.struct_size = sizeof(mh_formulation);
  f.descriptor = &kDescriptor;
  f.setup = setup;
  f.start = start;
  f.begin_step = nullptr;  // nothing to reset: the residual has no history
  f.residual = residual;
  f.tangent = tangent;
  f.iteration_done = nullptr;
  f.accept = accept;
  f.coordinates = coordinates;
  f.write_outputs = nullptr;
  f.destroy = monohydra::destroy_formulation<OpenLoop>;
  f.get_extension = get_extension;
  f.mechanics_map = mechanics_map;
  return f;
}();

const mh_formulation* create(const mh_host* host) {
  return monohydra::create_formulation<OpenLoop>(host, kOps);
}

}  // namespace

MONOHYDRA_FORMULATION_PLUGIN(kDescriptor, create);
