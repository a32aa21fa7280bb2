// The C API (simulation.h) over an Instance: each call checks its
// arguments, runs inside one guard that turns every exception into a status
// and a message, and keeps the rule that a failed step leaves the run at its
// last accepted state until a snapshot is restored.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "api_arguments.hpp"
#include "api_handle.hpp"
#include "instance.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/linearization.hpp"
#include "monohydra/core/run_state_bytes.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "monohydra/simulation.h"

using mh::embed::ensure_started;
using mh::embed::guarded;
using mh::embed::Instance;
using mh::embed::kNullHandle;
using mh::embed::read_settings;
using mh::embed::refuse;

struct mhs_linearization {
  mh::Linearization result;
};

struct mhs_snapshot {
  mh::RunState state;
  bool saved = false;  // holds a state (saved or read)
  std::vector<unsigned char> bytes;
  bool bytes_current = false;  // bytes are state's
};

namespace {

using monohydra::short_number;

mhs_status open(const mh::embed::OpenRequest& request, mhs_simulation** out) {
  if (out == nullptr) return MHS_ERROR;
  *out = nullptr;
  auto* sim = new (std::nothrow) mhs_simulation;
  if (sim == nullptr) return MHS_FATAL;
  *out = sim;
  try {
    sim->instance = std::make_unique<Instance>(request);
    // The plugins' words while setting up.
    sim->message = std::exchange(sim->instance->warnings, std::string());
    return sim->message.empty() ? MHS_OK : MHS_WARNING;
  } catch (const std::bad_alloc&) {
    sim->message = "out of memory while opening the model";
  } catch (const std::exception& err) {
    sim->message = err.what();
  } catch (...) {
    sim->message = "an unknown exception while opening the model";
  }
  return MHS_FATAL;
}

mhs_status refused_open(const std::string& why, mhs_simulation** out) {
  if (out == nullptr) return MHS_ERROR;
  *out = new (std::nothrow) mhs_simulation;
  if (*out != nullptr) (*out)->message = why;
  return MHS_FATAL;
}

}  // namespace

