// Private: the state behind a Simulation, shared by the files that implement
// it along the data flow: host services (host_services.cpp), construction
// (simulation.cpp), consistent initial states (initial_state.cpp), the
// integrator's map (integrator_map.cpp), the tangent (tangent.cpp), the
// step's Newton problem (newton_solve.cpp), the step (time_step.cpp) and the
// energy balance (energy_balance.cpp). The engine holds what its model fixes
// at set-up (plugin instances, names, sizes, the constraints), the run's data
// (RunData, run_state.hpp: everything a step changes, a snapshot's copy) and
// a workspace (Workspace: what a step works in and recomputes). Everything
// here is sized in the constructor and start(); step() allocates nothing.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <initializer_list>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "monohydra/core/articulated_solve.hpp"
#include "monohydra/core/constraint_derivatives.hpp"
#include "monohydra/core/constraints.hpp"
#include "monohydra/core/data.hpp"
#include "monohydra/core/dynamics_derivatives.hpp"
#include "monohydra/core/linear_solver.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_call.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/simulation.hpp"
#include "monohydra/core/sparse_pattern.hpp"
#include "monohydra/core/tangent_reuse.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "monohydra/cpp/unknowns.hpp"
#include "monohydra/monohydra.h"
#include "monohydra/parameters.h"
#include "plugins/guarded_array.hpp"
#include "plugins/plugin_instance.hpp"
#include "step/signals.hpp"

