// Forward sensitivities by differentiating the discrete step (sensitivities.hpp,
// docs/identification.md). A step maps the accepted state and the
// parameters p to the next accepted state in three parts, each
// differentiated here as it is computed:
//  - the integrator's map (Eq. 33): xd = c_v x + xd_off(history), xdd = c_a
//    x + xdd_off(history), the offsets linear in the history: an instance of
//    the same integrator per parameter, fed that parameter's column instead
//    of the state, gives the column's offsets exactly;
//  - Newton's solution of r(x, xd(x), xdd(x); p) = 0 (Eq. 37): J S = -(dr/dp
//    + dr/dxd dxd_off + dr/dxdd dxdd_off), J the tangent at the converged
//    iterate, factored once for every parameter; the right-hand side is the
//    residual's derivative along (xd_off, xdd_off, p) with x held, by central
//    differences (the residual is all the ABI gives of a plugin's
//    dependence on p). A formulation that iterates multipliers until Phi(z)
//    = 0 (MH_EXT_CONSTRAINED_AT_CONVERGENCE: penalty's augmented Lagrangian,
//    Eq. 19) converges on the constraints, not on frozen multipliers: its
//    system is bordered by Phi_z, so that Phi_z S = 0;
//  - the formulation's accept (penalty's projections, Eqs. 20-21; a new
//    choice of independent coordinates) and the coordinates and outputs it
//    writes: central differences of the same step replayed from the
//    formulation's saved state at x +- eps S (the ABI's step: begin_step,
//    residual, accept, coordinates, write_outputs), the run's own state
//    restored after.
// A time event's jump in the state rates (rates_after_jump) is differenced
// the same way. The initial columns are differences of start() itself.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine.hpp"
#include "monohydra/constrained.h"
#include "monohydra/core/kinematics.hpp"
#include "monohydra/core/plugin_registry.hpp"

