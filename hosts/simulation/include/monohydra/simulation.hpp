// monohydra's embedding API for C++17 (header-only, over simulation.h): the
// same calls as objects that free what they own and throw monohydra::Error
// (the status and the library's message) where the C call returns a status
// other than MHS_OK or MHS_WARNING. Nothing here is compiled into the
// library: a program that includes it links monohydra::simulation alone.
//
//   monohydra::Simulation sim = monohydra::Simulation::open_file("models/fourbar.yaml");
//   const uint32_t command = sim.find("valve_command");
//   while (sim.time() < 10.0) {
//     sim.set(command, my_controller(sim.get(sim.find("s"))));
//     sim.step();
//   }
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "monohydra/simulation.h"

namespace monohydra {

// A call that did not succeed: its status (MHS_ERROR or MHS_FATAL) and why.
class Error : public std::runtime_error {
 public:
  Error(mhs_status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  mhs_status status() const { return status_; }

 private:
  mhs_status status_;
};

// One variable of a run (mhs_variable_info), its strings copied.
struct Variable {
  mhs_kind kind = MHS_COORDINATE;
  std::string name, qualified, unit;
  double min = 0.0, max = -1.0;  // min > max: no range declared
};

// The whole state of a run between two steps (mhs_snapshot).
class Snapshot {
 public:
  mhs_snapshot* handle() const { return handle_.get(); }

 private:
  friend class Simulation;
  struct Free {
    void operator()(mhs_snapshot* s) const { mhs_snapshot_free(s); }
  };
  explicit Snapshot(mhs_snapshot* s) : handle_(s) {}
  std::unique_ptr<mhs_snapshot, Free> handle_;
};

// What an estimator is told (mhs_estimator_options): the filter, the
// parameters estimated beside the state, and the noise of states or
// parameters where the defaults will not do (NaN keeps a default).
struct EstimatorOptions {
  std::string filter = "ekf";  // or "ukf"
  std::vector<std::string> params;
  struct Noise {
    std::string name;  // a state's name or a parameter's path
    double plant = std::numeric_limits<double>::quiet_NaN();
    double initial = std::numeric_limits<double>::quiet_NaN();
  };
  std::vector<Noise> noise;
};

// A Kalman filter driving a run (mhs_estimator_*), made by
// Simulation::estimator(); the run must outlive it.
class Estimator {
 public:
  // The readings at time t, one per sensor (NaN: no sample): the run
  // stepped to t and corrected.
  void update(double t, const std::vector<double>& readings) {
    check(mhs_estimator_update(sim_, get(), t, readings.data(), readings.size()));
  }
  std::vector<std::string> states() const { return names(MHS_ESTIMATOR_STATE, false); }
  std::vector<std::string> state_units() const { return names(MHS_ESTIMATOR_STATE, true); }
  std::vector<std::string> sensors() const { return names(MHS_ESTIMATOR_SENSOR, false); }
  std::vector<double> state() const {
    std::vector<double> x(size(MHS_ESTIMATOR_STATE));
    check(mhs_estimator_state(sim_, get(), x.data(), nullptr, x.size()));
    return x;
  }
  // n x n, column-major.
  std::vector<double> covariance() const {
    const size_t n = size(MHS_ESTIMATOR_STATE);
    std::vector<double> x(n), p(n * n);
    check(mhs_estimator_state(sim_, get(), x.data(), p.data(), n));
    return p;
  }
  // Of the last update, per sensor (NaN without a sample).
  std::vector<double> innovation() const { return innovations(true); }
  std::vector<double> innovation_sd() const { return innovations(false); }
  double nis() const {
    double v = 0.0;
    check(mhs_estimator_innovations(sim_, get(), nullptr, nullptr, 0, &v));
    return v;
  }
  mhs_estimator* get() const { return handle_.get(); }

 private:
  friend class Simulation;
  struct Free {
    void operator()(mhs_estimator* e) const { mhs_estimator_free(e); }
  };
  Estimator(mhs_simulation* sim, mhs_estimator* e) : sim_(sim), handle_(e) {}

