#include "isolated_run.hpp"

#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "call_watchdog.hpp"
#include "crash_report.hpp"
#include "run_record_stream.hpp"
#include "stop_signals.hpp"

namespace mh::cli {
namespace {

// Writes all of `bytes` to `fd`; false when the parent is gone.
bool write_all(int fd, const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

[[noreturn]] void run_in_child(int fd, const ModelFile& file, const PluginRegistry& registry,
                               const std::string& formulation, const std::string& integrator,
                               RecordOptions options) {
  const rlimit no_core{0, 0};
  setrlimit(RLIMIT_CORE, &no_core);  // the table reports the crash
  std::string message;
  options.on_row = [fd, &message](const RunRecord& rec) {
    message.clear();
    if (rec.rows() == 1) append_record_description(message, rec, false);
    append_record_row(message, rec, rec.rows() - 1);
    write_all(fd, message);
  };
  const RunRecord rec = record_run(file, registry, formulation, integrator, options);
  message.clear();
  append_record_description(message, rec, true);
  const bool sent = write_all(fd, message);
  std::cerr.flush();
  _exit(sent ? 0 : 1);
}

std::string crash_text(int sig, const RunRecord& rec) {
  const std::string what = std::string("crashed (") + signal_name(sig) + ")";
  if (rec.rows() == 0) return what + " before its first row";
  char t[32];
  std::snprintf(t, sizeof t, "%g", rec.columns.front().back());
  return what + " after t = " + t + " s";
}

}  // namespace

RunRecord record_run_isolated(const ModelFile& file, const PluginRegistry& registry,
                              const std::string& formulation, const std::string& integrator,
                              RecordOptions options) {
  int fds[2];
  if (::pipe(fds) != 0) return record_run(file, registry, formulation, integrator, options);
  std::cout.flush();  // nothing buffered is written twice
  std::cerr.flush();
  std::fflush(nullptr);
  CrashReport* crash = shared_crash_report();
  const pid_t pid = fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    release_crash_report(crash);
    return record_run(file, registry, formulation, integrator, options);
  }
  if (pid == 0) {
    ::close(fds[0]);
    install_crash_handler(crash);
    start_call_watchdog();  // threads do not survive fork
    run_in_child(fds[1], file, registry, formulation, integrator, std::move(options));
  }
  ::close(fds[1]);

  std::string bytes;
  char buf[65536];
  bool forwarded = false;
  for (;;) {
    if (!forwarded && options.stop != nullptr && *options.stop != 0) {
      ::kill(pid, static_cast<int>(*options.stop));  // the child stops after its row
      forwarded = true;
    }
    pollfd p{fds[0], POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;  // a timeout or EINTR: look at the stop flag
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.append(buf, static_cast<size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }

  const std::string site = crash_site(crash);
  release_crash_report(crash);
  DecodedRecord decoded = decode_record_stream(bytes);
  RunRecord rec = std::move(decoded.record);
  if (decoded.complete && WIFEXITED(status) && WEXITSTATUS(status) == 0) return rec;
  if (rec.formulation.empty()) {  // no row came
    rec.formulation = formulation.empty() ? file.formulation.name : formulation;
    rec.integrator = integrator.empty() ? file.integrator.name : integrator;
    rec.label = rec.formulation;
  }
  rec.failed = true;
  if (WIFSIGNALED(status)) {
    rec.crashed_by = WTERMSIG(status);
    rec.failure = crash_text(rec.crashed_by, rec);
    rec.crash_site = site;
  } else {
    rec.failure = "its process exited with status " +
                  std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                  " before the run ended";
  }
  if (rec.rows() > 0) rec.failure_time = rec.columns.front().back();
  std::error_code ec;
  if (!options.csv_path.empty() && std::filesystem::exists(options.csv_path, ec))
    rec.csv_path = options.csv_path;
  return rec;
}

}  // namespace mh::cli
