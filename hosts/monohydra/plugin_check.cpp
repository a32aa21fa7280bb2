#include "plugin_check.hpp"

#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Core>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>

#include "cli_support.hpp"
#include "model_plugins.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/simulation.hpp"
#include "shipped_models.hpp"
#include "stop_signals.hpp"
#include "subcommand_parser.hpp"

namespace fs = std::filesystem;

namespace mh::cli {
namespace {

// Steps of the small run each component is checked on: enough to leave the
// initial state, short enough for a plugin's whole check to take seconds.
constexpr int kSteps = 20;
// A check that takes longer hangs (killed, reported).
constexpr unsigned kCheckSeconds = 120;
// Create/setup/destroy cycles.
constexpr int kCycles = 3;
// How a cycle check says that the component refused the model itself.
constexpr const char* kRefused = "refused the model: ";
// The assembled tangent agrees with forward differences when every entry is
// within this fraction of its row's largest difference (forward differences
// carry errors of about sqrt(machine epsilon) ~ 1e-8 relative, far below).
constexpr double kTangentTolerance = 1e-3;
// A row whose entries are all below this fraction of the matrix's largest
// (a coordinate nothing pushes along) is compared at that level instead:
// differences of it are rounding noise.
constexpr double kRowFloor = 1e-6;

// Runs `body` in a child process: "" from it is a pass, anything else the
// failure. A crash, an abort (an exception across the C boundary ends in
// std::terminate), an exception the body lets out or a hang is a failure too.
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
    return std::string("crashed (") + signal_name(sig) + ")";
  }
  if (got.empty() || got[0] != 'R') return "ended without a verdict";
  return got.substr(1);
}

struct Subject {
  ComponentKind kind;
  std::string id;
};

// The model a component is checked on and the choices that select it.
struct Setup {
  ModelFile file;
  RunChoices choices;
};

void shorten(Setup& s) {
  s.choices.t_end = kSteps * s.file.solver.dt;
  s.file.output = OutputSettings{};
}

// Unknowns of the tangent by name: the formulation's first, then the states.
std::string unknown_name(const Simulation& sim, int i) {
  const int n_m = const_cast<Simulation&>(sim).num_mechanical_unknowns();
  if (i < n_m) return "mechanical unknown " + std::to_string(i + 1);
  const auto& info = sim.state_info();
  const auto k = static_cast<size_t>(i - n_m);
  return "state " + (k < info.size() ? info[k].qualified : std::to_string(k + 1));
}

// The worst entry of `analytic` against `differences`, relative to its row's
// largest difference, but never to less than kRowFloor of `reference` (the
// largest entry of the derivatives checked together: a block of round-off,
// C where no force depends on the velocities, is not compared at its own
// size): "" within tolerance, else the failure.
std::string compare_blocks(const char* what, const Eigen::MatrixXd& analytic,
                           const Eigen::MatrixXd& differences, double reference) {
  const double floor = kRowFloor * std::max({differences.cwiseAbs().maxCoeff(), reference, 1e-300});
  double worst = 0.0;
  Eigen::Index wr = 0, wc = 0;
  for (Eigen::Index r = 0; r < analytic.rows(); ++r) {
    const double scale = std::max(differences.row(r).cwiseAbs().maxCoeff(), floor);
    for (Eigen::Index c = 0; c < analytic.cols(); ++c) {
      if (!std::isfinite(analytic(r, c))) return std::string(what) + " holds a non-finite entry";
      const double e = std::abs(analytic(r, c) - differences(r, c)) / scale;
      if (e > worst) {
        worst = e;
        wr = r;
        wc = c;
      }
    }
  }
  if (worst <= kTangentTolerance) return "";
  std::ostringstream msg;
  msg.precision(6);
  msg << what << " disagrees with differences: row " << wr + 1 << ", column z" << wc + 1
      << ": analytic " << analytic(wr, wc) << ", differences " << differences(wr, wc) << " (off by "
      << worst << " of the row's largest entry, tolerance " << kTangentTolerance << ")";
  return msg.str();
}

