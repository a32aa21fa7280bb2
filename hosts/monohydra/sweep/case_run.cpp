#include "case_run.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>

#include "parameter_path.hpp"
#include "run_record.hpp"
#include "stop_signals.hpp"

namespace fs = std::filesystem;

namespace mh::cli::sweep {
namespace {

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double wall_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void write_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent is gone
    done += static_cast<std::size_t>(n);
  }
}

// The parser's message without the place in the text the overrides produced
// (its lines are not the model file's): "FIELD: EXPECTATION".
std::string input_reason(const InputError& err) {
  std::string what = err.what();
  if (!err.field().empty()) {
    const auto at = what.find(err.field() + ": ");
    if (at != std::string::npos) return what.substr(at);
  }
  return what;
}

// `text` without a leading "MODEL:LINE:COL: ": the lines of the text the
// overrides produced are not the model file's.
std::string without_place(const std::string& text, const std::string& model_path) {
  if (text.rfind(model_path + ":", 0) != 0) return text;
  std::size_t at = model_path.size();
  for (int part = 0; part < 2 && at < text.size() && text[at] == ':'; ++part) {
    const std::size_t end = text.find_first_not_of("0123456789", at + 1);
    if (end == std::string::npos || end == at + 1) break;
    at = end;
  }
  if (text.compare(at, 2, ": ") == 0) return text.substr(at + 2);
  return text;
}

std::string file_stem(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return out;
}

// The columns error metrics compare, per reference.
std::vector<std::string> reference_columns(const Study& study, const std::string& reference) {
  std::vector<std::string> names;
  for (const auto& m : study.metrics)
    if (m.kind == "error" && m.reference == reference) names.push_back(m.column);
  return names;
}

// The reference runs of `model`, read from their CSVs once per process.
std::map<std::string, const ReferenceRun*> references_of(SweepContext& ctx, int model) {
  std::map<std::string, const ReferenceRun*> out;
  for (const auto& r : ctx.references) {
    if (r.model != model) continue;
    const auto key = std::make_pair(r.name, r.model);
    if (ctx.loaded.count(key) == 0) {
      std::optional<ReferenceRun> run;
      std::error_code ec;
      if (fs::exists(ctx.reference_csv(r), ec)) {
        try {
          run = load_reference(ctx.reference_csv(r), reference_columns(ctx.study, r.name));
        } catch (const std::exception&) {
        }
      }
      ctx.loaded[key] = std::move(run);
    }
    out[r.name] = ctx.loaded[key] ? &*ctx.loaded[key] : nullptr;
  }
  return out;
}

RecordOptions record_options(const std::string& csv_path) {
  RecordOptions options;
  options.csv_path = csv_path;
  options.log = [](mh_log_level, const std::string&, const std::string&) {};  // the row says why
  return options;
}

// A reference run: its CSV is written under a temporary name and renamed
// when the run reached t_end, so a CSV present is a whole reference.
std::string run_reference(SweepContext& ctx, const ReferenceJob& r) {
  try {
    const ModelFile file = case_model(ctx, r.model, ctx.study.references.at(r.name));
    const std::string path = ctx.reference_csv(r);
    const RunRecord rec = record_run(file, ctx.registry, "", "", record_options(path + ".part"));
    if (rec.failed) return rec.failure;
    std::error_code ec;
    fs::rename(path + ".part", path, ec);
    if (ec) return "cannot rename its CSV: " + ec.message();
    return "";
  } catch (const InputError& err) {
    return input_reason(err);
  } catch (const std::exception& err) {
    return err.what();
  }
}

[[noreturn]] void run_in_child(SweepContext& ctx, const Job& job, int fd, pid_t parent) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // a killed study leaves no case running
  if (::getppid() != parent) _exit(1);
  const rlimit no_core{0, 0};
  setrlimit(RLIMIT_CORE, &no_core);  // the row reports the crash
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  std::string message;
  if (job.reference) {
    message = run_reference(ctx, ctx.references[static_cast<std::size_t>(job.index)]);
    message = (message.empty() ? "ok\n" : "failed\n") + message;
  } else {
    const Case& c = ctx.cases[static_cast<std::size_t>(job.index)];
    message = "row\n" + format_row(ctx.study, c, run_case(ctx, c));
  }
  write_all(fd, message);
  _exit(0);
}

}  // namespace

// The reference's CSV is named after what defines it too (FNV-1a of its
// values, the study's fixed values and --dt/--t-end): a resumed study whose
// reference changed runs it again instead of reading the old one.
std::string SweepContext::reference_csv(const ReferenceJob& r) const {
  std::string key;
  for (const auto* overrides : {&study.set, &study.references.at(r.name)})
    for (const auto& [path, value] : *overrides) key += path + "=" + value.Scalar() + ";";
  if (dt) key += "dt=" + number_text(*dt) + ";";
  if (t_end) key += "t_end=" + number_text(*t_end) + ";";
  std::uint32_t hash = 2166136261u;
  for (const char ch : key) hash = (hash ^ static_cast<unsigned char>(ch)) * 16777619u;
  char hex[16];
  std::snprintf(hex, sizeof hex, "%08x", hash);
  return (fs::path(out_dir) / "references" /
          (file_stem(r.name) + "-" +
           file_stem(study.models[static_cast<std::size_t>(r.model)].name) + "-" + hex + ".csv"))
      .string();
}

std::string SweepContext::case_csv(int index) const {
  return (fs::path(out_dir) / "cases" / ("case-" + std::to_string(index) + ".csv")).string();
}