  size_t size(mhs_estimator_role role) const {
    uint32_t states = 0, sensors = 0;
    check(mhs_estimator_size(sim_, get(), &states, &sensors));
    return role == MHS_ESTIMATOR_STATE ? states : sensors;
  }
  std::vector<std::string> names(mhs_estimator_role role, bool units) const {
    std::vector<std::string> out;
    for (uint32_t k = 0; k < size(role); ++k) {
      const char* name = nullptr;
      const char* unit = nullptr;
      check(mhs_estimator_name(sim_, get(), role, k, &name, &unit));
      out.emplace_back(units ? unit : name);
    }
    return out;
  }
  std::vector<double> innovations(bool values) const {
    std::vector<double> nu(size(MHS_ESTIMATOR_SENSOR)), sd(nu.size());
    check(mhs_estimator_innovations(sim_, get(), nu.data(), sd.data(), nu.size(), nullptr));
    return values ? nu : sd;
  }
  void check(mhs_status status) const {
    if (status == MHS_OK || status == MHS_WARNING) return;
    const char* message = mhs_message(sim_);
    throw Error(status, message != nullptr ? message : "monohydra: a call failed");
  }

  mhs_simulation* sim_;
  std::unique_ptr<mhs_estimator, Free> handle_;
};

// The state-space matrices of a run about its accepted state (mhs_linearize):
// dX/dt = A X + B u, Y = C X + D u; each matrix column-major.
struct Linearization {
  uint32_t n = 0, m = 0, p = 0;  // states, inputs, outputs
  double t = 0.0;                // s, when it was taken
  std::vector<double> A, B, C, D;
  std::vector<std::string> states, state_units, inputs, input_units, outputs, output_units;
};

class Simulation {
 public:
  using Settings = std::vector<std::pair<std::string, std::string>>;  // {path, value}

  // A model file, with settings over it ({"formulation", "penalty"},
  // {"subsystems/valve/flow_coefficient", "2e-8"}, ...).
  static Simulation open_file(const std::string& path, const Settings& settings = {}) {
    const std::vector<mhs_setting> s = c_settings(settings);
    mhs_simulation* raw = nullptr;
    const mhs_status st = mhs_open_file(path.c_str(), s.data(), s.size(), &raw);
    return opened(st, raw);
  }
  // A model's text; `label` names it in messages, `base_dir` resolves its paths.
  static Simulation open_text(const std::string& yaml, const std::string& label,
                              const std::string& base_dir, const Settings& settings = {}) {
    const std::vector<mhs_setting> s = c_settings(settings);
    mhs_simulation* raw = nullptr;
    const mhs_status st =
        mhs_open_text(yaml.c_str(), label.c_str(), base_dir.c_str(), s.data(), s.size(), &raw);
    return opened(st, raw);
  }

  void start() { check(mhs_start(get())); }
  void step() { check(mhs_step(get())); }
  void advance(double t) { check(mhs_advance(get(), t)); }

  double time() const {
    double t = 0.0;
    check(mhs_time(get(), &t, nullptr, nullptr, nullptr));
    return t;
  }
  int64_t steps() const {
    int64_t n = 0;
    check(mhs_time(get(), nullptr, &n, nullptr, nullptr));
    return n;
  }

  std::vector<Variable> variables() const {
    uint32_t count = 0;
    check(mhs_variable_count(get(), &count));
    std::vector<Variable> out(count);
    for (uint32_t i = 0; i < count; ++i) {
      mhs_variable_info info{};
      info.struct_size = sizeof info;
      check(mhs_variable(get(), i, &info));
      out[i] = {info.kind, info.name, info.qualified, info.unit, info.min, info.max};
    }
    return out;
  }
  // The index of a variable by name (look it up once, outside the loop).
  uint32_t find(const std::string& name) const {
    uint32_t index = 0;
    check(mhs_find(get(), name.c_str(), &index));
    return index;
  }
  double get(uint32_t index) const {
    double value = 0.0;
    check(mhs_get(get(), &index, 1, &value));
    return value;
  }
  void set(uint32_t index, double value) { check(mhs_set(get(), &index, 1, &value)); }
  // A body's mass, centre of mass or inertia, or gravity, changed in place
  // (mhs_set_parameter): "bodies/body3/mass", "gravity/1".
  void set_parameter(const std::string& path, double value) {
    check(mhs_set_parameter(get(), path.c_str(), value));
  }

