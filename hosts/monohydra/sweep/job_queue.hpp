// The order in which a study's jobs are handed out, shared by the local pool
// and the MPI coordinator: the reference runs first (the cases' error
// metrics read them), then every case without a row in results.csv, each to
// whichever worker asks next (dynamic load balancing: runs differ in cost).
#pragma once

#include <cstddef>
#include <deque>
#include <optional>

#include "case_run.hpp"

namespace mh::cli::sweep {

class JobQueue {
 public:
  // `done(i)`: case i already has a row. A reference whose CSV exists has run.
  JobQueue(const SweepContext& ctx, const ResultsTable& table);

  // The next job; nullopt when none can start now (the cases wait for the
  // references) or none is left (finished() tells which).
  std::optional<Job> next();
  void done(const Job& job);
  // Nothing left to hand out (some may still run).
  bool exhausted() const { return pending_.empty() && cases_.empty(); }
  bool finished() const { return pending_.empty() && cases_.empty() && running_ == 0; }
  std::size_t cases_to_run() const { return case_count_; }

 private:
  std::deque<Job> pending_;  // references
  std::deque<Job> cases_;
  std::size_t running_references_ = 0;
  std::size_t running_ = 0;
  std::size_t case_count_ = 0;
};

}  // namespace mh::cli::sweep