namespace mh {

// A failed step that a shorter step may cure (see Engine::fail_step).
class StepFailure : public SimulationError {
 public:
  using SimulationError::SimulationError;
};

// A number for a message: 6 significant digits (the SDK's, as plugins write them).
using monohydra::short_number;

// What the host knows about one component instance; its mh_host table points here.
// One plugin instance's side of the host table. Its table's address is the
// handle the instance gets; the host keeps the handles it gave in a registry
// (host_services.cpp) from make_host to this struct's destruction, and every
// service refuses any other: NULL, forged, or kept past the instance.
struct InstanceHost {
  InstanceHost() = default;
  InstanceHost(const InstanceHost&) = delete;
  InstanceHost& operator=(const InstanceHost&) = delete;
  InstanceHost(InstanceHost&&) = delete;
  InstanceHost& operator=(InstanceHost&&) = delete;
  ~InstanceHost();
  Simulation::Engine* engine = nullptr;
  std::string source;   // for log lines: "subsystem 'spring'"
  std::string library;  // the file its factory came from
  std::string label;    // source and library's name, for messages and crash reports
  // The calls the host makes into plugins, each with its site (plugin_call.hpp).
  enum class Op {
    create,
    setup,
    accept,
    begin_step,
    coordinates,
    coupling_jacobian,
    energy,
    evaluate,
    finish_step,
    iteration_done,
    jacobian,
    mechanics_map,
    point_force_jacobian,
    residual,
    restart,
    stage_rates,
    stage_state,
    start,
    tangent,
    write_outputs,
    get_extension,
    save_state,
    load_state,
    parameter,  // monohydra/parameters.h: count, info, get, set
    destroy,
    count
  };
  std::array<PluginCallSite, static_cast<size_t>(Op::count)> sites{};
  void set_library(const std::string& path) {
    static constexpr const char* kNames[] = {"create",
                                             "setup",
                                             "accept",
                                             "begin_step",
                                             "coordinates",
                                             "coupling_jacobian",
                                             "energy",
                                             "evaluate",
                                             "finish_step",
                                             "iteration_done",
                                             "jacobian",
                                             "mechanics_map",
                                             "point_force_jacobian",
                                             "residual",
                                             "restart",
                                             "stage_rates",
                                             "stage_state",
                                             "start",
                                             "tangent",
                                             "write_outputs",
                                             "get_extension",
                                             "save_state",
                                             "load_state",
                                             "parameter",
                                             "destroy"};
    library = path;
    const std::string name = path.substr(path.find_last_of('/') + 1);
    label = name.empty() ? source : source + " of " + name;
    for (size_t i = 0; i < sites.size(); ++i) sites[i] = {label.c_str(), kNames[i]};
  }
  const OptionMap* options = nullptr;
  SourceMark mark;
  std::set<std::string> keys_read;
  enum class Role { formulation, subsystem, integrator } role = Role::subsystem;
  int subsystem = -1;  // index into Engine::subsystems for a subsystem
  bool in_setup = false;
  mh_host table{};
};

// Calls f() (one call into a plugin) with that call marked in flight, for
// a crash handler to name (plugin_call.hpp).
// Where a proxy's destroy is marked in flight (plugin_instance.hpp).
template <class Proxy>
void mark_destroy(Proxy& proxy, const InstanceHost& h) {
  proxy.destroy_site = &h.sites[static_cast<size_t>(InstanceHost::Op::destroy)];
}

template <class F>
auto in_flight(const InstanceHost& h, InstanceHost::Op op, F&& f) {
  const PluginCallScope scope(h.sites[static_cast<size_t>(op)]);
  return f();
}

struct SubsystemInstance {
  const SubsystemSpec* spec = nullptr;
  std::unique_ptr<InstanceHost> host;  // before api: it outlives the instance
  SubsystemProxy api;
  std::vector<int> touched;  // states it may read and add to; own first-call order
  std::vector<BodyPoint> points;
  std::vector<double> p, v;  // 3 per point: the points' motion, read by the instance
  GuardedArray f;            // 3 per point: the forces it writes (evaluate)
  std::vector<int> slots;    // touched x touched: value slots in the tangent (-1: none)
  // The entries of its block it declared (sparsity.h: global state indices,
  // row then column); empty: the block is dense.
  std::vector<std::pair<int, int>> declared;
  // The entries of its block that have a slot: where in d_dy (b k + a), the
  // slot, and the column's state. The tangent is assembled from these alone,
  // so a declared block costs its entries, not k^2.
  struct BlockEntry {
    int local = 0, slot = 0;
  };
  std::vector<BlockEntry> block;  // column by column
  struct BlockColumn {
    int state = 0;              // the column's state
    size_t begin = 0, end = 0;  // its entries in `block`
  };
  std::vector<BlockColumn> block_columns;
  Eigen::ArrayXd undeclared;   // k x k: 1 where a declared block has no entry (empty: dense)
  bool block_checked = false;  // its first jacobian wrote within the declaration
  GuardedArray d_dy, d_dydot;  // its jacobian's blocks
  double power = 0.0;          // sum F . v at the last evaluation
  // Point-force derivatives (3P x 3P, column-major) and the buffers that
  // difference them when the plugin gives none (mechanics_derivatives.cpp).
  GuardedArray dF_dp, dF_dv;
  std::vector<double> p_pert, v_pert, f_base;
  // Its rows' derivatives in its points' motion (k x 3P, row-major) and its
  // point forces' in its states (3P x k, column-major): subsystem_coupling.cpp.
  GuardedArray dR_dp, dR_dv, dF_dy, dF_dydot;
  // Where those couplings go in the tangent, found once (size_coupling):
  // its state rows in the mechanical columns (k x n_m, row-major) and the
  // mechanical rows in its state columns (k x n_m, a state's column by
  // column); -1 where the pattern has no entry (a coordinate that moves none
  // of its points).
  std::vector<int> rows_in_mech, mech_in_cols;
  size_t signals_begin = 0, signals_end = 0;  // its signals in Signals::list (option_signal)
};

// A test hook (Simulation::plant_derivative_error): one entry of one
// instance's derivative arrays scaled where the host receives it from the
// instance's op, so that a test shows `monohydra check` sees a 1 % error in
// any entry. Arrays in kDerivativeArrayNames' order, or the formulation's
// tangent blocks dr/dx, dr/dxd, dr/dxdd (0, 1, 2); neither: none.
struct PlantedError {
  const SubsystemInstance* instance = nullptr;
  bool formulation = false;
  int array = -1;
  size_t entry = 0;
  double factor = 1.0;
};
// The arrays of jacobian (0, 1), coupling_jacobian (2 to 5) and
// point_force_jacobian (6, 7), named as the check names them (subsystem.h).
inline constexpr const char* kDerivativeArrayNames[8] = {"dR/dy", "dR/dydot", "dR/dp", "dR/dv",
                                                         "dF/dy", "dF/dydot", "dF/dp", "dF/dv"};
// After the formulation's tangent op wrote its blocks.
inline void apply_planted(const PlantedError& planted, Eigen::MatrixXd* const blocks[3]) {
  if (!planted.formulation) return;
  Eigen::MatrixXd& b = *blocks[planted.array];
  if (planted.entry < static_cast<size_t>(b.size()))
    b(static_cast<Eigen::Index>(planted.entry)) *= planted.factor;
}
// After the op that wrote `arrays` (array numbers first, first + 1, ...).
template <class Array>
void apply_planted(const PlantedError& planted, const SubsystemInstance& s, int first,
                   std::initializer_list<Array*> arrays) {
  if (planted.instance != &s) return;
  int a = first;
  for (Array* v : arrays) {
    if (a++ == planted.array && planted.entry < v->size()) (*v)[planted.entry] *= planted.factor;
  }
}

// A node of a network (e.g. a hydraulic node): the ports the model joined under
// one name, sharing one effort state.
struct NodePort {
  int subsystem = -1;
  std::string key;
  uint32_t role = MH_PORT_FLOW;
};
struct Node {
  std::string name;
  std::string domain, unit;
  int state = -1;  // its effort's index among the subsystem states
  bool has_initial = false;
  std::vector<NodePort> ports;
  SourceMark mark;  // of the first port naming it
};

// The work of solve_initial_rates (initial_state.cpp), sized by
// classify_states: it runs at time events, inside the time step.
struct RatesWorkspace {
  Eigen::VectorXd f0, f1, fr, dr, du, step;
  Eigen::MatrixXd J, Jr;
  Eigen::FullPivLU<Eigen::MatrixXd> lu;
};

// ConsistentState's Jacobian of the rows in the rate unknowns
// (analysis/state_slots.cpp), equilibrated, factored and kept between its
// calls at one accepted step: a chord Newton on the Jacobian of a nearby
// state converges, and the filters make a state consistent twenty to forty
// times a step. Factored again at another step (so that what a step gives
// does not depend on the steps before: a filter that goes back and steps
// forward again gets the same), by linearize at its own state, when a solve
// on it contracts slowly or fails, or when the scales it was equilibrated
// with change. A workspace: no part of the run's state (a snapshot neither
// saves nor restores it).
struct RateFactorization {
  bool valid = false;
  long step = -1;                                  // the accepted step it was factored at
  Eigen::VectorXd scale, row_scale;                // its columns' and rows' scales
  Eigen::FullPivLU<Eigen::MatrixXd> full, states;  // all rows; the subsystems' block
};

// The parts of the engine's state, each owned by the part of the data flow
// that writes it (the files named); the Engine holds one of each.

// Names, kinds and tolerances of the coordinates, unknowns and outputs
// (simulation.cpp, host_services.cpp).
struct UnknownRegistry {
  std::vector<std::string> coordinate_names;
  std::vector<const char*> coordinate_name_ptrs;
  std::vector<uint8_t> coordinate_is_angle;
  std::vector<std::string> unknown_names;  // n_m, from add_unknown
  std::vector<uint8_t> unknown_kinds;      // n_m
  Eigen::VectorXd unknown_tol;             // n_m
  std::vector<uint8_t> kinds;              // n: mh_unknown_kind of every unknown
  Eigen::VectorXd tol;                     // n: Newton's increment tolerances
  std::vector<VariableInfo> output_info;
  Eigen::VectorXd outputs;      // of the last evaluation (accepted: RunData::outputs)
  std::vector<Visual> visuals;  // what the subsystems declared of their look (monohydra.visual/1)
};

// The subsystems' states, their nodes, the structure of their rates and the
// time events (host_services.cpp, network_nodes.cpp, initial_state.cpp).
struct StateSet {
  std::vector<VariableInfo> state_info;  // n_s: CSV name, qualified name, unit, role
  std::set<std::string> declared_names;  // qualified states and outputs: each once
  Eigen::VectorXd y, ydot;               // of the iterate (accepted: RunData::y, ydot)
  Eigen::VectorXd state_tol;
  std::vector<Node> nodes;
  std::vector<char> algebraic;              // states whose rate no row involves (constructor)
  std::vector<int> rate_states, rate_rows;  // the others, and the rows that involve rates
  RatesWorkspace rates_ws;
  std::vector<double> time_events;  // sorted, unique (constructor)
  // Per event: -1, or the input whose table jumps there (an event only while
  // the input follows its table).
  std::vector<int> time_event_inputs;
};

// The integrator's map of the step (integrator_map.cpp).
struct StepMapState {
  mh_step_map map{};  // the step's map; arrays below
  Eigen::VectorXd x_pred, xd_off, xdd_off;
};

// An explicit integrator's stages (explicit_step.cpp): Newton on the rates,
// x held, with a dense difference Jacobian; and the step's stability
// (explicit_stability.cpp), checked before the first step, after every
// restart and every kStabilityInterval steps. The rates Jacobian Newton may reuse and the checks'
// schedule and findings are the run's (RunData); rates_lu factors RunData::rates_jacobian.
struct ExplicitStages {
  Eigen::VectorXd xs, xds, xdds, r_rates, r_rates_pert, rates_step, rate_scale;
  Eigen::PartialPivLU<Eigen::MatrixXd> rates_lu;
  static constexpr long kStabilityInterval = 1000;
  std::unique_ptr<StageAmplification> amplification;  // its own integrator instance
};

// One evaluation of the mechanics and subsystems (host_services.cpp): where
// its rows go, what it was evaluated at, and the work counted.
struct EvaluationState {
  Eigen::VectorXd scratch_rows;   // rows of evaluations that are not the iterate's
  double* rows_target = nullptr;  // where MH_EVAL_SUBSYSTEMS writes the state rows
  bool iterate_evaluated = false;
  double power = 0.0;                     // of the iterate's evaluation
  Eigen::VectorXd z_iterate, zd_iterate;  // of the last MH_EVAL_SUBSYSTEMS evaluation
  bool kinematics_valid = false;          // data's kinematics are those of data.z, data.zd
  Eigen::VectorXd kin_z, kin_zd;          // kinematics_at's copies (no aliasing with data.z)
};

// Cut-joint constraints (m rows) and the assembled initial state
// (loop_assembly.cpp, host_services.cpp). phi, phi_z hold the constraints at
// RunData::constraint_z when constraint_positions_valid, phi_dot_zd at
// (constraint_z, constraint_zd) when also constraint_rates_valid: a
// formulation asks for them at the same kinematics more than once per
// iteration (its multiplier update, then the residual), and the accepted
// state's measure after its projections.
struct ConstraintState {
  Constraints constraints;
  Eigen::VectorXd phi, phi_dot_zd;
  Eigen::MatrixXd phi_z;
  Eigen::VectorXd z0, zd0;
};

// Derivatives of the mechanics (host service mech_derivatives,
// mechanics_derivatives.cpp).
struct DerivativesWorkspace {
  std::unique_ptr<DynamicsDerivativesWorkspace> dyn_ws;
  std::unique_ptr<ConstraintDerivativesWorkspace> con_ws;
  std::vector<PointForceTerm> force_terms;  // one per (point, other point) of each instance
  Eigen::MatrixXd K, C, dPhizT_v_dz, dA_dz, dA_dzd;
  Eigen::VectorXd saved_outputs, rows_discard, zdd_eval, v_eval;
};

// The step's Newton (newton_solve.cpp): increments, the linear solver and
// real time's limits (full or modified Newton and the step's statistics are
// the run's: RunData::reuse, last_step).
struct NewtonState {
  Eigen::VectorXd dx;
  Eigen::VectorXd dx_trial, dx_correction;  // the line search's (solver.line_search)
  std::unique_ptr<LinearSolver> linear_solver;
  // solver.newton: articulated: Newton's matrix is dxdd_dx M', factored by
  // the articulated-body recursion at every iterate (articulated_solve.hpp).
  std::unique_ptr<ArticulatedWorkspace> articulated;
  int real_time_cap = 0;  // real-time mode: Newton iterations per step at most (0: off)
  std::chrono::steady_clock::time_point step_deadline{};  // real-time mode: wall clock
  // Newton on the exact tangent contracts quadratically, and a linear
  // contraction says the tangent is wrong (TangentReuse::converged); not
  // where the formulation moves its multipliers at each residual call until
  // Phi = 0 (MH_EXT_CONSTRAINED_AT_CONVERGENCE: penalty's augmented
  // Lagrangian), whose iteration is linear by design.
  bool quadratic = true;
};

// The step's tangent (tangent.cpp): its pattern and values, the column
// groups it differences, and the formulation's blocks.
struct TangentWorkspace {
  Eigen::VectorXd r_pert, eps;
  Eigen::VectorXd xd_pert, xdd_pert;             // rates of a perturbed x (forward differences)
  std::shared_ptr<const SparsePattern> pattern;  // shared by the runs of a batch
  std::vector<double> values;
  std::vector<std::vector<int>> groups;
  std::vector<char> group_needs_fd;
  std::vector<char> column_analytic;       // state columns whose ss entries are all analytic
  Eigen::MatrixXd dr_dx, dr_dxd, dr_dxdd;  // n_m x n_m from the formulation's tangent
  std::vector<uint8_t> mech_column_given;  // n_m
  // The formulation's unknowns are the coordinates (MH_EXT_COORDINATE_UNKNOWNS):
  // the mechanical block is the topology's pattern (build_pattern).
  bool coordinate_unknowns = false;
  // Then the mechanical block's pattern alone (n_m columns), for the
  // formulation (sparsity.h, mechanical_pattern/1) and the checks on K and C.
  std::vector<int32_t> mech_column_start, mech_row_index;
  bool any_points = false;          // some subsystem is attached to body points
  Eigen::VectorXd z_base, zd_base;  // the iterate's, kept while the tangent differences
};

// The analytic coupling of subsystems with points to the mechanical
// unknowns (mechanics_map, subsystem_coupling.cpp).
struct CouplingWorkspace {
  bool coupling_possible = false;
  Eigen::MatrixXd map_dz_dx, map_dzd_dx, map_dzd_dxd, map_dzd_total;  // N x n_m
  Eigen::MatrixXd map_dr_dQ;                                          // n_m x N
  Eigen::Matrix<double, 3, Eigen::Dynamic> point_jp, point_jv;        // 3 x N
  Eigen::Matrix<double, 3, Eigen::Dynamic> point_dp_dx, point_dv_dx;  // 3 x n_m
  Eigen::Matrix<double, Eigen::Dynamic, 3> dr_dF;  // n_m x 3: dr/dQ' J_p^T of one point
};

// An instance's part of a snapshot (run_state.cpp), found after setup.
struct StatePart {
  const void* self = nullptr;  // the instance table
  mh_state_extension ext{};    // its MH_EXT_STATE; NULL ops: none
  InstanceHost* host = nullptr;
  bool keeps_state = false;  // a formulation, an integrator, a subsystem with accept
  uint64_t size = 0;         // bytes, fixed after setup
};

// The instances' parts of a snapshot, found at the first one, and the copy
// restore_state takes to undo a load that an instance refuses halfway: kept
// here so that a restore between two steps allocates nothing once sized
// (run_state.cpp).
struct SnapshotParts {
  bool found = false;
  std::vector<StatePart> parts;
  std::string key;  // run_key(), made with the parts
  RunState before;  // the run as it was, while restore_state loads
};

// Forward sensitivities (forward_sensitivities.cpp): the parameters, one
// integrator instance per parameter that carries its column's history
// through the same map, the columns at the accepted state, and the
// workspaces of a step's differences, sized when they are asked for.
struct SensitivityState {
  bool active = false;
  std::vector<ParameterDirection> params;
  std::vector<double> steps;  // per parameter: its value's difference step
  std::vector<IntegratorProxy> shadows;
  std::vector<StepMapState> shadow_maps;
  // Per parameter (columns): the unknowns', at the accepted state.
  Eigen::MatrixXd dx, dxd, dxdd;            // n x k
  Eigen::MatrixXd dz, dzd, dzdd;            // N x k
  Eigen::MatrixXd dy;                       // n_s x k: dx's states
  Eigen::MatrixXd doutputs;                 // n_o x k
  std::vector<char> output_differentiated;  // n_o
  // The formulation converges on Phi(z) = 0 (its multipliers iterated): the
  // step's linear system is bordered by Phi_z.
  bool bordered = false;
  Eigen::MatrixXd border, border_solved, schur;  // n x m, n x m, m x m
  Eigen::PartialPivLU<Eigen::MatrixXd> schur_lu;
  mh_state_extension formulation_state{};
  std::vector<unsigned char> before_step, after_step;  // the formulation's state bytes
  // A step's work: buffers the differences and the solves fill and read
  // within one step, sized once (nothing of the run's state).
  struct Work {
    Eigen::VectorXd xs, xds, xdds;  // the converged iterate, before accept corrects it
    Eigen::VectorXd xdq, xddq, rp, rm, col, outputs_saved, y_saved, ydot_saved;
    Eigen::VectorXd xp, xdp, xddp, xm, xdm, xddm;
    Eigen::VectorXd zp, zdp, zddp, zm, zdm, zddm, outp, outm;
    Eigen::MatrixXd rhs;            // n x k
    Eigen::VectorXd mu, mu_solved;  // m: the border's multipliers of one column
    double t_eval = 0.0;            // the step's evaluation time (an event's left limit)
  } work;
  // The model's values a parameter's difference moves, as they were.
  struct BodyValues {
    double mass = 0.0;
    Eigen::Vector3d com = Eigen::Vector3d::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    double z0 = 0.0, zd0 = 0.0;
  };
  std::vector<BodyValues> saved_bodies;
  Eigen::Vector3d saved_gravity = Eigen::Vector3d::Zero();
  // Per parameter: the component option it moves (parameters.h), found
  // when tracking begins; instance -1: none.
  struct ComponentOption {
    int instance = -1;
    uint32_t index = 0;
    mh_parameters_extension ext{};  // the component's parameter `index`,
    double* constant = nullptr;     // or a number it reads as a signal (signals.hpp)
    double saved = 0.0;
  };
  std::vector<ComponentOption> options;
  // The shadows' factory: the run's integrator's (the registry outlives the run).
  const ComponentInfo* integrator_info = nullptr;
};

// What the step works in and recomputes from the run's data: nothing here
// is part of a run's state (a snapshot neither saves nor restores it).
struct Workspace {
  Eigen::VectorXd r;  // Newton's residual
  StepMapState map_ws;
  ExplicitStages stages;
  EvaluationState eval;
  DerivativesWorkspace derivs;
  NewtonState solver;
  TangentWorkspace tangent_ws;
  CouplingWorkspace coupling;
  SnapshotParts snapshot;
  RateFactorization rate_factor;  // analysis/state_slots.cpp
};

// What the plugins said (host_services.cpp): their log lines, the last
// error one logged and the first bad option one reported.
struct PluginReports {
  LogSink log;
  std::string last_plugin_error;
  std::unique_ptr<InputError> option_error;
};

struct Simulation::Engine {
  explicit Engine(const Model& source) : model(source), data(model) {}
  const ModelFile* file = nullptr;
  Model model;
  Data data;
  SolverSettings settings;
  PluginReports reports;

