// Threads that step the runs of a batch. The standard library's threads,
// not a task library: a batch's work is a few coarse items (one run stepped
// to a time) handed out by one atomic counter, so a scheduler would add a
// dependency and nothing else. The threads live as long as the pool, so a
// batch advanced by one control period at a time does not start threads
// each period. Which thread steps a run changes nothing in its result: a
// run's state is its own and each step of it is the same calls in the same
// order.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace mh::embed {

class RunPool {
 public:
  // `threads` >= 1 in all, the calling thread among them (0: one per core).
  explicit RunPool(unsigned threads);
  ~RunPool();
  RunPool(const RunPool&) = delete;
  RunPool& operator=(const RunPool&) = delete;

  unsigned threads() const { return static_cast<unsigned>(workers_.size()) + 1; }

  // work(i) for every i in [0, n), each exactly once, on the pool's threads
  // and the caller's; returns when every call has returned. `work` must not
  // throw. One for_each at a time.
  void for_each(size_t n, const std::function<void(size_t)>& work);

 private:
  void work_loop();
  void take_items();

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;
  const std::function<void(size_t)>* work_ = nullptr;
  size_t n_ = 0;
  std::atomic<size_t> next_{0};
  unsigned long round_ = 0;  // for_each calls so far: a worker's signal to look for work
  unsigned busy_ = 0;        // workers still in this round
  bool stop_ = false;
};

}  // namespace mh::embed
