// fmu: an FMI 3.0 Model Exchange FMU as a subsystem. The FMU's continuous
// states are states of the run, each with the row xdot - f(t, x, u) = 0, and
// its Float64 outputs algebraic states with the row y - g(t, x, u) = 0, so
// the FMU's equations are solved in the same Newton step as the rest of the
// model (the host's integrator ties x to xdot, as for any state). Its inputs
// are signal ports named after the input variables; its parameters options
// named after the parameters. The tangent comes from the FMU's directional
// derivatives when it provides them, else from central differences of the
// FMU's functions (one column per state and per input that reads a state).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "archive.hpp"
#include "binary.hpp"
#include "components.hpp"
#include "model_description.hpp"
#include "monohydra/cpp/checked_options.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/signal_port.hpp"
#include "monohydra/cpp/specs.hpp"
#include "monohydra/cpp/touched_states.hpp"
#include "monohydra/model_folder.h"
#include "monohydra/state.h"

namespace fmu {
namespace {

constexpr double kNoEvent = std::numeric_limits<double>::infinity();
// The difference step: cbrt(eps) of the value's scale, central differences'
// balance of truncation and rounding (their error then ~ eps^(2/3)).
constexpr double kDifferenceStep = 6.0555e-6;
// Event iterations (fmi3UpdateDiscreteStates until no update is needed).
constexpr int kMaxEventIterations = 100;

// The FMU's messages go to the host's log, at the level of their status.
void fmu_log(fmi3InstanceEnvironment environment, fmi3Status status, fmi3String category,
             fmi3String message) {
  const auto* host = static_cast<const mh_host*>(environment);
  if (host == nullptr || host->log == nullptr) return;
  const mh_log_level level = status >= fmi3Error     ? MH_LOG_ERROR
                             : status == fmi3Warning ? MH_LOG_WARNING
                                                     : MH_LOG_INFO;
  const std::string text = std::string("FMU [") + (category != nullptr ? category : "") +
                           "]: " + (message != nullptr ? message : "");
  host->log(host, level, text.c_str());
}

class Fmu {
 public:
  static const mh_component_descriptor kDescriptor;

  explicit Fmu(const mh_host* host) : host_(host) {}
  ~Fmu() {
    if (instance_ == nullptr) return;
    if (saved_ != nullptr) fmi().free_state(instance_, &saved_);
    fmi().terminate(instance_);
    fmi().free_instance(instance_);
  }
  Fmu(const Fmu&) = delete;
  Fmu& operator=(const Fmu&) = delete;

  mh_status setup() {
    const mh_options_service& options = monohydra::options(host_);
    const char* file = nullptr;
    if (options.option_string(host_, "fmu", 1, "", &file) != MH_OK) return MH_ERROR;
    path_ = resolve(file);
    try {
      archive_ = std::make_unique<UnpackedArchive>(path_);
      md_ = read_model_description(archive_->folder());
      // Locating a state event needs the host to bisect a step on the
      // indicators' signs: not offered, so such an FMU is refused.
      if (md_.event_indicators > 0)
        throw std::runtime_error(
            "it has state events (" + std::to_string(md_.event_indicators) +
            " event indicators), which the import does not locate; only FMUs without event "
            "indicators are imported");
      binary_ = std::make_unique<Binary>(archive_->folder(), md_);
    } catch (const std::exception& e) {
      return refuse(e.what());
    }
    if (read_parameters() != MH_OK) return MH_ERROR;
    double tolerance = 0.0;
    if (monohydra::positive_option(host_, "tolerance", 0, 1e-9,
                                   "a positive Newton tolerance of the FMU's states and outputs",
                                   &tolerance) != MH_OK)
      return MH_ERROR;
    if (instantiate() != MH_OK) return MH_ERROR;
    archive_->keep_only_resources();
    return declare(tolerance);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) {
    const mh_status s = compute(eval);
    if (s != MH_OK) return s;
    for (size_t i = 0; i < nx_; ++i) eval.residual[x_idx_[i]] += eval.ydot[x_idx_[i]] - dx_[i];
    for (size_t j = 0; j < ny_; ++j) eval.residual[y_idx_[j]] += eval.y[y_idx_[j]] - y_[j];
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) {
    mh_status s = compute(eval);
    if (s != MH_OK) return s;
    monohydra::JacobianBlock dy(states_, d_dy), dydot(states_, d_dydot);
    for (size_t i = 0; i < nx_; ++i) dydot.add(x_idx_[i], x_idx_[i], 1.0);
    for (size_t j = 0; j < ny_; ++j) dy.add(y_idx_[j], y_idx_[j], 1.0);
    // One column per known: the states, then the inputs that read a state.
    for (size_t c = 0; c < knowns_.size(); ++c) {
      s = column(eval, c);
      if (s != MH_OK) return s;
      const int32_t of = known_state_[c];
      for (size_t i = 0; i < nx_; ++i) dy.add(x_idx_[i], of, -column_[i]);
      for (size_t j = 0; j < ny_; ++j) dy.add(y_idx_[j], of, -column_[nx_ + j]);
    }
    return MH_OK;
  }

