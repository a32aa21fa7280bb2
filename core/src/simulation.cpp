// Building a run: instances created from plugins in model order, set up, and
// the tangent's pattern analysed once; then the accessors of the results.
#include "monohydra/core/simulation.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "analysis/column_differences.hpp"
#include "engine.hpp"
#include "monohydra/constrained.h"
#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {

namespace {
void require_op(bool present, const std::string& who, const char* op) {
  if (!present) throw PluginError(who + " lacks the required operation '" + op + "'");
}
}  // namespace

// A component refused its options or setup: the option's own error when it
// reported one (file, line, field), else the instance and its logged reason.
[[noreturn]] static void throw_setup_failure(Simulation::Engine& e, const SourceMark& mark,
                                             const std::string& who) {
  if (e.reports.option_error) throw InputError(*e.reports.option_error);
  throw InputError(
      mark, who,
      e.reports.last_plugin_error.empty() ? "setup failed" : e.reports.last_plugin_error);
}

// The settings the plugins will read, checked once, before any of them does.
static SolverSettings checked_settings(const ModelFile& file, const RunChoices& choices) {
  SolverSettings s = file.solver;
  if (choices.dt) s.dt = *choices.dt;
  if (choices.t_end) s.t_end = *choices.t_end;
  if (!(s.dt > 0.0) || !std::isfinite(s.dt))
    throw InputError(s.mark, "solver.dt",
                     "expected a positive, finite time step (s), got " + short_number(s.dt));
  if (!(s.t_end >= 0.0) || !std::isfinite(s.t_end))
    throw InputError(s.mark, "solver.t_end",
                     "expected a non-negative, finite end time (s), got " + short_number(s.t_end));
  // line_search: on makes full Newton the default; another kind named is refused.
  if (s.line_search && s.newton == NewtonKind::automatic) s.newton = NewtonKind::full;
  if (s.line_search && s.newton != NewtonKind::full)
    throw InputError(s.mark, "solver.line_search",
                     std::string("expected off with newton: ") + to_string(s.newton) +
                         " (the line search damps full Newton only)");
  return s;
}

namespace {
// The coordinates move only through the formulation's unknowns: a
// formulation with fewer second-order unknowns (or pairs of first-order
// ones) than the mechanism's degrees of freedom at the assembled start would
// leave coordinates frozen while the run "succeeds". Refused at setup.
void require_moving_unknowns(const Simulation::Engine& e, const std::string& who) {
  int rank = 0;
  if (e.m > 0) rank = static_cast<int>(Eigen::FullPivLU<Eigen::MatrixXd>(e.cons.phi_z).rank());
  const int dof = e.N - rank;
  int second = 0, first = 0;
  for (uint8_t k : e.registry.unknown_kinds) {
    second += k == MH_UNKNOWN_SECOND_ORDER ? 1 : 0;
    first += k == MH_UNKNOWN_FIRST_ORDER ? 1 : 0;
  }
  if (2 * second + first >= 2 * dof) return;
  throw PluginError(who + " declares " + std::to_string(second) + " second-order and " +
                    std::to_string(first) + " first-order unknowns for a mechanism of " +
                    std::to_string(dof) + (dof == 1 ? " degree" : " degrees") + " of freedom (" +
                    std::to_string(e.N) + " coordinates, constraints of rank " +
                    std::to_string(rank) +
                    " at the start): the coordinates it leaves without one would not move");
}
}  // namespace

Simulation::Simulation(const ModelFile& file, const PluginRegistry& registry,
                       const std::string& formulation, LogSink log)
    : Simulation(file, registry, RunChoices{formulation, "", std::nullopt, std::nullopt},
                 std::move(log)) {}

