// The monohydra test host: loads ONE plugin library and drives a component of
// it (a formulation, a subsystem or an integrator) through its contract on a
// small model the test gives, without the command line, for plugin authors'
// unit tests with GoogleTest or any other framework (docs/plugin-guide.md).
// `monohydra check` is this library's check_library(): one implementation.
//
// Installed as lib/libmonohydra_testhost.so with the CMake target
// monohydra::testhost of find_package(monohydra_sdk 2). The engine (model
// files, Simulation, Eigen) is linked privately: this header is the whole
// API, C++17 and the standard library only. Every function reports a failure
// of the plugin as a value; std::runtime_error is thrown only for a library
// that cannot be loaded or a model that cannot be read (with its file, line
// and field), i.e. for a broken test.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#if defined(__GNUC__)
#define MONOHYDRA_TESTHOST_API __attribute__((visibility("default")))
#else
#define MONOHYDRA_TESTHOST_API
#endif

namespace monohydra::testhost {

enum class Kind { formulation, subsystem, integrator };
MONOHYDRA_TESTHOST_API const char* to_string(Kind kind);

// A model file: its YAML text (labelled `label` in error messages) or a path.
struct Model {
  std::string yaml;   // the text of a model file, or "" for `path`
  std::string path;   // a model file, read when yaml is ""
  std::string label;  // names the text in errors ("" = "<test model>")
  static Model text(std::string yaml_text, std::string label = "") {
    return Model{std::move(yaml_text), "", std::move(label)};
  }
  static Model file(std::string file_path) { return Model{"", std::move(file_path), ""}; }
};

// One line of a contract check.
struct Check {
  enum class Verdict { passed, failed, skipped, note };
  Verdict verdict;
  std::string what;    // "formulation penalty: create/setup/destroy x3"
  std::string detail;  // why it failed or was skipped, or what it did
};

struct CheckReport {
  std::vector<Check> checks;
  bool loaded = false;     // false: the library was refused (see the "load" check)
  bool bad_model = false;  // the model given could not be read (see the last check)
  int failures() const {
    int n = 0;
    for (const Check& c : checks) n += c.verdict == Check::Verdict::failed ? 1 : 0;
    return n;
  }
  bool passed() const { return loaded && !bad_model && failures() == 0; }
};

// Where a check finds the model of a component when the test gives none, and
// the other components a model needs.
struct CheckOptions {
  // Folders scanned for the model's other components after the model's own
  // plugin_paths; empty: $MONOHYDRA_PLUGIN_PATH, the plugins installed beside
  // this library (lib/monohydra/plugins) and the install prefix's.
  std::vector<std::string> search_path;
  // Models tried, in order, for a formulation or an integrator that declares
  // no example model (docs/sdk.md): the first it accepts. Empty: the
  // shipped four-bar, then the double pendulum (a tree).
  std::vector<std::string> fallback_models;
  // The folder whose models (smallest first) a subsystem that declares no
  // example model is checked on: the first that uses it. Empty: the shipped
  // models (share/monohydra/models beside this library).
  std::string models_folder;
  // Called with every line as it is decided (the command line prints them).
  std::function<void(const Check&)> on_check;
  // The times (s, from the run's start) at which a subsystem's derivative
  // blocks and a formulation's tangent blocks are compared with their
  // differences (`monohydra check --at`). Empty: the prediction of the first
  // step, after 3 steps, a third and two thirds into the model's run and its
  // last step (at most 2000 steps in).
  std::vector<double> at;
};

// Every component of `library` through every check `monohydra check` runs:
// loading (probe, ABI version, struct sizes, init), descriptors,
// create/setup/destroy cycles, bad options refused, the analytic tangent
// against differences of the plugin's own residual, bit-identical reruns;
// each check in a child process, so a crash or an exception across the C
// boundary is that check's failure. On `model` when given (path or text),
// else on each component's declared example model, else the fallbacks.
MONOHYDRA_TESTHOST_API CheckReport check_library(const std::string& library, const Model* model,
                                                 const CheckOptions& options = {});

// A run's time series: t, then every column below, one row per step.
struct Series {
  // Columns: the joint coordinates (z1, ...), their rates (z1_dot, ...), the
  // declared states and outputs under their result names (e.g. "acc.p"), and
  // the run's energy terms and constraint residual: "kinetic_energy",
  // "potential_energy", "stored_energy", "dissipated_energy", "work",
  // "drift", "phi_norm".
  std::vector<std::string> names;
  std::vector<std::string> units;         // parallel to names ("" when none)
  std::vector<double> time;               // s, from 0: the initial state, then each step
  std::vector<std::vector<double>> rows;  // rows[k][j]: column j at time[k]
  bool ok = false;                        // the run reached its last step
  std::string status;                     // "ok", or how and where it failed
  // Column `name` over time; throws std::out_of_range naming it when absent.
  MONOHYDRA_TESTHOST_API std::vector<double> column(const std::string& name) const;
  MONOHYDRA_TESTHOST_API bool has(const std::string& name) const;
};

// The analytic tangent against central differences of the residual, entry by
// entry, at the model's dt and at a coarse step where K and C show beside
// c_a M'. Each entry is compared at its own scale: its magnitude, but at
// least 1e-3 of the geometric mean of its row's and its column's largest
// (so rows and columns in other units, a pressure's beside a stroke's, are
// each seen), and never below ten times the differences' own estimated error.
struct TangentComparison {
  bool ok = false;          // max_error within `tolerance` at both steps
  double max_error = 0.0;   // worst |analytic - differences| / the entry's scale
  double tolerance = 0.0;   // what `monohydra check` accepts (1e-3)
  double worst_step = 0.0;  // s: the step (of the two) where the worst entry is
  std::string worst;        // the worst entry: step, row, column, both values
  std::string failure;      // when the comparison could not be made ("" otherwise)
  // Both matrices at each step, n x n column-major: the assembled tangent and
  // central differences of the residual (steps[0] is the model's dt).
  struct Sample {
    double step = 0.0;  // s
    int n = 0;
    std::vector<double> analytic, differences;
  };
  std::vector<Sample> samples;
};

// Host::planted_errors' account.
struct PlantedErrors {
  int planted = 0;  // entries planted (instance, block, row, column), each once
  // Those that no instant's comparison saw though at one of them the
  // differences could show 1 %: "dR/dy of subsystem 'v1': row v1.x, column
  // v1.p_A".
  std::vector<std::string> missed;
  // Those no instant saw because at each the differences were too noisy to
  // show 1 % of it (the check's line warns of such entries).
  std::vector<std::string> too_noisy;
  // Why nothing could be planted: the blocks fail unplanted, the component
  // is no subsystem, or the run failed ("" otherwise).
  std::string failure;
};

// The ids of the components of one kind that `library` offers, in its
// order. Throws std::runtime_error when the library is refused.
MONOHYDRA_TESTHOST_API std::vector<std::string> component_ids(const std::string& library,
                                                              Kind kind);

// The host for one component of one library. The library is loaded (probed
// in a child process first, then ABI version and init) and the component
// chosen over any other library offering the same id; the model's other
// components come from its plugin_paths and the search path.
class MONOHYDRA_TESTHOST_API Host {
 public:
  // Throws std::runtime_error when the library is refused (with the reason)
  // or does not offer `id`.
  Host(const std::string& library, const std::string& id,
       std::vector<std::string> search_path = {});
  ~Host();
  Host(const Host&) = delete;
  Host& operator=(const Host&) = delete;

