// One simulation run: a model, its formulation, integrator and subsystem
// instances loaded from plugins, and the monolithic implicit Newton step
// (Sect. 4) that integrates them together with one sparse tangent.
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/sensitivities.hpp"
#include "monohydra/core/sparse_pattern.hpp"
#include "monohydra/types.h"

namespace mh {

struct RunState;  // run_state.hpp
struct Linearization;
struct LinearizeOptions;  // linearization.hpp
struct LinearVariable;    // state_vector.hpp

// A run that cannot go on: names the time, the step and the reason.
class SimulationError : public std::runtime_error {
 public:
  SimulationError(double t, long step, const std::string& reason);
  double time() const { return t_; }
  long step() const { return step_; }
  const std::string& reason() const { return reason_; }

 private:
  double t_;
  long step_;
  std::string reason_;
};

using LogSink = std::function<void(mh_log_level, const std::string& source, const std::string&)>;

// Per-step diagnostics of the Newton iteration.
struct StepStats {
  int iterations = 0;  // linear solves this step (all its attempts)
  int retries = 0;     // halvings of the step (solver.max_step_halvings)
  int tangents = 0;    // tangents assembled and factored (all its attempts)
  int damped = 0;      // increments the line search shortened (solver.line_search)
  // Real-time mode only: false when the step was accepted before Newton
  // converged (its cap or its deadline came first), and its last increment.
  bool converged = true;
  double unconverged = 0.0;  // max_i |dx_i| / tol_i of the accepted iterate (0: converged)
  std::vector<double> increment_norms;  // max_i |dx_i| / tol_i after each solve
  std::vector<double> residual_norms;   // ||r||_inf at the predictor and after each solve
};

// What the command line may choose over the model file. Every choice reaches
// the plugins once, at setup.
struct RunChoices {
  std::string formulation;  // "" = the model file's
  std::string integrator;   // "" = the model file's
  std::optional<double> dt, t_end;
};

// A state or an output of the run, as its component declared it.
struct VariableInfo {
  std::string name;       // result column ("" = not written)
  std::string qualified;  // "instance.state", "formulation-id.output", or a node's name
  std::string unit;
  uint32_t kind = 0;  // outputs: mh_output_kind
  std::string role;   // MH_ROLE_* or ""
  double range_min = 0.0, range_max = 0.0;
};

// How a component looks, as it declared it (sdk/include/monohydra/visual.h):
// what a host draws of it without knowing its id.
struct Visual {
  enum class Kind { actuator, link };
  std::string instance;  // the subsystem's name
  Kind kind = Kind::link;
  BodyPoint a, b;                                                         // its two points
  double barrel_length = 0.0, barrel_diameter = 0.0, rod_diameter = 0.0;  // m
  int state_a = -1, state_b = -1;  // global state indices colouring it, or -1
};

class Simulation {
 public:
  // Creates and sets up every instance; `choices` override the model file.
  // Throws InputError for bad options or settings, PluginError for missing
  // plugins; every instance created before a failure is destroyed.
  Simulation(const ModelFile& file, const PluginRegistry& registry, const RunChoices& choices,
             LogSink log = nullptr);
  Simulation(const ModelFile& file, const PluginRegistry& registry,
             const std::string& formulation = "", LogSink log = nullptr);
  // The simulation reads its model file (and the registry) for as long as it
  // lives: a temporary would leave it reading freed memory, so it is refused
  // at compile time.
  Simulation(ModelFile&&, const PluginRegistry&, const RunChoices&, LogSink = nullptr) = delete;
  Simulation(ModelFile&&, const PluginRegistry&, const std::string& = "",
             LogSink = nullptr) = delete;
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const SolverSettings& settings() const;  // the file's, with the choices' dt and t_end

