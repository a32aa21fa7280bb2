#include "run_pool.hpp"

#include <algorithm>

namespace mh::embed {

RunPool::RunPool(unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  workers_.reserve(threads - 1);
  for (unsigned k = 1; k < threads; ++k) workers_.emplace_back([this] { work_loop(); });
}

RunPool::~RunPool() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void RunPool::take_items() {
  for (size_t i = next_.fetch_add(1); i < n_; i = next_.fetch_add(1)) (*work_)(i);
}

void RunPool::work_loop() {
  unsigned long seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || round_ != seen; });
      if (stop_) return;
      seen = round_;
    }
    take_items();
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      --busy_;
    }
    done_.notify_one();
  }
}

void RunPool::for_each(size_t n, const std::function<void(size_t)>& work) {
  if (workers_.empty() || n <= 1) {
    for (size_t i = 0; i < n; ++i) work(i);
    return;
  }
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    work_ = &work;
    n_ = n;
    next_.store(0);
    busy_ = static_cast<unsigned>(workers_.size());
    ++round_;
  }
  wake_.notify_all();
  take_items();
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [&] { return busy_ == 0; });
  work_ = nullptr;
}

}  // namespace mh::embed
