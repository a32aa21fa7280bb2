// The local worker pool: up to N jobs at once, each in its own forked child
// (case_run.hpp), the next job handed out as soon as one ends.
#pragma once

#include <csignal>
#include <functional>
#include <string>

#include "job_queue.hpp"

namespace mh::cli::sweep {

// What a finished job gave: a case's row, or for a reference "" or the
// reason it did not run.
using JobResult = std::function<void(const Job&, const std::string&)>;

// Runs the queue's jobs on `workers` children at a time until none is left
// (returns 0) or `stop` is set (its children are killed, their cases left
// without a row; returns the signal).
int run_local_pool(SweepContext& ctx, JobQueue& queue, int workers, const JobResult& on_result,
                   const volatile std::sig_atomic_t* stop);

}  // namespace mh::cli::sweep
