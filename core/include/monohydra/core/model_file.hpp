// Model files: YAML (yaml-cpp) to a Model plus the specification of its
// subsystems, formulation and solver. Every error is an InputError naming the
// file, line, field and what was expected. Format: docs/model-format.md.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "monohydra/core/explicit_stability.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/linear_solver.hpp"
#include "monohydra/core/model.hpp"

namespace mh {

// One option of a component as written in the model file (SI units).
struct OptionValue {
  enum class Kind { number, string, table };
  Kind kind = Kind::number;
  double number = 0.0;
  std::string text;           // string value, or the scalar's text for error messages
  std::vector<double> table;  // row-major; a flat list of numbers is one row
  int rows = 0;
  int columns = 0;
  SourceMark mark;
};
using OptionMap = std::map<std::string, OptionValue>;

struct PointSpec {
  BodyPoint point;  // body index into Model::bodies (kGround for the ground)
  SourceMark mark;
};

// A port of a subsystem joined to a named node of a network (e.g. a hydraulic
// node: every port naming it shares its pressure).
struct PortSpec {
  std::string node;
  SourceMark mark;
};

struct SubsystemSpec {
  std::string name;                         // unique among subsystems
  std::string type;                         // component id, e.g. "spring-damper"
  OptionMap options;                        // every key but name, type, points, states, outputs
  std::map<std::string, PointSpec> points;  // points/<key>
  std::map<std::string, PortSpec> ports;    // ports/<key>: node
  std::map<std::string, std::string> state_names;   // states/<local>: column ("" hidden)
  std::map<std::string, std::string> output_names;  // outputs/<local>: column ("" hidden)
  std::map<std::string, SourceMark> column_marks;   // "states.<local>", "outputs.<local>"
  SourceMark mark;
};

// A formulation or an integrator as the model file chooses it: an id and its options.
struct ComponentChoice {
  std::string name;
  OptionMap options;
  SourceMark mark;
};

// inputs/<i>: a named signal set from outside the run (the embedding API,
// a co-simulation master) that component options take in place of a time
// table (a valve's reference: NAME). Until something sets it, it follows its
// table, or holds its initial value.
struct InputSpec;

// sensors: an instrument on the machine (docs/model-format.md): it reads a
// column `run` writes, sampled at its rate, late by its delay, offset by its
// bias and with white noise of its standard deviation, each in the SI unit
// of that column whatever the file's units: say.
struct SensorSpec {
  std::string name;
  std::string measures;  // a result column: z1, p2, U, a named state or output
  double noise = 0.0;    // standard deviation
  double rate = 0.0;     // Hz; 0: every step
  double delay = 0.0;    // s
  double bias = 0.0;
  SourceMark mark, measures_mark, rate_mark, delay_mark;
};

struct InputSpec {
  std::string name;
  std::string unit;             // as declared (informative; the value is SI)
  double min = 1.0, max = 0.0;  // range: [min, max]; min > max: none declared
  bool clamp = false;           // out_of_range: clamp (true) or refuse
  double initial = 0.0;         // the value at t = 0 (its table's, when it has one)
  std::vector<double> table;    // rows [t, value], row-major; empty: none
  SourceMark mark;
};

// How Newton treats its tangent (tangent_reuse.hpp): `full` assembles and
// factors it at every iteration; `per_step` once per step, at the prediction,
// for all of the step's iterations; `modified` keeps the factorization across
// iterations and steps while the iteration contracts fast enough;
// `articulated` assembles none and takes the mass matrix, factored by the
// articulated-body recursion at every iterate, as Newton's matrix (a tree's
// equations of motion only); `automatic` is articulated where it applies to a
// deep tree and per-step otherwise, decided when the run is set up.
enum class NewtonKind { full, modified, per_step, articulated, automatic };
// "full", "modified", "per-step", "articulated", "auto"
const char* to_string(NewtonKind kind);

struct SolverSettings {
  double dt = 1e-3;            // s
  double t_end = 10.0;         // s
  int max_iterations = 25;     // Newton iterations per step before giving up
  int max_step_halvings = 0;   // a failed step is retried as two halves, this deep at most
  double tol_position = 1e-7;  // rad or m: Newton increment tolerance on coordinates
  LinearSolverKind linear = LinearSolverKind::klu;  // the tangent's linear solver
  // The fastest kind that passes every accuracy test (docs/performance.md);
  // the paper's comparison pins full Newton (models/paper-reference.yaml). A
  // Simulation's settings() hold the kind `automatic` chose.
  NewtonKind newton = NewtonKind::automatic;
  // solver.line_search: the time step's Newton damped (newton.hpp's
  // NewtonDamping): off by default, so that results stay as they are. It
  // damps full Newton only: on, it makes full Newton the default.
  bool line_search = false;
  // An explicit integrator's step beyond its stability bound (explicit_stability.hpp).
  ExplicitStabilityPolicy explicit_stability = ExplicitStabilityPolicy::warn;
  SourceMark mark;
  SourceMark dt_mark, t_end_mark;  // where the file writes them (line 0: it does not)
};

// output: which result columns a run writes, and how often (the command
// line's --output-interval overrides the interval). Checked against the run's
// columns and time step when the run is set up (csv_layout.hpp).
struct OutputSettings {
  double interval = 0.0;             // s: rows at multiples of it only; 0: every step
  std::vector<std::string> columns;  // in this order; empty: every column
  std::vector<SourceMark> column_marks;
  SourceMark mark, interval_mark;
};

// The components a model file that names none gets (docs/model-format.md):
// the one place they are named; hosts ask here.
inline constexpr const char* kDefaultFormulation = "open-loop";
inline constexpr const char* kDefaultIntegrator = "trapezoidal";

// bodies/<i>/shape: what the body looks like, in its own frame (a host draws
// it; its mass properties come from it unless com and inertia are given).
struct BodyShape {
  enum class Kind {
    none,      // no shape given: a host draws a default glyph
    beam,      // a slender bar from the joint point along +x: size (length, 0, 0)
    cuboid,    // a cube of side size.x centred on the joint point
    box,       // a box of sides size centred on `at` (the joint point by default)
    cylinder,  // a solid cylinder from the joint point along +x: size (length, radius, radius)
  };
  Kind kind = Kind::none;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // m
  Eigen::Vector3d at = Eigen::Vector3d::Zero();    // m, body frame: a box's centre
};
const char* to_string(BodyShape::Kind kind);  // "none", "beam", ...

struct ModelFile {
  std::string path;    // as given
  std::string folder;  // absolute: what relative paths in it are relative to
  Model model;
  std::vector<SourceMark> body_marks;  // parallel to model.bodies
  std::vector<BodyShape> body_shapes;  // parallel to model.bodies
  SourceMark assembly_mark;            // assembly.fixed (the file alone when absent)
  std::vector<SubsystemSpec> subsystems;
  ComponentChoice formulation{kDefaultFormulation, {}, {}};
  ComponentChoice integrator{kDefaultIntegrator, {}, {}};
  SolverSettings solver;
  OutputSettings output;
  // compare/formulations and compare/integrators: what `compare` runs by default.
  std::vector<std::string> compare_formulations, compare_integrators;
  std::vector<std::string> plugin_paths;  // absolute, resolved against the file's folder
  // plugins: component id -> the library (absolute file path) to take it from
  // when several libraries offer it.
  std::map<std::string, std::string> plugin_libraries;
  // nodes/<node>: the result column of a node's effort ("" hidden); unlisted
  // nodes are written under their own name.
  std::map<std::string, std::string> node_columns;
  SourceMark nodes_mark;
  // equilibrium/free: states (result columns or "instance.state" names) the
  // host solves at t = 0 so that the system starts at rest.
  std::vector<std::string> equilibrium_free;
  std::vector<SourceMark> equilibrium_marks;
  std::vector<InputSpec> inputs;    // inputs:, in file order
  std::vector<SensorSpec> sensors;  // sensors:, in file order
};

// Reads and validates a model file. Throws InputError.
ModelFile load_model_file(const std::string& path);
// The same from text; `file_label` names it in errors, `base_dir` resolves
// relative plugin paths.
ModelFile parse_model_text(const std::string& yaml_text, const std::string& file_label,
                           const std::string& base_dir = ".");

}  // namespace mh
