// The double-step semirecursive formulation (Sect. 2.2 and Sect. 4): coordinate
// partitioning. Full pivoting on Phi_z picks the f independent coordinates z^i
// (the Newton unknowns x = z^i, second order: the host's integrator ties
// xd = zd^i and xdd = zdd^i to them, by default the trapezoidal rule, Eqs.
// 32-34); every residual evaluation then takes two steps: the dependent
// coordinates z^d from Phi(z) = 0 by Newton-Raphson, then the reduced
// equations of motion M'' zdd^i = Q'' (Eq. 17), the rows r = M'' zdd^i - Q''
// (Eq. 38 without its dt^2/4). Outputs: independent1..independent_f (the
// 1-based index of each independent coordinate in use) and repartitions.
//
// Files: coordinate_partition.* (the choice of z^i and of the rows kept),
// dependent_coordinates.* (Newton on Phi(z) = 0), velocity_transformation.*
// (Eqs. 13-17), this file (options, the step's operations, entry point).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "coordinate_partition.hpp"
#include "dependent_coordinates.hpp"
#include "eigen.hpp"
#include "host_calls.hpp"
#include "lu_substitution.hpp"
#include "monohydra/constrained.h"
#include "monohydra/cpp/formulation_plugin.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/state.hpp"
#include "monohydra/monohydra.h"
#include "velocity_transformation.hpp"

namespace mh::double_step {
namespace {

// Defaults of the options (docs/formulations-double-step.md gives the reasons).
// The dependent Newton stops on an increment this small (rad or m): below the
// host's forward-difference increment (>= 1e-10, Eq. 41) by the quadratic
// convergence, so z^d is at round-off and the residual is smooth in x.
constexpr double kDefaultPositionTolerance = 1e-10;
constexpr int kDefaultMaxPositionIterations = 20;
// Re-partition when the pivot ratio of Phi_z^d falls below this: early enough
// that a limit position cannot be crossed within one 1 ms step unseen.
constexpr double kDefaultRepartitionRcond = 0.1;

// A re-partition must improve the pivot ratio of Phi_z^d at least this much.
constexpr double kRepartitionGain = 2.0;

// The formulation's options (setup).
struct DoubleStepSettings {
  double tolerance = 0.0;  // on x = z^i: the option, else the model's position tolerance
  double position_tolerance = kDefaultPositionTolerance;
  int max_position_iterations = kDefaultMaxPositionIterations;
  double repartition_rcond = kDefaultRepartitionRcond;
  std::string independent_option;  // the user's initial z^i, when given
};

// The coordinate partition in use and the factorizations that choose and
// check it (Sect. 2.2).
struct Partitioning {
  Partition partition, candidate;
  Eigen::FullPivLU<Eigen::MatrixXd> full_lu;   // m x N: Phi_z, for (re-)partitioning
  Eigen::FullPivLU<Eigen::MatrixXd> block_lu;  // r x r: Phi_z^d, its conditioning
  Eigen::MatrixXd block;                       // r x r: a candidate's Phi_z^d
  bool ill_conditioned_reported = false;
  // Sign of det Phi_z^d at the accepted state (0: none yet). det Phi_z^d is
  // continuous in z for a fixed partition, so a sign change within a step means
  // the step crossed a configuration where this partition is singular.
  double det_sign = 0.0;
  int repartitions = 0;
};

// The last evaluated iterate of the step (residual).
struct DoubleStepIterate {
  Eigen::VectorXd z_pred;               // N: z_k + zd_k h + zdd_k h^2 / 2
  Eigen::VectorXd z_it, zd_it, zdd_it;  // N: at the last evaluated iterate
  Eigen::VectorXd x_it, xd_it, xdd_it;  // f: that iterate's x, xd, xdd
  double t_it = 0.0;                    // and its time
  Eigen::VectorXd zdd_i;                // f: scratch
  Eigen::VectorXd dx_i, z_est;          // f, N: the dependent coordinates' estimate
  bool iterate_valid = false;
  // M' and Q' of the last iterate (N x N, N), kept for the analytic tangent.
  Eigen::MatrixXd M_prime;
  Eigen::VectorXd Q_prime;
};

// The derivatives of the last iterate (derivatives()): how z, zd and zdd
// move with x at fixed xd, xdd (dz/dx = R_z, dzd_dx, dzdd_dx) and with xd
// (dzd/dxd = R_z, dzdd_dxd), N x f each, zero on the independent rows but
// R_z's identity; and the tangent blocks dr/dx, dr/dxd (f x f).
struct DoubleStepDerivatives {
  bool derivatives_valid = false;
  Eigen::MatrixXd dzd_dx, dzdd_dx, dzdd_dxd, dr_dx, dr_dxd;
  // Scratch: d(Phi_z zd)/dz, dA/dz, dA/dzd on the kept rows (r x N); products
  // with R_z (r x f, N x f); e = M' zdd - Q' (N), its multipliers (r, m).
  Eigen::MatrixXd rate_stiffness, dA_dz_kept, dA_dzd_kept, rhs_rf, work_Nf;
  Eigen::VectorXd residual_force, lambda_r, lambda_m;
  Eigen::VectorXd column_r, scratch_r;  // r
};

// Outputs: names (the host may keep the pointers) and indices.
struct DoubleStepOutputs {
  std::vector<std::string> output_names;  // independent1..independent_f
  std::vector<int32_t> independent_out;   // f
  int32_t repartitions_out = -1;
};

struct DoubleStep {
  const mh_host* host = nullptr;
  const mh_mechanism_service* mech = nullptr;  // found once, at create
  int N = 0;                                   // coordinates
  int m = 0;                                   // constraint rows
  int r = 0;                                   // rank of Phi_z: rows kept, dependent coordinates
  int f = 0;         // degrees of freedom: independent coordinates, Newton unknowns
  double t0 = 0.0;   // the initial time (mech_info)
  double t_k = 0.0;  // the last accepted time (start, accept)
  std::vector<std::string> names;
  std::vector<bool> is_angle;
  Eigen::VectorXd z0, zd0;     // N: the host's assembled initial state (mech_info)
  Eigen::VectorXd z, zd, zdd;  // accepted at t_k, all N coordinates
  DependentCoordinates dependent;
  VelocityTransformation transform;

