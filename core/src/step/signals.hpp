// The signals the host keeps for its components (host.h mh_signal): a
// component's command option read as a time table or as one of the model's
// inputs, each written before every evaluation of its instance at that
// evaluation's time; or, at a signal port (3.2), a state of the run, written
// from the evaluation's y. The inputs hold what the embedding API set; until then
// they follow their table (or hold their initial value). A set value that
// changes the input is a jump at the accepted time: the next step starts
// from the rates at its right limit, as after a time event (time_step.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <utility>
#include <vector>

#include "model/time_table.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/run_state.hpp"

namespace mh {

// An input's value and whether it still follows its table are the run's
// (RunData::input_values, input_follows_table): a snapshot holds them.
struct InputSignal {
  const InputSpec* spec = nullptr;
  TimeTable table;  // its own (empty: none)
};

struct Signal {
  TimeTable table;          // a table option's (input < 0, state < 0)
  int input = -1;           // or the model's input it reads
  int state = -1;           // or the state of the run it reads (a signal port, 3.2)
  double* value = nullptr;  // what the component reads (mh_signal.value), in Signals::values
};

// A component's option written as a number where the component takes a
// signal (a pump's pressure, a flow source's flow): a constant the
// component reads through its pointer on every call, so the engine can
// change it in place as a parameter (Simulation::set_component_parameter,
// sensitivities) without the component offering monohydra/parameters.h.
struct ConstantSignal {
  int instance = -1;  // the subsystem instance that read it
  std::string key;
  double* value = nullptr;  // in Signals::values
};

struct Signals {
  std::vector<InputSignal> inputs;
  std::vector<Signal> list;
  std::deque<double> values;  // a deque: the components keep the values' addresses
  std::vector<ConstantSignal> constants;
  // The jumps of inputs' tables that components read (time, input): events
  // while the input follows its table (merged into the run's at setup).
  std::vector<std::pair<double, int>> input_events;

  // The inputs of `specs`, their values (run's) as the model gives them.
  void make_inputs(const std::vector<InputSpec>& specs, RunData& run);
  int find_input(const std::string& name) const;  // -1 when absent
  // Input k at time t in a run whose values are `run`'s.
  double input_value(int k, double t, const RunData& run) const {
    const auto i = static_cast<size_t>(k);
    return run.input_follows_table[i] != 0 ? inputs[i].table.value(t) : run.input_values[i];
  }
  // Writes the signals [begin, end) (one instance's) at time t and states y.
  void refresh(size_t begin, size_t end, double t, const double* y, const RunData& run) {
    for (size_t k = begin; k < end; ++k) {
      const Signal& s = list[k];
      *s.value = s.state >= 0  ? y[s.state]
                 : s.input < 0 ? s.table.value(t)
                               : input_value(s.input, t, run);
    }
  }
};

}  // namespace mh
