#include "batch.hpp"

#include <cmath>
#include <exception>
#include <stdexcept>

#include "instance.hpp"
#include "monohydra/core/run_limits.hpp"
#include "monohydra/cpp/number_text.hpp"

namespace mh::embed {

namespace {

// One run's steps; a failure is the run's alone. Only a step's own failure
// (SimulationError) is expected, but nothing may leave a pool's thread.
template <class Steps>
void stepped(BatchRun& run, Steps&& steps) {
  if (!run.failure.empty()) return;
  try {
    if (!run.started) {
      run.sim->start();
      run.started = true;
    }
    steps(*run.sim);
  } catch (const std::exception& err) {
    run.failure = err.what();
  }
}

}  // namespace

BatchRun::BatchRun(const OpenedModel& opened) : changed(opened) {
  sim = std::make_unique<Simulation>(opened.file, opened.registry, opened.choices,
                                     warnings_into(warnings));
}

Batch::Batch(const OpenRequest& request, size_t runs, unsigned threads)
    : opened_(std::make_unique<const OpenedModel>(request)), pool_(threads) {
  if (runs == 0) throw std::invalid_argument("a batch needs at least one run");
  // Each run set up on the pool's threads (its plugins' set-up as well as
  // its steps run beside the other runs').
  runs_.resize(runs);
  std::vector<std::string> failed(runs);
  pool_.for_each(runs, [&](size_t k) {
    try {
      runs_[k] = std::make_unique<BatchRun>(*opened_);
    } catch (const std::exception& err) {
      failed[k] = err.what();
    }
  });
  for (size_t k = 0; k < runs; ++k)
    if (!failed[k].empty()) throw std::runtime_error("run " + std::to_string(k) + ": " + failed[k]);
  // The tangent's pattern and its symbolic analysis are the same for every
  // run of one model: the first run's serve them all.
  for (size_t k = 1; k < runs; ++k) runs_[k]->sim->share_fixed_parts(*runs_.front()->sim);
  check_column_names(opened_->file, *runs_.front()->sim);
  variables_ = std::make_unique<VariableTable>(*runs_.front()->sim, opened_->file.model);
}

size_t Batch::step_each(const std::function<void(Simulation&)>& steps) {
  pool_.for_each(runs_.size(), [&](size_t k) { stepped(*runs_[k], steps); });
  if (cancel_hit_.load(std::memory_order_acquire))
    cancel_asked_.store(false, std::memory_order_release);  // taken by this call
  size_t stopped = 0;
  for (const auto& r : runs_) stopped += r->failure.empty() ? 0 : 1;
  return stopped;
}

void Batch::set_parameter(size_t run, const std::string& path, const std::string& value) {
  if (run >= runs_.size())
    throw std::invalid_argument("run " + std::to_string(run) + ": the batch has " +
                                std::to_string(runs_.size()) + " runs (0 .. " +
                                std::to_string(runs_.size() - 1) + ")");
  BatchRun& r = *runs_[run];
  embed::set_parameter(*r.sim, *opened_, r.changed, path, value);
}

size_t Batch::step(long steps) {
  return step_each([&](Simulation& s) {
    for (long i = 0; i < steps && !stop_asked(); ++i) s.step();
  });
}

size_t Batch::advance(double t) {
  return step_each([&](Simulation& s) {
    const double dt = s.settings().dt;
    while (s.time() < t - 1e-6 * dt && !stop_asked()) s.step();
  });
}

void Batch::values(const Variable& v, double* out) const {
  for (size_t k = 0; k < runs_.size(); ++k) out[k] = value(*runs_[k]->sim, v);
}

std::string Batch::set_input(const Variable& v, const double* values) {
  if (v.kind != MHS_INPUT)
    throw std::invalid_argument("'" + v.name + "' is not an input (the model's inputs: are)");
  for (size_t k = 0; k < runs_.size(); ++k) {
    const std::string refused = runs_[k]->sim->input_refusal(v.index, values[k]);
    if (!refused.empty()) throw std::invalid_argument("run " + std::to_string(k) + ": " + refused);
  }
  std::string clamped;
  for (size_t k = 0; k < runs_.size(); ++k) {
    const double took = runs_[k]->sim->set_input(v.index, values[k]);
    if (took != values[k])
      clamped += (clamped.empty() ? "" : "\n") + std::string("run ") + std::to_string(k) +
                 ": input '" + v.name + "' clamped from " + monohydra::short_number(values[k]) +
                 " to " + monohydra::short_number(took);
  }
  return clamped;
}

void Batch::save(std::vector<RunState>& into) const {
  into.resize(runs_.size());
  for (size_t k = 0; k < runs_.size(); ++k) runs_[k]->sim->save_state(into[k]);
}

std::string Batch::restore(const std::vector<RunState>& from) {
  if (from.size() != runs_.size())
    throw std::invalid_argument("the snapshot holds " + std::to_string(from.size()) +
                                " runs, the batch has " + std::to_string(runs_.size()));
  std::string differ;
  for (size_t k = 0; k < runs_.size(); ++k) {
    const std::string d = runs_[k]->sim->model_differences(from[k]);
    runs_[k]->sim->restore_state(from[k]);
    runs_[k]->started = true;
    runs_[k]->failure.clear();
    if (!d.empty())
      differ += (differ.empty() ? "" : "\n") + ("run " + std::to_string(k) + ": " + d);
  }
  return differ;
}

std::string Batch::failures() const {
  std::string out;
  for (size_t k = 0; k < runs_.size(); ++k)
    if (!runs_[k]->failure.empty())
      out += (out.empty() ? "" : "\n") + std::string("run ") + std::to_string(k) + ": " +
             runs_[k]->failure;
  return out;
}

std::string Batch::take_warnings() {
  std::string out;
  for (size_t k = 0; k < runs_.size(); ++k) {
    std::string& w = runs_[k]->warnings;
    if (w.empty()) continue;
    out += (out.empty() ? "" : "\n") + std::string("run ") + std::to_string(k) + ": " + w;
    w.clear();
  }
  return out;
}

}  // namespace mh::embed