Simulation::Simulation(const ModelFile& file, const PluginRegistry& registry,
                       const RunChoices& choices, LogSink log)
    : engine_(std::make_unique<Engine>(file.model)) {
  Engine& e = *engine_;
  e.file = &file;
  e.settings = checked_settings(file, choices);
  e.reports.log = std::move(log);
  e.N = e.model.num_coordinates();
  for (const auto& b : e.model.bodies) {
    e.registry.coordinate_names.push_back(b.coordinate.empty() ? b.name : b.coordinate);
    e.registry.coordinate_is_angle.push_back(b.joint == JointType::revolute ? 1 : 0);
  }
  for (const auto& name : e.registry.coordinate_names)
    e.registry.coordinate_name_ptrs.push_back(name.c_str());
  e.assemble_loops();
  // Instances read their points' initial positions during setup.
  forward_kinematics(e.model, e.data, e.cons.z0, e.cons.zd0);

  // The model's inputs, before the subsystems whose options read them.
  e.signals.make_inputs(file.inputs, e.run);
  // Subsystems, in model order (find_state sees the instances before it).
  e.subsystems.resize(file.subsystems.size());
  for (size_t i = 0; i < file.subsystems.size(); ++i) {
    const SubsystemSpec& spec = file.subsystems[i];
    SubsystemInstance& s = e.subsystems[i];
    s.spec = &spec;
    s.host = std::make_unique<InstanceHost>();
    const std::string who = "subsystem '" + spec.name + "' (" + spec.type + ")";
    e.make_host(*s.host, who, &spec.options, spec.mark, InstanceHost::Role::subsystem,
                static_cast<int>(i));
    const ComponentInfo* info = nullptr;
    try {
      info = &registry.find(ComponentKind::subsystem, spec.type);
    } catch (const PluginError& err) {
      throw InputError(spec.mark, "subsystems '" + spec.name + "'.type", err.what());
    }
    s.host->set_library(info->library);
    e.reports.last_plugin_error.clear();
    s.api = SubsystemProxy(in_flight(*s.host, InstanceHost::Op::create, [&] {
      return info->subsystem_factory.create(static_cast<const mh_subsystem_factory*>(info->factory),
                                            &s.host->table, spec.type.c_str());
    }));
    if (!s.api) throw_setup_failure(e, spec.mark, who);
    mark_destroy(s.api, *s.host);
    require_op(
        s.api.ops.setup != nullptr && s.api.ops.evaluate != nullptr && s.api.ops.destroy != nullptr,
        who, "setup/evaluate/destroy");
    s.host->in_setup = true;
    const mh_status st = normalized(
        in_flight(*s.host, InstanceHost::Op::setup, [&] { return s.api.ops.setup(s.api.self); }));
    s.host->in_setup = false;
    if (!status_ok(st)) throw_setup_failure(e, spec.mark, who);
    e.check_unread_options(*s.host);
    for (const auto& [key, point] : spec.points) {
      bool used = false;
      for (const auto& p : s.points)
        used = used || (p.body == point.point.body && p.p_B == point.point.p_B);
      if (!used)
        throw InputError(point.mark, who + " point '" + key + "'",
                         "unknown point (this component does not use it)");
    }
  }

  e.check_network();
  // The components' time events and their signals' jumps (owner -1: always)
  // with the jumps of inputs' tables (owner: the input, an event while it
  // follows its table), sorted; one event per time, always when any
  // unconditional one is there.
  std::vector<std::pair<double, int>> events = e.signals.input_events;
  for (double t : e.states.time_events) events.emplace_back(t, -1);
  std::sort(events.begin(), events.end());
  e.states.time_events.clear();
  e.states.time_event_inputs.clear();
  for (const auto& [t, owner] : events) {
    if (!e.states.time_events.empty() && e.states.time_events.back() == t) {
      int& kept = e.states.time_event_inputs.back();
      if (kept != owner) kept = -1;
      continue;
    }
    e.states.time_events.push_back(t);
    e.states.time_event_inputs.push_back(owner);
  }
  e.states.y.conservativeResize(e.n_s);
  e.states.state_tol.conservativeResize(e.n_s);
  e.work.eval.scratch_rows.setZero(e.n_s);
  e.registry.outputs.setZero(
      e.n_o);  // the subsystems' so far; the formulation's are appended below
  e.classify_states();

  // The formulation. Options in the model file belong to the model's
  // formulation; another one chosen on the command line starts from its own
  // defaults.
  e.formulation_name = choices.formulation.empty() ? file.formulation.name : choices.formulation;
  const ComponentInfo* finfo = nullptr;
  try {
    finfo = &registry.find(ComponentKind::formulation, e.formulation_name);
  } catch (const PluginError& err) {
    if (!choices.formulation.empty()) throw;
    throw InputError(file.formulation.mark, "formulation", err.what());
  }
  e.formulation_host = std::make_unique<InstanceHost>();
  const std::string fwho = "formulation '" + e.formulation_name + "'";
  const OptionMap* fopts =
      e.formulation_name == file.formulation.name ? &file.formulation.options : nullptr;
  e.make_host(*e.formulation_host, fwho, fopts, file.formulation.mark,
              InstanceHost::Role::formulation, -1);
  e.formulation_host->set_library(finfo->library);
  e.reports.last_plugin_error.clear();
  e.formulation = FormulationProxy(in_flight(*e.formulation_host, InstanceHost::Op::create, [&] {
    return finfo->formulation_factory.create(
        static_cast<const mh_formulation_factory*>(finfo->factory), &e.formulation_host->table,
        e.formulation_name.c_str());
  }));
  if (!e.formulation) throw_setup_failure(e, file.formulation.mark, fwho);
  mark_destroy(e.formulation, *e.formulation_host);
  const mh_formulation& f = e.formulation.ops;
  require_op(f.setup && f.start && f.residual && f.accept && f.coordinates && f.destroy, fwho,
             "setup/start/residual/accept/coordinates/destroy");
  e.formulation_host->in_setup = true;
  const mh_status fst = normalized(in_flight(*e.formulation_host, InstanceHost::Op::setup,
                                             [&] { return f.setup(e.formulation.self); }));
  e.formulation_host->in_setup = false;
  if (!status_ok(fst)) throw_setup_failure(e, file.formulation.mark, fwho);
  e.check_unread_options(*e.formulation_host);
  require_moving_unknowns(e, fwho);
  e.registry.outputs.conservativeResize(e.n_o);
  e.run.outputs.setZero(e.n_o);

  // The integrator, over every unknown: the formulation's, then the states.
  e.n = e.n_m + e.n_s;
  e.registry.kinds = e.registry.unknown_kinds;
  for (int i = 0; i < e.n_s; ++i)
    e.registry.kinds.push_back(e.states.algebraic[static_cast<size_t>(i)] != 0
                                   ? MH_UNKNOWN_ALGEBRAIC
                                   : MH_UNKNOWN_FIRST_ORDER);
  e.integrator_name = choices.integrator.empty() ? file.integrator.name : choices.integrator;
  const ComponentInfo* iinfo = nullptr;
  try {
    iinfo = &registry.find(ComponentKind::integrator, e.integrator_name);
  } catch (const PluginError& err) {
    if (!choices.integrator.empty()) throw;
    throw InputError(file.integrator.mark, "integrator", err.what());
  }
  e.integrator_host = std::make_unique<InstanceHost>();
  const std::string iwho = "integrator '" + e.integrator_name + "'";
  const OptionMap* iopts =
      e.integrator_name == file.integrator.name ? &file.integrator.options : nullptr;
  e.make_host(*e.integrator_host, iwho, iopts, file.integrator.mark, InstanceHost::Role::integrator,
              -1);
  e.integrator_host->set_library(iinfo->library);
  e.reports.last_plugin_error.clear();
  e.integrator = IntegratorProxy(in_flight(*e.integrator_host, InstanceHost::Op::create, [&] {
    return iinfo->integrator_factory.create(
        static_cast<const mh_integrator_factory*>(iinfo->factory), &e.integrator_host->table,
        e.integrator_name.c_str());
  }));
  if (!e.integrator) throw_setup_failure(e, file.integrator.mark, iwho);
  mark_destroy(e.integrator, *e.integrator_host);
  e.sens.integrator_info = iinfo;
  const mh_integrator& in = e.integrator.ops;
  if (in.explicit_method != nullptr) {
    // An explicit method's own operations, read as this host's (abi_struct.hpp).
    e.explicit_ops = read_struct(in.explicit_method);
    const mh_explicit_method& x = e.explicit_ops;
    if (in.begin_step != nullptr)
      throw PluginError(iwho + " gives both begin_step and explicit_method (exactly one: " +
                        "an implicit map or an explicit method's stages)");
    if (x.num_stages == 0 || x.stage_state == nullptr || x.stage_rates == nullptr ||
        x.finish_step == nullptr)
      throw PluginError(iwho +
                        " is an explicit method without all of its operations "
                        "(num_stages >= 1, stage_state, stage_rates, finish_step)");
    require_op(in.setup && in.restart && in.accept && in.destroy, iwho,
               "setup/restart/accept/destroy");
    e.explicit_method = true;
  } else {
    require_op(in.setup && in.restart && in.begin_step && in.accept && in.destroy, iwho,
               "setup/restart/begin_step/accept/destroy");
  }
  mh_integrator_problem problem{};
  problem.struct_size = sizeof(problem);
  problem.num_unknowns = static_cast<uint32_t>(e.n);
  problem.kinds = e.registry.kinds.data();
  problem.t0 = 0.0;
  problem.dt = e.settings.dt;
  const mh_status ist = normalized(in_flight(*e.integrator_host, InstanceHost::Op::setup, [&] {
    return in.setup(e.integrator.self, &problem);
  }));
  if (!status_ok(ist)) throw_setup_failure(e, file.integrator.mark, iwho);
  e.check_unread_options(*e.integrator_host);
  if (e.explicit_method) {  // its stability check's own instance (explicit_stability.hpp)
    const mh_integrator* probe =
        iinfo->integrator_factory.create(static_cast<const mh_integrator_factory*>(iinfo->factory),
                                         &e.integrator_host->table, e.integrator_name.c_str());
    if (probe == nullptr) throw_setup_failure(e, file.integrator.mark, iwho);
    e.work.stages.amplification = std::make_unique<StageAmplification>(probe);
  }

  for (const auto& v : e.states.state_info) {
    state_names_.push_back(v.name);
    state_units_.push_back(v.unit);
  }
  for (const auto& v : e.registry.output_info) {
    output_names_.push_back(v.name);
    output_units_.push_back(v.unit);
  }
  e.build_pattern();  // and the linear solver the model chose analyses it
  if (e.settings.newton == NewtonKind::automatic) e.settings.newton = e.automatic_newton();
  e.run.reuse.set_mode(reuse_mode(e.settings.newton));
  e.work.solver.quadratic = e.formulation.ops.get_extension == nullptr ||
                            in_flight(*e.formulation_host, InstanceHost::Op::get_extension, [&] {
                              return e.formulation.ops.get_extension(
                                  e.formulation.self, MH_EXT_CONSTRAINED_AT_CONVERGENCE);
                            }) == nullptr;
  if (e.settings.newton == NewtonKind::articulated) e.size_articulated();
  e.size_derivatives();
  e.size_explicit();
  e.size_coupling();
}