// The host's mechanics derivatives K and C (every subsystem's point force
// jacobian, ABI 2.1, in them) against central differences of the dynamics
// residual M zdd - Q in z and zd: what a formulation's analytic tangent is
// built from.
std::string mechanics_check(Simulation& sim) {
  const Eigen::VectorXd z = sim.z(), zd = sim.zd(), zdd = sim.zdd();
  const Eigen::Index n = z.size();
  if (n == 0) return "";
  const Simulation::MechanicsDerivatives d = sim.mechanics_derivatives(z, zd, zdd);
  Eigen::MatrixXd k(n, n), c(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double hz = 1e-6 * (1.0 + std::abs(z[j])), hv = 1e-6 * (1.0 + std::abs(zd[j]));
    Eigen::VectorXd zp = z, zm = z, vp = zd, vm = zd;
    zp[j] += hz;
    zm[j] -= hz;
    vp[j] += hv;
    vm[j] -= hv;
    k.col(j) =
        (sim.dynamics_residual(zp, zd, zdd) - sim.dynamics_residual(zm, zd, zdd)) / (2.0 * hz);
    c.col(j) = (sim.dynamics_residual(z, vp, zdd) - sim.dynamics_residual(z, vm, zdd)) / (2.0 * hv);
  }
  const double reference = std::max(k.cwiseAbs().maxCoeff(), c.cwiseAbs().maxCoeff());
  const std::string kc =
      compare_blocks("K = d(M zdd - Q)/dz (point force jacobians)", d.K, k, reference);
  return kc.empty()
             ? compare_blocks("C = d(M zdd - Q)/dzd (point force jacobians)", d.C, c, reference)
             : kc;
}

std::string tangent_check(const Setup& s, const PluginRegistry& registry) {
  Simulation sim(s.file, registry, s.choices);
  sim.start();
  for (int i = 0; i < 3; ++i) sim.step();
  const Eigen::MatrixXd a = sim.assembled_tangent();
  const Eigen::MatrixXd f = sim.finite_difference_tangent();
  if (a.rows() != f.rows() || a.cols() != f.cols()) return "tangent sizes differ";
  const double floor = kRowFloor * std::max(f.cwiseAbs().maxCoeff(), 1e-300);
  double worst = 0.0;
  Eigen::Index wr = -1, wc = -1;
  for (Eigen::Index r = 0; r < a.rows(); ++r) {
    const double scale = std::max(f.row(r).cwiseAbs().maxCoeff(), floor);
    for (Eigen::Index c = 0; c < a.cols(); ++c) {
      if (!std::isfinite(a(r, c))) return "the tangent holds a non-finite entry";
      const double e = std::abs(a(r, c) - f(r, c)) / scale;
      if (e > worst) {
        worst = e;
        wr = r;
        wc = c;
      }
    }
  }
  if (worst <= kTangentTolerance) return mechanics_check(sim);
  std::ostringstream msg;
  msg.precision(6);
  msg << "the analytic tangent disagrees with differences of the residual: row "
      << unknown_name(sim, static_cast<int>(wr)) << ", column "
      << unknown_name(sim, static_cast<int>(wc)) << ": analytic " << a(wr, wc) << ", differences "
      << f(wr, wc) << " (off by " << worst << " of the row's largest entry, tolerance "
      << kTangentTolerance << ")";
  return msg.str();
}

// z, states and outputs after kSteps, as bytes.
std::string fingerprint(const Setup& s, const PluginRegistry& registry) {
  Simulation sim(s.file, registry, s.choices);
  sim.start();
  while (sim.time() < sim.settings().t_end - 0.5 * sim.settings().dt) sim.step();
  std::string bytes;
  for (const Eigen::VectorXd* v : {&sim.z(), &sim.zd(), &sim.states(), &sim.outputs()})
    bytes.append(reinterpret_cast<const char*>(v->data()),
                 static_cast<size_t>(v->size()) * sizeof(double));
  return bytes;
}

// The options of the subject in the model, or null (an integrator's, or a
// component chosen from the command line without options).
OptionMap* subject_options(Setup& s, const Subject& who) {
  if (who.kind == ComponentKind::subsystem) {
    for (auto& spec : s.file.subsystems)
      if (spec.type == who.id) return &spec.options;
    return nullptr;
  }
  ComponentChoice& c =
      who.kind == ComponentKind::formulation ? s.file.formulation : s.file.integrator;
  return c.name == who.id ? &c.options : nullptr;
}

