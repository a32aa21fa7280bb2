// The batch's C API (simulation.h, 1.5): each call checks its arguments
// and runs inside one guard that turns every exception into a status and a
// message, as a run's calls do (simulation_api.cpp).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "api_arguments.hpp"
#include "api_handle.hpp"
#include "batch.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/run_state_bytes.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "monohydra/simulation.h"

struct mhs_batch {
  std::unique_ptr<mh::embed::Batch> batch;  // null: the model did not open
  // What the last call that did not return MHS_OK said, kept through the
  // calls that do until the next one that does not, or a restore.
  std::string message;
  std::atomic<bool> in_call{false};  // a thread is in a call on this batch
};

struct mhs_batch_snapshot {
  const mh::embed::Batch* of = nullptr;  // the batch it was made for
  std::vector<mh::RunState> runs;
  bool saved = false;
  std::vector<unsigned char> bytes;  // the runs' bytes (mhs_batch_snapshot_bytes)
  bool bytes_current = false;        // bytes are runs'
};

namespace {

using mh::embed::Batch;
using monohydra::short_number;

constexpr const char* kBatchInUse =
    "refused: another thread is in a call on this batch (a batch is used by one thread at a "
    "time; its own threads step its runs)";

// Runs `body` on an open batch (guarded_call).
template <class Body>
mhs_status guarded(mhs_batch* b, Body&& body) {
  return mh::embed::guarded_call(
      b, [](mhs_batch& h) { return h.batch.get(); },
      [](Batch& batch) { return batch.take_warnings(); }, "mhs_batch_free",
      std::forward<Body>(body));
}

constexpr unsigned char kBatchMagic[8] = {'M', 'H', 'B', 'A', 'T', 'C', 'H', '1'};

void append(std::vector<unsigned char>& out, uint64_t v) {
  unsigned char raw[sizeof v];
  std::memcpy(raw, &v, sizeof v);
  out.insert(out.end(), raw, raw + sizeof v);
}

// Takes n bytes off the front (into `into` when it is a uint64); false when
// fewer are left.
bool take(const unsigned char*& p, size_t& left, size_t n, uint64_t* into) {
  if (n > left) return false;
  if (into != nullptr) std::memcpy(into, p, sizeof *into);
  p += n;
  left -= n;
  return true;
}

mhs_status refuse(mhs_batch* b, const std::string& why) {
  b->message = why;
  return MHS_ERROR;
}

// After a step or an advance: the runs stopped, each named (MHS_DISCARD:
// done for the others).
mhs_status stopped(mhs_batch* b, size_t count) {
  if (count == 0) return MHS_OK;
  b->message = std::to_string(count) + " of " + std::to_string(b->batch->size()) +
               " runs are stopped (the others went on):\n" + b->batch->failures();
  return MHS_DISCARD;
}

// A step or advance that mhs_batch_cancel ended: each run stopped between
// two of its steps, at an accepted state, and goes on from there.
mhs_status cancelled(mhs_batch* b, const Batch& batch, const char* call) {
  double lo = batch.run(0).sim->time(), hi = lo;
  for (size_t k = 1; k < batch.size(); ++k) {
    lo = std::min(lo, batch.run(k).sim->time());
    hi = std::max(hi, batch.run(k).sim->time());
  }
  b->message =
      std::string(call) +
      ": cancelled (mhs_batch_cancel); each run is at an accepted state (t = " + short_number(lo) +
      (hi > lo ? " to " + short_number(hi) : std::string()) + " s) and goes on from there";
  const std::string failures = batch.failures();
  if (!failures.empty()) b->message += "; stopped runs:\n" + failures;
  return MHS_DISCARD;
}

mhs_status open(const mh::embed::OpenRequest& request, uint32_t runs, uint32_t threads,
                mhs_batch** out) {
  auto* b = new (std::nothrow) mhs_batch;
  if (b == nullptr) return MHS_FATAL;
  *out = b;
  try {
    b->batch = std::make_unique<Batch>(request, runs, threads);
    b->message = b->batch->take_warnings();  // the plugins' words while setting up
    return b->message.empty() ? MHS_OK : MHS_WARNING;
  } catch (const std::bad_alloc&) {
    b->message = "out of memory while opening the batch";
  } catch (const std::exception& err) {
    b->message = err.what();
  } catch (...) {
    b->message = "an unknown exception while opening the batch";
  }
  return MHS_FATAL;
}

mhs_status refused_open(const std::string& why, mhs_batch** out) {
  *out = new (std::nothrow) mhs_batch;
  if (*out != nullptr) (*out)->message = why;
  return MHS_FATAL;
}

}  // namespace