  // The step converged: the FMU is told (fmi3CompletedIntegratorStep), and
  // an event it asks for, or a time event the step reached, is handled.
  mh_status accept(const mh_subsystem_eval& eval) {
    const mh_status s = compute(eval);
    if (s != MH_OK) return s;
    fmi3Boolean enter = false, terminate = false;
    if (!ok(fmi().completed_integrator_step(instance_, true, &enter, &terminate),
            "fmi3CompletedIntegratorStep", eval.t))
      return MH_ERROR;
    if (terminate) return fail("the FMU asked to terminate the simulation", eval.t);
    const bool time_event = eval.t >= next_event_ - 1e-9 * std::max(1.0, std::abs(next_event_));
    if (!enter && !time_event) return MH_OK;
    if (!ok(fmi().enter_event_mode(instance_), "fmi3EnterEventMode", eval.t)) return MH_ERROR;
    if (event_iteration(eval.t) != MH_OK) return MH_ERROR;
    // The host owns the states: an FMU that re-initializes them at the event
    // would need the host to restart from new values.
    if (states_changed_) {
      if (!ok(fmi().get_continuous_states(instance_, x_.data(), nx_), "fmi3GetContinuousStates",
              eval.t))
        return MH_ERROR;
      for (size_t i = 0; i < nx_; ++i)
        if (x_[i] != eval.y[x_idx_[i]])
          return fail(
              "the FMU re-initializes its continuous states at an event, which the "
              "import does not take",
              eval.t);
    }
    return ok(fmi().enter_continuous_time_mode(instance_), "fmi3EnterContinuousTimeMode", eval.t)
               ? MH_OK
               : MH_ERROR;
  }

  const void* extension(const char* id) const {
    return std::strcmp(id, MH_EXT_STATE) == 0 ? &kStateExtension : nullptr;
  }

 private:
  const mh_host* host_;
  std::string path_;
  std::unique_ptr<UnpackedArchive> archive_;  // before binary_: removed after dlclose
  ModelDescription md_;
  std::unique_ptr<Binary> binary_;
  fmi3Instance instance_ = nullptr;
  fmi3FMUState saved_ = nullptr;  // the handle fmi3GetFMUState reuses
  size_t nx_ = 0, ny_ = 0;
  std::vector<int32_t> x_idx_, y_idx_;
  std::vector<monohydra::SignalPort> inputs_;
  std::vector<fmi3ValueReference> input_vr_, output_vr_, unknown_vr_;
  std::vector<double> x_, dx_, u_, y_, plus_, column_;
  // The tangent's columns: valueReference, the state it is the column of,
  // and whether it is an input (index into u_) or a state (into x_).
  std::vector<fmi3ValueReference> knowns_;
  std::vector<int32_t> known_state_;
  std::vector<size_t> known_slot_;
  std::vector<bool> known_is_input_;
  double next_event_ = kNoEvent;
  bool states_changed_ = false;
  uint64_t state_bytes_ = 0;  // 0: the FMU cannot serialize its state
  uint64_t serialized_capacity_ = 0;
  monohydra::TouchedStates states_;