// An option the component does not know, then each of its options as a word
// where it may expect a number: each refused with a message (InputError).
std::string bad_options_check(const Setup& base, const Subject& who,
                              const PluginRegistry& registry) {
  Setup s = base;
  const OptionMap* options = subject_options(s, who);
  if (options == nullptr) return "";
  std::vector<std::string> keys{"monohydra_check_unknown_option"};
  for (const auto& [key, value] : *options) keys.push_back(key);
  for (const auto& key : keys) {
    Setup bad = base;
    OptionMap& opts = *subject_options(bad, who);
    OptionValue word;
    word.kind = OptionValue::Kind::string;
    word.text = "not-a-valid-value";
    word.mark = bad.file.formulation.mark;
    if (opts.count(key) != 0) {
      if (opts[key].kind == OptionValue::Kind::string) continue;  // any word may be valid
      word.mark = opts[key].mark;
    }
    opts[key] = word;
    try {
      Simulation sim(bad.file, registry, bad.choices);
      sim.start();
      if (key == keys.front()) return "accepted an option it does not know ('" + key + "')";
      return "accepted the word 'not-a-valid-value' for its option '" + key + "'";
    } catch (const InputError&) {  // refused, with the file, field and expectation
    } catch (const PluginError&) {
    } catch (const SimulationError&) {
    }
  }
  return "";
}

bool model_uses(const ModelFile& file, const Subject& who) {
  if (who.kind != ComponentKind::subsystem) return true;  // chosen on the command line
  for (const auto& spec : file.subsystems)
    if (spec.type == who.id) return true;
  return false;
}

// The model a component is checked on: the one given, else the shipped four-bar
// for a formulation or an integrator, else the smallest shipped model that
// uses the subsystem. nullopt (and why in `why`) when there is none.
std::vector<Setup> setups_for(const Subject& who, const std::string& model_path, std::string& why) {
  std::vector<Setup> setups;
  std::vector<std::string> candidates;
  if (!model_path.empty()) {
    candidates.push_back(model_path);
  } else if (who.kind != ComponentKind::subsystem) {
    // A closed loop with hydraulics first; a tree for a formulation that
    // handles trees only.
    candidates.push_back(shipped_model("fourbar.yaml"));
    candidates.push_back(shipped_model("double-pendulum.yaml"));
  } else {
    const fs::path dir = fs::path(shipped_model("fourbar.yaml")).parent_path();
    std::vector<std::pair<std::uintmax_t, std::string>> found;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().extension() == ".yaml") found.emplace_back(e.file_size(ec), e.path().string());
    std::sort(found.begin(), found.end());
    for (const auto& f : found) candidates.push_back(f.second);
  }
  for (const auto& path : candidates) {
    Setup s;
    try {
      s.file = load_model_file(path);
    } catch (const InputError& err) {
      if (!model_path.empty()) {
        why = err.what();
        return setups;
      }
      continue;
    }
    if (!model_uses(s.file, who)) continue;
    // The model's own choice, so that options reach it (a component chosen
    // on the command line starts from its defaults).
    if (who.kind == ComponentKind::formulation && s.file.formulation.name != who.id)
      s.file.formulation = ComponentChoice{who.id, {}, s.file.formulation.mark};
    if (who.kind == ComponentKind::integrator && s.file.integrator.name != who.id)
      s.file.integrator = ComponentChoice{who.id, {}, s.file.integrator.mark};
    shorten(s);
    setups.push_back(std::move(s));
    // Subsystems: the smallest model that uses it is enough.
    if (who.kind == ComponentKind::subsystem) return setups;
  }
  if (!setups.empty()) return setups;
  why = model_path.empty()
            ? "no shipped model uses it, and the SDK cannot declare a subsystem's options, "
              "points and ports: give a model that does (monohydra check PLUGIN.so MODEL.yaml)"
            : "'" + model_path + "' does not use it";
  return setups;
}

}  // namespace