  // Forward sensitivities (mhs_track_sensitivities), before the run starts;
  // then d(value index)/d(parameter j) at the accepted step, one per parameter.
  void track_sensitivities(const std::vector<std::string>& paths) {
    std::vector<const char*> c;
    c.reserve(paths.size());
    for (const std::string& p : paths) c.push_back(p.c_str());
    check(mhs_track_sensitivities(get(), c.data(), c.size()));
    sensitivity_count_ = paths.size();
  }
  std::vector<double> sensitivities(uint32_t index) const {
    std::vector<double> out(sensitivity_count_);
    check(mhs_get_sensitivities(get(), &index, 1, out.data()));
    return out;
  }

  // The row's column names, and whether the last step is one the run writes
  // a row at (t = 0 and every output interval).
  std::vector<std::string> row_names() const {
    uint32_t columns = 0;
    check(mhs_row_size(get(), &columns));
    std::vector<std::string> names(columns);
    for (uint32_t c = 0; c < columns; ++c) {
      const char* name = nullptr;
      check(mhs_row_name(get(), c, &name));
      names[c] = name;
    }
    return names;
  }
  bool row_due() const {
    int32_t due = 0;
    check(mhs_row_due(get(), &due));
    return due != 0;
  }
  double dt() const {
    double dt = 0.0;
    check(mhs_time(get(), nullptr, nullptr, &dt, nullptr));
    return dt;
  }
  double t_end() const {
    double t_end = 0.0;
    check(mhs_time(get(), nullptr, nullptr, nullptr, &t_end));
    return t_end;
  }

  // The row of the last step, as `monohydra run` writes it.
  std::vector<double> row() const {
    uint32_t columns = 0;
    check(mhs_row_size(get(), &columns));
    std::vector<double> values(columns);
    check(mhs_row(get(), values.data(), values.size()));
    return values;
  }
  std::string row_text(bool header) const {
    size_t length = 0;
    (void)mhs_row_text(get(), header ? 1 : 0, nullptr, 0, &length);  // asks the length: refused
    std::string text(length + 1, '\0');
    check(mhs_row_text(get(), header ? 1 : 0, text.data(), text.size(), &length));
    text.resize(length);
    return text;
  }

  // A snapshot of this run's current state; save and restore it again later.
  Snapshot snapshot() {
    mhs_snapshot* raw = nullptr;
    check(mhs_snapshot_new(get(), &raw));
    Snapshot s(raw);
    check(mhs_save(get(), s.handle()));
    return s;
  }
  void save(Snapshot& s) { check(mhs_save(get(), s.handle())); }
  void restore(const Snapshot& s) { check(mhs_restore(get(), s.handle())); }
  // A snapshot as bytes (for a file, another process) and back.
  std::vector<unsigned char> bytes(Snapshot& s) {
    const void* data = nullptr;
    size_t size = 0;
    check(mhs_snapshot_bytes(get(), s.handle(), &data, &size));
    const auto* p = static_cast<const unsigned char*>(data);
    return std::vector<unsigned char>(p, p + size);
  }
  Snapshot snapshot_from(const std::vector<unsigned char>& bytes) {
    mhs_snapshot* raw = nullptr;
    check(mhs_snapshot_new(get(), &raw));
    Snapshot s(raw);
    check(mhs_snapshot_read(get(), s.handle(), bytes.data(), bytes.size()));
    return s;
  }

