// Building a run: instances created from plugins in model order, set up, and
// the tangent's pattern analysed once; then the accessors of the results.
#include "monohydra/core/simulation.hpp"

#include <algorithm>
#include <cmath>

#include "engine.hpp"
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
  if (e.option_error) throw InputError(*e.option_error);
  throw InputError(mark, who, e.last_plugin_error.empty() ? "setup failed" : e.last_plugin_error);
}

Simulation::Simulation(const ModelFile& file, const PluginRegistry& registry,
                       const std::string& formulation, LogSink log)
    : engine_(std::make_unique<Engine>(file.model)) {
  Engine& e = *engine_;
  e.file = &file;
  e.settings = file.solver;
  e.log = std::move(log);
  e.N = e.model.num_coordinates();
  for (const auto& b : e.model.bodies) {
    e.coordinate_names.push_back(b.coordinate.empty() ? b.name : b.coordinate);
    e.coordinate_is_angle.push_back(b.joint == JointType::revolute ? 1 : 0);
  }
  for (const auto& name : e.coordinate_names) e.coordinate_name_ptrs.push_back(name.c_str());
  e.assemble_loops();
  // Instances read their points' initial positions during setup.
  forward_kinematics(e.model, e.data, e.z0, e.zd0);

  // Subsystems, in model order (find_state sees the instances before it).
  e.subsystems.resize(file.subsystems.size());
  for (size_t i = 0; i < file.subsystems.size(); ++i) {
    const SubsystemSpec& spec = file.subsystems[i];
    SubsystemInstance& s = e.subsystems[i];
    s.spec = &spec;
    s.host = std::make_unique<InstanceHost>();
    const std::string who = "subsystem '" + spec.name + "' (" + spec.type + ")";
    e.make_host(*s.host, who, &spec.options, spec.mark, static_cast<int>(i));
    const ComponentInfo* info = nullptr;
    try {
      info = &registry.find(ComponentKind::subsystem, spec.type);
    } catch (const PluginError& err) {
      throw InputError(spec.mark, "subsystems '" + spec.name + "'.type", err.what());
    }
    e.last_plugin_error.clear();
    s.api =
        info->subsystem_factory->create(info->subsystem_factory, &s.host->table, spec.type.c_str());
    if (s.api == nullptr) throw_setup_failure(e, spec.mark, who);
    require_op(s.api->setup != nullptr && s.api->evaluate != nullptr && s.api->destroy != nullptr,
               who, "setup/evaluate/destroy");
    s.host->in_setup = true;
    const mh_status st = s.api->setup(s.api);
    s.host->in_setup = false;
    if (st >= MH_DISCARD) throw_setup_failure(e, spec.mark, who);
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
  std::sort(e.time_events.begin(), e.time_events.end());
  e.time_events.erase(std::unique(e.time_events.begin(), e.time_events.end()), e.time_events.end());

  // The formulation.
  e.formulation_name = formulation.empty() ? file.formulation.name : formulation;
  const ComponentInfo* finfo = nullptr;
  try {
    finfo = &registry.find(ComponentKind::formulation, e.formulation_name);
  } catch (const PluginError& err) {
    if (!formulation.empty()) throw;
    throw InputError(file.formulation.mark, "formulation", err.what());
  }
  e.formulation_host = std::make_unique<InstanceHost>();
  const std::string fwho = "formulation '" + e.formulation_name + "'";
  // Options in the model file belong to the model's formulation; another one
  // chosen on the command line starts from its own defaults.
  const OptionMap* fopts =
      e.formulation_name == file.formulation.name ? &file.formulation.options : nullptr;
  e.make_host(*e.formulation_host, fwho, fopts, file.formulation.mark, -1);
  e.last_plugin_error.clear();
  e.formulation = finfo->formulation_factory->create(
      finfo->formulation_factory, &e.formulation_host->table, e.formulation_name.c_str());
  if (e.formulation == nullptr) throw_setup_failure(e, file.formulation.mark, fwho);
  const mh_formulation* f = e.formulation;
  require_op(f->setup && f->start && f->predict && f->residual && f->accept && f->coordinates &&
                 f->destroy,
             fwho, "setup/start/predict/residual/accept/coordinates/destroy");
  uint32_t n_m = 0;
  if (f->setup(f, &n_m) >= MH_DISCARD) throw_setup_failure(e, file.formulation.mark, fwho);
  e.check_unread_options(*e.formulation_host);
  e.n_m = static_cast<int>(n_m);
  e.y.conservativeResize(e.n_s);
  e.state_tol.conservativeResize(e.n_s);
  e.outputs.setZero(e.n_o);
  e.outputs_k.setZero(e.n_o);
  e.build_pattern();
}

Simulation::~Simulation() {
  if (!engine_) return;
  if (engine_->formulation != nullptr) engine_->formulation->destroy(engine_->formulation);
  for (auto& s : engine_->subsystems)
    if (s.api != nullptr) s.api->destroy(s.api);
}

const SolverSettings& Simulation::settings() const {
  return engine_->settings;
}
SolverSettings& Simulation::settings() {
  return engine_->settings;
}
void Simulation::start() {
  engine_->start();
}
void Simulation::step() {
  engine_->step_once();
}
double Simulation::time() const {
  return engine_->t;
}
long Simulation::step_index() const {
  return engine_->step;
}
const std::string& Simulation::formulation_name() const {
  return engine_->formulation_name;
}
const Eigen::VectorXd& Simulation::z() const {
  return engine_->z;
}
const Eigen::VectorXd& Simulation::zd() const {
  return engine_->zd;
}
const Eigen::VectorXd& Simulation::zdd() const {
  return engine_->zdd;
}
const Eigen::VectorXd& Simulation::states() const {
  return engine_->y_k;
}
const Eigen::VectorXd& Simulation::state_rates() const {
  return engine_->ydot_k;
}
const std::vector<std::string>& Simulation::coordinate_names() const {
  return engine_->coordinate_names;
}
const std::vector<std::string>& Simulation::state_names() const {
  return engine_->state_names;
}
const Eigen::VectorXd& Simulation::outputs() const {
  return engine_->outputs_k;
}
const std::vector<std::string>& Simulation::output_names() const {
  return engine_->output_names;
}
const std::vector<std::string>& Simulation::state_units() const {
  return engine_->state_units;
}
const std::vector<std::string>& Simulation::output_units() const {
  return engine_->output_units;
}
int Simulation::output_index(const std::string& name) const {
  const auto& names = engine_->output_names;
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name || engine_->output_qualified[i] == name) return static_cast<int>(i);
  return -1;
}
int Simulation::state_index(const std::string& name) const {
  const auto& names = engine_->state_names;
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name || engine_->state_qualified[i] == name) return static_cast<int>(i);
  return -1;
}
double Simulation::kinetic_energy() const {
  return engine_->ke - engine_->ke0;
}
double Simulation::potential_energy() const {
  return engine_->pe - engine_->pe0;
}
double Simulation::work() const {
  return engine_->work;
}
double Simulation::drift() const {
  return kinetic_energy() + potential_energy() - work();
}
double Simulation::stored_energy() const {
  return engine_->stored - engine_->stored0;
}
double Simulation::dissipated_energy() const {
  return engine_->dissipated;
}
double Simulation::phi_norm() const {
  return engine_->phi_norm;
}
const StepStats& Simulation::last_step() const {
  return engine_->stats;
}
int Simulation::num_unknowns() const {
  return engine_->n;
}
int Simulation::num_mechanical_unknowns() const {
  return engine_->n_m;
}
int Simulation::tangent_nonzeros() const {
  return engine_->pattern->nonzeros();
}