  Kind kind() const;
  const std::string& id() const;
  std::string version() const;  // the descriptor's
  // The component's declared example model, or "" when it declares none.
  std::string example_model() const;

  // A formulation or an integrator replaces the model's; a subsystem must be
  // used by the model. dt, t_end of the model unless given (> 0).
  // `cycles` times: build the run, start it, destroy it. "" or the failure.
  std::string create_destroy(const Model& model, int cycles = 3) const;
  // `steps` steps of the model's dt (or `dt`): the series and the status. A
  // failing plugin gives ok = false and the reason, never an exception; an
  // unreadable model throws.
  Series run(const Model& model, int steps, double dt = 0.0) const;
  // After `steps_before` steps: the assembled analytic tangent against
  // forward differences of the residual.
  TangentComparison tangent(const Model& model, int steps_before = 3) const;
  // The contract checks of `monohydra check` for this component alone.
  CheckReport check(const Model& model) const;
  // How strong `check`'s comparison of a subsystem's own derivative blocks
  // or a formulation's tangent blocks is on this model: each nonzero entry
  // (above 1e-12 of the geometric mean of its row's and column's largest:
  // not a rounding residue)
  // of each block the ops give (a subsystem's jacobian, coupling_jacobian,
  // point_force_jacobian: dR/dy, dR/dydot, dR/dp, dR/dv, dF/dy, dF/dydot,
  // dF/dp, dF/dv; a formulation's tangent: dr/dx, dr/dxd, dr/dxdd in the
  // columns it gives) is multiplied by `factor` where the host receives it,
  // one at a time, at each instant `check` compares at; an entry is seen
  // when its block then fails the comparison at one of them. A mutation
  // test of the check on the author's own derivatives: what it would miss.
  PlantedErrors planted_errors(const Model& model, double factor = 1.01) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace monohydra::testhost