// Why solver.newton: articulated does not apply to this run ("" when it does).
std::string Simulation::Engine::articulated_refusal() const {
  const auto has = [&](const char* id) {
    return formulation.ops.get_extension != nullptr &&
           formulation.ops.get_extension(formulation.self, id) != nullptr;
  };
  if (!has(MH_EXT_COORDINATE_UNKNOWNS) || !has(MH_EXT_EQUATIONS_OF_MOTION))
    return "needs a formulation whose rows are the tree's equations of motion M' zdd = Q' "
           "(Eq. 12, e.g. open-loop); formulation '" +
           formulation_name + "' does not declare " + MH_EXT_EQUATIONS_OF_MOTION;
  if (n_s > 0)
    return "solves for the joint coordinates alone, and this model has " + std::to_string(n_s) +
           " subsystem state" + (n_s == 1 ? "" : "s") + " (e.g. '" +
           states.state_info[0].qualified + "')";
  if (explicit_method) return "is for implicit integrators: '" + integrator_name + "' is explicit";
  return "";
}

// solver.newton: auto. Articulated Newton's O(N) solve takes more iterations
// than a tangent (K and C left out), and a tangent costs its mechanical
// block's entries: on a deep tree (a chain: N^2 / N entries a column) the
// articulated solve wins, on a shallow one the tangent (measured per step,
// callgrind: chains of 4 beams 45k against 47k, of 8 107k against 103k, of
// 16 286k against 198k; trees of depth 3 with 33 and 257 bodies 0.32M
// against 0.43M and 2.5M against 3.8M). So: articulated where it applies
// and the block holds more than 6 entries a coordinate.
NewtonKind Simulation::Engine::automatic_newton() const {
  if (!articulated_refusal().empty() || N == 0) return NewtonKind::per_step;
  const auto entries = static_cast<double>(work.tangent_ws.mech_row_index.size());
  return entries > 6.0 * N ? NewtonKind::articulated : NewtonKind::per_step;
}

// solver.newton: articulated takes dxdd_dx M' for Newton's matrix: only where
// that is the tangent's leading part and every unknown is a coordinate.
void Simulation::Engine::size_articulated() {
  const std::string why = articulated_refusal();
  if (!why.empty())
    throw InputError(settings.mark, "solver.newton",
                     "expected auto, full, per-step or modified here: articulated " + why);
  work.solver.articulated = std::make_unique<ArticulatedWorkspace>(model);
}

