#include "job_queue.hpp"

#include <filesystem>

namespace mh::cli::sweep {

JobQueue::JobQueue(const SweepContext& ctx, const ResultsTable& table) {
  for (const auto& c : ctx.cases)
    if (!table.has(c.index)) cases_.push_back(Job{false, c.index});
  case_count_ = cases_.size();
  if (cases_.empty()) return;  // nothing left needs a reference
  std::error_code ec;
  for (std::size_t i = 0; i < ctx.references.size(); ++i)
    if (!std::filesystem::exists(ctx.reference_csv(ctx.references[i]), ec))
      pending_.push_back(Job{true, static_cast<int>(i)});
}

std::optional<Job> JobQueue::next() {
  std::deque<Job>* from = !pending_.empty() ? &pending_ : nullptr;
  if (from == nullptr && running_references_ == 0 && !cases_.empty()) from = &cases_;
  if (from == nullptr) return std::nullopt;
  const Job job = from->front();
  from->pop_front();
  ++running_;
  if (job.reference) ++running_references_;
  return job;
}

void JobQueue::done(const Job& job) {
  --running_;
  if (job.reference) --running_references_;
}

}  // namespace mh::cli::sweep