  const Functions& fmi() const { return binary_->fmi(); }

  // `fmu:` relative to the model file's folder (the host's model-folder
  // service), else to the working directory.
  std::string resolve(const char* file) const {
    namespace fs = std::filesystem;
    fs::path p(file != nullptr ? file : "");
    if (p.is_relative()) {
      const auto* folder = static_cast<const mh_model_folder_service*>(
          host_->get_service(host_, MH_SERVICE_MODEL_FOLDER));
      if (folder != nullptr && folder->model_folder != nullptr)
        p = fs::path(folder->model_folder(host_)) / p;
    }
    return p.lexically_normal().string();
  }

  mh_status refuse(const std::string& why) const {
    const std::string expected =
        "an FMI 3.0 Model Exchange FMU the import can run (" + path_ + ": " + why + ")";
    return monohydra::options(host_).option_error(host_, "fmu", expected.c_str());
  }

  mh_status fail(const std::string& what, double t) const {
    const std::string text = "FMU " + path_ + " at t = " + std::to_string(t) + " s: " + what;
    host_->log(host_, MH_LOG_ERROR, text.c_str());
    return MH_ERROR;
  }

  bool ok(fmi3Status status, const char* call, double t) const {
    if (status <= fmi3Warning) return true;
    (void)fail(std::string(call) + " returned " +
                   (status == fmi3Discard ? "fmi3Discard"
                    : status == fmi3Error ? "fmi3Error"
                                          : "fmi3Fatal"),
               t);
    return false;
  }

  // Parameters are options named after them (a number; default: start).
  std::vector<fmi3ValueReference> parameter_vr_;
  std::vector<double> parameter_value_;
  mh_status read_parameters() {
    for (const Variable& p : md_.parameters) {
      if (p.variability != "fixed" && p.variability != "tunable") continue;
      double value = p.start;
      const std::string expected = "a finite value of the FMU's parameter " + p.name;
      if (monohydra::finite_option(host_, p.name.c_str(), 0, p.start, expected.c_str(), &value) !=
          MH_OK)
        return MH_ERROR;
      parameter_vr_.push_back(p.vr);
      parameter_value_.push_back(value);
    }
    return MH_OK;
  }

  // Instantiation, initialization and the initial event iteration (FMI 3.0,
  // 3.2: Instantiated -> Initialization Mode -> Event Mode -> Continuous-Time Mode).
  mh_status instantiate() {
    const std::string resources = archive_->folder() + "/resources/";
    instance_ =
        fmi().instantiate(md_.model_name.c_str(), md_.instantiation_token.c_str(),
                          resources.c_str(), false, false, const_cast<mh_host*>(host_), fmu_log);
    if (instance_ == nullptr)
      return refuse(
          "fmi3InstantiateModelExchange returned NULL: the instantiationToken of its "
          "modelDescription.xml (" +
          md_.instantiation_token +
          ") is not its binary's, or the FMU failed as its log above says");
    if (!parameter_vr_.empty() &&
        !ok(fmi().set_float64(instance_, parameter_vr_.data(), parameter_vr_.size(),
                              parameter_value_.data(), parameter_value_.size()),
            "fmi3SetFloat64 (parameters)", 0.0))
      return MH_ERROR;
    if (!ok(fmi().enter_initialization(instance_, false, 0.0, 0.0, false, 0.0),
            "fmi3EnterInitializationMode", 0.0) ||
        !ok(fmi().exit_initialization(instance_), "fmi3ExitInitializationMode", 0.0) ||
        event_iteration(0.0) != MH_OK ||
        !ok(fmi().enter_continuous_time_mode(instance_), "fmi3EnterContinuousTimeMode", 0.0))
      return MH_ERROR;
    return MH_OK;
  }

