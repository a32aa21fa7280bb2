#include "local_pool.hpp"

#include <poll.h>
#include <sys/wait.h>

#include <cerrno>
#include <vector>

namespace mh::cli::sweep {

int run_local_pool(SweepContext& ctx, JobQueue& queue, int workers, const JobResult& on_result,
                   const volatile std::sig_atomic_t* stop) {
  std::vector<RunningJob> running;
  while (!queue.finished()) {
    if (stop != nullptr && *stop != 0) {
      for (auto& r : running) {  // an unfinished case has no row: a resumed study runs it
        ::kill(r.pid, SIGKILL);
        ::close(r.fd);
        while (::waitpid(r.pid, nullptr, 0) < 0 && errno == EINTR) {
        }
      }
      return static_cast<int>(*stop);
    }
    while (static_cast<int>(running.size()) < workers) {
      const auto job = queue.next();
      if (!job) break;
      running.push_back(start_job(ctx, *job));
    }
    std::vector<pollfd> fds;
    fds.reserve(running.size());
    for (const auto& r : running) fds.push_back(pollfd{r.fd, POLLIN, 0});
    if (::poll(fds.data(), fds.size(), 200) <= 0) continue;  // a timeout or EINTR
    for (std::size_t i = fds.size(); i-- > 0;) {
      if ((fds[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
      if (read_job(running[i])) continue;
      const std::string result = finish_job(ctx, running[i]);
      const Job job = running[i].job;
      running.erase(running.begin() + static_cast<long>(i));
      queue.done(job);
      on_result(job, result);
    }
  }
  return 0;
}

}  // namespace mh::cli::sweep