Simulation::~Simulation() = default;

const ExplicitStability& Simulation::explicit_stability() const {
  return engine_->run.stability;
}
const SolverSettings& Simulation::settings() const {
  return engine_->settings;
}
void Simulation::start() {
  // The plugins' histories begin at the first start: a second one would go on
  // from the last accepted state, not from t = 0, so it is refused.
  if (engine_->run.accepted.started)
    engine_->fail(
        "start() on a simulation that has already started: a new run needs a new "
        "Simulation");
  engine_->start();
}
void Simulation::step() {
  engine_->step_once();
}
void Simulation::set_real_time(int iteration_cap) {
  engine_->work.solver.real_time_cap = iteration_cap > 0 ? iteration_cap : 0;
  engine_->work.solver.step_deadline =
      std::chrono::steady_clock::time_point::max();  // until one is set
}
void Simulation::set_step_deadline(std::chrono::steady_clock::time_point deadline) {
  engine_->work.solver.step_deadline = deadline;
}
const std::vector<InputSpec>& Simulation::inputs() const {
  return engine_->file->inputs;
}
int Simulation::input_index(const std::string& name) const {
  return engine_->signals.find_input(name);
}
double Simulation::input(int k) const {
  return engine_->signals.input_value(k, engine_->run.accepted.t, engine_->run);
}
std::string Simulation::input_refusal(int k, double value) const {
  const Signals& signals = engine_->signals;
  if (k < 0 || static_cast<size_t>(k) >= signals.inputs.size())
    return "no input " + std::to_string(k) + " (the model declares " +
           std::to_string(signals.inputs.size()) + ")";
  const InputSpec& spec = *signals.inputs[static_cast<size_t>(k)].spec;
  if (!std::isfinite(value))
    return "input '" + spec.name + "': " + short_number(value) + " is not a finite value";
  if (spec.min < spec.max && !spec.clamp && !(value >= spec.min && value <= spec.max))
    return "input '" + spec.name + "': " + short_number(value) + " " + spec.unit +
           " is outside its range [" + short_number(spec.min) + ", " + short_number(spec.max) +
           "] (out_of_range: refuse)";
  return "";
}
double Simulation::set_input(int k, double value) {
  const std::string refused = input_refusal(k, value);
  if (!refused.empty()) throw std::invalid_argument(refused);
  Signals& signals = engine_->signals;
  InputSignal& in = signals.inputs[static_cast<size_t>(k)];
  const InputSpec& spec = *in.spec;
  if (spec.min < spec.max) value = std::clamp(value, spec.min, spec.max);  // out_of_range: clamp
  RunData& run = engine_->run;
  const double before = signals.input_value(k, run.accepted.t, run);
  run.input_values[static_cast<size_t>(k)] = value;
  run.input_follows_table[static_cast<size_t>(k)] = 0;
  if (run.accepted.started && value != before) run.input_jump_pending = true;
  return value;
}
namespace {

// KE and PE of the accepted state under the engine's model (energy_balance.cpp's terms).
// A Data of its own: the engine's holds the last evaluation's kinematics.
std::pair<double, double> mechanical_energy(const Simulation::Engine& e) {
  Data data(e.model);
  forward_kinematics(e.model, data, e.run.accepted.z, e.run.accepted.zd);
  return {mh::kinetic_energy(e.model, data), mh::potential_energy(e.model, data)};
}

// The change of the model `change` makes, with the energy balance's
// references moved by its jump and the kept factorization dropped.
template <class Change>
void change_in_place(Simulation::Engine& e, Change&& change) {
  if (!e.run.accepted.started) {
    change();
    return;
  }
  const auto [ke_before, pe_before] = mechanical_energy(e);
  change();
  const auto [ke_after, pe_after] = mechanical_energy(e);
  e.run.energy.ke0 += ke_after - ke_before;
  e.run.energy.pe0 += pe_after - pe_before;
  e.run.energy.ke = ke_after;
  e.run.energy.pe = pe_after;
  e.run.reuse.invalidate();  // modified Newton's factorization is of the old model
}

}  // namespace

void Simulation::set_body_inertia(int body, double mass, const Eigen::Vector3d& com_B,
                                  const Eigen::Matrix3d& inertia_B) {
  Engine& e = *engine_;
  if (body < 0 || body >= e.model.num_bodies())
    throw std::invalid_argument("body " + std::to_string(body) + ": the model has " +
                                std::to_string(e.model.num_bodies()) + " bodies");
  const std::string name = "body '" + e.model.bodies[static_cast<size_t>(body)].name + "'";
  if (!std::isfinite(mass) || !(mass > 0.0))
    throw std::invalid_argument(name + ": expected a positive finite mass (kg), got " +
                                short_number(mass));
  if (!com_B.allFinite())
    throw std::invalid_argument(name + ": expected a finite centre of mass (m)");
  if (!inertia_B.allFinite() || !inertia_B.isApprox(inertia_B.transpose(), 1e-12) ||
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia_B, Eigen::EigenvaluesOnly)
              .eigenvalues()
              .minCoeff() < -1e-12 * inertia_B.norm())
    throw std::invalid_argument(name +
                                ": expected a finite, symmetric, positive semi-definite inertia "
                                "(kg m^2)");
  change_in_place(e, [&] {
    Body& b = e.model.bodies[static_cast<size_t>(body)];
    b.mass = mass;
    b.com_B = com_B;
    b.inertia_B = inertia_B;
  });
}

void Simulation::set_gravity(const Eigen::Vector3d& gravity) {
  if (!gravity.allFinite()) throw std::invalid_argument("gravity: expected finite values (m/s^2)");
  change_in_place(*engine_, [&] { engine_->model.gravity = gravity; });
}