  mh_status event_iteration(double t) {
    fmi3Boolean again = true, terminate = false, nominals = false, changed = false;
    fmi3Boolean defined = false;
    fmi3Float64 next = 0.0;
    states_changed_ = false;
    for (int k = 0; again; ++k) {
      if (k == kMaxEventIterations)
        return fail("its event iteration did not end within " +
                        std::to_string(kMaxEventIterations) + " updates",
                    t);
      if (!ok(fmi().update_discrete_states(instance_, &again, &terminate, &nominals, &changed,
                                           &defined, &next),
              "fmi3UpdateDiscreteStates", t))
        return MH_ERROR;
      if (terminate) return fail("the FMU asked to terminate the simulation", t);
      states_changed_ = states_changed_ || changed;
    }
    next_event_ = defined ? next : kNoEvent;
    return MH_OK;
  }

  // States (x, initial from the initialized FMU), input ports, outputs (y),
  // the first time event, the tangent's columns and every buffer.
  mh_status declare(double tolerance) {
    const mh_subsystem_setup_service& setup = monohydra::subsystem_setup(host_);
    nx_ = md_.states.size();
    ny_ = md_.outputs.size();
    x_.assign(nx_, 0.0);
    dx_.assign(nx_, 0.0);
    y_.assign(ny_, 0.0);
    if (nx_ > 0 &&
        !ok(fmi().get_continuous_states(instance_, x_.data(), nx_), "fmi3GetContinuousStates", 0.0))
      return MH_ERROR;
    for (const Variable& o : md_.outputs) output_vr_.push_back(o.vr);
    if (ny_ > 0 && !ok(fmi().get_float64(instance_, output_vr_.data(), ny_, y_.data(), ny_),
                       "fmi3GetFloat64 (outputs)", 0.0))
      return MH_ERROR;
    for (size_t i = 0; i < nx_; ++i) {
      const mh_state_spec spec = monohydra::state_spec(
          md_.states[i].name.c_str(), md_.states[i].unit.c_str(), x_[i], tolerance);
      int32_t index = -1;
      if (setup.add_state(host_, &spec, &index) != MH_OK) return MH_ERROR;
      states_.add(index);
      x_idx_.push_back(index);
    }
    inputs_.resize(md_.inputs.size());
    for (size_t m = 0; m < md_.inputs.size(); ++m) {
      const Variable& in = md_.inputs[m];
      if (inputs_[m].read(host_, in.name.c_str(), 0, in.start, states_) != MH_OK) return MH_ERROR;
      input_vr_.push_back(in.vr);
    }
    u_.assign(inputs_.size(), 0.0);
    for (size_t j = 0; j < ny_; ++j) {
      const mh_state_spec spec = monohydra::state_spec(
          md_.outputs[j].name.c_str(), md_.outputs[j].unit.c_str(), y_[j], tolerance);
      int32_t index = -1;
      if (setup.add_state(host_, &spec, &index) != MH_OK) return MH_ERROR;
      states_.add(index);
      y_idx_.push_back(index);
    }
    // A time event known now is the host's: it ends a step there and
    // restarts the integrator after it. Later ones are taken at the step
    // that reaches them (docs/fmi.md).
    if (next_event_ < kNoEvent && setup.add_time_event(host_, next_event_) != MH_OK)
      return MH_ERROR;
    for (size_t i = 0; i < nx_; ++i) {
      knowns_.push_back(md_.states[i].vr);
      known_state_.push_back(x_idx_[i]);
      known_slot_.push_back(i);
      known_is_input_.push_back(false);
    }
    for (size_t m = 0; m < inputs_.size(); ++m) {
      if (inputs_[m].state() < 0) continue;  // a number, a table, an input: no column
      knowns_.push_back(input_vr_[m]);
      known_state_.push_back(inputs_[m].state());
      known_slot_.push_back(m);
      known_is_input_.push_back(true);
    }
    unknown_vr_ = md_.derivatives;
    unknown_vr_.insert(unknown_vr_.end(), output_vr_.begin(), output_vr_.end());
    column_.assign(nx_ + ny_, 0.0);
    plus_.assign(nx_ + ny_, 0.0);
    return size_state();
  }