  // Formulation: its n_m unknowns are the first entries of the Newton vector.
  std::string formulation_name;
  std::unique_ptr<InstanceHost> formulation_host;  // outlives the instance
  FormulationProxy formulation;
  // Integrator: applied by the host to all n unknowns; an explicit one
  // (explicit_step.cpp) has no map, and the host solves the rates at its
  // stages, through its own operations.
  std::string integrator_name;
  std::unique_ptr<InstanceHost> integrator_host;  // outlives the instance
  IntegratorProxy integrator;
  bool explicit_method = false;
  mh_explicit_method explicit_ops{};
  // Subsystems and their states (the last n_s unknowns).
  std::vector<SubsystemInstance> subsystems;

  int N = 0;    // joint coordinates
  int m = 0;    // constraint rows
  int n_m = 0;  // mechanical unknowns
  int n_s = 0;  // subsystem states
  int n = 0;    // unknowns: n_m + n_s
  int n_o = 0;  // outputs
  // What the step changes: Newton's unknowns x = [formulation unknowns;
  // subsystem states] and their rates, the accepted point, the states,
  // inputs, counters and what Newton keeps (run_state.hpp). A snapshot is
  // its copy.
  RunData run;
  Workspace work;

  UnknownRegistry registry;
  StateSet states;
  Signals signals;  // components' time signals and the model's inputs (signals.hpp)
  ConstraintState cons;
  SensitivityState sens;
  PlantedError planted;  // tests of the checks only (analysis/subsystem_blocks.cpp)
  // Component options resolved once (Simulation::component_parameter_handle).
  struct OptionHandle {
    std::string path;
    SensitivityState::ComponentOption option;
  };
  std::vector<OptionHandle> option_handles;