void Simulation::set_initial_state(int coordinate, double z0, double zd0) {
  Engine& e = *engine_;
  if (coordinate < 0 || coordinate >= e.N)
    throw std::invalid_argument("coordinate " + std::to_string(coordinate) + ": the model has " +
                                std::to_string(e.N));
  Body& b = e.model.bodies[static_cast<size_t>(coordinate)];
  const std::string name = "body '" + b.name + "'";
  if (e.run.accepted.started)
    throw std::invalid_argument(name +
                                ": an initial coordinate changes only before the run starts (it "
                                "is the state start() begins from)");
  if (!std::isfinite(z0) || !std::isfinite(zd0))
    throw std::invalid_argument(name + ": expected a finite initial coordinate and rate");
  const bool reads_at_start =
      e.formulation.ops.get_extension != nullptr &&
      in_flight(*e.formulation_host, InstanceHost::Op::get_extension, [&] {
        return e.formulation.ops.get_extension(e.formulation.self, MH_EXT_INITIAL_STATE_AT_START);
      }) != nullptr;
  if (!reads_at_start)
    throw std::invalid_argument(name + ": formulation '" + e.formulation_name +
                                "' reads the initial state once, at its setup (it does not "
                                "declare " +
                                MH_EXT_INITIAL_STATE_AT_START +
                                "): open the model with this initial coordinate");
  const double z0_was = b.z0, zd0_was = b.zd0;
  b.z0 = z0;
  b.zd0 = zd0;
  try {
    e.close_loops();
  } catch (const InputError& err) {
    b.z0 = z0_was;
    b.zd0 = zd0_was;
    e.close_loops();
    throw std::invalid_argument(name + ": " + err.what());
  }
}

void Simulation::track_sensitivities(const std::vector<ParameterDirection>& parameters) {
  engine_->track_sensitivities(parameters);
}
int Simulation::num_sensitivities() const {
  return engine_->sens.active ? static_cast<int>(engine_->sens.params.size()) : 0;
}
const Eigen::MatrixXd& Simulation::coordinate_sensitivities() const {
  return engine_->sens.dz;
}
const Eigen::MatrixXd& Simulation::coordinate_rate_sensitivities() const {
  return engine_->sens.dzd;
}
const Eigen::MatrixXd& Simulation::state_sensitivities() const {
  return engine_->sens.dy;
}
const Eigen::MatrixXd& Simulation::output_sensitivities() const {
  return engine_->sens.doutputs;
}
bool Simulation::output_differentiated(int i) const {
  const auto& d = engine_->sens.output_differentiated;
  return i >= 0 && static_cast<size_t>(i) < d.size() && d[static_cast<size_t>(i)] != 0;
}

void Simulation::set_component_parameter(const std::string& subsystem, const std::string& key,
                                         double value) {
  set_component_parameter(component_parameter_handle(subsystem, key), value);
}

int Simulation::component_parameter_handle(const std::string& subsystem, const std::string& key) {
  Engine& e = *engine_;
  ParameterDirection p;
  p.path = "subsystems/" + subsystem + "/" + key;
  p.subsystem = subsystem;
  p.key = key;
  for (size_t h = 0; h < e.option_handles.size(); ++h)
    if (e.option_handles[h].path == p.path) return static_cast<int>(h);
  e.option_handles.push_back({p.path, e.find_component_option(p)});
  return static_cast<int>(e.option_handles.size() - 1);
}

void Simulation::set_component_parameter(int handle, double value) {
  Engine& e = *engine_;
  if (handle < 0 || handle >= static_cast<int>(e.option_handles.size()))
    throw std::invalid_argument("component parameter handle " + std::to_string(handle) +
                                ": not one of this run's");
  const Engine::OptionHandle& h = e.option_handles[static_cast<size_t>(handle)];
  const SensitivityState::ComponentOption& option = h.option;
  if (option.constant != nullptr) {  // a number it reads as a signal
    if (!std::isfinite(value))
      throw std::invalid_argument(h.path + ": " + std::to_string(value) +
                                  " is not a finite number");
    *option.constant = value;
    e.run.reuse.invalidate();
    return;
  }
  const SubsystemInstance& s = e.subsystems[static_cast<size_t>(option.instance)];
  e.reports.last_plugin_error.clear();
  const mh_status st = normalized(in_flight(*s.host, InstanceHost::Op::parameter, [&] {
    return option.ext.set(s.api.self, option.index, value);
  }));
  if (!status_ok(st))
    throw std::invalid_argument(h.path + ": " +
                                (e.reports.last_plugin_error.empty()
                                     ? "refused by the component"
                                     : e.reports.last_plugin_error));
  e.run.reuse.invalidate();  // modified Newton's factorization is of the old value
}

