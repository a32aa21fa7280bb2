// A stand-in for the core's host, to drive one subsystem instance through the
// C ABI without the core: options from maps, states and ports numbered in a
// shared FakeNetwork (ports joined by node name share one state), points at
// given positions, and every option error, log line, time event, state spec
// and output spec recorded (the 2.0 host table).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "../../core/src/model/time_table.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/subsystem.h"
#include "test_support.hpp"

namespace mh::test {

// A signal the fake host keeps for an instance (host.h mh_signal): its time
// table, written at the evaluation's time before each Evaluation::run, as
// the core's host does.
struct FakeSignal {
  TimeTable table;
  double value = 0.0;
};

// The global numbering of states and outputs that several instances share.
struct FakeNetwork {
  mutable std::deque<FakeSignal> signals;  // a deque: instances keep the values' addresses
  std::vector<std::string> state_names;    // "node:X" for a node, "<instance>.<state>" otherwise
  std::vector<double> initial;             // NaN where nobody gave one
  std::map<std::string, int32_t> nodes;    // node name -> its pressure state
  int32_t num_outputs = 0;

  int32_t new_state(const std::string& name, double value) {
    state_names.push_back(name);
    initial.push_back(value);
    return static_cast<int32_t>(state_names.size() - 1);
  }
  size_t num_states() const { return state_names.size(); }
};

struct PortRecord {
  std::string key, domain, unit;
  uint32_t role = 0;
  double initial = 0.0, abs_tolerance = 0.0;
  int32_t index = -1;
};

struct StateRecord {
  std::string name, unit;
  double initial = 0.0, abs_tolerance = 0.0;
  std::string role;  // "" for none
  double range_min = 0.0, range_max = 0.0;
  int32_t index = -1;
};

struct OutputRecord {
  std::string name, unit;
  uint32_t kind = MH_OUTPUT_SIGNAL;
  std::string role;  // "" for none
  double range_min = 0.0, range_max = 0.0;
  int32_t index = -1;
};

class FakeHost {
 public:
  // `struct_size` below sizeof(mh_host) plays a host whose table ends earlier.
  explicit FakeHost(FakeNetwork& network, std::string name = "instance",
                    uint32_t struct_size = sizeof(mh_host))
      : network_(&network), name_(std::move(name)) {
    table.struct_size = struct_size;
    table.abi_version = MH_ABI_VERSION_INIT;
    table.host_data = this;
    table.log = log;
    table.get_service = get_service;
    options_ = {sizeof(mh_options_service), option_number, option_string, option_table,
                option_error};
    mechanism_ = {sizeof(mh_mechanism_service), mech_info, nullptr, nullptr};  // a subsystem's
    // A 3.1 host's table (no option_signal_port): signal_port falls back to
    // option_signal, so the components read tables as before.
    signals_ = {static_cast<uint32_t>(offsetof(mh_signals_service, option_signal_port)),
                option_signal, nullptr};
    outputs_ = {sizeof(mh_outputs_service), add_output};
    setup_ = {sizeof(mh_subsystem_setup_service),
              add_state,
              find_state,
              add_point,
              add_port,
              point_position,
              add_time_event};
  }
  FakeHost(const FakeHost&) = delete;
  FakeHost& operator=(const FakeHost&) = delete;

  mh_host table{};

  // What the instance may read.
  std::map<std::string, double> numbers;
  std::map<std::string, std::pair<uint32_t, std::vector<double>>> tables;  // columns, data
  std::map<std::string, std::string> port_nodes;                           // port key -> node name
  std::map<std::string, std::string> strings;                              // string options
  std::map<std::string, std::array<double, 3>> point_positions;            // point key -> world (m)

  // What the instance did.
  std::vector<std::string> option_errors;  // keys, in order
  std::vector<std::string> expected;       // the matching "expected ..." texts
  std::vector<std::string> logs;
  std::vector<double> time_events;
  std::vector<int32_t> touched;  // first-call order, no repeats (the jacobian's numbering)
  std::vector<PortRecord> ports;
  std::vector<StateRecord> states;
  std::vector<std::string> points;
  std::map<std::string, int32_t> outputs;  // name -> index
  std::vector<OutputRecord> output_specs;  // in declaration order