  // host_services.cpp
  void make_host(InstanceHost& h, const std::string& source, const OptionMap* options,
                 const SourceMark& mark, InstanceHost::Role role, int subsystem);
  void check_unread_options(const InstanceHost& h) const;
  // A new state of the run; returns its index.
  int add_state_record(const VariableInfo& info, double initial, double abs_tolerance);
  mh_status evaluate_mechanics(uint32_t flags, double t_eval, const double* zq, const double* zdq);
  mh_status evaluate_loads(uint32_t flags, double t_eval, const double* zq, const double* zdq);
  // forward_kinematics at (zq, zdq) unless `data` holds them already; counted.
  void kinematics_at(const double* zq, const double* zdq);
  // phi, phi_z, phi_dot_zd at the kinematics in `data`, unless they hold them already.
  void constraints_at_kinematics(bool rates = true);
  // Evaluates every subsystem at the kinematics in `data` and the current y,
  // ydot, adding rows to `rows` (zeroed first) and forces to the bodies.
  mh_status evaluate_subsystems(double t_eval, double* rows);
  // The evaluation record every subsystem call gets: current states, rates and
  // outputs, `rows` for the residual; point_at() fills in one instance's points.
  mh_subsystem_eval subsystem_eval(double t_eval, double* rows);
  static void point_at(mh_subsystem_eval& ev, SubsystemInstance& s);