  // The bytes of a snapshot, fixed now: the serialized state's size at the
  // start (FMUs of fixed structure keep it), with the event time and a length.
  mh_status size_state() {
    if (fmi().serialize == nullptr) return MH_OK;
    size_t size = 0;
    if (!ok(fmi().get_state(instance_, &saved_), "fmi3GetFMUState", 0.0) ||
        !ok(fmi().serialized_size(instance_, saved_, &size), "fmi3SerializedFMUStateSize", 0.0))
      return MH_ERROR;
    serialized_capacity_ = size;
    state_bytes_ = sizeof(double) + sizeof(uint64_t) + serialized_capacity_;
    return MH_OK;
  }

  // The FMU at eval: time, states, inputs; then its rates and outputs.
  mh_status compute(const mh_subsystem_eval& eval) {
    for (size_t i = 0; i < nx_; ++i) x_[i] = eval.y[x_idx_[i]];
    for (size_t m = 0; m < inputs_.size(); ++m) u_[m] = inputs_[m].value();
    return compute_at(eval.t, dx_.data(), y_.data());
  }
  mh_status compute_at(double t, double* dx, double* y) {
    if (!ok(fmi().set_time(instance_, t), "fmi3SetTime", t) ||
        (nx_ > 0 && !ok(fmi().set_continuous_states(instance_, x_.data(), nx_),
                        "fmi3SetContinuousStates", t)) ||
        (!u_.empty() &&
         !ok(fmi().set_float64(instance_, input_vr_.data(), input_vr_.size(), u_.data(), u_.size()),
             "fmi3SetFloat64 (inputs)", t)) ||
        (nx_ > 0 &&
         !ok(fmi().get_derivatives(instance_, dx, nx_), "fmi3GetContinuousStateDerivatives", t)) ||
        (ny_ > 0 && !ok(fmi().get_float64(instance_, output_vr_.data(), ny_, y, ny_),
                        "fmi3GetFloat64 (outputs)", t)))
      return MH_ERROR;
    return MH_OK;
  }

  // column_ = d(xdot, y)/d(known c) at the point compute() set: the FMU's
  // directional derivative, or central differences with a scaled step.
  mh_status column(const mh_subsystem_eval& eval, size_t c) {
    if (fmi().directional_derivative != nullptr) {
      const double seed = 1.0;
      return ok(fmi().directional_derivative(instance_, unknown_vr_.data(), unknown_vr_.size(),
                                             &knowns_[c], 1, &seed, 1, column_.data(),
                                             column_.size()),
                "fmi3GetDirectionalDerivative", eval.t)
                 ? MH_OK
                 : MH_ERROR;
    }
    double& v = known_is_input_[c] ? u_[known_slot_[c]] : x_[known_slot_[c]];
    const double base = v;
    const double h = kDifferenceStep * std::max(1.0, std::abs(base));
    v = base + h;
    mh_status s = compute_at(eval.t, plus_.data(), plus_.data() + nx_);
    if (s == MH_OK) {
      v = base - h;
      s = compute_at(eval.t, column_.data(), column_.data() + nx_);
    }
    v = base;
    if (s != MH_OK) return s;
    for (size_t r = 0; r < column_.size(); ++r) column_[r] = (plus_[r] - column_[r]) / (2.0 * h);
    return compute_at(eval.t, dx_.data(), y_.data());  // the FMU back at the point
  }