  const PortRecord& port(const std::string& key) const {
    for (const PortRecord& p : ports)
      if (p.key == key) return p;
    ADD_FAILURE() << "no port " << key;
    static const PortRecord none;
    return none;
  }
  int32_t state(const std::string& name) const { return state_record(name).index; }
  const StateRecord& state_record(const std::string& name) const {
    for (const StateRecord& s : states)
      if (s.name == name) return s;
    ADD_FAILURE() << "no state " << name;
    static const StateRecord none;
    return none;
  }
  const OutputRecord& output(const std::string& name) const {
    for (const OutputRecord& o : output_specs)
      if (o.name == name) return o;
    ADD_FAILURE() << "no output " << name;
    static const OutputRecord none;
    return none;
  }
  std::string all_logs() const {
    std::string text;
    for (const std::string& l : logs) text += l + "\n";
    return text;
  }

 private:
  FakeNetwork* network_;
  std::string name_;

  static FakeHost& self(const mh_host* h) { return *static_cast<FakeHost*>(h->host_data); }
  void touch(int32_t index) {
    if (std::find(touched.begin(), touched.end(), index) == touched.end()) touched.push_back(index);
  }

  static void log(const mh_host* h, mh_log_level, const char* message) {
    self(h).logs.emplace_back(message);
  }
  static mh_status option_number(const mh_host* h, const char* key, int required, double fallback,
                                 double* out) {
    const FakeHost& f = self(h);
    auto it = f.numbers.find(key);
    if (it != f.numbers.end()) {
      *out = it->second;
      return MH_OK;
    }
    if (required != 0) {
      self(h).logs.push_back(std::string("missing required option ") + key);
      return MH_ERROR;
    }
    *out = fallback;
    return MH_OK;
  }
  static mh_status option_string(const mh_host* h, const char* key, int, const char* fallback,
                                 const char** out) {
    const FakeHost& f = self(h);
    auto it = f.strings.find(key);
    *out = it == f.strings.end() ? fallback : it->second.c_str();
    return MH_OK;
  }
  static mh_status option_table(const mh_host* h, const char* key, int required, uint32_t columns,
                                const double** data, uint32_t* rows) {
    const FakeHost& f = self(h);
    auto it = f.tables.find(key);
    if (it == f.tables.end()) {
      *data = nullptr;
      *rows = 0;
      return required != 0 ? MH_ERROR : MH_OK;
    }
    if (it->second.first != columns) return MH_ERROR;
    *data = it->second.second.data();
    *rows = static_cast<uint32_t>(it->second.second.size() / columns);
    return MH_OK;
  }
  static mh_status option_error(const mh_host* h, const char* key, const char* what) {
    self(h).option_errors.emplace_back(key);
    self(h).expected.emplace_back(what);
    return MH_ERROR;
  }
  static mh_status mech_info(const mh_host*, mh_mech_info*) { return MH_ERROR; }
  static std::string text(const char* s) { return s != nullptr ? s : ""; }
  static mh_status add_state(const mh_host* h, const mh_state_spec* spec, int32_t* index) {
    FakeHost& f = self(h);
    if (spec == nullptr || spec->struct_size < sizeof(mh_state_spec) || spec->name == nullptr)
      return MH_ERROR;
    *index = f.network_->new_state(f.name_ + "." + spec->name, spec->initial);
    f.states.push_back({spec->name, text(spec->unit), spec->initial, spec->abs_tolerance,
                        text(spec->role), spec->range_min, spec->range_max, *index});
    f.touch(*index);
    return MH_OK;
  }
  static mh_status find_state(const mh_host*, const char*, int32_t*) { return MH_ERROR; }
  static mh_status add_point(const mh_host* h, const char* key, int32_t* index) {
    FakeHost& f = self(h);
    if (f.point_positions.count(key) == 0) return MH_ERROR;
    f.points.emplace_back(key);
    *index = static_cast<int32_t>(f.points.size() - 1);
    return MH_OK;
  }
  // A subsystem's services: options, mech_info, outputs and its setup (no
  // unknowns, no evaluate_mechanics).
  static const void* get_service(const mh_host* h, const char* id) {
    FakeHost& self = *static_cast<FakeHost*>(h->host_data);
    const std::string which = id != nullptr ? id : "";
    if (which == MH_SERVICE_OPTIONS) return &self.options_;
    if (which == MH_SERVICE_MECHANISM) return &self.mechanism_;
    if (which == MH_SERVICE_OUTPUTS) return &self.outputs_;
    if (which == MH_SERVICE_SUBSYSTEM_SETUP) return &self.setup_;
    if (which == MH_SERVICE_SIGNALS) return &self.signals_;
    return nullptr;
  }
  // A signal from `tables` (2 columns; its jumps recorded as time events) or
  // the constant fallback.
  static mh_status option_signal(const mh_host* h, const char* key, int required, double fallback,
                                 mh_signal* out) {
    FakeHost& f = self(h);
    FakeSignal signal;
    std::string error;
    auto it = f.tables.find(key);
    auto number = f.numbers.find(key);
    if (it == f.tables.end() && number != f.numbers.end()) {
      const double constant[2] = {0.0, number->second};  // a number: a constant signal
      signal.table.assign(constant, 1, error);
    } else if (it == f.tables.end()) {
      if (required != 0) return MH_ERROR;
      const double constant[2] = {0.0, fallback};
      signal.table.assign(constant, 1, error);
    } else {
      if (it->second.first != 2) return MH_ERROR;
      if (!signal.table.assign(it->second.second.data(),
                               static_cast<uint32_t>(it->second.second.size() / 2), error))
        return option_error(h, key, error.c_str());
      for (double t : signal.table.jump_times()) f.time_events.push_back(t);
    }
    signal.value = signal.table.value(0.0);  // as the host: the value at t = 0 until evaluated
    f.network_->signals.push_back(std::move(signal));
    out->value = &f.network_->signals.back().value;
    out->state = -1;
    return MH_OK;
  }
  mh_signals_service signals_{};
  mh_options_service options_{};
  mh_mechanism_service mechanism_{};
  mh_outputs_service outputs_{};
  mh_subsystem_setup_service setup_{};
  static mh_status add_output(const mh_host* h, const mh_output_spec* spec, int32_t* index) {
    FakeHost& f = self(h);
    if (spec == nullptr || spec->struct_size < sizeof(mh_output_spec) || spec->name == nullptr)
      return MH_ERROR;
    *index = f.network_->num_outputs++;
    f.outputs[spec->name] = *index;
    f.output_specs.push_back({spec->name, text(spec->unit), spec->kind, text(spec->role),
                              spec->range_min, spec->range_max, *index});
    return MH_OK;
  }
  static mh_status add_port(const mh_host* h, const mh_port_spec* spec, int32_t* index) {
    FakeHost& f = self(h);
    if (spec == nullptr || spec->struct_size < sizeof(mh_port_spec)) return MH_ERROR;
    auto named = f.port_nodes.find(spec->key);
    const std::string node =
        named != f.port_nodes.end() ? named->second : f.name_ + "." + spec->key;
    auto known = f.network_->nodes.find(node);
    if (known != f.network_->nodes.end()) {
      *index = known->second;
      double& initial = f.network_->initial[static_cast<size_t>(*index)];
      if (std::isnan(initial)) initial = spec->initial;
    } else {
      *index = f.network_->new_state("node:" + node, spec->initial);
      f.network_->nodes[node] = *index;
    }
    f.ports.push_back({spec->key, spec->domain, spec->unit, spec->role, spec->initial,
                       spec->abs_tolerance, *index});
    f.touch(*index);
    return MH_OK;
  }
  static mh_status point_position(const mh_host* h, int32_t point, double* position3) {
    const FakeHost& f = self(h);
    if (point < 0 || static_cast<size_t>(point) >= f.points.size()) return MH_ERROR;
    const std::array<double, 3>& x = f.point_positions.at(f.points[static_cast<size_t>(point)]);
    std::copy(x.begin(), x.end(), position3);
    return MH_OK;
  }
  static mh_status add_time_event(const mh_host* h, double t) {
    self(h).time_events.push_back(t);
    return MH_OK;
  }
};

// One instance of a subsystem component from the build's plugins, created on
// a FakeHost and destroyed with the object.
class Instance {
 public:
  Instance(const std::string& id, FakeHost& host) : host_(&host) {
    const ComponentInfo& info = build_plugins().find(ComponentKind::subsystem, id);
    api_ = info.subsystem_factory.create(static_cast<const mh_subsystem_factory*>(info.factory),
                                         &host.table, id.c_str());
  }
  ~Instance() {
    if (api_ != nullptr) api_->destroy(api_);
  }
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  const mh_subsystem* api() const { return api_; }
  mh_status setup() const { return api_->setup(api_); }
  FakeHost& host() const { return *host_; }