  // network_nodes.cpp: ports joined into nodes, and their checks after setup.
  mh_status add_port(InstanceHost& h, const mh_port_spec& spec, int32_t* index);
  void check_network() const;

  // initial_state.cpp: consistent initial states at t = 0.
  void classify_states();
  void solve_initial_rates(double t_eval);
  void solve_algebraic_and_equilibrium();

  // loop_assembly.cpp: the constraints, then z0 and zd0 made consistent with
  // them (close_loops again when a parameter moves the model's z0, zd0).
  void assemble_loops();
  void close_loops();

  // integrator_map.cpp: the integrator's map from x to its rates.
  void begin_step(double t_next, double h);
  void formulation_begin_step(const mh_step_coefficients& coefficients, double t_next,
                              const Eigen::VectorXd& xq, const Eigen::VectorXd& xdq,
                              const Eigen::VectorXd& xddq);
  void rates_of(const Eigen::VectorXd& xq, Eigen::VectorXd& xdq, Eigen::VectorXd& xddq) const;
  void restart_integrator();  // from x, xd, xdd at t
  // The state rates at the right limit of the accepted time, after a jump of
  // a signal there (a time event, an input set between steps).
  void rates_after_jump();
  // An input set between steps changed: the next step starts as after a time
  // event at the accepted time (rates at the right limit, the integrator
  // restarted).
  void apply_input_jump();

