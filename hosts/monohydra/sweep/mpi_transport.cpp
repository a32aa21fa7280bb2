#include "mpi_transport.hpp"

#include <poll.h>
#include <sys/wait.h>

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <cerrno>
#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <vector>

#include "build_tree.hpp"
#include "mpi_library.h"

namespace mh::cli::sweep {
namespace {

enum Tag : int { kReady = 1, kJob = 2, kResult = 3, kDone = 4 };

std::string encode(const Job& job) {
  return std::string(job.reference ? "r " : "c ") + std::to_string(job.index);
}

Job decode(const std::string& text) {
  Job job;
  job.reference = text.rfind("r ", 0) == 0;
  job.index = std::atoi(text.c_str() + 2);
  return job;
}

}  // namespace

struct MpiTransport::Library {
  boost::dll::shared_library so;
  std::function<int(int*, int*)> start;
  std::function<int(int, int, const char*, int)> send;
  std::function<int(int, int*, int*, char**, int*)> receive;
  std::function<void(char*)> release;
  std::function<int()> stop;
  std::function<void(int)> abort;

  void put(int dest, int tag, const std::string& text) const {
    if (send(dest, tag, text.data(), static_cast<int>(text.size())) != 0)
      throw std::runtime_error("MPI_Send to rank " + std::to_string(dest) + " failed");
  }
  // A message within `timeout_ms`: true and its source, tag and text.
  bool get(int timeout_ms, int& source, int& tag, std::string& text) const {
    char* data = nullptr;
    int bytes = 0;
    const int got = receive(timeout_ms, &source, &tag, &data, &bytes);
    if (got < 0) throw std::runtime_error("MPI receive failed");
    if (got == 0) return false;
    text.assign(data, static_cast<std::size_t>(bytes));
    release(data);
    return true;
  }
};

bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

MpiTransport::MpiTransport() : lib_(std::make_unique<Library>()) {
#ifndef MONOHYDRA_MPI_LIBRARY
  throw std::runtime_error(
      "started by mpirun, but this monohydra was built without MPI support (CMake found no "
      "MPI C library: install libopenmpi-dev and rebuild), so it cannot share a study between "
      "ranks; run `monohydra sweep` without mpirun to use this machine's cores");
#else
  std::error_code ec;
  const auto exe_dir = boost::dll::program_location(ec).parent_path();
  std::vector<boost::dll::fs::path> candidates = {
      exe_dir / ".." / "lib" / "monohydra" / MONOHYDRA_MPI_LIBRARY,
      boost::dll::fs::path(build_tree::mpi_transport)};
  std::string tried;
  for (const auto& path : candidates) {
    tried += (tried.empty() ? "" : ", ") + path.string();
    if (!boost::dll::fs::exists(path, ec)) continue;
    lib_->so.load(path, ec, boost::dll::load_mode::rtld_global);
    if (!ec) break;
  }
  if (!lib_->so.is_loaded())
    throw std::runtime_error("started by mpirun, but the MPI transport library was not found (" +
                             tried + ")");
  lib_->start = lib_->so.get<int(int*, int*)>("mh_mpi_start");
  lib_->send = lib_->so.get<int(int, int, const char*, int)>("mh_mpi_send");
  lib_->receive = lib_->so.get<int(int, int*, int*, char**, int*)>("mh_mpi_receive");
  lib_->release = lib_->so.get<void(char*)>("mh_mpi_release");
  lib_->stop = lib_->so.get<int()>("mh_mpi_stop");
  lib_->abort = lib_->so.get<void(int)>("mh_mpi_abort");
  if (lib_->start(&rank_, &size_) != 0) throw std::runtime_error("MPI_Init failed");
#endif
}

MpiTransport::~MpiTransport() {
  if (lib_ && lib_->stop) lib_->stop();
}

void MpiTransport::abort(int code) {
  lib_->abort(code);
  std::_Exit(code);
}

int MpiTransport::coordinate(JobQueue& queue, const JobResult& on_result,
                             const volatile std::sig_atomic_t* stop) {
  std::vector<int> idle;  // ranks waiting for the references to end
  int working = size_ - 1;
  const auto hand_out = [&](int rank) {
    if (const auto job = queue.next()) {
      lib_->put(rank, kJob, encode(*job));
    } else if (queue.exhausted()) {
      lib_->put(rank, kDone, "");
      --working;
    } else {
      idle.push_back(rank);
    }
  };
  while (working > 0) {
    if (stop != nullptr && *stop != 0) return static_cast<int>(*stop);
    int source = 0, tag = 0;
    std::string text;
    if (!lib_->get(200, source, tag, text)) continue;
    if (tag == kResult) {
      const std::size_t nl = text.find('\n');
      const Job job = decode(text.substr(0, nl));
      queue.done(job);
      on_result(job, nl == std::string::npos ? "" : text.substr(nl + 1));
      std::vector<int> waiting;
      waiting.swap(idle);
      for (int r : waiting) hand_out(r);
    }
    if (tag == kResult || tag == kReady) hand_out(source);
  }
  return 0;
}

int MpiTransport::work(SweepContext& ctx, const volatile std::sig_atomic_t* stop) {
  lib_->put(0, kReady, "");
  for (;;) {
    if (stop != nullptr && *stop != 0) return static_cast<int>(*stop);
    int source = 0, tag = 0;
    std::string text;
    if (!lib_->get(200, source, tag, text)) continue;
    if (tag == kDone) return 0;
    if (tag != kJob) continue;
    const Job job = decode(text);
    RunningJob running = start_job(ctx, job);
    for (;;) {
      if (stop != nullptr && *stop != 0) {
        ::kill(running.pid, SIGKILL);
        ::waitpid(running.pid, nullptr, 0);
        return static_cast<int>(*stop);
      }
      pollfd p{running.fd, POLLIN, 0};
      if (::poll(&p, 1, 200) <= 0) continue;
      if (!read_job(running)) break;
    }
    const std::string result = finish_job(ctx, running);
    lib_->put(0, kResult, encode(job) + "\n" + result);
  }
}

}  // namespace mh::cli::sweep