Simulation::ParameterRange Simulation::component_parameter_range(const std::string& subsystem,
                                                                 const std::string& key) {
  Engine& e = *engine_;
  ParameterDirection p;
  p.path = "subsystems/" + subsystem + "/" + key;
  p.subsystem = subsystem;
  p.key = key;
  const SensitivityState::ComponentOption option = e.find_component_option(p);
  if (option.constant != nullptr)  // a number it reads as a signal: it declares no range
    return {"", -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  const SubsystemInstance& s = e.subsystems[static_cast<size_t>(option.instance)];
  mh_parameter_info info{};
  info.struct_size = sizeof(info);
  const mh_status st = in_flight(*s.host, InstanceHost::Op::parameter,
                                 [&] { return option.ext.info(s.api.self, option.index, &info); });
  if (!status_ok(normalized(st)))
    throw std::invalid_argument(p.path + ": the component did not describe it");
  return {info.unit == nullptr ? std::string() : std::string(info.unit), info.lower, info.upper};
}

std::vector<std::string> Simulation::component_parameter_keys(const std::string& subsystem) {
  Engine& e = *engine_;
  mh_parameters_extension ops{};
  std::vector<std::string> keys =
      e.parameter_keys(e.subsystem_instance(subsystem, "subsystems/" + subsystem), ops);
  keys.erase(std::remove(keys.begin(), keys.end(), std::string()), keys.end());
  return keys;
}

double Simulation::component_parameter(const std::string& subsystem, const std::string& key) {
  Engine& e = *engine_;
  ParameterDirection p;
  p.path = "subsystems/" + subsystem + "/" + key;
  p.subsystem = subsystem;
  p.key = key;
  const SensitivityState::ComponentOption option = e.find_component_option(p);
  if (option.constant != nullptr) return *option.constant;
  const SubsystemInstance& s = e.subsystems[static_cast<size_t>(option.instance)];
  double value = 0.0;
  const mh_status st = in_flight(*s.host, InstanceHost::Op::parameter,
                                 [&] { return option.ext.get(s.api.self, option.index, &value); });
  if (!status_ok(normalized(st)))
    throw std::invalid_argument(p.path + ": the component did not give its value");
  return value;
}

const Model& Simulation::model() const {
  return engine_->model;
}

double Simulation::time() const {
  return engine_->run.accepted.t;
}
long Simulation::step_index() const {
  return engine_->run.accepted.step;
}
const std::string& Simulation::formulation_name() const {
  return engine_->formulation_name;
}
const std::string& Simulation::integrator_name() const {
  return engine_->integrator_name;
}
const std::vector<VariableInfo>& Simulation::state_info() const {
  return engine_->states.state_info;
}
const std::vector<VariableInfo>& Simulation::output_info() const {
  return engine_->registry.output_info;
}
const Eigen::VectorXd& Simulation::z() const {
  return engine_->run.accepted.z;
}
const Eigen::VectorXd& Simulation::zd() const {
  return engine_->run.accepted.zd;
}
const Eigen::VectorXd& Simulation::zdd() const {
  return engine_->run.accepted.zdd;
}
const Eigen::VectorXd& Simulation::states() const {
  return engine_->run.y;
}
const Eigen::VectorXd& Simulation::state_rates() const {
  return engine_->run.ydot;
}
const std::vector<std::string>& Simulation::coordinate_names() const {
  return engine_->registry.coordinate_names;
}
const std::vector<std::string>& Simulation::state_names() const {
  return state_names_;
}
const Eigen::VectorXd& Simulation::outputs() const {
  return engine_->run.outputs;
}
const std::vector<std::string>& Simulation::output_names() const {
  return output_names_;
}
const std::vector<std::string>& Simulation::state_units() const {
  return state_units_;
}
const std::vector<std::string>& Simulation::output_units() const {
  return output_units_;
}
const std::vector<Visual>& Simulation::visuals() const {
  return engine_->registry.visuals;
}
static int index_of(const std::vector<VariableInfo>& vars, const std::string& name) {
  for (size_t i = 0; i < vars.size(); ++i)
    if (vars[i].name == name || vars[i].qualified == name) return static_cast<int>(i);
  return -1;
}
int Simulation::output_index(const std::string& name) const {
  return index_of(engine_->registry.output_info, name);
}
int Simulation::state_index(const std::string& name) const {
  return index_of(engine_->states.state_info, name);
}
double Simulation::kinetic_energy() const {
  return engine_->run.energy.ke - engine_->run.energy.ke0;
}
double Simulation::potential_energy() const {
  return engine_->run.energy.pe - engine_->run.energy.pe0;
}
double Simulation::work() const {
  return engine_->run.energy.work;
}
double Simulation::drift() const {
  return kinetic_energy() + potential_energy() - work();
}
double Simulation::stored_energy() const {
  return engine_->run.energy.stored - engine_->run.energy.stored0;
}
double Simulation::dissipated_energy() const {
  return engine_->run.energy.dissipated;
}
std::vector<std::string> Simulation::subsystem_names() const {
  std::vector<std::string> names;
  for (const auto& s : engine_->subsystems) names.push_back(s.spec->name);
  return names;
}
void Simulation::dissipation_powers(double* out) {
  double stored = 0.0, dissipation = 0.0;
  engine_->energy_terms(stored, dissipation, out);
}
double Simulation::phi_norm() const {
  return engine_->run.energy.phi_norm;
}
const StepStats& Simulation::last_step() const {
  return engine_->run.last_step;
}
int Simulation::num_unknowns() const {
  return engine_->n;
}
int Simulation::num_mechanical_unknowns() const {
  return engine_->n_m;
}
bool Simulation::explicit_integration() const {
  return engine_->explicit_method;
}
int Simulation::tangent_nonzeros() const {
  return engine_->work.tangent_ws.pattern->nonzeros();
}
bool Simulation::share_fixed_parts(const Simulation& like) {
  Engine& e = *engine_;
  const Engine& o = *like.engine_;
  if (e.run.accepted.started)
    throw std::invalid_argument("share_fixed_parts: the run has started; share before start()");
  if (*e.work.tangent_ws.pattern != *o.work.tangent_ws.pattern) return false;
  e.work.tangent_ws.pattern = o.work.tangent_ws.pattern;
  e.work.solver.linear_solver = make_linear_solver(*e.work.tangent_ws.pattern, e.settings.linear,
                                                   o.work.solver.linear_solver.get());
  return true;
}

const SparsePattern& Simulation::tangent_pattern() const {
  return *engine_->work.tangent_ws.pattern;
}

namespace {
// An explicit integrator has no per-step map x -> (xd, xdd) and no Newton
// step: there is no tangent to assemble or difference (and its begin_step is
// NULL). Refused with a reason instead of calling through a null pointer.
void refuse_explicit(const Simulation::Engine& e, const char* what) {
  if (e.explicit_method)
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          std::string(what) +
                              " needs an implicit integrator's step; this run's integrator is "
                              "explicit and takes no Newton step");
}

// The assembled tangent's values as a dense matrix, through its pattern.
Eigen::MatrixXd dense_tangent(const Simulation::Engine& e) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(e.n, e.n);
  const auto& colptr = e.work.tangent_ws.pattern->column_start();
  const auto& rows = e.work.tangent_ws.pattern->row_index();
  for (int c = 0; c < e.n; ++c)
    for (int k = colptr[c]; k < colptr[c + 1]; ++k)
      J(rows[k], c) = e.work.tangent_ws.values[static_cast<size_t>(k)];
  return J;
}

}  // namespace

