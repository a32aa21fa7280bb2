// Many runs of one model stepped together (mhs_batch_*): the opened model
// (its parsed file, its plugins, the run choices) and the value table exist
// once; each run has its own simulation, its own changes to the model (a
// parameter by path, its inputs) and its own fate: a run whose step fails
// stops there with its time and reason while the others go on. Runs are
// stepped in parallel on a RunPool, each by one thread at a time, so each
// run's result is the one it has stepped alone, to the bit.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "monohydra/core/run_state.hpp"
#include "monohydra/core/simulation.hpp"
#include "opened_model.hpp"
#include "run_pool.hpp"
#include "variable_table.hpp"

namespace mh::embed {

// One run of a batch: what it changed of the model, its simulation, and
// how its last call went.
struct BatchRun {
  explicit BatchRun(const OpenedModel& opened);
  ChangedModel changed;
  std::string warnings;  // its plugins' warnings in the current call
  std::unique_ptr<Simulation> sim;
  bool started = false;
  std::string failure;  // why its last step failed ("": it did not)
};

class Batch {
 public:
  // Opens the model once and sets `runs` runs of it up; `threads` in all
  // (0: one per core). Throws as an Instance's opening does, and
  // std::invalid_argument for no runs.
  Batch(const OpenRequest& request, size_t runs, unsigned threads);

  size_t size() const { return runs_.size(); }
  unsigned threads() const { return pool_.threads(); }
  const VariableTable& variables() const { return *variables_; }
  const BatchRun& run(size_t k) const { return *runs_.at(k); }

  // A value of run k's model changed in place (opened_model.hpp).
  void set_parameter(size_t run, const std::string& path, const std::string& value);

  // Every run that has not failed (and has not started: it starts first,
  // so step(0) starts them all) takes `steps` steps, or steps until its
  // time reaches `t` (within a millionth of a step). A run whose step fails
  // keeps its last accepted state and its reason, and takes no step until
  // a restore; the others go on. Returns how many runs are stopped.
  size_t step(long steps);
  size_t advance(double t);
  // Ends the step or advance in flight: each run stops at its next look
  // between two steps (with none in flight, the next call at its start).
  // Any thread may call it, and a signal handler (it only sets a flag).
  void cancel() { cancel_asked_.store(true, std::memory_order_release); }
  // Whether cancel() ended the last step or advance (taken: asked once, it
  // ends one call).
  bool take_cancelled() { return cancel_hit_.exchange(false, std::memory_order_acq_rel); }

  // Variable `v` (the table's numbering) of every run, in run order.
  void values(const Variable& v, double* out) const;
  // Input `v` of each run from values[run] (refused for all when any is
  // refused; see Simulation::input_refusal). Returns the runs whose value
  // was clamped, as "run k: ..." lines.
  std::string set_input(const Variable& v, const double* values);

  // Every run's whole state, and every run put back into one (its failure
  // forgotten, as mhs_restore does). Returns the runs whose model has other
  // values than at the save, each "run k: ..." (Simulation::model_differences).
  void save(std::vector<RunState>& into) const;
  std::string restore(const std::vector<RunState>& from);

  // The runs that failed, each "run k: reason", one per line ("": none).
  std::string failures() const;
  // The plugins' warnings of the current call, each "run k: ...".
  std::string take_warnings();

 private:
  // `steps` on every run not yet stopped, in the pool (a run started first,
  // its failure its own); cancel() taken; how many runs have stopped.
  size_t step_each(const std::function<void(Simulation&)>& steps);
  // Whether a run's loop stops before its next step (cancel() was asked).
  bool stop_asked() {
    if (!cancel_asked_.load(std::memory_order_acquire)) return false;
    cancel_hit_.store(true, std::memory_order_release);
    return true;
  }

  std::unique_ptr<const OpenedModel> opened_;
  std::vector<std::unique_ptr<BatchRun>> runs_;  // each where its log sink points
  std::unique_ptr<VariableTable> variables_;
  RunPool pool_;
  std::atomic<bool> cancel_asked_{false};
  std::atomic<bool> cancel_hit_{false};
};

}  // namespace mh::embed