  void start();  // consistent initial state at t = 0
  void step();   // one step of dt; throws SimulationError, leaving the last accepted state
  // The run's state between two steps (after start()), as one copyable value
  // (run_state.hpp); the second form reuses `into`'s storage, so that saving
  // again allocates nothing. restore_state puts a saved state back, into this
  // run or another made from the same model and choices: the steps after it
  // are those that followed the save, to the bit (modified Newton's kept
  // factorization and the work counters included). Both throw
  // RunStateError naming the reason: an instance that keeps state between
  // steps and cannot save it (no MH_EXT_STATE), a state of another run.
  RunState save_state() const;
  void save_state(RunState& into) const;
  void restore_state(const RunState& from);
  // The values changed in place (a body's mass, centre of mass or inertia,
  // gravity) that differ between this run's model and the one `from` was
  // saved with, each named with both values ("" when none does, or when the
  // state is of another run, which restore refuses). A restore does not
  // change them: a host that restores for its user says so; the filters
  // restore on purpose into moved parameters.
  std::string model_differences(const RunState& from) const;

  // Real-time mode (`monohydra run --real-time`), the one mode whose results
  // depend on the machine: Newton stops after `iteration_cap` iterations or
  // at the step's wall-clock deadline, whichever comes first, and the step is
  // accepted unconverged (StepStats::converged) instead of failing. 0: off.
  void set_real_time(int iteration_cap);
  void set_step_deadline(std::chrono::steady_clock::time_point deadline);

  double time() const;
  long step_index() const;
  const std::string& formulation_name() const;
  const std::string& integrator_name() const;

  // The accepted state.
  const Eigen::VectorXd& z() const;
  const Eigen::VectorXd& zd() const;
  const Eigen::VectorXd& zdd() const;
  const Eigen::VectorXd& states() const;
  const Eigen::VectorXd& state_rates() const;
  const std::vector<std::string>& coordinate_names() const;
  const std::vector<std::string>& state_names() const;  // CSV names ("" not written)
  int state_index(const std::string& name) const;       // -1 if absent
  const std::vector<std::string>& state_units() const;  // as declared, e.g. "Pa", "V"
  const std::vector<VariableInfo>& state_info() const;
  // Outputs of the subsystems (e.g. a cylinder's stroke) and of the
  // formulation (e.g. its multipliers) at the accepted state.
  const Eigen::VectorXd& outputs() const;
  const std::vector<VariableInfo>& output_info() const;
  const std::vector<std::string>& output_names() const;  // CSV names ("" not written)
  int output_index(const std::string& name) const;       // -1 if absent
  const std::vector<std::string>& output_units() const;  // as declared, e.g. "m", "N"
  // What the components declared of their look, in model-file order.
  const std::vector<Visual>& visuals() const;

  // The model's inputs (its inputs:, in file order) and their values at the
  // accepted time.
  const std::vector<InputSpec>& inputs() const;
  int input_index(const std::string& name) const;  // -1 if absent
  double input(int k) const;
  // Sets input k from the accepted time on (before start(): from t = 0), in
  // place of its table. A value outside the input's range is refused
  // (std::invalid_argument naming the input, the value and the range) or,
  // with out_of_range: clamp, clamped; returns the value it took. A change
  // after start is a jump at the accepted time: the next step starts from
  // the rates at its right limit, as after a time event.
  double set_input(int k, double value);
  // Why set_input(k, value) would refuse the value ("" when it would not).
  std::string input_refusal(int k, double value) const;

