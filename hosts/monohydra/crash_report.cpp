#include "crash_report.hpp"

#include <dlfcn.h>
#include <signal.h>
#include <sys/mman.h>
#include <ucontext.h>
#include <unistd.h>

#include <cstring>
#include <new>

#include "monohydra/core/plugin_call.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "stop_signals.hpp"

namespace mh::cli {
namespace {

CrashReport* g_report = nullptr;
char g_alternate_stack[1 << 16];

// Bounded copy, async-signal-safe (no library call).
void copy_text(char* to, size_t capacity, const char* from) {
  size_t i = 0;
  if (from != nullptr)
    for (; i + 1 < capacity && from[i] != '\0'; ++i) to[i] = from[i];
  to[i] = '\0';
}

void write_text(const char* text) {
  size_t n = 0;
  while (text[n] != '\0') ++n;
  while (n > 0) {
    const ssize_t w = ::write(2, text, n);
    if (w <= 0) return;
    text += w;
    n -= static_cast<size_t>(w);
  }
}

// The crashing instruction's address, where the platform says it.
const void* crash_address(const void* context) {
  const auto* uc = static_cast<const ucontext_t*>(context);
#if defined(__x86_64__)
  return reinterpret_cast<const void*>(uc->uc_mcontext.gregs[REG_RIP]);
#elif defined(__aarch64__)
  return reinterpret_cast<const void*>(uc->uc_mcontext.pc);
#else
  (void)uc;
  return nullptr;
#endif
}

// The file name (no folder) of the library holding `address`, unless it is
// the C or C++ runtime's, the loader's or the host's own (the program, its
// libmonohydra_*): "" then. dladdr is not on POSIX's
// list of async-signal-safe calls; it only reads the loader's list of
// objects, and runs only for a crash outside every marked call.
void code_library(const void* address, char* to, size_t capacity) {
  to[0] = '\0';
  Dl_info info{};
  if (address == nullptr || dladdr(address, &info) == 0 || info.dli_fname == nullptr) return;
  const char* name = info.dli_fname;
  for (const char* c = info.dli_fname; *c != '\0'; ++c)
    if (*c == '/') name = c + 1;
  if (name[0] == '\0' || std::strncmp(name, "libc.so", 7) == 0 ||
      std::strncmp(name, "libstdc++", 9) == 0 || std::strncmp(name, "libgcc", 6) == 0 ||
      std::strncmp(name, "ld-linux", 8) == 0 || std::strcmp(name, "monohydra") == 0 ||
      std::strncmp(name, "libmonohydra", 12) == 0)
    return;
  copy_text(to, capacity, name);
}

extern "C" void on_crash(int signal, siginfo_t* /*info*/, void* context) {
  if (g_report == nullptr) {
    // This process reports its own crash (setting a run up, before any
    // fork): said on stderr, when a plugin call was in flight.
    const PluginCallSite* site = plugin_call_in_flight().site.load(std::memory_order_relaxed);
    if (site != nullptr && site->who != nullptr && site->call != nullptr) {
      write_text("monohydra: crashed (");
      // The five signals handled are in its table: no snprintf in a handler.
      write_text(signal_name(signal));
      write_text(") in ");
      write_text(site->who);
      write_text(", in its ");
      write_text(site->call);
      write_text("\n");
    }
  } else {
    const PluginCallInFlight& f = plugin_call_in_flight();
    const PluginCallSite* site = f.site.load(std::memory_order_relaxed);
    copy_text(g_report->who, sizeof g_report->who, site != nullptr ? site->who : nullptr);
    copy_text(g_report->call, sizeof g_report->call, site != nullptr ? site->call : nullptr);
    g_report->t = f.t.load(std::memory_order_relaxed);
    g_report->step = f.step.load(std::memory_order_relaxed);
    if (site == nullptr)
      code_library(crash_address(context), g_report->code, sizeof g_report->code);
    g_report->signal = signal;
  }
  // SA_RESETHAND restored the default action; SA_NODEFER lets it act now.
  raise(signal);
}

}  // namespace

CrashReport* shared_crash_report() {
  void* page = ::mmap(nullptr, sizeof(CrashReport), PROT_READ | PROT_WRITE,
                      MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (page == MAP_FAILED) return nullptr;
  return new (page) CrashReport();
}

void release_crash_report(CrashReport* report) {
  if (report != nullptr) ::munmap(report, sizeof(CrashReport));
}

void install_crash_handler(CrashReport* report) {
  g_report = report;
  stack_t alternate{};
  alternate.ss_sp = g_alternate_stack;
  alternate.ss_size = sizeof g_alternate_stack;
  sigaltstack(&alternate, nullptr);
  struct sigaction action {};
  action.sa_sigaction = on_crash;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND | SA_NODEFER | SA_ONSTACK | SA_SIGINFO;
  for (int signal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) sigaction(signal, &action, nullptr);
}

std::string crash_site(const CrashReport* report) {
  if (report == nullptr || report->signal == 0) return "";
  if (report->who[0] == '\0')
    return report->code[0] == '\0' ? ""
                                   : std::string(" in the code of ") + report->code +
                                         ", outside the plugin calls the host marks (a thread "
                                         "it started)";
  return std::string(" in ") + report->who + ", in its " + report->call +
         ", at t = " + monohydra::short_number(report->t) + " s, step " +
         std::to_string(report->step);
}

}  // namespace mh::cli