  // A Kalman filter on this run (mhs_estimator_new), from the model's sensors.
  Estimator estimator(const EstimatorOptions& options = {}) {
    std::vector<const char*> params, names;
    std::vector<double> plant, initial;
    for (const std::string& p : options.params) params.push_back(p.c_str());
    for (const EstimatorOptions::Noise& n : options.noise) {
      names.push_back(n.name.c_str());
      plant.push_back(n.plant);
      initial.push_back(n.initial);
    }
    mhs_estimator_options o{};
    o.struct_size = sizeof o;
    o.filter = options.filter.c_str();
    o.params = params.data();
    o.param_count = params.size();
    o.noise_names = names.data();
    o.plant_sd = plant.data();
    o.initial_sd = initial.data();
    o.noise_count = names.size();
    mhs_estimator* raw = nullptr;
    check(mhs_estimator_new(get(), &o, &raw));
    return Estimator(get(), raw);
  }

  // About the last accepted state, over the model's inputs and these values
  // (by name: coordinates, rates, states, outputs); the run is left as it was.
  Linearization linearize(const std::vector<std::string>& outputs) {
    std::vector<uint32_t> indices;
    indices.reserve(outputs.size());
    for (const std::string& name : outputs) indices.push_back(find(name));
    mhs_linearization* raw = nullptr;
    check(mhs_linearize(get(), indices.data(), indices.size(), &raw));
    const std::unique_ptr<mhs_linearization, void (*)(mhs_linearization*)> lin(
        raw, mhs_linearization_free);
    Linearization out;
    check(mhs_linearization_size(get(), lin.get(), &out.n, &out.m, &out.p, &out.t));
    const auto matrix = [&](char which, size_t rows, size_t cols) {
      std::vector<double> v(rows * cols);
      check(mhs_linearization_matrix(get(), lin.get(), which, v.data(), v.size()));
      return v;
    };
    out.A = matrix('A', out.n, out.n);
    out.B = matrix('B', out.n, out.m);
    out.C = matrix('C', out.p, out.n);
    out.D = matrix('D', out.p, out.m);
    const auto names = [&](mhs_linear_role role, uint32_t count, std::vector<std::string>& name,
                           std::vector<std::string>& unit) {
      for (uint32_t k = 0; k < count; ++k) {
        const char* nm = nullptr;
        const char* un = nullptr;
        check(mhs_linearization_name(get(), lin.get(), role, k, &nm, &un));
        name.emplace_back(nm);
        unit.emplace_back(un);
      }
    };
    names(MHS_LINEAR_STATE, out.n, out.states, out.state_units);
    names(MHS_LINEAR_INPUT, out.m, out.inputs, out.input_units);
    names(MHS_LINEAR_OUTPUT, out.p, out.outputs, out.output_units);
    return out;
  }

  // The C handle, for the calls this layer does not wrap.
  mhs_simulation* get() const { return handle_.get(); }
  // The message of the last call that warned (MHS_WARNING), or "".
  const std::string& warning() const { return warning_; }
  // The same, forgotten once read: each warning read once.
  std::string take_warning() { return std::exchange(warning_, std::string()); }
  // Ends the call in flight at the next look between two steps (mhs_cancel):
  // from another thread or a signal handler.
  void cancel() { mhs_cancel(get()); }

 private:
  struct Free {
    void operator()(mhs_simulation* s) const { mhs_free(s); }
  };
  explicit Simulation(mhs_simulation* s) : handle_(s) {}
  size_t sensitivity_count_ = 0;  // the parameters tracked

  static std::vector<mhs_setting> c_settings(const Settings& settings) {
    std::vector<mhs_setting> out;
    for (const auto& [path, value] : settings) out.push_back({path.c_str(), value.c_str()});
    return out;
  }
  static Simulation opened(mhs_status status, mhs_simulation* raw) {
    Simulation sim(raw);  // freed by it whatever the status
    if (status != MHS_OK && status != MHS_WARNING)
      throw Error(status, raw != nullptr ? mhs_message(raw) : "the model did not open");
    if (status == MHS_WARNING) sim.warning_ = mhs_message(raw);
    return sim;
  }
  void check(mhs_status status) const {
    if (status == MHS_OK) return;
    const char* message = mhs_message(get());
    if (status == MHS_WARNING) {
      warning_ = message != nullptr ? message : "";
      return;
    }
    throw Error(status, message != nullptr ? message : "monohydra: a call failed");
  }