  // A body's inertial values and gravity changed in place, before start() or
  // between steps, without opening the model again (a payload picked up, a
  // parameter being identified): the run goes on as a run of the model with
  // these values from the accepted state on, the step after the change
  // starting from the accelerations before it, as a snapshot restored into a
  // model opened with them would. The energy balance's references move by
  // the change's own jump in kinetic and potential energy, so that drift
  // stays the integration's. Refused with std::invalid_argument naming the
  // value: a body index out of range, a mass that is not positive and
  // finite, a non-finite centre of mass, gravity or inertia, an inertia that
  // is not symmetric positive semi-definite.
  void set_body_inertia(int body, double mass, const Eigen::Vector3d& com_B,
                        const Eigen::Matrix3d& inertia_B);
  void set_gravity(const Eigen::Vector3d& gravity);
  // The model as the run has it now: its bodies' inertia and gravity as
  // set in place.
  const Model& model() const;
  // A coordinate's initial value and rate (rad or m, rad/s or m/s), before
  // start(): the loops are closed again around them as when the model is
  // opened. Refused with std::invalid_argument naming why: after start(),
  // a coordinate out of range, a value that is not finite, loops that cannot
  // be closed from it (nothing changed), a formulation that reads the
  // initial state once at its setup (MH_EXT_INITIAL_STATE_AT_START).
  void set_initial_state(int coordinate, double z0, double zd0);
  // A component's option that it changes in place (monohydra/parameters.h),
  // or a number it reads as a signal (a pump's pressure: the engine holds
  // it), before start() or between steps: the run goes on as one of the model
  // with that value from the accepted state on. Refused with
  // std::invalid_argument naming why: no subsystem of that name, a
  // component that does not change that option in place (naming those it
  // does), a value it refuses (its reason, e.g. the range).
  void set_component_parameter(const std::string& subsystem, const std::string& key, double value);
  // The same, its option found once (a handle of this run): for a caller
  // that sets it every step, with no lookup by name there.
  int component_parameter_handle(const std::string& subsystem, const std::string& key);
  void set_component_parameter(int handle, double value);
  // What the component declares of that option: its SI unit and the values
  // it takes, [lower, upper] (+-infinity: no bound). Refused as
  // set_component_parameter refuses a subsystem or an option.
  struct ParameterRange {
    std::string unit;
    double lower = 0.0, upper = 0.0;
  };
  ParameterRange component_parameter_range(const std::string& subsystem, const std::string& key);
  // The keys of the options the subsystem's component changes in place (its
  // parameters.h), in its order; none when it offers no such extension.
  // std::invalid_argument for a subsystem the model does not have.
  std::vector<std::string> component_parameter_keys(const std::string& subsystem);
  // Such an option's value now (or a number it reads as a signal); refused
  // as set_component_parameter refuses.
  double component_parameter(const std::string& subsystem, const std::string& key);

  // Forward sensitivities (sensitivities.hpp, docs/identification.md): from
  // start() on, every accepted step also carries d/dp of the coordinates,
  // their rates, the states and the outputs for each parameter given, by
  // differentiating the discrete step: the converged tangent, factored once,
  // solves one right-hand side per parameter; the integrator's history is
  // differentiated by an instance of its own per parameter, the formulation's
  // corrections at accept by differences along the solved direction. Before
  // start() only. Refused (std::invalid_argument naming why): an explicit
  // integrator, solver.newton: articulated, a subsystem that keeps state of
  // its own (an accept operation), a formulation that cannot save its state,
  // a body index out of range.
  void track_sensitivities(const std::vector<ParameterDirection>& parameters);
  int num_sensitivities() const;  // k: 0 when none are tracked
  // At the accepted state, one column per parameter.
  const Eigen::MatrixXd& coordinate_sensitivities() const;       // N x k: dz/dp
  const Eigen::MatrixXd& coordinate_rate_sensitivities() const;  // N x k: dzd/dp
  const Eigen::MatrixXd& state_sensitivities() const;            // n_s x k: dy/dp
  const Eigen::MatrixXd& output_sensitivities() const;           // n_o x k
  // Whether output i's column is differentiated (a formulation's outputs of
  // its own iteration, such as penalty's multipliers, are not).
  bool output_differentiated(int i) const;