extern "C" {

MHS_API uint32_t mhs_api_version(void) {
  return MHS_API_VERSION_MAJOR << 16 | MHS_API_VERSION_MINOR;
}

MHS_API mhs_status mhs_open_file(const char* model_path, const mhs_setting* settings, size_t count,
                                 mhs_simulation** out) {
  mh::embed::OpenRequest request;
  if (model_path == nullptr) return refused_open("the model path is NULL", out);
  request.path = model_path;
  if (request.path.empty()) return refused_open("the model path is empty", out);
  const std::string why = read_settings(settings, count, request);
  if (!why.empty()) return refused_open(why, out);
  return open(request, out);
}

MHS_API mhs_status mhs_open_text(const char* yaml_text, const char* label, const char* base_dir,
                                 const mhs_setting* settings, size_t count, mhs_simulation** out) {
  mh::embed::OpenRequest request;
  if (yaml_text == nullptr) return refused_open("the model text is NULL", out);
  request.text = yaml_text;
  request.label = label != nullptr ? label : "(model text)";
  request.base_dir = base_dir != nullptr ? base_dir : "";
  const std::string why = read_settings(settings, count, request);
  if (!why.empty()) return refused_open(why, out);
  return open(request, out);
}

MHS_API void mhs_free(mhs_simulation* sim) {
  delete sim;  // the simulation destroys every plugin instance of the run
}

MHS_API const char* mhs_message(const mhs_simulation* sim) {
  if (sim == nullptr) return kNullHandle;
  if (mh::embed::refused_in_use<mhs_simulation>() == sim) return mh::embed::kInUse;
  return sim->message.c_str();
}

MHS_API void mhs_cancel(mhs_simulation* sim) {
  if (sim != nullptr) sim->cancelled.store(true, std::memory_order_release);
}

MHS_API mhs_status mhs_start(mhs_simulation* sim) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (sim->started) return refuse(sim, "the run has started already");
    ensure_started(sim, in);
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_step(mhs_simulation* sim) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (!sim->failure.empty())
      return refuse(sim, "the run takes no step after a failed one (" + sim->failure +
                             "); restore a snapshot (mhs_restore) to go on");
    ensure_started(sim, in);
    try {
      in.sim().step();
    } catch (const mh::SimulationError& err) {
      sim->failure = err.what();
      return refuse(sim, sim->failure);
    }
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_advance(mhs_simulation* sim, double t) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (!sim->failure.empty())
      return refuse(sim, "the run takes no step after a failed one (" + sim->failure +
                             "); restore a snapshot (mhs_restore) to go on");
    if (!std::isfinite(t))
      return refuse(sim, "mhs_advance: t = " + short_number(t) + " is not a finite time");
    ensure_started(sim, in);
    mh::Simulation& s = in.sim();
    const double dt = s.settings().dt;
    if (t < s.time() - 1e-6 * dt)
      return refuse(sim, "mhs_advance: t = " + short_number(t) + " s is before the run's time " +
                             short_number(s.time()) + " s");
    while (s.time() < t - 1e-6 * dt) {
      if (sim->cancelled.load(std::memory_order_relaxed) && mh::embed::cancel_asked(sim)) {
        sim->message = "mhs_advance: cancelled (mhs_cancel) at t = " + short_number(s.time()) +
                       " s, step " + std::to_string(s.step_index()) +
                       "; the run goes on from there";
        return MHS_DISCARD;
      }
      try {
        s.step();
      } catch (const mh::SimulationError& err) {
        sim->failure = err.what();
        return refuse(sim, sim->failure);
      }
    }
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_time(const mhs_simulation* csim, double* t, int64_t* steps, double* dt,
                            double* t_end) {
  auto* sim = const_cast<mhs_simulation*>(csim);  // the message is the handle's own
  return guarded(sim, [&](Instance& in) -> mhs_status {
    const mh::Simulation& s = in.sim();
    if (t != nullptr) *t = s.time();
    if (steps != nullptr) *steps = s.step_index();
    if (dt != nullptr) *dt = s.settings().dt;
    if (t_end != nullptr) *t_end = s.settings().t_end;
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_variable_count(const mhs_simulation* csim, uint32_t* count) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (count == nullptr) return refuse(sim, "mhs_variable_count: count is NULL");
    *count = static_cast<uint32_t>(in.variables().size());
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_variable(const mhs_simulation* csim, uint32_t index,
                                mhs_variable_info* info) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    const std::string why = mh::embed::describe("mhs_variable", in.variables(), index, info);
    return why.empty() ? MHS_OK : refuse(sim, why);
  });
}

MHS_API mhs_status mhs_find(const mhs_simulation* csim, const char* name, uint32_t* index) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (name == nullptr || index == nullptr) return refuse(sim, "mhs_find: name or index is NULL");
    const int k = in.find(name);
    if (k < 0)
      return refuse(sim, std::string("mhs_find: no value is called '") + name +
                             "' (mhs_variable lists them)");
    *index = static_cast<uint32_t>(k);
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_get(const mhs_simulation* csim, const uint32_t* indices, size_t count,
                           double* values) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (count > 0 && (indices == nullptr || values == nullptr))
      return refuse(sim, "mhs_get: indices or values is NULL");
    if (!sim->started) return refuse(sim, "mhs_get: the run has not started (mhs_start)");
    const auto& vars = in.variables();
    for (size_t i = 0; i < count; ++i)
      if (indices[i] >= vars.size())
        return refuse(sim, "mhs_get: indices[" + std::to_string(i) +
                               "] = " + std::to_string(indices[i]) + " is not below " +
                               std::to_string(vars.size()));
    for (size_t i = 0; i < count; ++i) values[i] = in.value(vars[indices[i]]);
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_set(mhs_simulation* sim, const uint32_t* indices, size_t count,
                           const double* values) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (count > 0 && (indices == nullptr || values == nullptr))
      return refuse(sim, "mhs_set: indices or values is NULL");
    const auto& vars = in.variables();
    // Everything checked before anything is set: all or nothing.
    for (size_t i = 0; i < count; ++i) {
      if (indices[i] >= vars.size())
        return refuse(sim, "mhs_set: indices[" + std::to_string(i) +
                               "] = " + std::to_string(indices[i]) + " is not below " +
                               std::to_string(vars.size()));
      const mh::embed::Variable& v = vars[indices[i]];
      if (v.kind != MHS_INPUT)
        return refuse(sim, "mhs_set: '" + v.name +
                               "' is not an input (only the model's inputs: "
                               "are set)");
      const std::string refused = in.sim().input_refusal(v.index, values[i]);
      if (!refused.empty()) return refuse(sim, "mhs_set: " + refused);
    }
    std::string clamped;
    for (size_t i = 0; i < count; ++i) {
      const mh::embed::Variable& v = vars[indices[i]];
      const double took = in.sim().set_input(v.index, values[i]);
      if (took != values[i])
        clamped +=
            (clamped.empty() ? "" : "; ") + ("input '" + v.name + "': " + short_number(values[i]) +
                                             " clamped to " + short_number(took));
    }
    if (!clamped.empty()) {
      sim->message = "mhs_set: " + clamped + " (out_of_range: clamp)";
      return MHS_WARNING;
    }
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_set_parameter(mhs_simulation* sim, const char* path, double value) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (path == nullptr) return refuse(sim, "mhs_set_parameter: path is NULL");
    if (!std::isfinite(value))
      return refuse(sim, std::string("mhs_set_parameter: ") + path +
                             ": expected a finite value, got " + short_number(value));
    try {
      in.set_parameter(path, mh::embed::exact_text(value));
    } catch (const std::invalid_argument& err) {
      return refuse(sim, std::string("mhs_set_parameter: ") + err.what());
    }
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_track_sensitivities(mhs_simulation* sim, const char* const* paths,
                                           size_t count) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (paths == nullptr || count == 0)
      return refuse(sim, "mhs_track_sensitivities: expected count > 0 paths");
    std::vector<std::string> list;
    for (size_t i = 0; i < count; ++i) {
      if (paths[i] == nullptr)
        return refuse(sim, "mhs_track_sensitivities: path " + std::to_string(i) + " is NULL");
      list.emplace_back(paths[i]);
    }
    try {
      in.track_sensitivities(list);
    } catch (const std::invalid_argument& err) {
      return refuse(sim, std::string("mhs_track_sensitivities: ") + err.what());
    }
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_get_sensitivities(const mhs_simulation* csim, const uint32_t* indices,
                                         size_t count, double* out) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    const int k = in.num_sensitivities();
    if (k == 0)
      return refuse(sim,
                    "mhs_get_sensitivities: no parameters are tracked "
                    "(mhs_track_sensitivities, before the run starts)");
    if (count > 0 && (indices == nullptr || out == nullptr))
      return refuse(sim, "mhs_get_sensitivities: indices or out is NULL");
    const auto& variables = in.variables();
    for (size_t i = 0; i < count; ++i)
      if (indices[i] >= variables.size())
        return refuse(sim, "mhs_get_sensitivities: index " + std::to_string(indices[i]) +
                               " is not below " + std::to_string(variables.size()));
    for (size_t i = 0; i < count; ++i)
      for (int j = 0; j < k; ++j)
        out[i * static_cast<size_t>(k) + static_cast<size_t>(j)] =
            in.sensitivity(variables[indices[i]], j);
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_row_size(const mhs_simulation* csim, uint32_t* columns) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (columns == nullptr) return refuse(sim, "mhs_row_size: columns is NULL");
    *columns = static_cast<uint32_t>(in.layout().names().size());
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_row_name(const mhs_simulation* csim, uint32_t column, const char** name) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (name == nullptr) return refuse(sim, "mhs_row_name: name is NULL");
    const auto& names = in.layout().names();
    if (column >= names.size())
      return refuse(sim, "mhs_row_name: column " + std::to_string(column) + " is not below " +
                             std::to_string(names.size()));
    *name = names[column].c_str();
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_row_due(const mhs_simulation* csim, int32_t* due) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (due == nullptr) return refuse(sim, "mhs_row_due: due is NULL");
    *due = sim->started && in.sim().step_index() % in.layout().every_steps() == 0 ? 1 : 0;
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_row(const mhs_simulation* csim, double* values, size_t capacity) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    const size_t n = in.layout().names().size();
    if (values == nullptr || capacity < n)
      return refuse(sim, "mhs_row: the row has " + std::to_string(n) + " values, the buffer " +
                             (values == nullptr ? std::string("is NULL")
                                                : "holds " + std::to_string(capacity)));
    if (!sim->started) return refuse(sim, "mhs_row: the run has not started (mhs_start)");
    in.layout().values(in.sim(), values);
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_row_text(const mhs_simulation* csim, int32_t header, char* text,
                                size_t capacity, size_t* length) {
  auto* sim = const_cast<mhs_simulation*>(csim);
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (header == 0 && !sim->started)
      return refuse(sim, "mhs_row_text: the run has not started (mhs_start)");
    const std::string& row = in.row_text(header != 0);
    if (length != nullptr) *length = row.size();
    if (text == nullptr || capacity < row.size() + 1)
      return refuse(
          sim,
          "mhs_row_text: the text needs " + std::to_string(row.size() + 1) + " bytes, the buffer " +
              (text == nullptr ? std::string("is NULL") : "holds " + std::to_string(capacity)));
    std::memcpy(text, row.c_str(), row.size() + 1);
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_snapshot_new(mhs_simulation* sim, mhs_snapshot** out) {
  return guarded(sim, [&](Instance&) -> mhs_status {
    if (out == nullptr) return refuse(sim, "mhs_snapshot_new: out is NULL");
    *out = new mhs_snapshot;
    return MHS_OK;
  });
}

MHS_API void mhs_snapshot_free(mhs_snapshot* snapshot) {
  delete snapshot;
}

MHS_API mhs_status mhs_save(mhs_simulation* sim, mhs_snapshot* snapshot) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (snapshot == nullptr) return refuse(sim, "mhs_save: the snapshot is NULL");
    if (!sim->started) return refuse(sim, "mhs_save: the run has not started (mhs_start)");
    snapshot->bytes_current = false;
    snapshot->saved = false;
    in.sim().save_state(snapshot->state);
    snapshot->saved = true;
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_restore(mhs_simulation* sim, const mhs_snapshot* snapshot) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (snapshot == nullptr) return refuse(sim, "mhs_restore: the snapshot is NULL");
    if (!snapshot->saved) return refuse(sim, "mhs_restore: the snapshot holds no state yet");
    const std::string differ = in.sim().model_differences(snapshot->state);
    in.sim().restore_state(snapshot->state);
    sim->started = true;
    sim->failure.clear();
    sim->message.clear();  // what the failure said goes with it
    if (differ.empty()) return MHS_OK;
    sim->message = "mhs_restore: the snapshot was saved with other values of the model (" + differ +
                   "): the run goes on from its state as this run's model";
    return MHS_WARNING;
  });
}