  std::unique_ptr<mhs_simulation, Free> handle_;
  mutable std::string warning_;
};

// Many runs of one model stepped together (mhs_batch_*, docs/batches.md):
// the model is read and its plugins loaded once; each run has its own
// parameters by path and inputs; calls step every run on the batch's
// threads, and each run's result is the one it would have alone. A run
// whose step fails stops alone: step() and advance() return how many runs
// are stopped, status(k) says why; a bad argument throws Error.
class Batch {
 public:
  using Settings = Simulation::Settings;
  struct RunStatus {
    bool stopped = false;
    double time = 0.0;  // s, of its last accepted state
    int64_t steps = 0;
    std::string reason;  // why it stopped ("" when it did not)
  };
  class Snapshot {
   public:
    mhs_batch_snapshot* handle() const { return handle_.get(); }

   private:
    friend class Batch;
    struct Free {
      void operator()(mhs_batch_snapshot* s) const { mhs_batch_snapshot_free(s); }
    };
    explicit Snapshot(mhs_batch_snapshot* s) : handle_(s) {}
    std::unique_ptr<mhs_batch_snapshot, Free> handle_;
  };

  // `runs` runs of the model at `path`, on `threads` threads (0: one per core).
  static Batch open_file(const std::string& path, uint32_t runs, uint32_t threads = 0,
                         const Settings& settings = {}) {
    const std::vector<mhs_setting> s = c_settings(settings);
    mhs_batch* raw = nullptr;
    const mhs_status st =
        mhs_batch_open_file(path.c_str(), s.data(), s.size(), runs, threads, &raw);
    return opened(st, raw);
  }
  // The same from the model's text (`label` in messages, `base_dir` for its relative paths).
  static Batch open_text(const std::string& yaml, const std::string& label,
                         const std::string& base_dir, uint32_t runs, uint32_t threads = 0,
                         const Settings& settings = {}) {
    const std::vector<mhs_setting> s = c_settings(settings);
    mhs_batch* raw = nullptr;
    const mhs_status st = mhs_batch_open_text(yaml.c_str(), label.c_str(), base_dir.c_str(),
                                              s.data(), s.size(), runs, threads, &raw);
    return opened(st, raw);
  }