Eigen::MatrixXd Simulation::assembled_tangent() {
  Engine& e = *engine_;
  const double t_next = e.t + e.settings.dt;
  if (e.residual(t_next, e.x, e.r) >= MH_DISCARD || e.assemble_tangent(t_next) >= MH_DISCARD)
    throw SimulationError(e.t, e.step, "tangent assembly failed: " + e.last_plugin_error);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(e.n, e.n);
  const auto& colptr = e.pattern->column_start();
  const auto& rows = e.pattern->row_index();
  for (int c = 0; c < e.n; ++c)
    for (int k = colptr[c]; k < colptr[c + 1]; ++k)
      J(rows[k], c) = e.values[static_cast<size_t>(k)];
  return J;
}

Eigen::MatrixXd Simulation::finite_difference_tangent() {
  Engine& e = *engine_;
  const double t_next = e.t + e.settings.dt;
  Eigen::MatrixXd J(e.n, e.n);
  e.residual(t_next, e.x, e.r);
  for (int c = 0; c < e.n; ++c) {
    const double h = 1e-8 * std::max(1e-2, std::abs(e.x[c]));
    e.x[c] += h;
    e.residual(t_next, e.x, e.r_pert);
    e.x[c] -= h;
    J.col(c) = (e.r_pert - e.r) / h;
  }
  e.residual(t_next, e.x, e.r);
  return J;
}

}  // namespace mh
