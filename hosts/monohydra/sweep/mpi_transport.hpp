// A study across the ranks mpirun started: rank 0 hands out the jobs one at
// a time to whichever rank asks (dynamic load balancing) and writes the
// table; every other rank runs its job in a forked child (case_run.hpp) and
// sends back the row. The MPI library (mpi_library.h) is loaded with
// Boost.DLL only here: the monohydra executable does not link libmpi.
#pragma once

#include <csignal>
#include <memory>
#include <string>

#include "local_pool.hpp"

namespace mh::cli::sweep {

// True when mpirun (OpenMPI, or an MPICH-style launcher) started this process.
bool launched_by_mpirun();

class MpiTransport {
 public:
  // Loads the library and starts MPI; throws std::runtime_error saying why
  // not (this build has no MPI support, or the library is missing).
  MpiTransport();
  ~MpiTransport();
  MpiTransport(const MpiTransport&) = delete;
  MpiTransport& operator=(const MpiTransport&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  // Rank 0: hands out the queue's jobs until none is left; returns 0, or the
  // stop signal.
  int coordinate(JobQueue& queue, const JobResult& on_result,
                 const volatile std::sig_atomic_t* stop);
  // Other ranks: runs the jobs rank 0 sends until it says done.
  int work(SweepContext& ctx, const volatile std::sig_atomic_t* stop);
  // Ends every rank at once (a stopped study).
  [[noreturn]] void abort(int code);

 private:
  struct Library;
  std::unique_ptr<Library> lib_;
  int rank_ = 0, size_ = 1;
};

}  // namespace mh::cli::sweep