int check(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "check",
      "Load PLUGIN.so and drive each of its components through its contract on MODEL.yaml "
      "(default: the shipped four-bar, or the smallest shipped model using a subsystem): load "
      "and version, descriptors, create/destroy cycles, bad options refused, analytic tangent "
      "against differences, bit-identical reruns; each check in a child process. Exit 0 when "
      "every check passed, 1 when one failed.");
  CLI::App& app = *app_holder;
  std::vector<std::string> files;
  app.add_option("PLUGIN.so [MODEL.yaml]", files, "the plugin library, then the model");
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (files.empty() || files.size() > 2) {
    std::cerr << "usage: monohydra check PLUGIN.so [MODEL.yaml]\n";
    return 2;
  }
  const std::string& plugin = files[0];
  const std::string model_path = files.size() == 2 ? files[1] : "";
  int failures = 0;
  const auto report = [&failures](const std::string& what, const std::string& failure,
                                  const std::string& detail = "") {
    if (failure.empty()) {
      std::cout << "  ok    " << what << (detail.empty() ? "" : ": " + detail) << '\n';
    } else {
      std::cout << "  FAIL  " << what << ": " << failure << '\n';
      ++failures;
    }
  };

  std::cout << "check " << plugin << '\n';
  // Loading: probed in a child first, then the version, the entry and init.
  PluginRegistry registry;
  try {
    registry.load(plugin);
  } catch (const PluginError& err) {
    report("load", err.what());
    std::cout << "monohydra check: FAILED (the library cannot be loaded)\n";
    return 1;
  }
  std::vector<Subject> subjects;
  std::string library;
  for (const auto& c : registry.components()) {
    library = c.library;
    subjects.push_back({c.kind, c.id});
  }
  if (subjects.empty()) {
    report("components",
           "the library offers none (every factory's count is 0 or its factories "
           "are missing)");
    std::cout << "monohydra check: FAILED\n";
    return 1;
  }
  {
    const mh_version v = registry.components().front().abi_version;
    report("load", "",
           "ABI " + std::to_string(v.major) + "." + std::to_string(v.minor) + "." +
               std::to_string(v.patch) + " on host ABI " + std::to_string(MH_ABI_VERSION_MAJOR) +
               "." + std::to_string(MH_ABI_VERSION_MINOR) + "; its structs read up to their " +
               "struct_size");
  }
  for (const auto& c : registry.components()) {
    const mh_component_descriptor* d = c.descriptor;
    std::string bad;
    if (d->struct_size < sizeof(uint32_t) + 5 * sizeof(const char*))
      bad = "descriptor struct_size " + std::to_string(d->struct_size) + " is too small";
    else if (d->name == nullptr || d->version == nullptr || d->version[0] == '\0')
      bad = "descriptor without a name or a version";
    report(std::string(to_string(c.kind)) + " " + c.id + ": descriptor", bad,
           bad.empty() ? std::string("v") + d->version : "");
  }

  // The rest of the model (other components) from the usual search path;
  // this library's components win over any other library offering their ids.
  for (const auto& who : subjects) registry.choose(who.id, library);
  ModelFile given;
  if (!model_path.empty()) {
    try {
      given = load_model_file(model_path);
      load_model_plugins(given, registry);
    } catch (const InputError& err) {
      std::cerr << "monohydra: " << err.what() << '\n';
      return 2;
    }
  } else {
    registry.scan(PluginRegistry::default_search_path());
  }

  for (const auto& who : subjects) {
    const std::string name = std::string(to_string(who.kind)) + " " + who.id;
    std::string why;
    const std::vector<Setup> setups = setups_for(who, model_path, why);
    if (setups.empty()) {
      std::cout << "  skip  " << name << ": " << why << '\n';
      continue;
    }
    // The first model it accepts (a formulation for trees only refuses the
    // four-bar's cut joints with an input error, and gets the next).
    const Setup* setup = nullptr;
    std::string cycles;
    for (const Setup& candidate : setups) {
      setup = &candidate;
      cycles = isolated([&] {
        for (int i = 0; i < kCycles; ++i) {
          try {
            Simulation sim(candidate.file, registry, candidate.choices);
            sim.start();
          } catch (const InputError& err) {
            return std::string(kRefused) + err.what();
          }
        }
        return std::string();
      });
      if (cycles.rfind(kRefused, 0) != 0) break;
    }
    std::cout << "  on    " << name << ": " << setup->file.path << ", " << kSteps << " steps of "
              << setup->file.solver.dt << " s\n";
    report(name + ": create/setup/destroy x" + std::to_string(kCycles), cycles);
    if (!cycles.empty()) continue;  // the rest needs it created
    Setup counted = *setup;
    const OptionMap* given_options = subject_options(counted, who);
    const std::string tried = "an unknown option and " +
                              std::to_string(given_options != nullptr ? given_options->size() : 0) +
                              " of the model's options made invalid, one at a time";
    const std::string bad = isolated([&] { return bad_options_check(*setup, who, registry); });
    report(name + ": bad options refused", bad, tried);
    report(name + ": analytic tangent against differences of its residual",
           isolated([&] { return tangent_check(*setup, registry); }));
    report(name + ": repeated runs bit-identical", isolated([&] {
             const std::string a = fingerprint(*setup, registry);
             const std::string b = fingerprint(*setup, registry);
             return a == b ? std::string() : std::string("two runs of the same model differ");
           }));
  }
  std::cout << "monohydra check: " << (failures == 0 ? "OK" : "FAILED") << " (" << failures
            << " failure" << (failures == 1 ? "" : "s") << ")\n";
  return failures == 0 ? 0 : 1;
}

}  // namespace mh::cli