Eigen::MatrixXd Simulation::assembled_tangent() {
  Engine& e = *engine_;
  refuse_explicit(e, "the assembled tangent");
  const double t_next = e.run.accepted.t + e.settings.dt;
  e.prepare_step(t_next, e.settings.dt);
  if (!status_ok(e.residual(t_next, e.run.x, e.work.r)) || !status_ok(e.assemble_tangent(t_next)))
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "tangent assembly failed: " + e.reports.last_plugin_error);
  return dense_tangent(e);
}

Eigen::MatrixXd Simulation::finite_difference_tangent() {
  Engine& e = *engine_;
  refuse_explicit(e, "the differenced tangent");
  const double t_next = e.run.accepted.t + e.settings.dt;
  e.prepare_step(t_next, e.settings.dt);
  Eigen::MatrixXd J(e.n, e.n);
  e.residual(t_next, e.run.x, e.work.r);
  for (int c = 0; c < e.n; ++c) {
    const double h = 1e-8 * std::max(1e-2, std::abs(e.run.x[c]));
    e.run.x[c] += h;
    e.residual(t_next, e.run.x, e.work.tangent_ws.r_pert);
    e.run.x[c] -= h;
    J.col(c) = (e.work.tangent_ws.r_pert - e.work.r) / h;
  }
  e.residual(t_next, e.run.x, e.work.r);
  return J;
}

Eigen::MatrixXd Simulation::central_difference_tangent() {
  Engine& e = *engine_;
  refuse_explicit(e, "the differenced tangent");
  const double t_next = e.run.accepted.t + e.settings.dt;
  e.prepare_step(t_next, e.settings.dt);
  Eigen::MatrixXd J(e.n, e.n);
  for (int c = 0; c < e.n; ++c) {
    const double h = 1e-6 * std::max(1e-2, std::abs(e.run.x[c]));
    const double x0 = e.run.x[c];
    e.run.x[c] = x0 + h;
    e.residual(t_next, e.run.x, e.work.tangent_ws.r_pert);
    J.col(c) = e.work.tangent_ws.r_pert;
    e.run.x[c] = x0 - h;
    e.residual(t_next, e.run.x, e.work.tangent_ws.r_pert);
    e.run.x[c] = x0;
    J.col(c) = (J.col(c) - e.work.tangent_ws.r_pert) / (2.0 * h);
  }
  e.residual(t_next, e.run.x, e.work.r);
  return J;
}

Simulation::TangentSample Simulation::tangent_sample(double h) {
  Engine& e = *engine_;
  refuse_explicit(e, "the tangent sample");
  TangentSample out;
  out.h = h;
  e.prepare_step(e.run.accepted.t + e.settings.dt, e.settings.dt);
  const Eigen::VectorXd x0 = e.run.x;  // the model's own prediction: every value in range
  const double t_next = e.run.accepted.t + h;
  if (h != e.settings.dt) {
    e.begin_step(t_next, h);
    e.run.x = x0;
    e.rates_of(e.run.x, e.run.xd, e.run.xdd);
    e.formulation_begin_step(e.work.map_ws.map.coefficients, t_next, e.run.x, e.run.xd, e.run.xdd);
  }
  if (!status_ok(e.residual(t_next, e.run.x, e.work.r)) || !status_ok(e.assemble_tangent(t_next)))
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "tangent assembly failed: " + e.reports.last_plugin_error);
  out.analytic = dense_tangent(e);
  const Eigen::VectorXd r0 = e.work.r;
  difference_columns(
      e.run.x, e.n, r0,
      [&]() -> const Eigen::VectorXd& {
        if (!status_ok(e.residual(t_next, e.run.x, e.work.tangent_ws.r_pert)))
          throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                                "residual failed at a perturbed x: " + e.reports.last_plugin_error);
        return e.work.tangent_ws.r_pert;
      },
      out);
  e.run.x = x0;
  e.residual(t_next, e.run.x, e.work.r);
  return out;
}

