#include "isolated_check.hpp"

#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>

#include "monohydra/core/input_error.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh::testhost {
namespace {

std::string signal_name(int sig) {
  if (const char* abbrev = sigabbrev_np(sig); abbrev != nullptr) return std::string("SIG") + abbrev;
  return "signal " + std::to_string(sig);
}

}  // namespace

std::string isolated(const std::function<std::string()>& body) {
  int fds[2];
  if (::pipe(fds) != 0) return "cannot create a pipe: " + std::string(std::strerror(errno));
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return "cannot fork: " + std::string(std::strerror(errno));
  if (pid == 0) {
    ::close(fds[0]);
    const rlimit no_core{0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    ::alarm(kCheckSeconds);
    std::string verdict;
    try {
      verdict = body();
    } catch (const SimulationError& err) {  // a run that failed, with its time and step
      verdict = std::string("the run failed: ") + err.what();
    } catch (const PluginError& err) {
      verdict = std::string("a plugin failed: ") + err.what();
    } catch (const InputError& err) {
      verdict = std::string("the model was refused: ") + err.what();
    } catch (const std::exception& err) {
      verdict = std::string("an exception reached the host: ") + err.what();
    } catch (...) {
      verdict = "an exception of unknown type reached the host";
    }
    verdict = "R" + verdict;  // "R" alone: passed
    size_t done = 0;
    while (done < verdict.size()) {
      const ssize_t n = ::write(fds[1], verdict.data() + done, verdict.size() - done);
      if (n <= 0 && errno != EINTR) break;
      if (n > 0) done += static_cast<size_t>(n);
    }
    std::cerr.flush();
    std::_Exit(0);
  }
  ::close(fds[1]);
  std::string got;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got.append(buf, static_cast<size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (sig == SIGALRM) return "did not finish within " + std::to_string(kCheckSeconds) + " s";
    if (sig == SIGABRT)
      return "aborted (SIGABRT): typically an exception thrown across the C boundary "
             "(std::terminate) or a failed assertion";
    return "crashed (" + signal_name(sig) + ")";
  }
  if (got.empty() || got[0] != 'R') return "ended without a verdict";
  return got.substr(1);
}

}  // namespace mh::testhost