MHS_API mhs_status mhs_snapshot_bytes(mhs_simulation* sim, mhs_snapshot* snapshot,
                                      const void** bytes, size_t* size) {
  return guarded(sim, [&](Instance&) -> mhs_status {
    if (snapshot == nullptr || bytes == nullptr || size == nullptr)
      return refuse(sim, "mhs_snapshot_bytes: the snapshot, bytes or size is NULL");
    if (!snapshot->saved) return refuse(sim, "mhs_snapshot_bytes: the snapshot holds no state yet");
    if (!snapshot->bytes_current) {
      mh::write_run_state_bytes(snapshot->state, snapshot->bytes);
      snapshot->bytes_current = true;
    }
    *bytes = snapshot->bytes.data();
    *size = snapshot->bytes.size();
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_snapshot_read(mhs_simulation* sim, mhs_snapshot* snapshot, const void* bytes,
                                     size_t size) {
  return guarded(sim, [&](Instance&) -> mhs_status {
    if (snapshot == nullptr || (bytes == nullptr && size > 0))
      return refuse(sim, "mhs_snapshot_read: the snapshot or bytes is NULL");
    snapshot->saved = false;
    snapshot->bytes_current = false;
    mh::read_run_state_bytes(static_cast<const unsigned char*>(bytes), size, snapshot->state);
    snapshot->saved = true;
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_linearize(mhs_simulation* sim, const uint32_t* outputs, size_t count,
                                 mhs_linearization** out) {
  if (out != nullptr) *out = nullptr;
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (out == nullptr) return refuse(sim, "mhs_linearize: out is NULL");
    if (count > 0 && outputs == nullptr)
      return refuse(sim, "mhs_linearize: outputs is NULL with a count of " + std::to_string(count));
    if (!sim->started) return refuse(sim, "mhs_linearize: the run has not started (mhs_start)");
    if (!sim->failure.empty())
      return refuse(sim, "mhs_linearize: the last step failed (" + sim->failure +
                             "); restore a snapshot (mhs_restore) first");
    // The core names outputs as mhs_find does: coordinates, "z1_dot", qualified names.
    std::vector<std::string> names;
    for (size_t i = 0; i < count; ++i) {
      if (outputs[i] >= in.variables().size())
        return refuse(sim, "mhs_linearize: output " + std::to_string(i) + " is value " +
                               std::to_string(outputs[i]) + ", not one of the " +
                               std::to_string(in.variables().size()) + " (mhs_variable_count)");
      const mh::embed::Variable& v = in.variables()[outputs[i]];
      if (v.kind == MHS_INPUT)
        return refuse(sim, "mhs_linearize: output " + std::to_string(i) + " is the input '" +
                               v.name + "' (inputs are the columns of B and D)");
      names.push_back(v.kind == MHS_COORDINATE || v.kind == MHS_COORDINATE_RATE ? v.name
                                                                                : v.qualified);
    }
    auto lin = std::make_unique<mhs_linearization>();
    lin->result = mh::linearize(in.sim(), names);
    for (size_t i = 0; i < count; ++i)
      lin->result.outputs[i].name = in.variables()[outputs[i]].name;
    *out = lin.release();
    return MHS_OK;
  });
}

MHS_API void mhs_linearization_free(mhs_linearization* lin) {
  delete lin;
}

MHS_API mhs_status mhs_linearization_size(mhs_simulation* sim, const mhs_linearization* lin,
                                          uint32_t* n, uint32_t* m, uint32_t* p, double* t) {
  return guarded(sim, [&](Instance&) -> mhs_status {
    if (lin == nullptr) return refuse(sim, "mhs_linearization_size: the linearisation is NULL");
    const mh::Linearization& r = lin->result;
    if (n != nullptr) *n = static_cast<uint32_t>(r.states.size());
    if (m != nullptr) *m = static_cast<uint32_t>(r.inputs.size());
    if (p != nullptr) *p = static_cast<uint32_t>(r.outputs.size());
    if (t != nullptr) *t = r.t;
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_linearization_matrix(mhs_simulation* sim, const mhs_linearization* lin,
                                            char which, double* values, size_t capacity) {
  return guarded(sim, [&](Instance&) -> mhs_status {
    if (lin == nullptr) return refuse(sim, "mhs_linearization_matrix: the linearisation is NULL");
    const mh::Linearization& r = lin->result;
    const Eigen::MatrixXd* matrix = which == 'A'   ? &r.A
                                    : which == 'B' ? &r.B
                                    : which == 'C' ? &r.C
                                    : which == 'D' ? &r.D
                                                   : nullptr;
    if (matrix == nullptr)
      return refuse(sim, std::string("mhs_linearization_matrix: which = '") + which +
                             "' (expected 'A', 'B', 'C' or 'D')");
    const auto size = static_cast<size_t>(matrix->size());
    if (size > 0 && (values == nullptr || capacity < size))
      return refuse(sim, std::string("mhs_linearization_matrix: ") + which + " has " +
                             std::to_string(size) + " entries; values holds " +
                             std::to_string(values == nullptr ? 0 : capacity));
    std::copy(matrix->data(), matrix->data() + size, values);  // Eigen: column-major
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_linearization_name(mhs_simulation* sim, const mhs_linearization* lin,
                                          mhs_linear_role role, uint32_t k, const char** name,
                                          const char** unit) {
  return guarded(sim, [&](Instance&) -> mhs_status {
    if (lin == nullptr) return refuse(sim, "mhs_linearization_name: the linearisation is NULL");
    const mh::Linearization& r = lin->result;
    const std::vector<mh::LinearVariable>* list = role == MHS_LINEAR_STATE    ? &r.states
                                                  : role == MHS_LINEAR_INPUT  ? &r.inputs
                                                  : role == MHS_LINEAR_OUTPUT ? &r.outputs
                                                                              : nullptr;
    if (list == nullptr)
      return refuse(sim, "mhs_linearization_name: role " + std::to_string(role) +
                             " (expected MHS_LINEAR_STATE, _INPUT or _OUTPUT)");
    if (k >= list->size())
      return refuse(sim, "mhs_linearization_name: " + std::to_string(k) + " is not below " +
                             std::to_string(list->size()));
    if (name != nullptr) *name = (*list)[k].name.c_str();
    if (unit != nullptr) *unit = (*list)[k].unit.c_str();
    return MHS_OK;
  });
}

}  // extern "C"