  // Energy balance, all relative to t = 0: kinetic and potential energy of the
  // bodies, work W done on them by subsystem forces (trapezoidal integral of
  // the power), drift = KE + PE - W.
  double kinetic_energy() const;
  double potential_energy() const;
  double work() const;
  double drift() const;
  // Energy stored in subsystems (relative to t = 0) and dissipated by them.
  double stored_energy() const;
  double dissipated_energy() const;
  // Where the dissipation happens: every subsystem instance, in the model's
  // order, and the power each dissipates (W, 0 for one without an energy op)
  // at the accepted state, into out[0 .. subsystem_names().size()). Their sum
  // is what dissipated_energy() integrates. For a host that breaks the
  // dissipated energy down (the report); step() does not need it.
  std::vector<std::string> subsystem_names() const;
  void dissipation_powers(double* out);
  double phi_norm() const;  // norm of the cut-joint constraints at z
  const StepStats& last_step() const;
  // An explicit integrator's stability checks so far (checks = 0: none).
  const ExplicitStability& explicit_stability() const;
  // What the run has cost since start(): passes of the kinematics (every
  // forward_kinematics the host made, for any service) and residual
  // evaluations (the Newton iterate's and the differenced ones).
  struct WorkCounters {
    long kinematics_passes = 0;
    long residual_evaluations = 0;
    // Runs of the K, C recursion (mech_derivatives with MH_DERIV_DYNAMICS).
    long derivative_passes = 0;
    // Evaluations of Phi and Phi_z, and of Phi_z_dot zd (the host keeps
    // each while its kinematics stand; MH_EVAL_POSITIONS_ONLY skips the latter).
    long constraint_position_passes = 0;
    long constraint_rate_passes = 0;
  };
  const WorkCounters& counters() const;