  uint32_t size() const {
    uint32_t runs = 0;
    check(mhs_batch_size(get(), &runs, nullptr));
    return runs;
  }
  uint32_t threads() const {
    uint32_t threads = 0;
    check(mhs_batch_size(get(), nullptr, &threads));
    return threads;
  }
  double dt() const {
    double dt = 0.0;
    check(mhs_batch_time(get(), &dt, nullptr));
    return dt;
  }
  double t_end() const {
    double t_end = 0.0;
    check(mhs_batch_time(get(), nullptr, &t_end));
    return t_end;
  }
  std::vector<Variable> variables() const {
    uint32_t count = 0;
    check(mhs_batch_variable_count(get(), &count));
    std::vector<Variable> out(count);
    for (uint32_t i = 0; i < count; ++i) {
      mhs_variable_info info{};
      info.struct_size = sizeof info;
      check(mhs_batch_variable(get(), i, &info));
      out[i] = {info.kind, info.name, info.qualified, info.unit, info.min, info.max};
    }
    return out;
  }
  void set_parameter(uint32_t run, const std::string& path, double value) {
    check(mhs_batch_set_parameter(get(), run, path.c_str(), value));
  }
  size_t start() { return stepped(mhs_batch_start(get())); }
  size_t step(uint64_t steps = 1) { return stepped(mhs_batch_step(get(), steps)); }
  size_t advance(double t) { return stepped(mhs_batch_advance(get(), t)); }
  // Ends the step or advance in flight (mhs_batch_cancel): from another
  // thread or a signal handler; that call's warning() says where the runs are.
  void cancel() { mhs_batch_cancel(get()); }
  uint32_t find(const std::string& name) const {
    uint32_t index = 0;
    check(mhs_batch_find(get(), name.c_str(), &index));
    return index;
  }
  // Value `index` of every run, in run order.
  std::vector<double> get(uint32_t index) const {
    std::vector<double> out(size());
    check(mhs_batch_get(get(), index, out.data(), out.size()));
    return out;
  }
  std::vector<double> get(const std::string& name) const { return get(find(name)); }
  // Input `index` of each run: all or nothing; clamped values are named in warning().
  void set(uint32_t index, const std::vector<double>& values) {
    check(mhs_batch_set(get(), index, values.data(), values.size()));
  }
  RunStatus status(uint32_t run) const {
    RunStatus out;
    mhs_status st = MHS_OK;
    const char* reason = nullptr;
    check(mhs_batch_run_status(get(), run, &st, &out.time, &out.steps, &reason));
    out.stopped = st != MHS_OK;
    out.reason = reason != nullptr ? reason : "";
    return out;
  }
  Snapshot snapshot() {
    mhs_batch_snapshot* raw = nullptr;
    check(mhs_batch_snapshot_new(get(), &raw));
    Snapshot s(raw);
    check(mhs_batch_save(get(), s.handle()));
    return s;
  }
  void restore(const Snapshot& s) { check(mhs_batch_restore(get(), s.handle())); }
  // The snapshot as bytes, and one read back from them (in another process too).
  std::vector<unsigned char> bytes(const Snapshot& s) {
    const void* data = nullptr;
    size_t size = 0;
    check(mhs_batch_snapshot_bytes(get(), s.handle(), &data, &size));
    const auto* p = static_cast<const unsigned char*>(data);
    return std::vector<unsigned char>(p, p + size);
  }
  Snapshot snapshot_from(const std::vector<unsigned char>& data) {
    mhs_batch_snapshot* raw = nullptr;
    check(mhs_batch_snapshot_new(get(), &raw));
    Snapshot s(raw);
    check(mhs_batch_snapshot_read(get(), s.handle(), data.data(), data.size()));
    return s;
  }

  mhs_batch* get() const { return handle_.get(); }
  // The message of the last call that warned (MHS_WARNING) or stopped runs, or "".
  const std::string& warning() const { return warning_; }

 private:
  struct Free {
    void operator()(mhs_batch* b) const { mhs_batch_free(b); }
  };
  explicit Batch(mhs_batch* b) : handle_(b) {}
  static std::vector<mhs_setting> c_settings(const Settings& settings) {
    std::vector<mhs_setting> out;
    for (const auto& [path, value] : settings) out.push_back({path.c_str(), value.c_str()});
    return out;
  }
  static Batch opened(mhs_status status, mhs_batch* raw) {
    Batch b(raw);  // freed by it whatever the status
    if (status != MHS_OK && status != MHS_WARNING)
      throw Error(status, raw != nullptr ? mhs_batch_message(raw) : "the model did not open");
    if (status == MHS_WARNING) b.warning_ = mhs_batch_message(raw);
    return b;
  }
  size_t stepped(mhs_status status) {
    check(status);
    if (status != MHS_DISCARD) return 0;
    size_t stopped = 0;
    for (uint32_t k = 0; k < size(); ++k) stopped += status_of(k) ? 1 : 0;
    return stopped;
  }
  bool status_of(uint32_t run) const {
    mhs_status st = MHS_OK;
    check(mhs_batch_run_status(get(), run, &st, nullptr, nullptr, nullptr));
    return st != MHS_OK;
  }
  void check(mhs_status status) const {
    if (status == MHS_OK) return;
    const char* message = mhs_batch_message(get());
    if (status == MHS_WARNING || status == MHS_DISCARD) {
      warning_ = message != nullptr ? message : "";
      return;
    }
    throw Error(status, message != nullptr ? message : "monohydra: a batch call failed");
  }

  std::unique_ptr<mhs_batch, Free> handle_;
  mutable std::string warning_;
};

}  // namespace monohydra
