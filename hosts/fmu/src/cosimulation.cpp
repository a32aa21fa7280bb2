#include "cosimulation.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <utility>
#include <vector>

#include "monohydra/cpp/number_text.hpp"

namespace mh::fmu {

using monohydra::exact_number;  // the shortest text that reads back as the same double

namespace {

const char* mode_name(Mode m) {
  switch (m) {
    case Mode::instantiated:
      return "Instantiated";
    case Mode::initialization:
      return "Initialization Mode";
    case Mode::step:
      return "Step Mode";
    case Mode::terminated:
      return "Terminated";
    case Mode::error:
      return "the error state (after a failed call)";
    case Mode::fatal:
      return "the fatal state";
  }
  return "?";
}

// An FMU state: a snapshot of the run and the tunable parameters' values
// (the snapshot holds the run's state, not the model's values).
struct FmuState {
  mhs_snapshot* snapshot = nullptr;
  std::vector<double> tunable;  // in the order of the variables
};

}  // namespace

CoSimulation::CoSimulation(const std::string& resources_dir, const std::string& token,
                           Logger logger, bool logging_on)
    : packed_(read_packed_model(resources_dir)),
      logger_(std::move(logger)),
      logging_on_(logging_on) {
  if (token != packed_.token)
    throw std::runtime_error("the instantiation token '" + token + "' is not this FMU's ('" +
                             packed_.token +
                             "'): the modelDescription.xml belongs to another FMU or the "
                             "model in resources/ was changed");
  const std::vector<mhs_setting> settings = api_settings(packed_);
  if (mhs_open_file(packed_.model_path.c_str(), settings.data(), settings.size(), &sim_) >=
      MHS_ERROR) {
    const std::string why = sim_ != nullptr ? mhs_message(sim_) : "out of memory";
    mhs_free(sim_);
    throw std::runtime_error(why);
  }
  mhs_time(sim_, nullptr, nullptr, &dt_, nullptr);
  try {
    // Started so that the inputs' values at t = 0 are there: the run stays
    // as it is unless something is set before initialisation ends.
    if (mhs_start(sim_) >= MHS_ERROR) throw std::runtime_error(mhs_message(sim_));
    started_ = true;
    variables_ = variable_table(sim_, packed_.model_text);
  } catch (...) {
    mhs_free(sim_);
    throw;
  }
  parameters_.assign(variables_.size(), 0.0);
  inputs_.assign(variables_.size(), 0.0);
  input_set_.assign(variables_.size(), false);
  for (const FmuVariable& v : variables_) {
    if (v.causality == Causality::parameter) parameters_[v.value_reference] = v.start;
    if (v.causality == Causality::input) inputs_[v.value_reference] = v.start;
  }
  uint32_t columns = 0;
  mhs_row_size(sim_, &columns);
  row_.assign(columns, 0.0);
}

CoSimulation::~CoSimulation() {
  mhs_free(sim_);
}

Status CoSimulation::open(bool with_settings) {
  std::vector<std::string> values;
  std::vector<mhs_setting> settings = api_settings(packed_);
  if (with_settings) {
    for (const FmuVariable& v : variables_) {
      if (v.causality != Causality::parameter || parameters_[v.value_reference] == v.start)
        continue;
      values.push_back(exact_number(parameters_[v.value_reference]));
    }
    std::size_t k = 0;
    for (const FmuVariable& v : variables_) {
      if (v.causality != Causality::parameter || parameters_[v.value_reference] == v.start)
        continue;
      settings.push_back({v.path.c_str(), values[k++].c_str()});
    }
  }
  mhs_free(sim_);
  sim_ = nullptr;
  const mhs_status s =
      mhs_open_file(packed_.model_path.c_str(), settings.data(), settings.size(), &sim_);
  started_ = false;
  row_valid_ = false;
  if (s >= MHS_ERROR) {
    mode_ = Mode::fatal;
    return error("fmi3Instantiate", sim_ != nullptr ? mhs_message(sim_) : "out of memory");
  }
  mhs_time(sim_, nullptr, nullptr, &dt_, nullptr);
  return Status::ok;
}

Status CoSimulation::ensure_started() {
  if (started_ && !restart_) return Status::ok;
  if (started_ || restart_) {
    const Status s = open(true);
    if (s != Status::ok) return s;
  }
  restart_ = false;
  for (const FmuVariable& v : variables_) {
    if (v.causality != Causality::input || !input_set_[v.value_reference]) continue;
    const Status s = from_api(mhs_set(sim_, &v.index, 1, &inputs_[v.value_reference]), "fmi3Set");
    if (s >= Status::error) return s;
  }
  const Status s = from_api(mhs_start(sim_), "fmi3EnterInitializationMode");
  if (s >= Status::error) return s;
  started_ = true;
  row_valid_ = false;
  return s;
}

Status CoSimulation::error(const char* function, const std::string& why) {
  if (logger_) logger_(Status::error, "logStatusError", std::string(function) + ": " + why);
  return Status::error;
}

Status CoSimulation::refuse(const char* function, const std::string& why) {
  return error(function, why);
}

Status CoSimulation::from_api(mhs_status s, const char* function) {
  if (s == MHS_OK) return Status::ok;
  const std::string message = mhs_message(sim_);
  if (s == MHS_WARNING) {
    if (logging_on_ && logger_) logger_(Status::warning, "logStatusWarning", message);
    return Status::warning;
  }
  if (s == MHS_FATAL) {
    mode_ = Mode::fatal;
    if (logger_) logger_(Status::fatal, "logStatusFatal", std::string(function) + ": " + message);
    return Status::fatal;
  }
  return error(function, message);
}

double CoSimulation::current_time() const {
  double t = 0.0;
  mhs_time(sim_, &t, nullptr, nullptr, nullptr);
  return t;
}

const FmuVariable* CoSimulation::variable(std::uint32_t vr, const char* function) {
  if (vr >= variables_.size()) {
    error(function, "no variable has the value reference " + std::to_string(vr) + " (0 .. " +
                        std::to_string(variables_.size() - 1) + ")");
    return nullptr;
  }
  return &variables_[vr];
}

Status CoSimulation::enter_initialization(bool tolerance_defined, double tolerance,
                                          double start_time) {
  (void)tolerance_defined;
  (void)tolerance;  // the step's tolerances are the model's (solver:)
  if (mode_ != Mode::instantiated)
    return error("fmi3EnterInitializationMode",
                 std::string("called in ") + mode_name(mode_) + ", not after instantiation");
  if (start_time != 0.0)
    return error("fmi3EnterInitializationMode",
                 "the model starts at t = 0 s (its consistent initial state), not at " +
                     exact_number(start_time) + " s");
  mode_ = Mode::initialization;
  return Status::ok;
}

Status CoSimulation::exit_initialization() {
  if (mode_ != Mode::initialization)
    return error("fmi3ExitInitializationMode",
                 std::string("called in ") + mode_name(mode_) + ", not in Initialization Mode");
  const Status s = ensure_started();
  if (s >= Status::error) return s;
  mode_ = Mode::step;
  return s;
}

Status CoSimulation::do_step(double t, double h, double* last_successful_time) {
  if (mode_ != Mode::step)
    return error("fmi3DoStep", std::string("called in ") + mode_name(mode_) + ", not in Step Mode");
  const double now = current_time();
  if (last_successful_time != nullptr) *last_successful_time = now;
  if (!std::isfinite(t) || std::fabs(t - now) > 1e-6 * dt_)
    return error("fmi3DoStep", "the communication point " + exact_number(t) +
                                   " s is not the FMU's time " + exact_number(now) + " s");
  const double steps = h / dt_;
  if (!std::isfinite(h) || h <= 0.0 || std::fabs(steps - std::round(steps)) > 1e-6)
    return error("fmi3DoStep", "the communication step " + exact_number(h) +
                                   " s is not a positive multiple of the FMU's fixed step " +
                                   exact_number(dt_) + " s (fixedInternalStepSize)");
  row_valid_ = false;
  const Status s = from_api(mhs_advance(sim_, now + std::round(steps) * dt_), "fmi3DoStep");
  if (last_successful_time != nullptr) *last_successful_time = current_time();
  if (s == Status::error) mode_ = Mode::error;
  return s;
}

Status CoSimulation::terminate() {
  if (mode_ != Mode::step && mode_ != Mode::error && mode_ != Mode::initialization)
    return error("fmi3Terminate", std::string("called in ") + mode_name(mode_));
  mode_ = Mode::terminated;
  return Status::ok;
}

Status CoSimulation::reset() {
  if (mode_ == Mode::fatal) return Status::fatal;
  for (const FmuVariable& v : variables_) {
    parameters_[v.value_reference] = v.start;
    inputs_[v.value_reference] = v.start;
    input_set_[v.value_reference] = false;
  }
  restart_ = false;
  const Status s = open(false);
  if (s == Status::ok) mode_ = Mode::instantiated;
  return s;
}

Status CoSimulation::get(const std::uint32_t* vrs, std::size_t n, double* values) {
  if (n > 0 && (vrs == nullptr || values == nullptr))
    return error("fmi3GetFloat64", "valueReferences or values is NULL");
  if (mode_ == Mode::instantiated || mode_ == Mode::fatal)
    return error("fmi3GetFloat64", std::string("called in ") + mode_name(mode_) +
                                       ": values are there from Initialization Mode on");
  for (std::size_t k = 0; k < n; ++k)
    if (variable(vrs[k], "fmi3GetFloat64") == nullptr) return Status::error;
  if (mode_ == Mode::initialization) {
    const Status s = ensure_started();
    if (s >= Status::error) return s;
  }
  if (!row_valid_) {
    const Status s = from_api(mhs_row(sim_, row_.data(), row_.size()), "fmi3GetFloat64");
    if (s >= Status::error) return s;
    row_valid_ = true;
  }
  for (std::size_t k = 0; k < n; ++k) {
    const FmuVariable& v = variables_[vrs[k]];
    switch (v.causality) {
      case Causality::independent:
        values[k] = current_time();
        break;
      case Causality::output:
        values[k] = row_[v.index];
        break;
      case Causality::parameter:
        values[k] = parameters_[v.value_reference];
        break;
      case Causality::input: {
        const Status s = from_api(mhs_get(sim_, &v.index, 1, &values[k]), "fmi3GetFloat64");
        if (s >= Status::error) return s;
        break;
      }
    }
  }
  return Status::ok;
}

Status CoSimulation::set(const std::uint32_t* vrs, std::size_t n, const double* values) {
  if (n > 0 && (vrs == nullptr || values == nullptr))
    return error("fmi3SetFloat64", "valueReferences or values is NULL");
  if (mode_ != Mode::instantiated && mode_ != Mode::initialization && mode_ != Mode::step)
    return error("fmi3SetFloat64", std::string("called in ") + mode_name(mode_));
  // Every value is checked before any is set: all or nothing, as mhs_set.
  for (std::size_t k = 0; k < n; ++k) {
    const FmuVariable* v = variable(vrs[k], "fmi3SetFloat64");
    if (v == nullptr) return Status::error;
    if (v->causality == Causality::output || v->causality == Causality::independent)
      return error("fmi3SetFloat64", "'" + v->name + "' is an output: it cannot be set");
    if (v->causality == Causality::parameter && !v->tunable && mode_ == Mode::step)
      return error("fmi3SetFloat64", "the parameter '" + v->name +
                                         "' is fixed: it is set before the end of initialisation");
    if (!std::isfinite(values[k]))
      return error("fmi3SetFloat64", "'" + v->name + "' set to " + exact_number(values[k]) +
                                         ": a value must be finite");
  }
  Status worst = Status::ok;
  for (std::size_t k = 0; k < n; ++k) {
    const FmuVariable& v = variables_[vrs[k]];
    if (v.causality == Causality::parameter && mode_ == Mode::step) {  // tunable (above)
      if (parameters_[v.value_reference] == values[k]) continue;
      row_valid_ = false;
      const Status s =
          from_api(mhs_set_parameter(sim_, v.path.c_str(), values[k]), "fmi3SetFloat64");
      if (s >= Status::error) return s;
      parameters_[v.value_reference] = values[k];
    } else if (v.causality == Causality::parameter) {
      if (parameters_[v.value_reference] != values[k]) restart_ = true;
      parameters_[v.value_reference] = values[k];
    } else if (mode_ == Mode::step) {
      row_valid_ = false;
      const Status s = from_api(mhs_set(sim_, &v.index, 1, &values[k]), "fmi3SetFloat64");
      if (s >= Status::error) return s;
      if (s > worst) worst = s;
    } else {
      inputs_[v.value_reference] = values[k];
      input_set_[v.value_reference] = true;
      if (started_) restart_ = true;
    }
  }
  return worst;
}

Status CoSimulation::get_state(void** state) {
  if (state == nullptr) return error("fmi3GetFMUState", "FMUState is NULL");
  if (mode_ != Mode::step && mode_ != Mode::initialization && mode_ != Mode::terminated &&
      mode_ != Mode::error)
    return error("fmi3GetFMUState", std::string("called in ") + mode_name(mode_));
  if (mode_ == Mode::initialization) {
    const Status s = ensure_started();
    if (s >= Status::error) return s;
  }
  auto* fmu_state = static_cast<FmuState*>(*state);
  if (fmu_state == nullptr) {
    fmu_state = new FmuState();
    if (mhs_snapshot_new(sim_, &fmu_state->snapshot) != MHS_OK) {
      delete fmu_state;
      return from_api(MHS_ERROR, "fmi3GetFMUState");
    }
  }
  const Status s = from_api(mhs_save(sim_, fmu_state->snapshot), "fmi3GetFMUState");
  fmu_state->tunable.clear();
  for (const FmuVariable& v : variables_)
    if (v.tunable) fmu_state->tunable.push_back(parameters_[v.value_reference]);
  if (*state == nullptr) {
    if (s >= Status::error) {
      mhs_snapshot_free(fmu_state->snapshot);
      delete fmu_state;
      return s;
    }
    *state = fmu_state;
  }
  return s;
}

Status CoSimulation::set_state(void* state) {
  if (state == nullptr) return error("fmi3SetFMUState", "FMUState is NULL");
  if (mode_ == Mode::fatal || mode_ == Mode::instantiated)
    return error("fmi3SetFMUState", std::string("called in ") + mode_name(mode_));
  if (mode_ == Mode::initialization) {
    const Status s = ensure_started();
    if (s >= Status::error) return s;
  }
  row_valid_ = false;
  const auto* fmu_state = static_cast<const FmuState*>(state);
  // The tunable values first: the snapshot then puts the run's own state
  // (its energy balance included) back over what changing them moved.
  std::size_t k = 0;
  for (const FmuVariable& v : variables_) {
    if (!v.tunable) continue;
    if (k >= fmu_state->tunable.size())
      return error("fmi3SetFMUState", "the state is of another FMU");
    const double value = fmu_state->tunable[k++];
    if (value == parameters_[v.value_reference]) continue;
    const Status t = from_api(mhs_set_parameter(sim_, v.path.c_str(), value), "fmi3SetFMUState");
    if (t >= Status::error) return t;
    parameters_[v.value_reference] = value;
  }
  const Status s = from_api(mhs_restore(sim_, fmu_state->snapshot), "fmi3SetFMUState");
  if (s < Status::error && mode_ == Mode::error) mode_ = Mode::step;
  return s;
}

Status CoSimulation::free_state(void** state) {
  if (state == nullptr || *state == nullptr) return Status::ok;
  auto* fmu_state = static_cast<FmuState*>(*state);
  mhs_snapshot_free(fmu_state->snapshot);
  delete fmu_state;
  *state = nullptr;
  return Status::ok;
}

// Serialized, a state is the count of tunable values (8 bytes), the values
// (8 bytes each), then the snapshot's bytes (mhs_snapshot_bytes).
Status CoSimulation::serialized_size(void* state, std::size_t* size) {
  if (state == nullptr || size == nullptr)
    return error("fmi3SerializedFMUStateSize", "FMUState or size is NULL");
  const auto* fmu_state = static_cast<FmuState*>(state);
  const void* bytes = nullptr;
  std::size_t snapshot_size = 0;
  const Status s = from_api(mhs_snapshot_bytes(sim_, fmu_state->snapshot, &bytes, &snapshot_size),
                            "fmi3SerializedFMUStateSize");
  if (s < Status::error)
    *size = sizeof(std::uint64_t) + fmu_state->tunable.size() * sizeof(double) + snapshot_size;
  return s;
}

Status CoSimulation::serialize(void* state, std::uint8_t* bytes, std::size_t size) {
  if (state == nullptr || bytes == nullptr)
    return error("fmi3SerializeFMUState", "FMUState or serializedState is NULL");
  const auto* fmu_state = static_cast<FmuState*>(state);
  const void* own = nullptr;
  std::size_t own_size = 0;
  const Status s = from_api(mhs_snapshot_bytes(sim_, fmu_state->snapshot, &own, &own_size),
                            "fmi3SerializeFMUState");
  if (s >= Status::error) return s;
  const std::uint64_t count = fmu_state->tunable.size();
  const std::size_t head = sizeof count + count * sizeof(double);
  if (size != head + own_size)
    return error("fmi3SerializeFMUState",
                 "the buffer has " + std::to_string(size) + " bytes, the state " +
                     std::to_string(head + own_size) + " (fmi3SerializedFMUStateSize)");
  std::memcpy(bytes, &count, sizeof count);
  if (count > 0)
    std::memcpy(bytes + sizeof count, fmu_state->tunable.data(), count * sizeof(double));
  std::memcpy(bytes + head, own, own_size);
  return s;
}

Status CoSimulation::deserialize(const std::uint8_t* bytes, std::size_t size, void** state) {
  if (bytes == nullptr || state == nullptr)
    return error("fmi3DeserializeFMUState", "serializedState or FMUState is NULL");
  std::size_t tunable = 0;
  for (const FmuVariable& v : variables_) tunable += v.tunable ? 1 : 0;
  std::uint64_t count = 0;
  if (size >= sizeof count) std::memcpy(&count, bytes, sizeof count);
  if (size < sizeof count || count != tunable || size - sizeof count < tunable * sizeof(double))
    return error("fmi3DeserializeFMUState", "the bytes are not a state of this FMU (" +
                                                std::to_string(tunable) +
                                                " tunable values, then the run's state)");
  const std::size_t head = sizeof count + tunable * sizeof(double);
  auto* fmu_state = static_cast<FmuState*>(*state);
  const bool fresh = fmu_state == nullptr;
  if (fresh) {
    fmu_state = new FmuState();
    if (mhs_snapshot_new(sim_, &fmu_state->snapshot) != MHS_OK) {
      delete fmu_state;
      return from_api(MHS_ERROR, "fmi3DeserializeFMUState");
    }
  }
  const Status s = from_api(mhs_snapshot_read(sim_, fmu_state->snapshot, bytes + head, size - head),
                            "fmi3DeserializeFMUState");
  if (s < Status::error) {
    fmu_state->tunable.resize(tunable);
    if (tunable > 0)
      std::memcpy(fmu_state->tunable.data(), bytes + sizeof count, tunable * sizeof(double));
  }
  if (fresh) {
    if (s >= Status::error) {
      mhs_snapshot_free(fmu_state->snapshot);
      delete fmu_state;
      return s;
    }
    *state = fmu_state;
  }
  return s;
}

}  // namespace mh::fmu