  // The state extension (state.h): the FMU's serialized state and the next
  // time event; refused, with the reason, when the FMU cannot serialize.
  static Fmu& of(const void* instance) {
    return monohydra::SubsystemAdapter<Fmu>::object_of(instance);
  }
  mh_status cannot_snapshot() const {
    const std::string text =
        "FMU " + path_ +
        " cannot save or restore its state (its modelDescription.xml does not declare both "
        "canGetAndSetFMUState and canSerializeFMUState): a run with it has no snapshot";
    host_->log(host_, MH_LOG_ERROR, text.c_str());
    return MH_ERROR;
  }
  static uint64_t state_size(const void* instance) noexcept {
    return instance != nullptr ? of(instance).state_bytes_ : 0;
  }
  static mh_status save_state(const void* instance, void* bytes, uint64_t size) noexcept {
    if (instance == nullptr) return MH_ERROR;
    Fmu& f = of(instance);
    if (f.state_bytes_ == 0) return f.cannot_snapshot();
    if (bytes == nullptr || size != f.state_bytes_) return f.fail("save: wrong buffer size", 0.0);
    size_t n = 0;
    if (!f.ok(f.fmi().get_state(f.instance_, &f.saved_), "fmi3GetFMUState", 0.0) ||
        !f.ok(f.fmi().serialized_size(f.instance_, f.saved_, &n), "fmi3SerializedFMUStateSize",
              0.0))
      return MH_ERROR;
    if (n > f.serialized_capacity_)
      return f.fail("its serialized state grew to " + std::to_string(n) + " bytes from " +
                        std::to_string(f.serialized_capacity_) +
                        " at the start: a snapshot's size is fixed",
                    0.0);
    auto* at = static_cast<unsigned char*>(bytes);
    const uint64_t length = n;
    std::memcpy(at, &f.next_event_, sizeof(double));
    std::memcpy(at + sizeof(double), &length, sizeof length);
    unsigned char* serialized = at + sizeof(double) + sizeof length;
    std::memset(serialized, 0, static_cast<size_t>(f.serialized_capacity_));
    return f.ok(f.fmi().serialize(f.instance_, f.saved_, serialized, n), "fmi3SerializeFMUState",
                0.0)
               ? MH_OK
               : MH_ERROR;
  }
  static mh_status load_state(const void* instance, const void* bytes, uint64_t size) noexcept {
    if (instance == nullptr) return MH_ERROR;
    Fmu& f = of(instance);
    if (f.state_bytes_ == 0) return f.cannot_snapshot();
    if (bytes == nullptr || size != f.state_bytes_)
      return f.fail("load: " + std::to_string(size) + " bytes given, " +
                        std::to_string(f.state_bytes_) + " expected",
                    0.0);
    const auto* at = static_cast<const unsigned char*>(bytes);
    double next = 0.0;
    uint64_t length = 0;
    std::memcpy(&next, at, sizeof next);
    std::memcpy(&length, at + sizeof(double), sizeof length);
    if (length > f.serialized_capacity_) return f.fail("load: a serialized state too long", 0.0);
    fmi3FMUState state = nullptr;
    if (!f.ok(f.fmi().deserialize(f.instance_, at + sizeof(double) + sizeof length,
                                  static_cast<size_t>(length), &state),
              "fmi3DeserializeFMUState", 0.0))
      return MH_ERROR;
    const bool set = f.ok(f.fmi().set_state(f.instance_, state), "fmi3SetFMUState", 0.0);
    f.fmi().free_state(f.instance_, &state);
    if (!set) return MH_ERROR;
    f.next_event_ = next;
    return MH_OK;
  }
  static const mh_state_extension kStateExtension;
};

const mh_state_extension Fmu::kStateExtension{sizeof(mh_state_extension), Fmu::state_size,
                                              Fmu::save_state, Fmu::load_state};

const mh_component_descriptor Fmu::kDescriptor{
    sizeof(mh_component_descriptor),
    "fmu",
    "FMI 3.0 Model Exchange FMU",
    "monohydra",
    "1.0.0",
    "An FMI 3.0 Model Exchange FMU's equations in the Newton step. Options: fmu (the .fmu file, "
    "relative to the model file), each Float64 input by its name (a signal port: a number, a "
    "table, an input or a state instance.state; default its start), each Float64 parameter by "
    "its name (default its start), tolerance (default 1e-9). States: the FMU's continuous states "
    "and its Float64 outputs (algebraic), by their names."};

}  // namespace

const monohydra::SubsystemComponent kFmu = monohydra::subsystem_component<Fmu>();

}  // namespace fmu