  // explicit_stability.cpp
  void check_explicit_stability(double h);
  std::vector<std::complex<double>> rates_eigenvalues(double t_eval, double h);

  // explicit_step.cpp: one step of an explicit integrator, and the rates
  // f(t, x) it combines.
  void size_explicit();
  void explicit_attempt(double t_eval, double h);
  // Solves r(x, xd, xdd) = 0 at t_eval for xdd (second-order unknowns), xd
  // (first-order) and x (algebraic), the rest held; ends with a residual
  // evaluation at the solution (the step's record when it is the end's).
  void solve_rates(double t_eval, double h, Eigen::VectorXd& xq, Eigen::VectorXd& xdq,
                   Eigen::VectorXd& xddq);

  // mechanics_derivatives.cpp
  void size_derivatives();
  mh_status mechanics_derivatives(const mh_mech_derivatives_request& rq);

  // solver.newton: articulated and auto (simulation.cpp): refused where it
  // does not apply, else its workspace; auto's choice.
  std::string articulated_refusal() const;
  NewtonKind automatic_newton() const;
  void size_articulated();

  // subsystem_coupling.cpp
  void size_coupling();
  mh_status read_mechanics_map();
  mh_status couple_subsystems(double t_eval);

  // tangent.cpp
  void build_pattern();
  mh_status assemble_tangent(double t_eval);
  void check_formulation_blocks() const;  // the entries the host reads, each finite
  void check_tangent_values() const;      // the assembled values, then who wrote one
  // Inside a host service no exception may reach the plugin: the reason is
  // kept in last_plugin_error and the service returns MH_ERROR.
  mh_status refuse_nonfinite_derivatives();
  bool derivatives_finite() const;  // K and C, on the mechanical pattern when there is one
  // r(x): the formulation's rows (which evaluate the subsystems' rows) at the
  // rates the integrator's map gives x.
  mh_status residual(double t_eval, const Eigen::VectorXd& xq, Eigen::VectorXd& rq);
  // r(x, xd, xdd) at rates given: the one call of the formulation's residual
  // (residual, explicit stages, the check's blocks), with the subsystems'
  // rows routed into rq and the ABI's evaluate_mechanics contract checked.
  mh_status residual_at(double t_eval, const Eigen::VectorXd& xq, const Eigen::VectorXd& xdq,
                        const Eigen::VectorXd& xddq, Eigen::VectorXd& rq);