  // The Newton tangent the step assembles (analytic blocks where plugins give
  // them) and the one forward differences alone give, both at the current
  // iterate of the next step, dense (to test analytic blocks).
  Eigen::MatrixXd assembled_tangent();
  // What the host service mech_derivatives gives a formulation at
  // (z, zd, zdd) with the current subsystem states: K = d(M' zdd - Q')/dz and
  // C = d(M' zdd - Q')/dzd, every subsystem force included; and M' zdd - Q'
  // itself, to test them against differences.
  struct MechanicsDerivatives {
    Eigen::MatrixXd K, C;
  };
  MechanicsDerivatives mechanics_derivatives(const Eigen::VectorXd& z, const Eigen::VectorXd& zd,
                                             const Eigen::VectorXd& zdd);
  Eigen::VectorXd dynamics_residual(const Eigen::VectorXd& z, const Eigen::VectorXd& zd,
                                    const Eigen::VectorXd& zdd);
  Eigen::MatrixXd finite_difference_tangent();
  // The same by central differences (x +- h, h = 1e-6 max(1e-2, |x_i|)), the
  // reference of the analytic blocks' tests.
  Eigen::MatrixXd central_difference_tangent();
  // The formulation's mechanics_map at the prediction of the next
  // step, every array asked for: dz/dx and the total dzd/dx along the
  // integrator's map (dzd_dx + dxd_dx dzd_dxd), and the same from central
  // differences of the coordinates its residual passed at x +- h.
  struct CoordinateMaps {
    Eigen::MatrixXd dz_dx, dzd_dx, dz_dx_cd, dzd_dx_cd;
  };
  CoordinateMaps coordinate_maps();
  // The conformance check's matrices (monohydra check): at the prediction x
  // of the next step of the model's dt, the assembled tangent and differences
  // of the residual, with the rates tied to x by the integrator's map for a
  // step of `h`. A coarse h makes K and C visible beside c_a M' (at h = 1 ms,
  // c_a = 4e6 1/s^2 hides them at 1e-6 of each row). Forward and backward
  // differences at the relative step 1e-6 (their mean is the central one; at
  // a kink of the model, a valve's spool crossing zero, the analytic tangent
  // is one of them), and central differences at 1e-5, whose distance from
  // those at 1e-6 estimates the differences' own error entry by entry.
  // Central differences at 1e-4 and 1e-3 too (`central_wide`,
  // `central_wider`): an entry whose row is dominated by far larger terms
  // (a pump's leakage beside its delivered flow) is rounded away at 1e-6,
  // and is judged by the wider pair where they agree more closely.
  struct TangentSample {
    Eigen::MatrixXd analytic, forward, backward, central_coarse, central_wide, central_wider;
    double h = 0.0;
    // Each column's magnitude, whose 1e-6 the differences stepped it by:
    // |value|, at least 1e-2 (a rate's at least its state's over dt).
    Eigen::VectorXd column_scale;
  };
  TangentSample tangent_sample(double h);
  // The formulation's own analytic blocks dr/dx, dr/dxd, dr/dxdd (its n_m
  // rows and columns, subsystem states held) at the prediction of the next
  // step, each against differences of its residual in that argument alone,
  // the other two held: what its tangent op promises, whether or not this
  // host uses the block (without mechanics_map the host differences the
  // mechanical columns of a model whose subsystems have points). `given`:
  // the columns the formulation wrote (empty when it has no tangent op).
  struct FormulationBlocks {
    // The blocks' names, as every check and message writes them.
    static constexpr const char* kNames[3] = {"dr/dx", "dr/dxd", "dr/dxdd"};
    TangentSample block[3];  // of x, xd, xdd
    std::vector<unsigned char> given;
  };
  FormulationBlocks formulation_blocks(bool differences = true);
  // A subsystem instance's derivative arrays as its ops give them
  // (jacobian, coupling_jacobian, point_force_jacobian), at the prediction
  // of the next step, each against differences of the instance's own
  // evaluate in that argument alone, the others held: what `monohydra
  // check` compares entry by entry, each block in one pair of units.
  // Rows: its touched states' residual rows (dR/...) or its points' forces
  // (dF/..., 3 per point); columns: its touched states (y), their rates
  // (ydot), or its points' world positions (p) and velocities (v). A block
  // whose op the instance lacks is not `given` (the host differences it);
  // a block of no rows or columns is left out. Without `differences`, the
  // analytic arrays alone (forward, backward, central_coarse empty).
  struct DerivativeBlock {
    std::string name;  // "dR/dy", "dR/dydot", "dR/dp", "dR/dv", "dF/dy", ...
    bool given = false;
    TangentSample sample;
    std::vector<std::string> rows, columns;  // their names
  };
  std::vector<DerivativeBlock> subsystem_blocks(const std::string& instance,
                                                bool differences = true);
  // For tests of the checks only: entry `entry` (column-major) of block
  // `block` of `instance` (a DerivativeBlock name) or of the formulation
  // (`instance` "", block "dr/dx", "dr/dxd" or "dr/dxdd") scaled by
  // `factor` each time the host receives it from the op, until cleared
  // (factor 1). Throws std::invalid_argument for an unknown instance or
  // block.
  void plant_derivative_error(const std::string& instance, const std::string& block, long entry,
                              double factor);
  int num_unknowns() const;
  int num_mechanical_unknowns() const;
  // True when the run's integrator is explicit (its own stage operations): it takes no
  // Newton step, so the tangent accessors refuse it.
  bool explicit_integration() const;
  int tangent_nonzeros() const;
  // The tangent's sparsity pattern (tangent.cpp build_pattern), analysed once.
  const SparsePattern& tangent_pattern() const;
  // Before start: this run takes the fixed parts `like` (a run of the same
  // model) has made, instead of keeping its own: the tangent's sparsity
  // pattern and the linear solver's symbolic analysis (KLU's). False, and
  // nothing changes, when the patterns differ. A batch's runs share their
  // first run's.
  bool share_fixed_parts(const Simulation& like);

  struct Engine;

 private:
  // linearization.hpp: perturbs the engine's accepted state between steps.
  friend Linearization linearize(Simulation& sim, const std::vector<std::string>& outputs,
                                 const LinearizeOptions& options);
  // state_vector.hpp: reads and sets the accepted state between steps.
  friend std::vector<LinearVariable> state_variables(const Simulation& sim);
  friend Eigen::VectorXd state_values(const Simulation& sim);
  friend void set_state_values(Simulation& sim, const Eigen::VectorXd& values);

  std::unique_ptr<Engine> engine_;
  std::vector<std::string> state_names_, state_units_, output_names_, output_units_;
};

}  // namespace mh