  DoubleStepSettings settings;
  Partitioning partitioning;
  DoubleStepIterate iterate;
  DoubleStepDerivatives derivs;
  DoubleStepOutputs outputs;

  // What a step reads of the last one (MH_EXT_STATE, monohydra/cpp/state.hpp):
  // the accepted coordinates and the partition in use, with its history.
  template <class Archive>
  void state(Archive& a) {
    a(t_k);
    a(z);
    a(zd);
    a(zdd);
    a(partitioning.partition.rows);
    a(partitioning.partition.dependent);
    a(partitioning.partition.independent);
    a(partitioning.det_sign);
    a(partitioning.repartitions);
    a(partitioning.ill_conditioned_reported);
  }
  std::string state_loaded();
};

// A loaded partition must split 0..N-1 into r dependent and f independent
// coordinates, each list ascending, and keep r distinct rows of 0..m-1.
std::string DoubleStep::state_loaded() {
  const Partition& p = partitioning.partition;
  const auto ascending_in = [](const std::vector<int>& v, int end) {
    for (size_t k = 0; k < v.size(); ++k)
      if (v[k] < 0 || v[k] >= end || (k > 0 && v[k] <= v[k - 1])) return false;
    return true;
  };
  std::vector<char> seen(static_cast<size_t>(N), 0);
  for (const int i : p.dependent)
    if (i >= 0 && i < N) seen[static_cast<size_t>(i)] = 1;
  bool disjoint = true;
  for (const int i : p.independent)
    disjoint = disjoint && i >= 0 && i < N && seen[static_cast<size_t>(i)] == 0;
  if (!ascending_in(p.rows, m) || !ascending_in(p.dependent, N) ||
      !ascending_in(p.independent, N) || !disjoint)
    return "its coordinate partition is not one of this mechanism's " + std::to_string(N) +
           " coordinates and " + std::to_string(m) + " constraint rows";
  transform.set_partition(p);
  // At a step's end the last iterate is the accepted state (accept): the
  // next step's positions-only evaluations pass its rates.
  iterate.z_it = z;
  iterate.zd_it = zd;
  iterate.zdd_it = zdd;
  iterate.iterate_valid = false;
  derivs.derivatives_valid = false;
  return "";
}

DoubleStep& self(const mh_formulation* f) {
  return *static_cast<DoubleStep*>(f->plugin_data);
}

void log_error(const DoubleStep& s, const std::string& message) {
  log(s.host, MH_LOG_ERROR, message);
}

// Runs an operation with no exception crossing the C boundary.
template <class Op>
mh_status guarded(const DoubleStep& s, const char* what, Op&& op) noexcept {
  return monohydra::guarded(s.host, what, std::forward<Op>(op));
}

// ---------------------------------------------------------------- setup ----

mh_status read_options(DoubleStep& s) {
  const mh_host* h = s.host;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (monohydra::options(h).option_number(h, "tolerance", 0, nan, &s.settings.tolerance) != MH_OK)
    return MH_ERROR;
  if (!std::isnan(s.settings.tolerance) && !(s.settings.tolerance > 0.0))
    return monohydra::options(h).option_error(h, "tolerance", "a positive number (rad or m)");
  if (monohydra::options(h).option_number(h, "position_tolerance", 0, kDefaultPositionTolerance,
                                          &s.settings.position_tolerance) != MH_OK)
    return MH_ERROR;
  if (!(s.settings.position_tolerance > 0.0))
    return monohydra::options(h).option_error(h, "position_tolerance",
                                              "a positive number (rad or m)");
  double iterations = kDefaultMaxPositionIterations;
  if (monohydra::options(h).option_number(h, "max_position_iterations", 0, iterations,
                                          &iterations) != MH_OK)
    return MH_ERROR;
  if (!(iterations >= 1.0 && iterations <= 1000.0 && iterations == std::floor(iterations)))
    return monohydra::options(h).option_error(h, "max_position_iterations",
                                              "an integer from 1 to 1000");
  s.settings.max_position_iterations = static_cast<int>(iterations);
  if (monohydra::options(h).option_number(h, "repartition_rcond", 0, kDefaultRepartitionRcond,
                                          &s.settings.repartition_rcond) != MH_OK)
    return MH_ERROR;
  if (!(s.settings.repartition_rcond > kRankThreshold && s.settings.repartition_rcond < 1.0))
    return monohydra::options(h).option_error(h, "repartition_rcond",
                                              "a number between 1e-8 and 1");
  const char* independent = "";
  if (monohydra::options(h).option_string(h, "independent_coordinates", 0, "", &independent) !=
      MH_OK)
    return MH_ERROR;
  s.settings.independent_option = independent != nullptr ? independent : "";
  return MH_OK;
}

// The option independent_coordinates ("z3" or "z2, z5") as coordinate indices;
// false after reporting the option error.
bool parse_independent(DoubleStep& s, std::vector<int>& out) {
  const char* key = "independent_coordinates";
  std::string all;
  for (const auto& n : s.names) all += (all.empty() ? "" : ", ") + n;
  const std::string expected = std::to_string(s.f) + " of the coordinates " + all +
                               ", separated by commas (the mechanism has " + std::to_string(s.f) +
                               (s.f == 1 ? " degree of freedom)" : " degrees of freedom)");
  std::string token;
  const std::string& text = s.settings.independent_option;
  for (size_t i = 0; i <= text.size(); ++i) {
    const char c = i < text.size() ? text[i] : ',';
    if (c != ',' && c != ' ' && c != '\t') {
      token += c;
      continue;
    }
    if (token.empty()) continue;
    const auto it = std::find(s.names.begin(), s.names.end(), token);
    if (it == s.names.end() ||
        std::find(out.begin(), out.end(), static_cast<int>(it - s.names.begin())) != out.end()) {
      monohydra::options(s.host).option_error(s.host, key, expected.c_str());
      return false;
    }
    out.push_back(static_cast<int>(it - s.names.begin()));
    token.clear();
  }
  if (static_cast<int>(out.size()) != s.f) {
    monohydra::options(s.host).option_error(s.host, key, expected.c_str());
    return false;
  }
  return true;
}

void size_buffers(DoubleStep& s) {
  for (Eigen::VectorXd* v : {&s.z, &s.zd, &s.zdd, &s.iterate.z_pred, &s.iterate.z_it,
                             &s.iterate.zd_it, &s.iterate.zdd_it})
    v->setZero(s.N);
  for (Eigen::VectorXd* v :
       {&s.iterate.x_it, &s.iterate.xd_it, &s.iterate.xdd_it, &s.iterate.zdd_i, &s.iterate.dx_i})
    v->setZero(s.f);
  s.iterate.z_est.setZero(s.N);
  s.dependent.resize(s.m, s.N, s.r);
  s.transform.resize(s.N, s.r);
  s.transform.set_partition(s.partitioning.partition);
  s.partitioning.block_lu = Eigen::FullPivLU<Eigen::MatrixXd>(s.r, s.r);
  s.partitioning.block.setZero(s.r, s.r);
  s.iterate.M_prime.setZero(s.N, s.N);
  s.iterate.Q_prime.setZero(s.N);
  for (Eigen::MatrixXd* a :
       {&s.derivs.dzd_dx, &s.derivs.dzdd_dx, &s.derivs.dzdd_dxd, &s.derivs.work_Nf})
    a->setZero(s.N, s.f);
  s.derivs.dr_dx.setZero(s.f, s.f);
  s.derivs.dr_dxd.setZero(s.f, s.f);
  for (Eigen::MatrixXd* a : {&s.derivs.rate_stiffness, &s.derivs.dA_dz_kept, &s.derivs.dA_dzd_kept})
    a->setZero(s.r, s.N);
  s.derivs.rhs_rf.setZero(s.r, s.f);
  s.derivs.residual_force.setZero(s.N);
  s.derivs.lambda_r.setZero(s.r);
  s.derivs.lambda_m.setZero(s.m);
  s.derivs.column_r.setZero(s.r);
  s.derivs.scratch_r.setZero(s.r);
  size_partition(s.partitioning.candidate, s.N, s.r);
}

// The unknowns x = z^i (second order, named after the coordinates chosen now)
// and the outputs.
mh_status declare(DoubleStep& s) {
  for (int k = 0; k < s.f; ++k) {
    const auto i =
        static_cast<size_t>(s.partitioning.partition.independent[static_cast<size_t>(k)]);
    const mh_unknown_spec spec =
        monohydra::unknown_spec(s.names[i].c_str(), s.is_angle[i] ? "rad" : "m",
                                MH_UNKNOWN_SECOND_ORDER, s.settings.tolerance);
    int32_t index = -1;
    if (monohydra::unknowns(s.host).add_unknown(s.host, &spec, &index) != MH_OK) return MH_ERROR;
  }
  s.outputs.output_names.clear();
  for (int k = 1; k <= s.f; ++k)
    s.outputs.output_names.push_back("independent" + std::to_string(k));
  s.outputs.independent_out.assign(static_cast<size_t>(s.f), -1);
  for (size_t k = 0; k < s.outputs.independent_out.size(); ++k) {
    const mh_output_spec spec =
        monohydra::output_spec(s.outputs.output_names[k].c_str(), "", MH_OUTPUT_COORDINATE);
    if (monohydra::outputs(s.host).add_output(s.host, &spec, &s.outputs.independent_out[k]) !=
        MH_OK)
      return MH_ERROR;
  }
  const mh_output_spec spec = monohydra::output_spec("repartitions", "", MH_OUTPUT_COUNTER);
  return monohydra::outputs(s.host).add_output(s.host, &spec, &s.outputs.repartitions_out);
}

mh_status setup(const mh_formulation* fo) noexcept {
  DoubleStep& s = self(fo);
  return guarded(s, "setup", [&]() -> mh_status {
    mh_mech_info info{};
    info.struct_size = sizeof(info);
    if (monohydra::mechanism(s.host).mech_info(s.host, &info) != MH_OK) {
      log_error(s, "the host did not describe the mechanism (mech_info failed)");
      return MH_ERROR;
    }
    s.N = static_cast<int>(info.num_coordinates);
    s.m = static_cast<int>(info.num_constraints);
    if (read_options(s) != MH_OK) return MH_ERROR;
    if (s.m == 0) {
      log_error(s,
                "the model has no cut joints (0 constraint rows): double-step partitions "
                "the coordinates of closed loops; use open-loop for a tree");
      return MH_ERROR;
    }
    if (info.z0 == nullptr || info.zd0 == nullptr || info.coordinate_names == nullptr ||
        info.coordinate_is_angle == nullptr) {
      log_error(s,
                "the host gave no assembled initial coordinates (mech_info z0, zd0): "
                "they are needed to choose the independent coordinates");
      return MH_ERROR;
    }
    s.names.assign(info.coordinate_names, info.coordinate_names + s.N);
    s.is_angle.assign(info.coordinate_is_angle, info.coordinate_is_angle + s.N);
    s.t0 = info.t0;
    s.z0 = Eigen::Map<const Eigen::VectorXd>(info.z0, s.N);
    s.zd0 = Eigen::Map<const Eigen::VectorXd>(info.zd0, s.N);
    if (std::isnan(s.settings.tolerance))
      s.settings.tolerance = info.position_tolerance;  // the default

    // Full pivoting on Phi_z(z0) chooses z^d and z^i (Sect. 2.2).
    mh_mech_result rs{};
    const mh_status st =
        evaluate(s.host, *s.mech, MH_EVAL_CONSTRAINTS, s.t0, info.z0, info.zd0, rs);
    if (st >= MH_DISCARD) return st;
    s.partitioning.full_lu = Eigen::FullPivLU<Eigen::MatrixXd>(s.m, s.N);
    s.r = factor_full_pivoting(Eigen::Map<const Eigen::MatrixXd>(rs.phi_z, s.m, s.N),
                               s.partitioning.full_lu);
    if (s.r == 0) {
      log_error(s,
                "the constraint Jacobian Phi_z vanishes at the initial configuration: "
                "no coordinate is constrained");
      return MH_ERROR;
    }
    if (s.r == s.N) {
      log_error(s, "the " + std::to_string(s.m) + " constraint rows fix all " +
                       std::to_string(s.N) +
                       " coordinates (rank N): the mechanism has no degree of freedom");
      return MH_ERROR;
    }
    s.f = s.N - s.r;
    size_partition(s.partitioning.partition, s.N, s.r);
    partition_from_pivots(s.partitioning.full_lu, s.r, s.partitioning.partition);
    std::string origin;
    if (!s.settings.independent_option.empty()) {
      // The user's choice replaces full pivoting's, if Phi_z^d is invertible.
      std::vector<int> chosen;
      if (!parse_independent(s, chosen)) return MH_ERROR;
      const std::string pivoting = coordinate_list(s.partitioning.partition.independent, s.names);
      const double ratio = partition_with_independent(
          Eigen::Map<const Eigen::MatrixXd>(rs.phi_z, s.m, s.N), chosen, s.partitioning.partition);
      if (!(ratio > kRankThreshold))
        return monohydra::options(s.host).option_error(
            s.host, "independent_coordinates",
            ("coordinates whose complement makes Phi_z^d invertible at the initial "
             "configuration (with these, Phi_z^d is singular; full pivoting picks " +
             pivoting + ")")
                .c_str());
      origin = " (from the option independent_coordinates; full pivoting picks " + pivoting + ")";
    }
    if (s.r < s.m)
      log(s.host, MH_LOG_WARNING,
          "redundant constraints: using " + std::to_string(s.r) + " of " + std::to_string(s.m) +
              " rows (" + (s.m - s.r == 1 ? "row " : "rows ") +
              dropped_rows(s.partitioning.partition.rows, s.m) + " dropped)");
    log(s.host, MH_LOG_INFO,
        "independent coordinates: " +
            coordinate_list(s.partitioning.partition.independent, s.names) + origin);
    size_buffers(s);
    return declare(s);
  });
}

// ----------------------------------------------------- the two steps ----

// Why the dependent Newton failed, for the log.
std::string dependent_failure(const DoubleStep& s, const DependentSolveResult& res, double t) {
  const std::string where = " at t = " + short_number(t) + " s with independent coordinates " +
                            coordinate_list(s.partitioning.partition.independent, s.names);
  if (res.outcome == DependentSolveResult::Outcome::singular)
    return "Phi_z^d is singular" + where + " (pivot ratio " + short_number(res.pivot_ratio) +
           " after " + std::to_string(res.iterations) +
           " iterations, max |Phi| = " + short_number(res.residual) + ")";
  return "the dependent coordinates did not converge" + where + ": " +
         std::to_string(res.iterations) +
         " Newton iterations, max |Phi| = " + short_number(res.residual) + ", last increment " +
         short_number(res.increment) + " (tolerance " +
         short_number(s.settings.position_tolerance) + ")";
}

// With z_it and zd_it set on z^i and z_it on z^d set to the estimate: z^d by
// Newton, zd^d (Eq. 13), R_z (Eq. 14), one evaluation of M', Q' with `flags`
// added, Rdot_z zd^i (Eq. 15) and M'', Q'' (Eq. 17).
mh_status two_steps(DoubleStep& s, double t, uint32_t flags) {
  const DependentSolveResult res =
      s.dependent.solve(s.host, *s.mech, t, s.partitioning.partition, s.settings.position_tolerance,
                        s.settings.max_position_iterations, s.iterate.z_it, s.iterate.zd_it);
  if (res.outcome == DependentSolveResult::Outcome::host_failed) return res.host_status;
  if (res.outcome != DependentSolveResult::Outcome::converged) {
    // At error level so the host's failure message carries the reason.
    log_error(s, dependent_failure(s, res, t));
    return MH_DISCARD;
  }
  const double det = s.dependent.lu().determinant();
  if (s.partitioning.det_sign != 0.0 && !(det * s.partitioning.det_sign > 0.0)) {
    log_error(s, "the step to t = " + short_number(t) +
                     " s crosses a configuration where the partition with independent "
                     "coordinates " +
                     coordinate_list(s.partitioning.partition.independent, s.names) +
                     " is singular (det Phi_z^d changed sign): the re-partition check "
                     "(repartition_rcond = " +
                     short_number(s.settings.repartition_rcond) +
                     ") came too late; raise it or shorten the step");
    return MH_DISCARD;
  }
  s.transform.rates(s.dependent.lu(), s.dependent.phi_z_i(), s.partitioning.partition,
                    s.iterate.zd_it);
  mh_mech_result rs{};
  const mh_status st = evaluate(s.host, *s.mech, MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS | flags, t,
                                s.iterate.z_it.data(), s.iterate.zd_it.data(), rs);
  if (st >= MH_DISCARD) return st;
  // The velocity-product term at the full zd just completed.
  s.transform.velocity_term(s.dependent.lu(), rs.phi_dot_zd, s.partitioning.partition);
  s.transform.reduce(rs.M, rs.Q);
  s.iterate.M_prime = Eigen::Map<const Eigen::MatrixXd>(rs.M, s.N, s.N);  // for the tangent
  s.iterate.Q_prime = Eigen::Map<const Eigen::VectorXd>(rs.Q, s.N);
  return MH_OK;
}

// The iterate x = z^i with the integrator's xd = zd^i, xdd = zdd^i (Eq. 33 for
// the trapezoidal rule), z^d from the step's estimate, then the two steps and
// zdd^d (Eq. 15).
mh_status evaluate_iterate(DoubleStep& s, double t, const double* x, const double* xd,
                           const double* xdd, uint32_t flags) {
  // The dependent entries start from the best estimate: within a step, the
  // last iterate's z moved along its tangent R_z (Eq. 14) to this x (a
  // difference column's x is 1e-8 away, a Newton update's close); else the
  // step's prediction.
  if (s.iterate.iterate_valid) {
    s.iterate.dx_i = Eigen::Map<const Eigen::VectorXd>(x, s.f) - s.iterate.x_it;
    s.iterate.z_est.noalias() = s.transform.R_z().lazyProduct(s.iterate.dx_i);
    s.iterate.z_it += s.iterate.z_est;
  } else {
    s.iterate.z_it = s.iterate.z_pred;
  }
  s.iterate.iterate_valid = false;
  s.derivs.derivatives_valid = false;
  s.iterate.t_it = t;
  for (int k = 0; k < s.f; ++k) {
    const int i = s.partitioning.partition.independent[static_cast<size_t>(k)];
    s.iterate.z_it[i] = x[k];
    s.iterate.zd_it[i] = xd[k];
    s.iterate.zdd_it[i] = xdd[k];
  }
  const mh_status st = two_steps(s, t, flags);
  if (st >= MH_DISCARD) return st;
  s.transform.accelerations(s.partitioning.partition, s.iterate.zdd_it);  // Eq. (15)
  s.iterate.x_it = Eigen::Map<const Eigen::VectorXd>(x, s.f);
  s.iterate.xd_it = Eigen::Map<const Eigen::VectorXd>(xd, s.f);
  s.iterate.xdd_it = Eigen::Map<const Eigen::VectorXd>(xdd, s.f);
  s.iterate.iterate_valid = true;
  return MH_OK;
}

// True when the last evaluated iterate was at (x, xd, xdd).
bool is_last_iterate(const DoubleStep& s, const double* x, const double* xd, const double* xdd) {
  using Map = Eigen::Map<const Eigen::VectorXd>;
  return s.iterate.iterate_valid && s.iterate.x_it == Map(x, s.f) &&
         s.iterate.xd_it == Map(xd, s.f) && s.iterate.xdd_it == Map(xdd, s.f);
}

// x, xd, xdd (f each) from the accepted z, zd, zdd on the current partition.
void write_unknowns(const DoubleStep& s, double* x, double* xd, double* xdd) {
  for (int k = 0; k < s.f; ++k) {
    const int i = s.partitioning.partition.independent[static_cast<size_t>(k)];
    x[k] = s.z[i];
    xd[k] = s.zd[i];
    xdd[k] = s.zdd[i];
  }
}

// ------------------------------------------------------------- start ----

mh_status start(const mh_formulation* fo, const mh_unknown_buffers* out) noexcept {
  double* x0 = out->x;
  double* xd0 = out->xd;
  double* xdd0 = out->xdd;
  DoubleStep& s = self(fo);
  return guarded(s, "start", [&]() -> mh_status {
    // Consistent initial state on this partition: z^d from Phi(z) = 0 with
    // z^i = z0^i (the host assembled z0, so this only polishes it), zd^d by
    // Eq. (13), then zdd^i from M'' zdd^i = Q'' (Eq. 17) and zdd^d by Eq. (15).
    s.partitioning.det_sign = 0.0;  // no reference yet
    // The host's initial state now, not setup's copy of it
    // (MH_EXT_INITIAL_STATE_AT_START): an initial coordinate may be a parameter.
    mh_mech_info info{};
    info.struct_size = sizeof(info);
    if (s.mech->mech_info(s.host, &info) != MH_OK || info.z0 == nullptr || info.zd0 == nullptr) {
      log_error(s, "start: the host gave no assembled initial coordinates (mech_info z0, zd0)");
      return MH_ERROR;
    }
    s.z0 = Eigen::Map<const Eigen::VectorXd>(info.z0, s.N);
    s.zd0 = Eigen::Map<const Eigen::VectorXd>(info.zd0, s.N);
    s.iterate.z_it = s.z0;
    s.iterate.zd_it = s.zd0;
    const mh_status st = two_steps(s, s.t0, 0u);
    if (st >= MH_DISCARD) {
      log_error(s, "the initial state is not consistent on the chosen partition");
      return MH_ERROR;
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(s.transform.M_reduced());
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
      log_error(s,
                "the reduced mass matrix M'' = R_z^T M' R_z is singular at the initial "
                "state (a massless chain of bodies?)");
      return MH_ERROR;
    }
    s.iterate.zdd_i = ldlt.solve(s.transform.Q_reduced());  // Eq. (17)
    for (int k = 0; k < s.f; ++k)
      s.iterate.zdd_it[s.partitioning.partition.independent[static_cast<size_t>(k)]] =
          s.iterate.zdd_i[k];
    s.transform.accelerations(s.partitioning.partition, s.iterate.zdd_it);  // Eq. (15)
    const double moved = (s.iterate.z_it - s.z0).lpNorm<Eigen::Infinity>();
    if (moved > s.settings.tolerance)
      log(s.host, MH_LOG_INFO,
          "start: dependent coordinates moved by up to " + short_number(moved) +
              " to close the loops");
    s.z = s.iterate.z_it;
    s.zd = s.iterate.zd_it;
    s.zdd = s.iterate.zdd_it;
    s.iterate.iterate_valid = false;
    s.partitioning.ill_conditioned_reported = false;
    s.partitioning.det_sign = s.dependent.lu().determinant() > 0.0 ? 1.0 : -1.0;
    s.t_k = s.t0;
    s.partitioning.repartitions = 0;
    write_unknowns(s, x0, xd0, xdd0);
    return MH_OK;
  });
}

// ------------------------------------------------------------ the step ----

// The step to t_next begins from the accepted state at t_k: the estimate of
// z_{k+1} the dependent Newton starts from (after Eq. 34), with h = t_next - t_k.
mh_status begin_step(const mh_formulation* fo, const mh_step_begin* step) noexcept {
  const double t_next = step->predicted.t;
  DoubleStep& s = self(fo);
  return guarded(s, "begin_step", [&]() -> mh_status {
    const double h = t_next - s.t_k;
    s.iterate.z_pred = s.z + h * s.zd + (0.5 * h * h) * s.zdd;
    s.iterate.iterate_valid = false;
    return MH_OK;
  });
}

mh_status residual(const mh_formulation* fo, const mh_unknown_values* at, double* r) noexcept {
  const double t = at->t;
  const double* x = at->x;
  const double* xd = at->xd;
  const double* xdd = at->xdd;
  DoubleStep& s = self(fo);
  return guarded(s, "residual", [&]() -> mh_status {
    const mh_status st = evaluate_iterate(s, t, x, xd, xdd, MH_EVAL_SUBSYSTEMS);
    if (st >= MH_DISCARD) return st;
    for (int k = 0; k < s.f; ++k)
      s.iterate.zdd_i[k] =
          s.iterate.zdd_it[s.partitioning.partition.independent[static_cast<size_t>(k)]];
    // Eq. (17) as rows (Eq. 38 without dt^2/4): M'' zdd^i - Q''.
    Eigen::Map<Eigen::VectorXd> rows(r, s.f);
    rows.noalias() = s.transform.M_reduced().lazyProduct(s.iterate.zdd_i);
    rows -= s.transform.Q_reduced();
    return MH_OK;
  });
}

// -dep rows of (Phi_z^d)^{-1} rhs (r x f) into the dependent rows of out (N x f).
void solve_dependent_rows(DoubleStep& s, const Eigen::MatrixXd& rhs, Eigen::MatrixXd& out) {
  for (int c = 0; c < s.f; ++c) {
    s.derivs.column_r = -rhs.col(c);
    lu_solve_in_place(s.dependent.lu(), s.derivs.column_r, s.derivs.scratch_r);
    for (int k = 0; k < s.r; ++k)
      out(s.partitioning.partition.dependent[static_cast<size_t>(k)], c) = s.derivs.column_r[k];
  }
}

// The derivatives of the last iterate's z, zd, zdd and rows r = R_z^T e,
// e = M' zdd - Q' (Eq. 17 with Eq. 15's zdd), from the host's recursions
//, no differences. With z = z(x) on Phi(z) = 0 and the kept rows of
// Phi_z zd = 0 and A = Phi_z zdd + Phi_z_dot zd = 0 (Eqs. 13-15):
//   dz/dx = R_z,  Phi_z^d dzd^d/dx = -G R_z,  G = d(Phi_z zd)/dz,
//   Phi_z^d dzdd^d/dx = -(dA/dz R_z + dA/dzd dzd/dx),
//   Phi_z^d dzdd^d/dxd = -dA/dzd R_z  (dzd/dxd = R_z, dzdd/dxdd = R_z);
// and R_z's own derivative, from Phi_z R_z = 0: (dR_z/dx_k)^T e =
// -R_z^T S R_z e_k with S = d(Phi_z^T lambda)/dz, Phi_z^d^T lambda = e^d. So
//   dr/dx   = R_z^T ((K - S) R_z + C dzd/dx + M' dzdd/dx),
//   dr/dxd  = R_z^T (C R_z + M' dzdd/dxd),
//   dr/dxdd = R_z^T M' R_z = M''.
mh_status derivatives(DoubleStep& s) {
  if (s.derivs.derivatives_valid) return MH_OK;
  const Eigen::MatrixXd& R = s.transform.R_z();
  const Partition& p = s.partitioning.partition;
  // lambda on the kept rows from e^d, zero on dropped ones.
  s.derivs.residual_force.noalias() = s.iterate.M_prime * s.iterate.zdd_it;
  s.derivs.residual_force -= s.iterate.Q_prime;
  for (int k = 0; k < s.r; ++k)
    s.derivs.lambda_r[k] = s.derivs.residual_force[p.dependent[static_cast<size_t>(k)]];
  lu_solve_transpose_in_place(s.dependent.lu(), s.derivs.lambda_r, s.derivs.scratch_r);
  s.derivs.lambda_m.setZero();
  for (int a = 0; a < s.r; ++a)
    s.derivs.lambda_m[p.rows[static_cast<size_t>(a)]] = s.derivs.lambda_r[a];

  mh_mech_derivatives_request rq{};
  rq.struct_size = sizeof(rq);
  rq.flags = MH_DERIV_DYNAMICS | MH_DERIV_CONSTRAINT_FORCES | MH_DERIV_CONSTRAINT_ACCELERATIONS;
  rq.t = s.iterate.t_it;
  rq.z = s.iterate.z_it.data();
  rq.zd = s.iterate.zd_it.data();
  rq.zdd = s.iterate.zdd_it.data();
  rq.v = s.derivs.lambda_m.data();
  mh_mech_derivatives d{};
  d.struct_size = sizeof(d);
  const mh_status st = s.mech->mech_derivatives(s.host, &rq, &d);
  if (st >= MH_DISCARD) return st;
  using ConstMap = Eigen::Map<const Eigen::MatrixXd>;
  const ConstMap K(d.K, s.N, s.N), C(d.C, s.N, s.N), S(d.dPhizT_v_dz, s.N, s.N);
  const ConstMap dA_dz(d.dA_dz, s.m, s.N), dA_dzd(d.dA_dzd, s.m, s.N);
  for (int a = 0; a < s.r; ++a) {
    const int row = p.rows[static_cast<size_t>(a)];
    s.derivs.dA_dz_kept.row(a) = dA_dz.row(row);
    s.derivs.dA_dzd_kept.row(a) = dA_dzd.row(row);
    for (int k = 0; k < s.r; ++k) {
      const int j = p.dependent[static_cast<size_t>(k)];
      s.derivs.rate_stiffness(a, j) = 0.5 * dA_dzd(row, j);
    }
    for (int k = 0; k < s.f; ++k) {
      const int j = p.independent[static_cast<size_t>(k)];
      s.derivs.rate_stiffness(a, j) = 0.5 * dA_dzd(row, j);
    }
  }
  // Zero on the independent rows, which a re-partition may have moved.
  s.derivs.dzd_dx.setZero();
  s.derivs.dzdd_dx.setZero();
  s.derivs.dzdd_dxd.setZero();
  s.derivs.rhs_rf.noalias() = s.derivs.rate_stiffness * R;
  solve_dependent_rows(s, s.derivs.rhs_rf, s.derivs.dzd_dx);
  s.derivs.rhs_rf.noalias() = s.derivs.dA_dz_kept * R;
  s.derivs.rhs_rf.noalias() += s.derivs.dA_dzd_kept * s.derivs.dzd_dx;
  solve_dependent_rows(s, s.derivs.rhs_rf, s.derivs.dzdd_dx);
  s.derivs.rhs_rf.noalias() = s.derivs.dA_dzd_kept * R;
  solve_dependent_rows(s, s.derivs.rhs_rf, s.derivs.dzdd_dxd);

  s.derivs.work_Nf.noalias() = K * R;
  s.derivs.work_Nf.noalias() -= S * R;
  s.derivs.work_Nf.noalias() += C * s.derivs.dzd_dx;
  s.derivs.work_Nf.noalias() += s.iterate.M_prime * s.derivs.dzdd_dx;
  s.derivs.dr_dx.noalias() = R.transpose() * s.derivs.work_Nf;
  s.derivs.work_Nf.noalias() = C * R;
  s.derivs.work_Nf.noalias() += s.iterate.M_prime * s.derivs.dzdd_dxd;
  s.derivs.dr_dxd.noalias() = R.transpose() * s.derivs.work_Nf;
  s.derivs.derivatives_valid = true;
  return MH_OK;
}

// The analytic tangent at the last residual call (derivatives()): every
// column given, so the host differences nothing mechanical. Without
// mech_derivatives the host differences every column (Eqs. 40-41).
mh_status tangent(const mh_formulation* fo, const mh_unknown_values* at,
                  const mh_tangent_blocks* blocks) noexcept {
  const double t = at->t;
  const double* x = at->x;
  const double* xd = at->xd;
  const double* xdd = at->xdd;
  double* dr_dx = blocks->dr_dx;
  double* dr_dxd = blocks->dr_dxd;
  double* dr_dxdd = blocks->dr_dxdd;
  uint8_t* column_given = blocks->column_given;
  DoubleStep& s = self(fo);
  return guarded(s, "tangent", [&]() -> mh_status {
    if (!monohydra::has_mech_derivatives(*s.mech)) return MH_OK;
    if (!is_last_iterate(s, x, xd, xdd)) {
      const mh_status st = evaluate_iterate(s, t, x, xd, xdd, 0u);
      if (st >= MH_DISCARD) return st;
    }
    const mh_status st = derivatives(s);
    if (st >= MH_DISCARD) return st;
    Eigen::Map<Eigen::MatrixXd>(dr_dx, s.f, s.f) = s.derivs.dr_dx;
    Eigen::Map<Eigen::MatrixXd>(dr_dxd, s.f, s.f) = s.derivs.dr_dxd;
    Eigen::Map<Eigen::MatrixXd>(dr_dxdd, s.f, s.f) = s.transform.M_reduced();
    std::fill(column_given, column_given + s.f, uint8_t{1});
    return MH_OK;
  });
}

// How the last residual's mechanics depended on x = z^i, so that the
// host couples the subsystems to them without differences: z = z(z^i) with
// dz/dz^i = R_z (Eq. 14), zd = R_z zd^i, the rows r = M'' zdd^i - Q'' take Q'
// as -R_z^T (Eq. 17), and at fixed zd^i the dependent rates move with z^i by
// Phi_z^d dzd^d = -(d(Phi_z zd)/dz) R_z (derivatives()).
mh_status mechanics_map(const mh_formulation* fo, const mh_mechanics_map* map) noexcept {
  double* dz_dx = map->dz_dx;
  double* dzd_dx = map->dzd_dx;
  double* dzd_dxd = map->dzd_dxd;
  double* dr_dQ = map->dr_dQ;
  DoubleStep& s = self(fo);
  return guarded(s, "mechanics_map", [&]() -> mh_status {
    if (!s.iterate.iterate_valid) {
      log_error(s, "mechanics_map: no residual was evaluated in this step");
      return MH_ERROR;
    }
    const Eigen::MatrixXd& R = s.transform.R_z();
    Eigen::Map<Eigen::MatrixXd> Q_map(dr_dQ, s.f, s.N);
    for (int k = 0; k < s.f; ++k)
      for (int j = 0; j < s.N; ++j) Q_map(k, j) = -R(j, k);
    if (dz_dx == nullptr || dzd_dx == nullptr || dzd_dxd == nullptr) return MH_OK;  // not needed
    if (!monohydra::has_mech_derivatives(*s.mech)) {
      log_error(s, "mechanics_map: the host has no mech_derivatives");
      return MH_ERROR;
    }
    const mh_status st = derivatives(s);
    if (st >= MH_DISCARD) return st;
    Eigen::Map<Eigen::MatrixXd>(dz_dx, s.N, s.f) = R;
    Eigen::Map<Eigen::MatrixXd>(dzd_dxd, s.N, s.f) = R;
    Eigen::Map<Eigen::MatrixXd>(dzd_dx, s.N, s.f) = s.derivs.dzd_dx;
    return MH_OK;
  });
}

// After an accepted step: is Phi_z^d still well conditioned? If not, choose the
// independent coordinates again by full pivoting at the accepted z;
// *changed tells whether it did.
mh_status check_partition(DoubleStep& s, double t, bool* changed) {
  *changed = false;
  s.partitioning.block_lu.compute(
      s.dependent.phi_z_d());  // at the accepted z (r x r, no reallocation)
  const double ratio = pivot_ratio(s.partitioning.block_lu);
  if (ratio >= s.settings.repartition_rcond) return MH_OK;

  mh_mech_result rs{};
  const mh_status st =
      evaluate(s.host, *s.mech, MH_EVAL_CONSTRAINTS, t, s.z.data(), s.zd.data(), rs);
  if (st >= MH_DISCARD) return st;
  const int rank = factor_full_pivoting(Eigen::Map<const Eigen::MatrixXd>(rs.phi_z, s.m, s.N),
                                        s.partitioning.full_lu);
  if (rank < s.r) {
    log_error(s, "singular configuration at t = " + short_number(t) +
                     " s: the constraint Jacobian "
                     "Phi_z has rank " +
                     std::to_string(rank) + " < " + std::to_string(s.r) +
                     ", so no choice of independent coordinates can go on (the mechanism is at a "
                     "bifurcation or a dead point)");
    return MH_ERROR;
  }
  partition_from_pivots(s.partitioning.full_lu, s.r, s.partitioning.candidate);
  // The candidate's Phi_z^d has the first r pivots of the full LU.
  const auto& LU = s.partitioning.full_lu.matrixLU();
  double lo = std::abs(LU(0, 0));
  for (int k = 1; k < s.r; ++k) lo = std::min(lo, std::abs(LU(k, k)));
  const double candidate_ratio = lo / std::abs(LU(0, 0));
  // Switch only for a clear gain: two partitions of similar conditioning
  // would otherwise take turns, one re-partition per step.
  if (s.partitioning.candidate == s.partitioning.partition ||
      !(candidate_ratio > kRepartitionGain * ratio)) {
    if (!s.partitioning.ill_conditioned_reported)
      log(s.host, MH_LOG_WARNING,
          "Phi_z^d is ill-conditioned at t = " + short_number(t) + " s (pivot ratio " +
              short_number(ratio) +
              ") but full pivoting finds no better independent coordinates than " +
              coordinate_list(s.partitioning.partition.independent, s.names) +
              "; going on with them");
    s.partitioning.ill_conditioned_reported = true;
    return MH_OK;
  }
  std::string message = "re-partitioned at t = " + short_number(t) +
                        " s: independent coordinates " +
                        coordinate_list(s.partitioning.candidate.independent, s.names) + " (were " +
                        coordinate_list(s.partitioning.partition.independent, s.names) + ")";
  if (s.r < s.m && s.partitioning.candidate.rows != s.partitioning.partition.rows)
    message += "; dropped rows " + dropped_rows(s.partitioning.candidate.rows, s.m) + " (were " +
               dropped_rows(s.partitioning.partition.rows, s.m) + ")";
  std::swap(s.partitioning.partition, s.partitioning.candidate);  // equal sizes: no allocation
  s.transform.set_partition(s.partitioning.partition);
  // The new partition's reference sign of det Phi_z^d, at the accepted z.
  const Eigen::Map<const Eigen::MatrixXd> phi_z(rs.phi_z, s.m, s.N);
  for (int a = 0; a < s.r; ++a)
    for (int k = 0; k < s.r; ++k)
      s.partitioning.block(a, k) =
          phi_z(s.partitioning.partition.rows[static_cast<size_t>(a)],
                s.partitioning.partition.dependent[static_cast<size_t>(k)]);
  s.partitioning.block_lu.compute(s.partitioning.block);
  s.partitioning.det_sign = s.partitioning.block_lu.determinant() > 0.0 ? 1.0 : -1.0;
  s.partitioning.ill_conditioned_reported = false;
  ++s.partitioning.repartitions;
  *changed = true;
  log(s.host, MH_LOG_WARNING, message);
  return MH_OK;
}

// The step converged: commit the full z, zd, zdd (the next step's estimate),
// then check the partition. A re-partition redefines the unknowns: x, xd, xdd
// become the new independent coordinates' z, zd, zdd.
mh_status accept(const mh_formulation* fo, double t, const mh_step_coefficients*,
                 const mh_unknown_buffers* values, uint32_t* flags) noexcept {
  double* x = values->x;
  double* xd = values->xd;
  double* xdd = values->xdd;
  DoubleStep& s = self(fo);
  return guarded(s, "accept", [&]() -> mh_status {
    // The host's last residual call was at the converged iterate; should it not
    // have been, evaluate it again (without the subsystems' rows: they are recorded).
    if (!is_last_iterate(s, x, xd, xdd)) {
      const mh_status st = evaluate_iterate(s, t, x, xd, xdd, 0u);
      if (st >= MH_DISCARD) return st;
    }
    s.z = s.iterate.z_it;
    s.zd = s.iterate.zd_it;
    s.zdd = s.iterate.zdd_it;
    s.t_k = t;
    s.iterate.iterate_valid = false;
    s.partitioning.det_sign = s.dependent.lu().determinant() > 0.0 ? 1.0 : -1.0;
    bool changed = false;
    const mh_status st = check_partition(s, t, &changed);
    if (st >= MH_DISCARD) return st;
    if (changed) {
      *flags |= MH_ACCEPT_REDEFINED;
      write_unknowns(s, x, xd, xdd);
    }
    return st;
  });
}

mh_status coordinates(const mh_formulation* fo, const mh_coordinate_buffers* out) noexcept {
  double* z = out->z;
  double* zd = out->zd;
  double* zdd = out->zdd;
  const DoubleStep& s = self(fo);
  return guarded(s, "coordinates", [&]() -> mh_status {
    Eigen::Map<Eigen::VectorXd>(z, s.N) = s.z;
    Eigen::Map<Eigen::VectorXd>(zd, s.N) = s.zd;
    Eigen::Map<Eigen::VectorXd>(zdd, s.N) = s.zdd;
    return MH_OK;
  });
}

// The independent coordinates in use (1-based) and the re-partitions so far.
mh_status write_outputs(const mh_formulation* fo, double* outputs, uint32_t num_outputs) noexcept {
  const DoubleStep& s = self(fo);
  return guarded(s, "write_outputs", [&]() -> mh_status {
    const auto put = [&](int32_t index, double value) {
      if (index >= 0 && static_cast<uint32_t>(index) < num_outputs) outputs[index] = value;
    };
    for (size_t k = 0; k < s.outputs.independent_out.size(); ++k)
      put(s.outputs.independent_out[k], s.partitioning.partition.independent[k] + 1.0);
    put(s.outputs.repartitions_out, s.partitioning.repartitions);
    return MH_OK;
  });
}

// Its state saves and loads (MH_EXT_STATE).
const int kInitialStateAtStart = 1;  // any non-NULL pointer

const void* get_extension(const mh_formulation*, const char* id) noexcept {
  if (id == nullptr) return nullptr;
  if (std::strcmp(id, MH_EXT_STATE) == 0)
    return monohydra::state_extension<mh_formulation, DoubleStep>();
  if (std::strcmp(id, MH_EXT_INITIAL_STATE_AT_START) == 0) return &kInitialStateAtStart;
  return nullptr;
}

// ------------------------------------------------------- entry point ----

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "double-step",
    "Double-step semirecursive formulation (coordinate partitioning)",
    "monohydra",
    "2.0.0",
    "Closed loops by coordinate partitioning (Sect. 2.2): full pivoting on Phi_z picks the "
    "independent coordinates, the second-order Newton unknowns of the host's integrator; the "
    "dependent ones come from Phi(z) = 0 by Newton-Raphson in every residual; reduced "
    "equations M'' zdd^i = Q'' (Eq. 17). Outputs: independent1..independent_f, "
    "repartitions."};

// The instance's operations; every instance gets a copy with its own state.
const mh_formulation kOps = [] {
  mh_formulation f{};
  f.struct_size = sizeof(mh_formulation);
  f.descriptor = &kDescriptor;
  f.setup = setup;
  f.start = start;
  f.begin_step = begin_step;
  f.residual = residual;
  f.tangent = tangent;  // analytic; forward differences without mech_derivatives
  f.iteration_done = nullptr;
  f.accept = accept;
  f.coordinates = coordinates;
  f.write_outputs = write_outputs;
  f.destroy = monohydra::destroy_formulation<DoubleStep>;
  f.get_extension = get_extension;
  f.mechanics_map = mechanics_map;
  return f;
}();

const mh_formulation* create(const mh_host* host) {
  return monohydra::create_formulation<DoubleStep>(host, kOps);
}

}  // namespace
}  // namespace mh::double_step

MONOHYDRA_FORMULATION_PLUGIN(mh::double_step::kDescriptor, mh::double_step::create);