  // newton_solve.cpp
  void newton_solve(double t_eval, double t_next);

  // time_step.cpp
  void start();      // start_run(), with the sensitivities' initial columns when tracked
  void start_run();  // the consistent initial state
  void step_once();
  void find_state_parts();
  std::string run_key() const;
  void save_state(RunState& into);
  void restore_state(const RunState& from);
  void advance(double t_to, int halvings_left);
  void attempt(double t_next);
  void prepare_step(double t_next, double h);
  void accept_step(double t_next, bool event, double h, double t_eval);

  // forward_sensitivities.cpp
  void track_sensitivities(const std::vector<ParameterDirection>& parameters);
  // The model's values moved by `amount` times parameter j's direction, and
  // back as they were.
  // The subsystem instance named `name` (std::invalid_argument starting with `path`).
  int subsystem_instance(const std::string& name, const std::string& path) const;
  // Its parameters extension into `ops` (null entries: none) and the keys,
  // in its order ("" for one it did not describe).
  std::vector<std::string> parameter_keys(int instance, mh_parameters_extension& ops);
  SensitivityState::ComponentOption find_component_option(const ParameterDirection& p);
  void perturb_parameter(size_t j, double amount);
  void restore_parameter(size_t j);
  double difference_step(size_t j, const Eigen::VectorXd& at, double largest_move) const;
  void start_sensitivities();  // start_run() at p +- step, then at p: the initial columns
  void restart_shadow(size_t j);
  void save_formulation_state(std::vector<unsigned char>& into);
  void load_formulation_state(const std::vector<unsigned char>& from);
  void sensitivities_before_accept(double t_eval, double t_next, double h);
  void replay_accept(size_t j, double amount, double t_next, bool plus);
  void sensitivities_after_accept(double t_next, uint32_t flags, bool event);

  // energy_balance.cpp
  // The subsystems' stored energy and dissipated power at the accepted state;
  // with `per_instance`, each instance's dissipation too (0 without an energy op).
  void energy_terms(double& stored_out, double& dissipation_out, double* per_instance = nullptr);
  void start_energy_balance();
  void update_energy_balance(double h);
  void measure_mechanism();  // KE, PE, phi_norm at the accepted z, zd