namespace {

// Why a per-run array is refused ("" when it is not).
std::string per_run(const char* call, const Batch& batch, uint32_t index, const void* values,
                    size_t runs) {
  const auto& table = batch.variables().list();
  if (values == nullptr) return std::string(call) + ": values is NULL";
  if (runs != batch.size())
    return std::string(call) + ": " + std::to_string(runs) + " values for " +
           std::to_string(batch.size()) + " runs";
  if (index >= table.size())
    return std::string(call) + ": index " + std::to_string(index) + " is not below " +
           std::to_string(table.size());
  return "";
}

}  // namespace

extern "C" {

MHS_API mhs_status mhs_batch_open_file(const char* model_path, const mhs_setting* settings,
                                       size_t count, uint32_t runs, uint32_t threads,
                                       mhs_batch** out) {
  if (out == nullptr) return MHS_ERROR;
  mh::embed::OpenRequest request;
  if (model_path == nullptr || *model_path == '\0')
    return refused_open("the model path is NULL or empty", out);
  request.path = model_path;
  const std::string why = mh::embed::read_settings(settings, count, request);
  if (!why.empty()) return refused_open(why, out);
  return open(request, runs, threads, out);
}

MHS_API mhs_status mhs_batch_open_text(const char* yaml_text, const char* label,
                                       const char* base_dir, const mhs_setting* settings,
                                       size_t count, uint32_t runs, uint32_t threads,
                                       mhs_batch** out) {
  if (out == nullptr) return MHS_ERROR;
  mh::embed::OpenRequest request;
  if (yaml_text == nullptr) return refused_open("the model text is NULL", out);
  request.text = yaml_text;
  request.label = label != nullptr ? label : "(model text)";
  request.base_dir = base_dir != nullptr ? base_dir : "";
  const std::string why = mh::embed::read_settings(settings, count, request);
  if (!why.empty()) return refused_open(why, out);
  return open(request, runs, threads, out);
}

MHS_API void mhs_batch_free(mhs_batch* batch) {
  delete batch;
}

MHS_API const char* mhs_batch_message(const mhs_batch* batch) {
  if (batch == nullptr) return "the batch handle is NULL";
  if (mh::embed::refused_in_use<mhs_batch>() == batch) return kBatchInUse;
  return batch->message.c_str();
}

MHS_API void mhs_batch_cancel(mhs_batch* batch) {
  if (batch != nullptr && batch->batch) batch->batch->cancel();
}

MHS_API mhs_status mhs_batch_size(const mhs_batch* cb, uint32_t* runs, uint32_t* threads) {
  auto* b = const_cast<mhs_batch*>(cb);  // the message is the handle's own
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (runs != nullptr) *runs = static_cast<uint32_t>(batch.size());
    if (threads != nullptr) *threads = batch.threads();
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_batch_time(const mhs_batch* cb, double* dt, double* t_end) {
  auto* b = const_cast<mhs_batch*>(cb);
  return guarded(b, [&](Batch& batch) -> mhs_status {
    const mh::SolverSettings& s = batch.run(0).sim->settings();
    if (dt != nullptr) *dt = s.dt;
    if (t_end != nullptr) *t_end = s.t_end;
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_batch_set_parameter(mhs_batch* b, uint32_t run, const char* path,
                                           double value) {
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (path == nullptr) return refuse(b, "mhs_batch_set_parameter: path is NULL");
    if (!std::isfinite(value))
      return refuse(b, std::string("mhs_batch_set_parameter: ") + path +
                           ": expected a finite value, got " + short_number(value));
    try {
      batch.set_parameter(run, path, mh::embed::exact_text(value));
    } catch (const std::invalid_argument& err) {
      return refuse(b, "mhs_batch_set_parameter: run " + std::to_string(run) + ": " + err.what());
    }
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_batch_start(mhs_batch* b) {
  return guarded(b, [&](Batch& batch) -> mhs_status { return stopped(b, batch.step(0)); });
}

MHS_API mhs_status mhs_batch_step(mhs_batch* b, uint64_t steps) {
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (steps > static_cast<uint64_t>(1) << 40)
      return refuse(b, "mhs_batch_step: " + std::to_string(steps) + " steps is more than 2^40");
    const size_t stopped_runs = batch.step(static_cast<long>(steps));
    if (batch.take_cancelled()) return cancelled(b, batch, "mhs_batch_step");
    return stopped(b, stopped_runs);
  });
}

MHS_API mhs_status mhs_batch_advance(mhs_batch* b, double t) {
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (!std::isfinite(t))
      return refuse(b, "mhs_batch_advance: t = " + short_number(t) + " is not a finite time");
    for (size_t k = 0; k < batch.size(); ++k) {
      const mh::Simulation& s = *batch.run(k).sim;
      if (t < s.time() - 1e-6 * s.settings().dt)
        return refuse(b, "mhs_batch_advance: t = " + short_number(t) + " s is before run " +
                             std::to_string(k) + "'s time " + short_number(s.time()) + " s");
    }
    const size_t stopped_runs = batch.advance(t);
    if (batch.take_cancelled()) return cancelled(b, batch, "mhs_batch_advance");
    return stopped(b, stopped_runs);
  });
}

MHS_API mhs_status mhs_batch_variable_count(const mhs_batch* cb, uint32_t* count) {
  auto* b = const_cast<mhs_batch*>(cb);
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (count == nullptr) return refuse(b, "mhs_batch_variable_count: count is NULL");
    *count = static_cast<uint32_t>(batch.variables().list().size());
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_batch_variable(const mhs_batch* cb, uint32_t index,
                                      mhs_variable_info* info) {
  auto* b = const_cast<mhs_batch*>(cb);
  return guarded(b, [&](Batch& batch) -> mhs_status {
    const std::string why =
        mh::embed::describe("mhs_batch_variable", batch.variables().list(), index, info);
    return why.empty() ? MHS_OK : refuse(b, why);
  });
}

MHS_API mhs_status mhs_batch_find(const mhs_batch* cb, const char* name, uint32_t* index) {
  auto* b = const_cast<mhs_batch*>(cb);
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (name == nullptr || index == nullptr)
      return refuse(b, "mhs_batch_find: name or index is NULL");
    const int k = batch.variables().find(name);
    if (k < 0)
      return refuse(b, std::string("mhs_batch_find: the model has no value '") + name + "'");
    *index = static_cast<uint32_t>(k);
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_batch_get(const mhs_batch* cb, uint32_t index, double* values, size_t runs) {
  auto* b = const_cast<mhs_batch*>(cb);
  return guarded(b, [&](Batch& batch) -> mhs_status {
    const std::string why = per_run("mhs_batch_get", batch, index, values, runs);
    if (!why.empty()) return refuse(b, why);
    batch.values(batch.variables().list()[index], values);
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_batch_set(mhs_batch* b, uint32_t index, const double* values, size_t runs) {
  return guarded(b, [&](Batch& batch) -> mhs_status {
    const std::string why = per_run("mhs_batch_set", batch, index, values, runs);
    if (!why.empty()) return refuse(b, why);
    std::string clamped;
    try {
      clamped = batch.set_input(batch.variables().list()[index], values);
    } catch (const std::invalid_argument& err) {
      return refuse(b, std::string("mhs_batch_set: ") + err.what());
    }
    if (clamped.empty()) return MHS_OK;
    b->message = "mhs_batch_set: " + clamped + " (out_of_range: clamp)";
    return MHS_WARNING;
  });
}

MHS_API mhs_status mhs_batch_run_status(const mhs_batch* cb, uint32_t run, mhs_status* status,
                                        double* t, int64_t* steps, const char** message) {
  auto* b = const_cast<mhs_batch*>(cb);
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (status == nullptr) return refuse(b, "mhs_batch_run_status: status is NULL");
    if (run >= batch.size())
      return refuse(b, "mhs_batch_run_status: run " + std::to_string(run) + " is not below " +
                           std::to_string(batch.size()));
    const mh::embed::BatchRun& r = batch.run(run);
    *status = r.failure.empty() ? MHS_OK : MHS_ERROR;
    if (t != nullptr) *t = r.sim->time();
    if (steps != nullptr) *steps = r.sim->step_index();
    if (message != nullptr) *message = r.failure.c_str();
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_batch_snapshot_new(mhs_batch* b, mhs_batch_snapshot** out) {
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (out == nullptr) return refuse(b, "mhs_batch_snapshot_new: out is NULL");
    *out = new mhs_batch_snapshot;
    (*out)->of = &batch;
    return MHS_OK;
  });
}

MHS_API void mhs_batch_snapshot_free(mhs_batch_snapshot* snapshot) {
  delete snapshot;
}

MHS_API mhs_status mhs_batch_save(mhs_batch* b, mhs_batch_snapshot* snapshot) {
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (snapshot == nullptr) return refuse(b, "mhs_batch_save: snapshot is NULL");
    if (snapshot->of != &batch)
      return refuse(b, "mhs_batch_save: the snapshot was made for another batch");
    for (size_t k = 0; k < batch.size(); ++k)
      if (!batch.run(k).started)
        return refuse(
            b, "mhs_batch_save: run " + std::to_string(k) + " has not started (mhs_batch_start)");
    snapshot->saved = false;
    snapshot->bytes_current = false;
    batch.save(snapshot->runs);
    snapshot->saved = true;
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_batch_restore(mhs_batch* b, const mhs_batch_snapshot* snapshot) {
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (snapshot == nullptr) return refuse(b, "mhs_batch_restore: snapshot is NULL");
    if (snapshot->of != &batch)
      return refuse(b, "mhs_batch_restore: the snapshot was made for another batch");
    if (!snapshot->saved) return refuse(b, "mhs_batch_restore: the snapshot holds no state yet");
    const std::string differ = batch.restore(snapshot->runs);
    b->message.clear();  // the runs' past calls' words are of states gone
    if (differ.empty()) return MHS_OK;
    b->message =
        "mhs_batch_restore: saved with other values of the model (the runs go on as "
        "their models now are):\n" +
        differ;
    return MHS_WARNING;
  });
}

// The bytes: "MHBATCH1", the run count, then each run's length and its
// bytes (run_state_bytes.hpp: each with its own version, layout and checksum).
MHS_API mhs_status mhs_batch_snapshot_bytes(mhs_batch* b, mhs_batch_snapshot* snapshot,
                                            const void** bytes, size_t* size) {
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (snapshot == nullptr || bytes == nullptr || size == nullptr)
      return refuse(b, "mhs_batch_snapshot_bytes: the snapshot, bytes or size is NULL");
    if (snapshot->of != &batch)
      return refuse(b, "mhs_batch_snapshot_bytes: the snapshot was made for another batch");
    if (!snapshot->saved)
      return refuse(b, "mhs_batch_snapshot_bytes: the snapshot holds no state yet");
    if (!snapshot->bytes_current) {
      std::vector<unsigned char>& out = snapshot->bytes;
      out.assign(kBatchMagic, kBatchMagic + sizeof kBatchMagic);
      append(out, static_cast<uint64_t>(snapshot->runs.size()));
      std::vector<unsigned char> one;
      for (const mh::RunState& run : snapshot->runs) {
        mh::write_run_state_bytes(run, one);
        append(out, static_cast<uint64_t>(one.size()));
        out.insert(out.end(), one.begin(), one.end());
      }
      snapshot->bytes_current = true;
    }
    *bytes = snapshot->bytes.data();
    *size = snapshot->bytes.size();
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_batch_snapshot_read(mhs_batch* b, mhs_batch_snapshot* snapshot,
                                           const void* bytes, size_t size) {
  return guarded(b, [&](Batch& batch) -> mhs_status {
    if (snapshot == nullptr || (bytes == nullptr && size > 0))
      return refuse(b, "mhs_batch_snapshot_read: the snapshot or bytes is NULL");
    if (snapshot->of != &batch)
      return refuse(b, "mhs_batch_snapshot_read: the snapshot was made for another batch");
    const auto* p = static_cast<const unsigned char*>(bytes);
    size_t left = size;
    uint64_t runs = 0;
    if (size < sizeof kBatchMagic || std::memcmp(p, kBatchMagic, sizeof kBatchMagic) != 0 ||
        !take(p, left, sizeof kBatchMagic, nullptr) || !take(p, left, sizeof runs, &runs))
      return refuse(b, "mhs_batch_snapshot_read: the bytes are not a batch's snapshot");
    if (runs != batch.size())
      return refuse(b, "mhs_batch_snapshot_read: the bytes hold " + std::to_string(runs) +
                           " runs, the batch has " + std::to_string(batch.size()));
    std::vector<mh::RunState> read(batch.size());
    for (size_t k = 0; k < read.size(); ++k) {
      uint64_t length = 0;
      if (!take(p, left, sizeof length, &length) || length > left)
        return refuse(
            b, "mhs_batch_snapshot_read: the bytes are cut short at run " + std::to_string(k));
      try {
        mh::read_run_state_bytes(p, static_cast<size_t>(length), read[k]);
      } catch (const mh::RunStateError& err) {
        return refuse(b, "mhs_batch_snapshot_read: run " + std::to_string(k) + ": " + err.what());
      }
      p += length;
      left -= static_cast<size_t>(length);
    }
    if (left != 0) return refuse(b, "mhs_batch_snapshot_read: the bytes run on after the last run");
    snapshot->runs = std::move(read);
    snapshot->saved = true;
    snapshot->bytes_current = false;
    return MHS_OK;
  });
}

}  // extern "C"
