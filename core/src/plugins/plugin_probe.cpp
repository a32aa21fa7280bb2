#include "plugins/plugin_probe.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstddef>
#include <cstring>

#include "monohydra/entry.h"
#include "monohydra/formulation.h"
#include "monohydra/integrator.h"
#include "monohydra/subsystem.h"

namespace mh {
namespace {

// Every factory starts with struct_size, count, descriptor, create; a count
// beyond the host's own bound is refused by the host, so it is not walked.
// Each kind through its own type: a call through a pointer of another
// function type is undefined (clang's -fsanitize=function reports it).
template <typename Factory>
void walk_factory(const void* raw) {
  if (raw == nullptr) return;
  const auto* f = static_cast<const Factory*>(raw);
  if (f->struct_size < offsetof(Factory, descriptor) + sizeof(void*) || f->count == nullptr ||
      f->descriptor == nullptr)
    return;
  const uint32_t count = f->count(f);
  if (count > kMaxComponents) return;
  // Every text the host will measure (plugin_registry.cpp), measured here
  // first, as far as the host reads: one that runs into unmapped memory
  // crashes this child, not the host.
  volatile size_t sink = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const mh_component_descriptor* d = f->descriptor(f, i);
    if (d == nullptr || d->id == nullptr) continue;
    for (const char* text : {d->id, d->name, d->vendor, d->version, d->description})
      if (text != nullptr) sink = sink + strnlen(text, kMaxMeasuredText);
  }
}

// The phases of a probe, each announced to the parent by one byte on the
// pipe before it starts, so that a crash or a hang is told with its phase.
constexpr char kPhases[] = "oifdu";
const char* phase_text(char phase) {
  switch (phase) {
    case 'o':
      return "while loading (its constructors)";
    case 'i':
      return "in its init";
    case 'f':
      return "listing its components (get_factory, count, descriptor)";
    case 'd':
      return "in its deinit";
    case 'u':
      return "while unloading (its destructors)";
    default:
      return "during probing";
  }
}

void announce(int fd, char phase) {
  while (::write(fd, &phase, 1) < 0 && errno == EINTR) {
  }
}

// The child's whole life: never returns.
[[noreturn]] void probe_in_child(const std::string& path, int fd) {
  const rlimit no_core{0, 0};
  setrlimit(RLIMIT_CORE, &no_core);  // a crash here is expected, not a bug report
  announce(fd, kPhases[0]);
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) _exit(0);
  const auto* entry = static_cast<const mh_plugin_entry*>(dlsym(handle, MH_ENTRY_SYMBOL));
  if (entry == nullptr || entry->abi_version.major != MH_ABI_VERSION_MAJOR ||
      entry->init == nullptr || entry->get_factory == nullptr)
    _exit(0);
  announce(fd, kPhases[1]);
  if (entry->init(path.c_str()) == 0) _exit(0);
  announce(fd, kPhases[2]);
  walk_factory<mh_formulation_factory>(entry->get_factory(MH_FORMULATION_FACTORY_ID));
  walk_factory<mh_subsystem_factory>(entry->get_factory(MH_SUBSYSTEM_FACTORY_ID));
  walk_factory<mh_integrator_factory>(entry->get_factory(MH_INTEGRATOR_FACTORY_ID));
  announce(fd, kPhases[3]);
  if (entry->deinit != nullptr) entry->deinit();
  announce(fd, kPhases[4]);
  // Unloaded here, so that its destructors run in the child too: a library
  // whose destructor crashes is refused before the host ever loads it.
  if (dlclose(handle) != 0) _exit(0);
  _exit(0);
}

}  // namespace

std::string signal_abbreviation(int sig) {
  switch (sig) {
    case SIGSEGV:
      return "SIGSEGV";
    case SIGBUS:
      return "SIGBUS";
    case SIGABRT:
      return "SIGABRT";
    case SIGFPE:
      return "SIGFPE";
    case SIGILL:
      return "SIGILL";
    case SIGKILL:
      return "SIGKILL";
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    case SIGTRAP:
      return "SIGTRAP";
    default:
      return "signal " + std::to_string(sig);
  }
}

ProbeVerdict probe_library(const std::string& path, std::chrono::milliseconds limit) {
  // The child holds the write end of a pipe: its end wakes the parent at once.
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return {};  // cannot probe: trust the library as before
  const pid_t pid = fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return {};
  }
  if (pid == 0) {
    ::close(fds[0]);
    probe_in_child(path, fds[1]);
  }
  ::close(fds[1]);

  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + limit;
  int status = 0;
  char phase = 0;  // the last the child announced
  // Reads what the child announced so far, without waiting; false at its end.
  const auto drain = [&]() {
    for (;;) {
      pollfd p{fds[0], POLLIN, 0};
      if (::poll(&p, 1, 0) <= 0) return true;
      char byte = 0;
      const ssize_t got = ::read(fds[0], &byte, 1);
      if (got == 0) return false;
      if (got < 0) return errno == EINTR;
      phase = byte;
    }
  };
  for (;;) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (r < 0 && errno != EINTR) {
      ::close(fds[0]);
      return {};
    }
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) {
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      drain();
      ::close(fds[0]);
      const auto ms = limit.count();
      const std::string amount =
          ms % 1000 == 0 ? std::to_string(ms / 1000) + " s" : std::to_string(ms) + " ms";
      return {false, "timed out after " + amount + " during probing, " + phase_text(phase)};
    }
    // Wakes when the child ends (the pipe closes), or to look again: a library
    // may have handed the pipe on to a process of its own.
    pollfd p{fds[0], POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(std::min<long long>(left, 100))) > 0 && !drain()) {
      // closed: the child is gone or going
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      break;
    }
  }
  drain();
  ::close(fds[0]);
  if (WIFSIGNALED(status))
    return {false, "crashed with " + signal_abbreviation(WTERMSIG(status)) + " during probing, " +
                       phase_text(phase)};
  if (WIFEXITED(status) && WEXITSTATUS(status) != 0)
    return {false, "exited with status " + std::to_string(WEXITSTATUS(status)) + " during probing"};
  return {};
}

}  // namespace mh