 private:
  FakeHost* host_;
  const mh_subsystem* api_ = nullptr;
};

// The inputs of one evaluation and what came out of it.
struct Evaluation {
  double t = 0.0;
  std::vector<double> y, ydot;           // every state of the network
  std::vector<double> point_p, point_v;  // 3 per point of the instance
  std::vector<double> residual, point_f, outputs;
  mh_status status = MH_OK;
  size_t num_touched = 0;  // the instance's touched states: its jacobian blocks' size

  explicit Evaluation(const FakeNetwork& network, size_t num_points = 0)
      : y(network.num_states(), 0.0),
        ydot(network.num_states(), 0.0),
        point_p(3 * num_points, 0.0),
        point_v(3 * num_points, 0.0),
        num_outputs_(static_cast<size_t>(network.num_outputs)),
        network_(&network) {}

  mh_subsystem_eval record() {
    residual.assign(y.size(), 0.0);
    point_f.assign(point_p.size(), 0.0);
    outputs.assign(num_outputs_, 0.0);
    mh_subsystem_eval e{};
    e.struct_size = sizeof(e);
    e.t = t;
    e.num_states = static_cast<uint32_t>(y.size());
    e.y = y.data();
    e.ydot = ydot.data();
    e.residual = residual.data();
    e.num_points = static_cast<uint32_t>(point_p.size() / 3);
    e.point_p = point_p.data();
    e.point_v = point_v.data();
    e.point_f = point_f.data();
    e.num_outputs = static_cast<uint32_t>(outputs.size());
    e.outputs = outputs.data();
    e.num_touched = static_cast<uint32_t>(num_touched);
    return e;
  }
  // Runs the instance's evaluate; the results land in residual, point_f, outputs.
  mh_status run(const mh_subsystem* api) {
    for (FakeSignal& signal : network_->signals) signal.value = signal.table.value(t);
    const mh_subsystem_eval e = record();
    status = api->evaluate(api, &e);
    return status;
  }
  mh_status run(const Instance& instance) { return run(instance.api()); }