void prepare_context(SweepContext& ctx) {
  ctx.cases = expand_cases(ctx.study);
  for (const auto& [name, overrides] : ctx.study.references) {
    bool used = false;
    for (const auto& m : ctx.study.metrics) used = used || m.reference == name;
    if (!used) continue;
    for (std::size_t m = 0; m < ctx.study.models.size(); ++m)
      ctx.references.push_back({name, static_cast<int>(m)});
  }
  std::vector<std::string> search;
  for (const auto& m : ctx.study.models) {
    try {  // plugin_paths as the model file resolves them, and its chosen libraries
      const ModelFile file = parse_model_text(YAML::Dump(m.tree) + "\n", m.path,
                                              fs::path(m.path).parent_path().string());
      for (const auto& p : file.plugin_paths) search.push_back(p);
      for (const auto& [id, library] : file.plugin_libraries) {
        ctx.registry.load(library);
        ctx.registry.choose(id, library);
      }
    } catch (const InputError&) {  // each case reports its model's errors
    } catch (const PluginError&) {
    }
  }
  for (const auto& p : PluginRegistry::default_search_path()) search.push_back(p);
  ctx.registry.scan(search);
}

ModelFile case_model(const SweepContext& ctx, int model, const Overrides& values) {
  const BaseModel& base = ctx.study.models[static_cast<std::size_t>(model)];
  YAML::Node tree = YAML::Clone(base.tree);
  for (const auto& [path, value] : ctx.study.set) host::set_path(tree, path, value);
  if (ctx.dt) host::set_path(tree, "solver/dt", YAML::Node(number_text(*ctx.dt)));
  if (ctx.t_end) host::set_path(tree, "solver/t_end", YAML::Node(number_text(*ctx.t_end)));
  for (const auto& [path, value] : values)
    if (value.IsScalar()) host::set_path(tree, path, value);  // a listed case may leave a path out
  YAML::Emitter out;
  out << tree;
  std::string dir = fs::path(base.path).parent_path().string();
  return parse_model_text(std::string(out.c_str()) + "\n", base.path, dir.empty() ? "." : dir);
}

CaseOutcome run_case(SweepContext& ctx, const Case& c) {
  CaseOutcome outcome;
  ModelFile file;
  try {
    file = case_model(ctx, c.model, c.values);
  } catch (const InputError& err) {
    outcome.status = "error";
    outcome.reason =
        without_place(input_reason(err), ctx.study.models[static_cast<std::size_t>(c.model)].path);
    return outcome;
  } catch (const std::exception& err) {
    outcome.status = "error";
    outcome.reason = err.what();
    return outcome;
  }
  const auto references = references_of(ctx, c.model);
  if (ctx.keep_csv) {
    std::error_code ec;
    fs::create_directories(fs::path(ctx.case_csv(c.index)).parent_path(), ec);
  }
  const double cpu0 = cpu_seconds(), wall0 = wall_seconds();
  const RunRecord rec = record_run(file, ctx.registry, "", "",
                                   record_options(ctx.keep_csv ? ctx.case_csv(c.index) : ""));
  outcome.cpu_s = cpu_seconds() - cpu0;
  outcome.wall_s = wall_seconds() - wall0;
  if (rec.rows() > 0) outcome.t_reached = rec.columns.front().back();
  outcome.status = !rec.failed ? "ok" : rec.rows() == 0 ? "error" : "failed";
  outcome.reason = without_place(rec.failure, file.path);
  try {
    outcome.metrics = case_metrics(ctx.study, rec, references);
  } catch (const std::invalid_argument& err) {  // a metric's column the run does not have
    if (outcome.status == "ok") {
      outcome.status = "error";
      outcome.reason = err.what();
    }
    outcome.metrics.clear();
  }
  return outcome;
}

RunningJob start_job(SweepContext& ctx, const Job& job) {
  RunningJob running;
  running.job = job;
  if (!job.reference) references_of(ctx, ctx.cases[static_cast<std::size_t>(job.index)].model);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot create a pipe");
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error("cannot fork a case's process");
  }
  if (pid == 0) {
    ::close(fds[0]);
    run_in_child(ctx, job, fds[1], parent);
  }
  ::close(fds[1]);
  running.pid = pid;
  running.fd = fds[0];
  return running;
}

bool read_job(RunningJob& running) {
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(running.fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) return true;
    if (n <= 0) return false;
    running.message.append(buf, static_cast<std::size_t>(n));
    return true;
  }
}

std::string finish_job(SweepContext& ctx, RunningJob& running) {
  ::close(running.fd);
  running.fd = -1;
  int status = 0;
  while (::waitpid(running.pid, &status, 0) < 0 && errno == EINTR) {
  }
  const std::string& msg = running.message;
  const bool sent = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  std::string why;
  if (WIFSIGNALED(status)) {
    why = std::string("crashed (") + signal_name(WTERMSIG(status)) + ")";
  } else if (!sent) {
    why = "its process exited with status " + std::to_string(WEXITSTATUS(status));
  }
  if (running.job.reference) {
    if (sent && msg.rfind("ok\n", 0) == 0) return "";
    if (sent && msg.rfind("failed\n", 0) == 0) return msg.substr(7);
    return why.empty() ? "it sent no result" : why;
  }
  if (sent && msg.rfind("row\n", 0) == 0 && msg.size() > 4 && msg.back() == '\n')
    return msg.substr(4);
  CaseOutcome crash;
  crash.status = "crashed";
  crash.reason = why.empty() ? "its process sent no result" : why;
  return format_row(ctx.study, ctx.cases[static_cast<std::size_t>(running.job.index)], crash);
}

std::string row_status(const std::string& row, const Study& study) {
  const auto fields = split_csv_line(row);
  const std::size_t at = 2 + varied_paths(study).size();
  return at < fields.size() ? fields[at] : "";
}

}  // namespace mh::cli::sweep
