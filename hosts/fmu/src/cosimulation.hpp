// One instance of an exported FMU: a run of the packed model behind the
// embedding API (simulation.h), with the states and rules FMI's
// Co-Simulation interface gives it (FMI 3.0, 4.2; FMI 2.0, 4.2), shared by
// the FMI 3.0 and FMI 2.0 entry points. Every call returns a Status and
// says why through the log; none throws.
//
// Parameters are the model's numeric options: a value set before the end of
// initialisation reopens the model with it (the embedding API's settings),
// so the consistent initial state is the model's own for those values.
// Inputs set before then define the initial state; after, each set is a
// jump at the current time. An input never set follows the model's table.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "monohydra/simulation.h"
#include "packed_model.hpp"

namespace mh::fmu {

// FMI's statuses, in the order both versions number them.
enum class Status : int { ok = 0, warning = 1, discard = 2, error = 3, fatal = 4 };

// Where the instance is in FMI's state machine.
enum class Mode { instantiated, initialization, step, terminated, error, fatal };

// (status, category, message): called for errors always, for warnings and
// information when logging is on.
using Logger = std::function<void(Status, const char*, const std::string&)>;

class CoSimulation {
 public:
  // Opens resources_dir/model.yaml; throws std::runtime_error with the reason
  // (the model's error, a token that does not match).
  CoSimulation(const std::string& resources_dir, const std::string& token, Logger logger,
               bool logging_on);
  ~CoSimulation();
  CoSimulation(const CoSimulation&) = delete;
  CoSimulation& operator=(const CoSimulation&) = delete;

  void set_logging(bool on) { logging_on_ = on; }
  Mode mode() const { return mode_; }
  const std::vector<FmuVariable>& variables() const { return variables_; }

  Status enter_initialization(bool tolerance_defined, double tolerance, double start_time);
  Status exit_initialization();
  Status do_step(double t, double h, double* last_successful_time);
  Status terminate();
  Status reset();

  Status get(const std::uint32_t* vrs, std::size_t n, double* values);
  Status set(const std::uint32_t* vrs, std::size_t n, const double* values);
  // Refuses a call that FMI does not allow in this mode (an Error, logged).
  Status refuse(const char* function, const std::string& why);

  // FMU states are snapshots of the run (mhs_snapshot).
  Status get_state(void** state);
  Status set_state(void* state);
  Status free_state(void** state);
  Status serialized_size(void* state, std::size_t* size);
  Status serialize(void* state, std::uint8_t* bytes, std::size_t size);
  Status deserialize(const std::uint8_t* bytes, std::size_t size, void** state);

 private:
  Status open(bool with_settings);  // (re)opens the model, the parameters as set
  Status ensure_started();          // the run at t = 0 with what was set
  Status from_api(mhs_status s, const char* function);
  Status error(const char* function, const std::string& why);
  const FmuVariable* variable(std::uint32_t vr, const char* function);
  double current_time() const;

  PackedModel packed_;
  Logger logger_;
  bool logging_on_;
  Mode mode_ = Mode::instantiated;
  mhs_simulation* sim_ = nullptr;
  std::vector<FmuVariable> variables_;
  std::vector<double> parameters_;  // by value reference: the value each parameter has now
  std::vector<double> inputs_;      // by value reference: inputs set before start
  std::vector<bool> input_set_;
  bool started_ = false;
  bool restart_ = false;  // something set since the start changes the initial state
  double dt_ = 0.0;
  std::vector<double> row_;
  bool row_valid_ = false;
};

}  // namespace mh::fmu