 private:
  size_t num_outputs_;
  const FakeNetwork* network_;
};

// The largest relative difference between the instance's analytic jacobian
// (d/dy and d/dydot over the states it touched) and central differences of
// its evaluate at `at`. Each entry's error is |analytic - fd| over the
// largest of |analytic|, |fd| and 1e-9 of its row's largest entry (so an
// entry that is zero next to large ones is judged on the row's scale).
inline double jacobian_error(const Instance& instance, Evaluation at) {
  const std::vector<int32_t>& touched = instance.host().touched;
  const size_t n = touched.size();
  std::vector<double> d_dy(n * n, 0.0), d_dydot(n * n, 0.0);
  at.num_touched = n;
  {
    const mh_subsystem_eval e = at.record();
    EXPECT_NE(instance.api()->jacobian, nullptr);
    if (instance.api()->jacobian == nullptr) return 1.0;
    EXPECT_EQ(instance.api()->jacobian(instance.api(), &e, d_dy.data(), d_dydot.data()), MH_OK);
  }
  double worst = 0.0;
  for (int which = 0; which < 2; ++which) {
    std::vector<double>& analytic = which == 0 ? d_dy : d_dydot;
    std::vector<double> fd(n * n, 0.0);
    for (size_t j = 0; j < n; ++j) {
      std::vector<double>& x = which == 0 ? at.y : at.ydot;
      const size_t g = static_cast<size_t>(touched[j]);
      const double x0 = x[g];
      const double h = 1e-6 * std::max(1.0, std::abs(x0));
      x[g] = x0 + h;
      EXPECT_EQ(at.run(instance), MH_OK);
      const std::vector<double> plus = at.residual;
      x[g] = x0 - h;
      EXPECT_EQ(at.run(instance), MH_OK);
      const std::vector<double> minus = at.residual;
      x[g] = x0;
      for (size_t i = 0; i < n; ++i) {
        const size_t r = static_cast<size_t>(touched[i]);
        fd[j * n + i] = (plus[r] - minus[r]) / (2.0 * h);  // column-major
      }
    }
    for (size_t i = 0; i < n; ++i) {
      double row = 0.0;
      for (size_t j = 0; j < n; ++j)
        row = std::max({row, std::abs(analytic[j * n + i]), std::abs(fd[j * n + i])});
      for (size_t j = 0; j < n; ++j) {
        const double a = analytic[j * n + i], f = fd[j * n + i];
        // Central differences at h = 1e-6 |x| resolve an entry down to about
        // 1e-8 of its row's largest (the residual's round-off over 2h): a
        // smaller one is held to that floor (a load-sensing section shut by
        // its compensator has entries of 1e-18 beside 1e-9 in one row).
        const double scale = std::max({std::abs(a), std::abs(f), 1e-8 * row, 1e-300});
        worst = std::max(worst, std::abs(a - f) / scale);
      }
    }
  }
  return worst;
}

}  // namespace mh::test