Simulation::FormulationBlocks Simulation::formulation_blocks(bool differences) {
  Engine& e = *engine_;
  refuse_explicit(e, "the formulation's blocks");
  FormulationBlocks out;
  const double t_next = e.run.accepted.t + e.settings.dt;
  e.prepare_step(t_next, e.settings.dt);
  const Eigen::VectorXd x0 = e.run.x, xd0 = e.run.xd, xdd0 = e.run.xdd;
  const int n_m = e.n_m;
  // r(x, xd, xdd) of the formulation's rows, the three arguments given
  // independently (the subsystems' rows land in `full` through the host).
  Eigen::VectorXd full(e.n);
  Eigen::VectorXd args[3] = {x0, xd0, xdd0};
  const auto rows_at = [&]() -> Eigen::VectorXd {
    e.run.xd = args[1];
    e.run.xdd = args[2];
    full.setZero();
    if (!status_ok(e.residual_at(t_next, args[0], e.run.xd, e.run.xdd, full)))
      throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                            "formulation '" + e.formulation_name +
                                "' residual failed: " + e.reports.last_plugin_error);
    return full.head(n_m);
  };
  const Eigen::VectorXd r0 = rows_at();
  Eigen::MatrixXd analytic[3];
  for (auto& a : analytic) a = Eigen::MatrixXd::Zero(n_m, n_m);
  if (e.formulation.ops.tangent != nullptr) {
    out.given.assign(static_cast<size_t>(n_m), 0);
    const mh_unknown_values at = monohydra::unknown_values(
        t_next, static_cast<size_t>(n_m), args[0].data(), e.run.xd.data(), e.run.xdd.data());
    const mh_tangent_blocks blocks{sizeof(mh_tangent_blocks), static_cast<uint32_t>(n_m),
                                   analytic[0].data(),        analytic[1].data(),
                                   analytic[2].data(),        out.given.data()};
    const mh_status st = normalized(e.formulation.ops.tangent(e.formulation.self, &at, &blocks));
    if (!status_ok(st))
      throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                            "formulation '" + e.formulation_name +
                                "' tangent failed: " + e.reports.last_plugin_error);
    Eigen::MatrixXd* const written[3] = {&analytic[0], &analytic[1], &analytic[2]};
    apply_planted(e.planted, written);
  }
  for (int b = 0; b < 3; ++b) {
    TangentSample& t = out.block[b];
    t.h = e.settings.dt;
    t.analytic = analytic[b];
    if (differences) difference_columns(args[b], n_m, r0, rows_at, t);
  }
  e.run.x = x0;
  e.residual(t_next, e.run.x, e.work.r);  // the engine at the prediction again, rates by the map
  return out;
}

Simulation::CoordinateMaps Simulation::coordinate_maps() {
  Engine& e = *engine_;
  refuse_explicit(e, "the coordinate maps");
  if (e.formulation.ops.mechanics_map == nullptr)
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "the formulation gives no mechanics_map");
  const double t_next = e.run.accepted.t + e.settings.dt;
  e.prepare_step(t_next, e.settings.dt);
  CoordinateMaps out;
  out.dz_dx_cd.setZero(e.N, e.n_m);
  out.dzd_dx_cd.setZero(e.N, e.n_m);
  for (int c = 0; c < e.n_m; ++c) {
    const double h = 1e-6 * std::max(1e-2, std::abs(e.run.x[c]));
    const double x0 = e.run.x[c];
    for (int side = 0; side < 2; ++side) {
      e.run.x[c] = x0 + (side == 0 ? h : -h);
      e.residual(t_next, e.run.x, e.work.tangent_ws.r_pert);
      const double w = (side == 0 ? 1.0 : -1.0) / (2.0 * h);
      out.dz_dx_cd.col(c) += w * e.work.eval.z_iterate;
      out.dzd_dx_cd.col(c) += w * e.work.eval.zd_iterate;
    }
    e.run.x[c] = x0;
  }
  if (!status_ok(e.residual(t_next, e.run.x, e.work.r)))
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "residual failed: " + e.reports.last_plugin_error);
  Eigen::MatrixXd dzd_dx = Eigen::MatrixXd::Zero(e.N, e.n_m);
  Eigen::MatrixXd dzd_dxd = Eigen::MatrixXd::Zero(e.N, e.n_m);
  Eigen::MatrixXd dr_dQ = Eigen::MatrixXd::Zero(e.n_m, e.N);
  out.dz_dx.setZero(e.N, e.n_m);
  const mh_mechanics_map map{sizeof(mh_mechanics_map),
                             static_cast<uint32_t>(e.N),
                             static_cast<uint32_t>(e.n_m),
                             out.dz_dx.data(),
                             dzd_dx.data(),
                             dzd_dxd.data(),
                             dr_dQ.data()};
  if (!status_ok(normalized(e.formulation.ops.mechanics_map(e.formulation.self, &map))))
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "mechanics_map failed: " + e.reports.last_plugin_error);
  out.dzd_dx = dzd_dx;
  for (int c = 0; c < e.n_m; ++c) {
    const uint8_t kind = e.registry.kinds[static_cast<size_t>(c)];
    const double cv = kind == MH_UNKNOWN_SECOND_ORDER ? e.work.map_ws.map.coefficients.dxd_dx_second
                      : kind == MH_UNKNOWN_FIRST_ORDER ? e.work.map_ws.map.coefficients.dxd_dx_first
                                                       : 0.0;
    out.dzd_dx.col(c) += cv * dzd_dxd.col(c);
  }
  return out;
}

const Simulation::WorkCounters& Simulation::counters() const {
  return engine_->run.counters;
}

Simulation::MechanicsDerivatives Simulation::mechanics_derivatives(const Eigen::VectorXd& z,
                                                                   const Eigen::VectorXd& zd,
                                                                   const Eigen::VectorXd& zdd) {
  Engine& e = *engine_;
  mh_mech_derivatives_request rq{};
  rq.struct_size = sizeof(rq);
  rq.flags = MH_DERIV_DYNAMICS;
  rq.t = e.run.accepted.t;
  rq.z = z.data();
  rq.zd = zd.data();
  rq.zdd = zdd.data();
  if (!status_ok(e.mechanics_derivatives(rq)))
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "mech_derivatives failed: " + e.reports.last_plugin_error);
  return {e.work.derivs.K, e.work.derivs.C};
}

Eigen::VectorXd Simulation::dynamics_residual(const Eigen::VectorXd& z, const Eigen::VectorXd& zd,
                                              const Eigen::VectorXd& zdd) {
  Engine& e = *engine_;
  if (!status_ok(e.evaluate_mechanics(MH_EVAL_DYNAMICS, e.run.accepted.t, z.data(), zd.data())))
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "evaluation failed: " + e.reports.last_plugin_error);
  return e.data.M * zdd - e.data.Q;
}

}  // namespace mh