  [[noreturn]] void fail(const std::string& reason) const;
  // A failure of this step that a shorter one may cure (Newton, a discarded
  // evaluation): retried by advance() while halvings are left.
  [[noreturn]] void fail_step(const std::string& reason) const;
  // Every value a plugin writes is checked where it crosses into the host:
  // the first non-finite one of `count` at `values` stops the step naming
  // the instance, its library, the call, what it wrote and the index. Within
  // the step's iteration (`retryable`) a shorter step may cure it; once the
  // step is being accepted it ends the run.
  void check_finite(const double* values, size_t count, const InstanceHost& writer,
                    const char* call, const char* what, bool retryable = true) const {
    if (all_finite(values, count)) return;
    const size_t i = first_nonfinite(values, count);  // < count: the two agree
    if (i < count) fail_nonfinite(values[i], i, writer, call, what, retryable);
  }
  // v * 0 is 0 for a finite v and NaN otherwise: one pass without a branch
  // per entry; the entry is looked for only when one is not finite.
  static bool all_finite(const double* values, size_t count) {
    double zero = 0.0;
    for (size_t i = 0; i < count; ++i) zero += values[i] * 0.0;
    return zero == 0.0;
  }
  // The index of the first non-finite value, or `count` when there is none.
  static size_t first_nonfinite(const double* values, size_t count) {
    size_t i = 0;
    while (i < count && std::isfinite(values[i])) ++i;
    return i;
  }
  // The message naming a non-finite value's writer, call, what and index.
  std::string nonfinite_reason(double value, size_t index, const InstanceHost& writer,
                               const char* call, const char* what) const;
  [[noreturn]] void fail_nonfinite(double value, size_t index, const InstanceHost& writer,
                                   const char* call, const char* what, bool retryable) const;
  // An instance wrote past the end of `array` in `call`: the run stops
  // (the memory after it is the host's, so no retry), naming them; the
  // guard is set again first.
  [[noreturn]] void fail_overrun(GuardedArray& array, const InstanceHost& writer, const char* call,
                                 const char* what) const;
  // After `call` of `writer` that wrote `arrays`: stops the run at the first
  // whose guard it changed.
  void check_guards(const InstanceHost& writer, const char* call,
                    std::initializer_list<std::pair<GuardedArray*, const char*>> arrays) const {
    for (const auto& [array, what] : arrays)
      if (!array->intact()) fail_overrun(*array, writer, call, what);
  }
  // The outputs of the step's evaluation, each checked and named by its owner.
  void check_outputs(const char* when) const;
  std::string status_reason(mh_status s, const std::string& what) const;
  std::string unknown_name(int i) const;
  // Throws SimulationError naming the plugin and the operation when `s` is
  // not a success (one place for every plugin call of the step).
  void check(mh_status s, const std::string& what) const {
    if (status_ok(s)) return;
    if (s == MH_DISCARD) fail_step(status_reason(s, what));
    fail(status_reason(s, what));
  }
  // The same for the time step's calls: the message is made only on failure
  // (a std::string of a literal would allocate at every call).
  void check(mh_status s, const char* what) const {
    if (status_ok(s)) return;
    check(s, std::string(what));
  }
  // ... naming an instance: "PREFIX 'NAME' SUFFIX".
  void check(mh_status s, const char* prefix, const std::string& name, const char* suffix) const {
    if (status_ok(s)) return;
    check(s, std::string(prefix) + " '" + name + "' " + suffix);
  }
  // The plugin that made state row `row` non-finite at the kinematics in data.
  std::string nonfinite_source(int row);
};

// One subsystem's evaluate at ev.t, its signals written first: every evaluate
// the host makes goes through here. Inline: it runs for every instance at
// every evaluation of the step, most of them with no signal.
// Writes the instance's signals (option_signal, option_signal_port) at `ev`:
// before every call that reads them (evaluate, jacobian, coupling_jacobian,
// energy, accept), so each sees the values of its own time and states.
// The model file's Newton kind as the tangent's reuse rule.
inline TangentReuse::Mode reuse_mode(NewtonKind kind) {
  switch (kind) {
    case NewtonKind::modified:
      return TangentReuse::Mode::modified;
    case NewtonKind::per_step:
      return TangentReuse::Mode::per_step;
    case NewtonKind::articulated:
      return TangentReuse::Mode::approximate;
    case NewtonKind::automatic:  // resolved at setup; per-step until then
      return TangentReuse::Mode::per_step;
    case NewtonKind::full:
      break;
  }
  return TangentReuse::Mode::full;
}

inline void refresh_signals(SubsystemInstance& s, const mh_subsystem_eval& ev) {
  if (s.signals_begin != s.signals_end)
    s.host->engine->signals.refresh(s.signals_begin, s.signals_end, ev.t, ev.y,
                                    s.host->engine->run);
}

inline mh_status evaluate_instance(SubsystemInstance& s, const mh_subsystem_eval& ev) {
  refresh_signals(s, ev);
  const mh_status st = in_flight(*s.host, InstanceHost::Op::evaluate,
                                 [&] { return s.api.ops.evaluate(s.api.self, &ev); });
  if (!s.f.intact()) s.host->engine->fail_overrun(s.f, *s.host, "evaluate", "point forces");
  return st;
}

}  // namespace mh