namespace mh {

namespace {

// Each column's rates from its x column and its offsets, as rates_of does
// for the state (Eq. 33 without the history it differentiates away).
void column_rates(const std::vector<uint8_t>& kinds, const mh_step_coefficients& c,
                  const Eigen::VectorXd& dx, const StepMapState& map,
                  Eigen::Ref<Eigen::VectorXd> dxd, Eigen::Ref<Eigen::VectorXd> dxdd) {
  for (Eigen::Index i = 0; i < dx.size(); ++i) {
    switch (kinds[static_cast<size_t>(i)]) {
      case MH_UNKNOWN_SECOND_ORDER:
        dxd[i] = c.dxd_dx_second * dx[i] + map.xd_off[i];
        dxdd[i] = c.dxdd_dx_second * dx[i] + map.xdd_off[i];
        break;
      case MH_UNKNOWN_FIRST_ORDER:
        dxd[i] = c.dxd_dx_first * dx[i] + map.xd_off[i];
        dxdd[i] = 0.0;
        break;
      default:
        dxd[i] = 0.0;
        dxdd[i] = 0.0;
        break;
    }
  }
}

// Column j of the accepted unknowns to its integrator instance, as the
// state went to the run's: restarted (a time event, redefined unknowns) or
// accepted. A column of a column-major matrix is contiguous: no copy.
void hand_column(Simulation::Engine& e, size_t j, bool restart) {
  IntegratorProxy& shadow = e.sens.shadows[j];
  const auto cj = static_cast<Eigen::Index>(j);
  const mh_unknown_values at = monohydra::unknown_values(
      e.run.accepted.t, static_cast<size_t>(e.n), e.sens.dx.col(cj).data(),
      e.sens.dxd.col(cj).data(), e.sens.dxdd.col(cj).data());
  if (restart)
    e.check(in_flight(*e.integrator_host, InstanceHost::Op::restart,
                      [&] { return shadow.ops.restart(shadow.self, &at); }),
            "integrator", e.integrator_name, "restart (a sensitivity's instance)");
  else
    e.check(in_flight(*e.integrator_host, InstanceHost::Op::accept,
                      [&] { return shadow.ops.accept(shadow.self, &at); }),
            "integrator", e.integrator_name, "accept (a sensitivity's instance)");
}

}  // namespace

// Parameter j's difference step now: its own, unless that would move an
// unknown along the column by more than `largest_move` of its size (at
// least 1). Two bounds, measured (largest error against whole runs, of the
// largest sensitivity, over 10 s of the four-bar):
//  - the replayed accept: 3e-6. Penalty's projections solve with W +
//    Phi_z^T alpha Phi_z / c_a, ill-conditioned by design, and their
//    rounding grows as the step shrinks: 1e-9 gave 1.4e-3, 1e-7 1.7e-3
//    (where the mechanism comes to rest after the valve closes at 8 s),
//    1e-6 1.8e-4; 3e-6 and 1e-5 under 7e-5 with either formulation (the
//    accept is smooth in the unknowns: its truncation stays far below);
//  - the residual's right-hand side and a time event's state rates: 1e-9.
//    The right-hand side moves the rates by the map's offsets, some 2/h
//    times the column: where the cylinder comes to rest after the valve
//    closes, its friction is steep in the rate: 1e-7 missed by 2.3e-3,
//    1e-8 by 3e-3 (penalty, an initial angle); 3e-10 passed (8.1e-5).
constexpr double kLargestMove = 3e-6;
constexpr double kLargestRateMove = 1e-9;

double Simulation::Engine::difference_step(size_t j, const Eigen::VectorXd& at,
                                           double largest_move) const {
  const auto cj = static_cast<Eigen::Index>(j);
  double ratio = 0.0;
  for (int i = 0; i < n; ++i)
    ratio = std::max(ratio, std::abs(sens.dx(i, cj)) / std::max(std::abs(at[i]), 1.0));
  const double step = sens.steps[j];
  return ratio * step > largest_move ? largest_move / ratio : step;
}

void Simulation::Engine::track_sensitivities(const std::vector<ParameterDirection>& parameters) {
  if (run.accepted.started)
    throw std::invalid_argument("sensitivities are tracked from start(): ask for them before it");
  if (explicit_method)
    throw std::invalid_argument("integrator '" + integrator_name +
                                "' is explicit: forward sensitivities differentiate an implicit "
                                "step's Newton solution (use trapezoidal, bdf2 or "
                                "generalized-alpha)");
  if (settings.newton == NewtonKind::articulated)
    throw std::invalid_argument(
        "solver.newton: articulated assembles no tangent, and sensitivities solve with it: use "
        "full, per-step or modified Newton");
  for (const SubsystemInstance& s : subsystems)
    if (s.api.ops.accept != nullptr)
      throw std::invalid_argument("subsystem '" + s.spec->name + "' (" + s.spec->type +
                                  ") keeps state of its own between steps (an accept operation), "
                                  "which sensitivities do not carry");
  const void* ext = formulation.ops.get_extension == nullptr
                        ? nullptr
                        : in_flight(*formulation_host, InstanceHost::Op::get_extension, [&] {
                            return formulation.ops.get_extension(formulation.self, MH_EXT_STATE);
                          });
  const mh_state_extension state = read_struct(static_cast<const mh_state_extension*>(ext));
  if (state.size == nullptr || state.save == nullptr || state.load == nullptr)
    throw std::invalid_argument("formulation '" + formulation_name + "' cannot save its state (" +
                                MH_EXT_STATE +
                                "): sensitivities replay its accept from the state before it");
  const bool reads_initial_state_at_start =
      formulation.ops.get_extension != nullptr &&
      in_flight(*formulation_host, InstanceHost::Op::get_extension, [&] {
        return formulation.ops.get_extension(formulation.self, MH_EXT_INITIAL_STATE_AT_START);
      }) != nullptr;
  for (const ParameterDirection& p : parameters) {
    for (const ParameterDirection::BodyChange& b : p.bodies)
      if (b.body < 0 || b.body >= model.num_bodies())
        throw std::invalid_argument(p.path + ": body " + std::to_string(b.body) +
                                    " is not one of the model's " +
                                    std::to_string(model.num_bodies()));
    for (const ParameterDirection::InitialChange& c : p.initial)
      if (c.coordinate < 0 || c.coordinate >= N)
        throw std::invalid_argument(p.path + ": coordinate " + std::to_string(c.coordinate) +
                                    " is not one of the model's " + std::to_string(N));
    if (!p.initial.empty() && !reads_initial_state_at_start)
      throw std::invalid_argument(p.path + ": formulation '" + formulation_name +
                                  "' reads the initial state once, at setup (it does not declare " +
                                  MH_EXT_INITIAL_STATE_AT_START +
                                  "), so an initial coordinate cannot be differenced through "
                                  "start()");
    if (!std::isfinite(p.value) || !(p.step >= 0.0))
      throw std::invalid_argument(p.path + ": expected a finite value and a step of 0 or more");
  }
  // Each component option by its instance and key, now: none is looked up in the step.
  std::vector<SensitivityState::ComponentOption> options(parameters.size());
  for (size_t j = 0; j < parameters.size(); ++j) {
    const ParameterDirection& p = parameters[j];
    if (p.subsystem.empty()) continue;
    options[j] = find_component_option(p);
  }
  const ComponentInfo* integrator_info = sens.integrator_info;  // the run's, set up once
  sens = SensitivityState{};
  sens.integrator_info = integrator_info;
  sens.options = std::move(options);
  const size_t k = parameters.size();
  if (k == 0) return;
  sens.params = parameters;
  for (const ParameterDirection& p : parameters)
    sens.steps.push_back(p.step > 0.0 ? p.step : 1e-6 * (p.value != 0.0 ? std::abs(p.value) : 1.0));
  sens.formulation_state = state;
  const uint64_t bytes = in_flight(*formulation_host, InstanceHost::Op::get_extension,
                                   [&] { return state.size(formulation.self); });
  sens.before_step.resize(bytes);
  sens.after_step.resize(bytes);

  // One instance of the run's integrator per parameter, set up as the run's.
  mh_integrator_problem problem{};
  problem.struct_size = sizeof(problem);
  problem.num_unknowns = static_cast<uint32_t>(n);
  problem.kinds = registry.kinds.data();
  problem.t0 = 0.0;
  problem.dt = settings.dt;
  sens.shadow_maps.resize(k);
  for (size_t j = 0; j < k; ++j) {
    const mh_integrator* made = sens.integrator_info->integrator_factory.create(
        static_cast<const mh_integrator_factory*>(sens.integrator_info->factory),
        &integrator_host->table, integrator_name.c_str());
    if (made == nullptr)
      throw std::invalid_argument(
          "integrator '" + integrator_name +
          "' could not make an instance for a parameter's sensitivities" +
          (reports.last_plugin_error.empty() ? "" : ": " + reports.last_plugin_error));
    sens.shadows.emplace_back(made);
    IntegratorProxy& shadow = sens.shadows.back();
    mark_destroy(shadow, *integrator_host);
    const mh_status st = normalized(in_flight(*integrator_host, InstanceHost::Op::setup, [&] {
      return shadow.ops.setup(shadow.self, &problem);
    }));
    if (!status_ok(st))
      throw std::invalid_argument(status_reason(
          st, "integrator '" + integrator_name + "' setup of a sensitivity's instance"));
    StepMapState& map = sens.shadow_maps[j];
    for (Eigen::VectorXd* v : {&map.x_pred, &map.xd_off, &map.xdd_off}) v->setZero(n);
    map.map.struct_size = sizeof(map.map);
    map.map.num_unknowns = static_cast<uint32_t>(n);
    map.map.coefficients.struct_size = sizeof(map.map.coefficients);
    map.map.x_predicted = map.x_pred.data();
    map.map.xd_offset = map.xd_off.data();
    map.map.xdd_offset = map.xdd_off.data();
  }
  const auto cols = static_cast<Eigen::Index>(k);
  for (Eigen::MatrixXd* mtx : {&sens.dx, &sens.dxd, &sens.dxdd, &sens.work.rhs})
    mtx->setZero(n, cols);
  for (Eigen::MatrixXd* mtx : {&sens.dz, &sens.dzd, &sens.dzdd}) mtx->setZero(N, cols);
  sens.doutputs.setZero(n_o, cols);
  sens.dy.setZero(n_s, cols);
  for (Eigen::VectorXd* v :
       {&sens.work.xs, &sens.work.xds, &sens.work.xdds, &sens.work.xdq, &sens.work.xddq,
        &sens.work.rp, &sens.work.rm, &sens.work.col, &sens.work.xp, &sens.work.xdp,
        &sens.work.xddp, &sens.work.xm, &sens.work.xdm, &sens.work.xddm})
    v->setZero(n);
  for (Eigen::VectorXd* v : {&sens.work.zp, &sens.work.zdp, &sens.work.zddp, &sens.work.zm,
                             &sens.work.zdm, &sens.work.zddm})
    v->setZero(N);
  for (Eigen::VectorXd* v : {&sens.work.outputs_saved, &sens.work.outp, &sens.work.outm})
    v->setZero(n_o);
  sens.work.y_saved.setZero(n_s);
  sens.work.ydot_saved.setZero(n_s);

  sens.bordered =
      m > 0 && formulation.ops.get_extension != nullptr &&
      in_flight(*formulation_host, InstanceHost::Op::get_extension, [&] {
        return formulation.ops.get_extension(formulation.self, MH_EXT_CONSTRAINED_AT_CONVERGENCE);
      }) != nullptr;
  if (sens.bordered && !work.tangent_ws.coordinate_unknowns)
    throw std::invalid_argument("formulation '" + formulation_name + "' declares " +
                                MH_EXT_CONSTRAINED_AT_CONVERGENCE + " without " +
                                MH_EXT_COORDINATE_UNKNOWNS +
                                ": its unknowns must be the coordinates Phi_z is of");
  if (sens.bordered) {
    sens.border.setZero(n, m);
    sens.border_solved.setZero(n, m);
    sens.schur.setZero(m, m);
    sens.schur_lu = Eigen::PartialPivLU<Eigen::MatrixXd>(m);
    sens.work.mu.setZero(m);
    sens.work.mu_solved.setZero(m);
  }
  // The formulation's outputs of its own iteration (the multipliers) follow
  // no differentiable map of the columns when it converges on Phi = 0.
  sens.output_differentiated.assign(static_cast<size_t>(n_o), 1);
  for (int i = 0; i < n_o; ++i) {
    const std::string& q = registry.output_info[static_cast<size_t>(i)].qualified;
    if (sens.bordered && q.substr(0, q.find('.')) == formulation_name)
      sens.output_differentiated[static_cast<size_t>(i)] = 0;
  }
  sens.saved_bodies.resize(static_cast<size_t>(model.num_bodies()));
  sens.active = true;
}

int Simulation::Engine::subsystem_instance(const std::string& name, const std::string& path) const {
  for (size_t i = 0; i < subsystems.size(); ++i)
    if (subsystems[i].spec->name == name) return static_cast<int>(i);
  throw std::invalid_argument(path + ": the model has no subsystem '" + name + "'");
}

std::vector<std::string> Simulation::Engine::parameter_keys(int instance,
                                                            mh_parameters_extension& ops) {
  SubsystemInstance& s = subsystems[static_cast<size_t>(instance)];
  const void* ext = s.api.ops.get_extension == nullptr
                        ? nullptr
                        : in_flight(*s.host, InstanceHost::Op::get_extension, [&] {
                            return s.api.ops.get_extension(s.api.self, MH_EXT_PARAMETERS);
                          });
  ops = read_struct(static_cast<const mh_parameters_extension*>(ext));
  std::vector<std::string> keys;
  if (ops.count == nullptr || ops.info == nullptr) return keys;
  in_flight(*s.host, InstanceHost::Op::parameter, [&] {
    const uint32_t count = ops.count(s.api.self);
    for (uint32_t i = 0; i < count; ++i) {
      mh_parameter_info info{};
      info.struct_size = sizeof(info);
      keys.emplace_back(ops.info(s.api.self, i, &info) == MH_OK && info.key != nullptr ? info.key
                                                                                       : "");
    }
    return MH_OK;
  });
  return keys;
}

// The option `p` names: a number its instance reads as a signal, or one it
// offers as a parameter (parameters.h); std::invalid_argument naming what is
// missing.
SensitivityState::ComponentOption Simulation::Engine::find_component_option(
    const ParameterDirection& p) {
  SensitivityState::ComponentOption found;
  found.instance = subsystem_instance(p.subsystem, p.path);
  // A number the component reads as a signal: the engine holds it.
  for (const ConstantSignal& c : signals.constants)
    if (c.instance == found.instance && c.key == p.key) {
      found.constant = c.value;
      return found;
    }
  const std::vector<std::string> keys = parameter_keys(found.instance, found.ext);
  const SubsystemInstance& s = subsystems[static_cast<size_t>(found.instance)];
  const std::string who = "subsystem '" + p.subsystem + "' (" + s.spec->type + ")";
  const mh_parameters_extension& ops = found.ext;
  if (ops.count == nullptr || ops.info == nullptr || ops.get == nullptr || ops.set == nullptr)
    throw std::invalid_argument(p.path + ": " + who +
                                " changes none of its options in place (it offers no " +
                                MH_EXT_PARAMETERS + "): they are read when it is set up");
  std::string listed;
  for (size_t i = 0; i < keys.size(); ++i) {
    if (keys[i].empty()) continue;
    if (keys[i] == p.key) {
      found.index = static_cast<uint32_t>(i);
      return found;
    }
    listed += (listed.empty() ? "" : ", ") + keys[i];
  }
  throw std::invalid_argument(p.path + ": " + who + " does not change '" + p.key +
                              "' in place (its parameters: " + (listed.empty() ? "none" : listed) +
                              ")");
}

void Simulation::Engine::perturb_parameter(size_t j, double amount) {
  const ParameterDirection& p = sens.params[j];
  SensitivityState::ComponentOption& option = sens.options[j];
  if (option.constant != nullptr) {
    option.saved = *option.constant;
    *option.constant = option.saved + amount * p.option;
  } else if (option.instance >= 0) {
    const SubsystemInstance& s = subsystems[static_cast<size_t>(option.instance)];
    check(in_flight(*s.host, InstanceHost::Op::parameter,
                    [&] { return option.ext.get(s.api.self, option.index, &option.saved); }),
          "subsystem", s.spec->name, "parameter get");
    check(in_flight(*s.host, InstanceHost::Op::parameter,
                    [&] {
                      return option.ext.set(s.api.self, option.index,
                                            option.saved + amount * p.option);
                    }),
          "subsystem", s.spec->name, "parameter set");
  }
  for (const ParameterDirection::BodyChange& c : p.bodies) {
    const Body& b = model.bodies[static_cast<size_t>(c.body)];
    SensitivityState::BodyValues& v = sens.saved_bodies[static_cast<size_t>(c.body)];
    v.mass = b.mass;
    v.com = b.com_B;
    v.inertia = b.inertia_B;
  }
  for (const ParameterDirection::BodyChange& c : p.bodies)
    move_body(model.bodies[static_cast<size_t>(c.body)], c, amount);
  // The body of coordinate i is body i (Model::initial_coordinates).
  for (const ParameterDirection::InitialChange& c : p.initial) {
    Body& b = model.bodies[static_cast<size_t>(c.coordinate)];
    SensitivityState::BodyValues& v = sens.saved_bodies[static_cast<size_t>(c.coordinate)];
    v.z0 = b.z0;
    v.zd0 = b.zd0;
    b.z0 += amount * c.z0;
    b.zd0 += amount * c.zd0;
  }
  sens.saved_gravity = model.gravity;
  model.gravity += amount * p.gravity;
}

void Simulation::Engine::restore_parameter(size_t j) {
  const SensitivityState::ComponentOption& option = sens.options[j];
  if (option.constant != nullptr) {
    *option.constant = option.saved;
  } else if (option.instance >= 0) {
    const SubsystemInstance& s = subsystems[static_cast<size_t>(option.instance)];
    check(in_flight(*s.host, InstanceHost::Op::parameter,
                    [&] { return option.ext.set(s.api.self, option.index, option.saved); }),
          "subsystem", s.spec->name, "parameter set");
  }
  for (const ParameterDirection::BodyChange& c : sens.params[j].bodies) {
    Body& b = model.bodies[static_cast<size_t>(c.body)];
    const SensitivityState::BodyValues& v = sens.saved_bodies[static_cast<size_t>(c.body)];
    b.mass = v.mass;
    b.com_B = v.com;
    b.inertia_B = v.inertia;
  }
  for (const ParameterDirection::InitialChange& c : sens.params[j].initial) {
    Body& b = model.bodies[static_cast<size_t>(c.coordinate)];
    const SensitivityState::BodyValues& v = sens.saved_bodies[static_cast<size_t>(c.coordinate)];
    b.z0 = v.z0;
    b.zd0 = v.zd0;
  }
  model.gravity = sens.saved_gravity;
}

// The initial columns: start() at p + eps and p - eps, then at p (the run's
// own start, last). start() is deterministic, and begins from the same
// states each time (the equilibrium it solves for moves with p; an initial
// coordinate moves z0 and zd0, whose loops are closed again first).
void Simulation::Engine::start_sensitivities() {
  const Eigen::VectorXd y0 = states.y;
  const size_t k = sens.params.size();
  for (size_t j = 0; j < k; ++j) {
    const double h = sens.steps[j];
    const bool initial = !sens.params[j].initial.empty();
    for (const double sign : {1.0, -1.0}) {
      perturb_parameter(j, sign * h);
      if (initial) close_loops();
      states.y = y0;
      start_run();
      restore_parameter(j);
      if (initial) close_loops();
      const bool plus = sign > 0.0;
      (plus ? sens.work.xp : sens.work.xm) = run.x;
      (plus ? sens.work.xdp : sens.work.xdm) = run.xd;
      (plus ? sens.work.xddp : sens.work.xddm) = run.xdd;
      (plus ? sens.work.zp : sens.work.zm) = run.accepted.z;
      (plus ? sens.work.zdp : sens.work.zdm) = run.accepted.zd;
      (plus ? sens.work.zddp : sens.work.zddm) = run.accepted.zdd;
      (plus ? sens.work.outp : sens.work.outm) = registry.outputs;
    }
    const auto c = static_cast<Eigen::Index>(j);
    sens.dx.col(c) = (sens.work.xp - sens.work.xm) / (2.0 * h);
    sens.dxd.col(c) = (sens.work.xdp - sens.work.xdm) / (2.0 * h);
    sens.dxdd.col(c) = (sens.work.xddp - sens.work.xddm) / (2.0 * h);
    sens.dz.col(c) = (sens.work.zp - sens.work.zm) / (2.0 * h);
    sens.dzd.col(c) = (sens.work.zdp - sens.work.zdm) / (2.0 * h);
    sens.dzdd.col(c) = (sens.work.zddp - sens.work.zddm) / (2.0 * h);
    sens.doutputs.col(c) = (sens.work.outp - sens.work.outm) / (2.0 * h);
  }
  states.y = y0;
  start_run();
  for (size_t j = 0; j < k; ++j) restart_shadow(j);
  sens.dy = sens.dx.bottomRows(n_s);
  save_formulation_state(sens.before_step);
}

void Simulation::Engine::restart_shadow(size_t j) {
  hand_column(*this, j, true);
}

void Simulation::Engine::save_formulation_state(std::vector<unsigned char>& into) {
  const mh_state_extension& ext = sens.formulation_state;
  check(in_flight(*formulation_host, InstanceHost::Op::save_state,
                  [&] { return ext.save(formulation.self, into.data(), into.size()); }),
        "formulation save_state (sensitivities)");
}

void Simulation::Engine::load_formulation_state(const std::vector<unsigned char>& from) {
  const mh_state_extension& ext = sens.formulation_state;
  check(in_flight(*formulation_host, InstanceHost::Op::load_state,
                  [&] { return ext.load(formulation.self, from.data(), from.size()); }),
        "formulation load_state (sensitivities)");
}

// At the converged iterate, before the formulation's accept: the columns of
// the unknowns as Newton's solution moves them (the step's second part).
void Simulation::Engine::sensitivities_before_accept(double t_eval, double t_next, double h) {
  sens.work.t_eval = t_eval;
  sens.work.xs = run.x;
  sens.work.xds = run.xd;
  sens.work.xdds = run.xdd;
  // The tangent at the converged iterate (a kept factorization may be of an
  // earlier one; the last residual call was at this one).
  check(assemble_tangent(t_eval), "tangent assembly (sensitivities)");
  if (!work.solver.linear_solver->factor(work.tangent_ws.values.data()))
    fail("sensitivities: " + work.solver.linear_solver->error());
  run.reuse.invalidate();  // the factorization is the sensitivities' now
  const mh_step_coefficients& c = work.map_ws.map.coefficients;
  const size_t k = sens.params.size();
  for (size_t j = 0; j < k; ++j) {
    IntegratorProxy& shadow = sens.shadows[j];
    StepMapState& map = sens.shadow_maps[j];
    check(in_flight(*integrator_host, InstanceHost::Op::begin_step,
                    [&] { return shadow.ops.begin_step(shadow.self, t_next, h, &map.map); }),
          "integrator", integrator_name, "begin_step (a sensitivity's instance)");
    // r's derivative along (0, xd_off, xdd_off, p): x held.
    const double step = difference_step(j, sens.work.xs, kLargestRateMove);
    for (const double sign : {1.0, -1.0}) {
      for (int i = 0; i < n; ++i) {
        const auto kind = registry.kinds[static_cast<size_t>(i)];
        sens.work.xdq[i] =
            sens.work.xds[i] + (kind == MH_UNKNOWN_ALGEBRAIC ? 0.0 : sign * step * map.xd_off[i]);
        sens.work.xddq[i] = sens.work.xdds[i] +
                            (kind == MH_UNKNOWN_SECOND_ORDER ? sign * step * map.xdd_off[i] : 0.0);
      }
      perturb_parameter(j, sign * step);
      const mh_status st = residual_at(t_eval, sens.work.xs, sens.work.xdq, sens.work.xddq,
                                       sign > 0.0 ? sens.work.rp : sens.work.rm);
      restore_parameter(j);
      check(st, "residual evaluation (sensitivities)");
    }
    sens.work.rhs.col(static_cast<Eigen::Index>(j)) = -(sens.work.rp - sens.work.rm) / (2.0 * step);
  }
  if (sens.bordered) {
    // [J G^T; G 0] [S; mu] = [b; 0], G = [Phi_z 0]: S = J^-1 b - J^-1 G^T mu,
    // mu from G S = 0 (m more solves with the same factorization).
    kinematics_at(sens.work.xs.data(), sens.work.xds.data());
    constraints_at_kinematics(false);
    sens.border.setZero();
    sens.border.topRows(N) = cons.phi_z.transpose();
    for (int i = 0; i < m; ++i) {
      sens.work.col = sens.border.col(i);
      work.solver.linear_solver->solve(sens.work.col.data());
      sens.border_solved.col(i) = sens.work.col;
    }
    sens.schur.noalias() = sens.border.transpose() * sens.border_solved;
    sens.schur_lu.compute(sens.schur);
  }
  for (size_t j = 0; j < k; ++j) {
    const auto cj = static_cast<Eigen::Index>(j);
    sens.work.col = sens.work.rhs.col(cj);
    work.solver.linear_solver->solve(sens.work.col.data());
    if (sens.bordered) {
      sens.work.mu.noalias() = sens.border.transpose() * sens.work.col;
      sens.work.mu_solved = sens.schur_lu.solve(sens.work.mu);
      sens.work.col.noalias() -= sens.border_solved * sens.work.mu_solved;
    }
    sens.dx.col(cj) = sens.work.col;
    column_rates(registry.kinds, c, sens.work.col, sens.shadow_maps[j], sens.dxd.col(cj),
                 sens.dxdd.col(cj));
  }
  if (!sens.dx.allFinite() || !sens.dxd.allFinite() || !sens.dxdd.allFinite())
    fail("sensitivities: a column of the step's solution is not finite");
  // The converged iterate's evaluation again, at p: what accept reads of
  // the last residual call (and the outputs of the step).
  check(residual_at(t_eval, sens.work.xs, sens.work.xds, sens.work.xdds, work.r),
        "residual evaluation");
}

// The step replayed from the formulation's state before it, at the
// converged iterate moved by `amount` along column j and p by as much: what
// accept leaves of the unknowns, the coordinates and the outputs.
void Simulation::Engine::replay_accept(size_t j, double amount, double t_next, bool plus) {
  const auto cj = static_cast<Eigen::Index>(j);
  load_formulation_state(sens.before_step);
  Eigen::VectorXd& xq = plus ? sens.work.xp : sens.work.xm;
  Eigen::VectorXd& xdq = plus ? sens.work.xdp : sens.work.xdm;
  Eigen::VectorXd& xddq = plus ? sens.work.xddp : sens.work.xddm;
  xq = sens.work.xs + amount * sens.dx.col(cj);
  xdq = sens.work.xds + amount * sens.dxd.col(cj);
  xddq = sens.work.xdds + amount * sens.dxdd.col(cj);
  perturb_parameter(j, amount);
  formulation_begin_step(work.map_ws.map.coefficients, t_next, xq, xdq, xddq);
  mh_status st = residual_at(sens.work.t_eval, xq, xdq, xddq, plus ? sens.work.rp : sens.work.rm);
  if (status_ok(st)) {
    uint32_t flags = 0;
    st = in_flight(*formulation_host, InstanceHost::Op::accept, [&] {
      const mh_unknown_buffers values =
          monohydra::unknown_buffers(static_cast<size_t>(n_m), xq.data(), xdq.data(), xddq.data());
      return formulation.ops.accept(formulation.self, t_next, &work.map_ws.map.coefficients,
                                    &values, &flags);
    });
  }
  if (status_ok(st))
    st = in_flight(*formulation_host, InstanceHost::Op::coordinates, [&] {
      const mh_coordinate_buffers out{sizeof(mh_coordinate_buffers), static_cast<uint32_t>(N),
                                      (plus ? sens.work.zp : sens.work.zm).data(),
                                      (plus ? sens.work.zdp : sens.work.zdm).data(),
                                      (plus ? sens.work.zddp : sens.work.zddm).data()};
      return formulation.ops.coordinates(formulation.self, &out);
    });
  if (status_ok(st) && formulation.ops.write_outputs != nullptr)
    st = in_flight(*formulation_host, InstanceHost::Op::write_outputs, [&] {
      return formulation.ops.write_outputs(formulation.self, registry.outputs.data(),
                                           static_cast<uint32_t>(n_o));
    });
  restore_parameter(j);
  // After the run's own accept: no shorter step can cure it (check() would
  // retry a step already accepted).
  if (!status_ok(st)) fail(status_reason(st, "formulation step replayed for a sensitivity"));
  (plus ? sens.work.outp : sens.work.outm) = registry.outputs;
}

// After the run's own accept (and the integrator's): the formulation's
// corrections differenced, a time event's jump in the state rates too, and
// each column handed to its integrator instance as the state was to the
// run's.
void Simulation::Engine::sensitivities_after_accept(double t_next, uint32_t flags, bool event) {
  save_formulation_state(sens.after_step);
  sens.work.outputs_saved = registry.outputs;
  sens.work.y_saved = states.y;
  sens.work.ydot_saved = states.ydot;
  const size_t k = sens.params.size();
  for (size_t j = 0; j < k; ++j) {
    const double step = difference_step(j, sens.work.xs, kLargestMove);
    replay_accept(j, step, t_next, true);
    replay_accept(j, -step, t_next, false);
    const auto cj = static_cast<Eigen::Index>(j);
    const double scale = 1.0 / (2.0 * step);
    sens.dx.col(cj) = (sens.work.xp - sens.work.xm) * scale;
    sens.dxd.col(cj) = (sens.work.xdp - sens.work.xdm) * scale;
    sens.dxdd.col(cj) = (sens.work.xddp - sens.work.xddm) * scale;
    sens.dz.col(cj) = (sens.work.zp - sens.work.zm) * scale;
    sens.dzd.col(cj) = (sens.work.zdp - sens.work.zdm) * scale;
    sens.dzdd.col(cj) = (sens.work.zddp - sens.work.zddm) * scale;
    sens.doutputs.col(cj) = (sens.work.outp - sens.work.outm) * scale;
  }
  load_formulation_state(sens.after_step);
  std::swap(sens.before_step, sens.after_step);  // the next step's "before"
  registry.outputs = sens.work.outputs_saved;
  states.y = sens.work.y_saved;
  states.ydot = sens.work.ydot_saved;
  if (event) {
    // The state rates' right limit (rates_after_jump), differenced along
    // each column: y, z, zd moved, the rows solved for ydot again.
    // The accepted z, zd, kept in the replay's buffers (used up by now):
    // the step allocates nothing.
    Eigen::VectorXd& z_acc = sens.work.zm;
    Eigen::VectorXd& zd_acc = sens.work.zdm;
    z_acc = run.accepted.z;
    zd_acc = run.accepted.zd;
    for (size_t j = 0; j < k; ++j) {
      const auto cj = static_cast<Eigen::Index>(j);
      const double step = difference_step(j, sens.work.xs, kLargestRateMove);
      for (const double sign : {1.0, -1.0}) {
        perturb_parameter(j, sign * step);
        states.y = sens.work.y_saved + sign * step * sens.dx.col(cj).tail(n_s);
        states.ydot = sens.work.ydot_saved;
        sens.work.zp = z_acc + sign * step * sens.dz.col(cj);
        sens.work.zdp = zd_acc + sign * step * sens.dzd.col(cj);
        kinematics_at(sens.work.zp.data(), sens.work.zdp.data());
        solve_initial_rates(std::nextafter(run.accepted.t, HUGE_VAL));
        restore_parameter(j);
        (sign > 0.0 ? sens.work.rp : sens.work.rm).tail(n_s) = states.ydot;
      }
      sens.dxd.col(cj).tail(n_s) = (sens.work.rp.tail(n_s) - sens.work.rm.tail(n_s)) / (2.0 * step);
    }
    states.y = sens.work.y_saved;
    states.ydot = sens.work.ydot_saved;
  }
  kinematics_at(run.accepted.z.data(), run.accepted.zd.data());
  sens.dy = sens.dx.bottomRows(n_s);
  const bool restart = event || (flags & MH_ACCEPT_REDEFINED) != 0;
  for (size_t j = 0; j < k; ++j) hand_column(*this, j, restart);
}

}  // namespace mh
