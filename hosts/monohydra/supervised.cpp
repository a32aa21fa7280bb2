#include "supervised.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "call_watchdog.hpp"
#include "cli_support.hpp"
#include "crash_report.hpp"
#include "stop_signals.hpp"

namespace mh::cli {

bool wait_passing_stop(pid_t pid, const volatile std::sig_atomic_t* stop, int& status) {
  bool forwarded = false;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) return true;
    if (done < 0 && errno != EINTR) return false;
    if (!forwarded && *stop != 0) {
      ::kill(pid, static_cast<int>(*stop));
      forwarded = true;
    }
    ::usleep(20000);
  }
}

int supervised(const std::function<int()>& body) {
  std::cout.flush();  // nothing buffered is written twice
  std::cerr.flush();
  std::fflush(nullptr);
  CrashReport* crash = shared_crash_report();
  const pid_t pid = ::fork();
  if (pid < 0) {
    release_crash_report(crash);
    return body();
  }
  if (pid == 0) {
    install_crash_handler(crash);
    start_call_watchdog();  // threads do not survive fork; a command may set its own limits
    int code = 70;
    try {
      code = body();
    } catch (const std::exception& err) {  // a bug: said as main() says it
      std::cerr << "monohydra: internal error: " << err.what() << '\n';
    }
    code = with_output_written(code);
    std::cerr.flush();
    std::_Exit(code);  // the parent owns everything else: no destructors, no atexit
  }
  // Installed after the fork: the child keeps the default actions unless
  // its command installs handlers of its own.
  const volatile std::sig_atomic_t* stop = install_stop_handlers();
  int status = 0;
  if (!wait_passing_stop(pid, stop, status)) {
    release_crash_report(crash);
    return 70;
  }
  const std::string site = crash_site(crash);
  release_crash_report(crash);
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  const int sig = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  if (sig == SIGINT || sig == SIGTERM) {
    std::cerr << "monohydra: interrupted by " << signal_name(sig) << '\n';
    return exit_status_for_signal(sig);
  }
  std::cerr << "monohydra: crashed (" << signal_name(sig) << ")"
            << (site.empty() ? " outside the plugin calls the host marks (in the host, or in a "
                               "thread a plugin started)"
                             : site)
            << '\n';
  return 1;
}

}  // namespace mh::cli
