#include "contract_checks.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "isolated_check.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/run_state.hpp"

namespace mh::testhost {
namespace {

using monohydra::testhost::Check;
using monohydra::testhost::TangentComparison;

// How a cycle check says that the component refused the model itself.
constexpr const char* kRefused = "refused the model: ";
// A row whose entries are all below this fraction of the matrix's largest
// (a coordinate nothing pushes along) is compared at that level instead:
// differences of it are rounding noise.
constexpr double kRowFloor = 1e-6;

// Unknowns of the tangent by name: the formulation's first, then the states.
std::string unknown_name(Simulation& sim, int i) {
  const int n_m = sim.num_mechanical_unknowns();
  if (i < n_m) return "mechanical unknown " + std::to_string(i + 1);
  const auto& info = sim.state_info();
  const auto k = static_cast<size_t>(i - n_m);
  return "state " + (k < info.size() ? info[k].qualified : std::to_string(k + 1));
}

// The worst entry of `analytic` against `differences`, relative to its row's
// largest difference, but never to less than kRowFloor of `reference` (the
// largest entry of the derivatives checked together: a block of round-off,
// C where no force depends on the velocities, is not compared at its own
// size). Sets row and column of the worst; -1 for a non-finite entry.
double worst_entry(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& differences,
                   double reference, Eigen::Index& wr, Eigen::Index& wc) {
  const double floor = kRowFloor * std::max({differences.cwiseAbs().maxCoeff(), reference, 1e-300});
  double worst = 0.0;
  wr = 0;
  wc = 0;
  for (Eigen::Index r = 0; r < analytic.rows(); ++r) {
    const double scale = std::max(differences.row(r).cwiseAbs().maxCoeff(), floor);
    for (Eigen::Index c = 0; c < analytic.cols(); ++c) {
      if (!std::isfinite(analytic(r, c))) {
        wr = r;
        wc = c;
        return -1.0;
      }
      const double e = std::abs(analytic(r, c) - differences(r, c)) / scale;
      if (e > worst) {
        worst = e;
        wr = r;
        wc = c;
      }
    }
  }
  return worst;
}

// "" within tolerance, else the failure.
std::string compare_blocks(const char* what, const Eigen::MatrixXd& analytic,
                           const Eigen::MatrixXd& differences, double reference) {
  Eigen::Index wr = 0, wc = 0;
  const double worst = worst_entry(analytic, differences, reference, wr, wc);
  if (worst < 0.0) return std::string(what) + " holds a non-finite entry";
  if (worst <= kTangentTolerance) return "";
  std::ostringstream msg;
  msg.precision(6);
  msg << what << " disagrees with differences: row " << wr + 1 << ", column z" << wc + 1
      << ": analytic " << analytic(wr, wc) << ", differences " << differences(wr, wc) << " (off by "
      << worst << " of the row's largest entry, tolerance " << kTangentTolerance << ")";
  return msg.str();
}

// The host's mechanics derivatives K and C (every subsystem's point force
// jacobian in them) against central differences of the dynamics
// residual M zdd - Q in z and zd: what a formulation's analytic tangent is
// built from.
std::string mechanics_check(Simulation& sim) {
  const Eigen::VectorXd z = sim.z(), zd = sim.zd(), zdd = sim.zdd();
  const Eigen::Index n = z.size();
  if (n == 0) return "";
  const Simulation::MechanicsDerivatives d = sim.mechanics_derivatives(z, zd, zdd);
  Eigen::MatrixXd k(n, n), c(n, n);
  double mass = 0.0;  // the mass matrix's largest entry: the residual is linear in zdd
  for (Eigen::Index j = 0; j < n; ++j) {
    Eigen::VectorXd ap = zdd, am = zdd;
    ap[j] += 1.0;
    am[j] -= 1.0;
    mass =
        std::max(mass, (0.5 * (sim.dynamics_residual(z, zd, ap) - sim.dynamics_residual(z, zd, am)))
                           .cwiseAbs()
                           .maxCoeff());
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
  // K and C are compared down to kRowFloor of the largest of K, C and M: in
  // the Newton matrix K + (2/h) C + (4/h^2) M an entry below that moves
  // nothing for h <= 2 s (a force whose rate dependence has saturated,
  // tanh'(100) ~ 1e-87, is not compared at its own size).
  const double reference = std::max({k.cwiseAbs().maxCoeff(), c.cwiseAbs().maxCoeff(), mass});
  const std::string kc =
      compare_blocks("K = d(M zdd - Q)/dz (point force jacobians)", d.K, k, reference);
  return kc.empty()
             ? compare_blocks("C = d(M zdd - Q)/dzd (point force jacobians)", d.C, c, reference)
             : kc;
}

// The worst entry of an analytic matrix against its differences (central,
// forward, backward at 1e-6; central at 1e-5 for their own error), each at
// its scale: |d|, at least kEntryFloor of the geometric mean of its row's and
// its column's largest |d|, and ten times the differences' estimated error
// over the tolerance. At a kink (a spool crossing zero) the analytic entry is
// one of the one-sided derivatives, not their mean, so the nearest counts.
// Columns with given[c] == 0 are not compared.
struct EntryError {
  bool compared = false, non_finite = false;
  double error = 0.0, analytic = 0.0, differences = 0.0, scale = 0.0;
  Eigen::Index row = 0, col = 0;
};

// Entry (r, c)'s differences and their own error: the central ones at 1e-6
// (their distance from those at 1e-5), or those at 1e-4 where their
// distance from those at 1e-3 is smaller (an entry beside far larger terms
// of its row, whose 1e-6 step rounding hides).
struct Differenced {
  double value = 0.0, noise = 0.0;
};

Differenced differenced(const Simulation::TangentSample& t, Eigen::Index r, Eigen::Index c) {
  const double fine = 0.5 * (t.forward(r, c) + t.backward(r, c));
  const Differenced central{fine, std::abs(fine - t.central_coarse(r, c))};
  if (t.central_wide.size() == 0) return central;
  const Differenced wide{t.central_wide(r, c),
                         std::abs(t.central_wide(r, c) - t.central_wider(r, c))};
  return wide.noise < central.noise ? wide : central;
}

EntryError worst_entry_error(const Simulation::TangentSample& t,
                             const std::vector<unsigned char>* given,
                             const Eigen::VectorXd* row_effect = nullptr, int* noisy = nullptr) {
  EntryError w;
  const Eigen::MatrixXd& a = t.analytic;
  if (a.size() == 0) return w;
  const Eigen::MatrixXd d = 0.5 * (t.forward + t.backward);
  const Eigen::VectorXd row_max = d.cwiseAbs().rowwise().maxCoeff();
  const Eigen::VectorXd col_max = d.cwiseAbs().colwise().maxCoeff().transpose();
  for (Eigen::Index c = 0; c < a.cols(); ++c) {
    if (given != nullptr && (*given)[static_cast<size_t>(c)] == 0) continue;
    for (Eigen::Index r = 0; r < a.rows(); ++r) {
      if (!std::isfinite(a(r, c))) {
        w.non_finite = true;
        w.row = r;
        w.col = c;
        return w;
      }
      const Differenced best = differenced(t, r, c);
      const double noise = best.noise;
      const double floor = row_effect != nullptr
                               ? kBlockFloor * (*row_effect)[r] / t.column_scale[c]
                               : kEntryFloor * std::sqrt(row_max[r] * col_max[c]);
      const double scale = std::abs(best.value) + floor + 10.0 * noise / kTangentTolerance;
      // A nonzero entry 1 % off that this scale would not show, for the
      // differences' own error (not for the floor: a rounding residue).
      if (noisy != nullptr && a(r, c) != 0.0 && 10.0 * noise / kTangentTolerance > floor &&
          0.01 * std::abs(a(r, c)) <= kTangentTolerance * scale)
        ++*noisy;
      const double e =
          std::min({std::abs(a(r, c) - d(r, c)), std::abs(a(r, c) - t.forward(r, c)),
                    std::abs(a(r, c) - t.backward(r, c)), std::abs(a(r, c) - best.value)}) /
          std::max(scale, 1e-300);
      if (!w.compared || e > w.error) {
        w.compared = true;
        w.error = e;
        w.row = r;
        w.col = c;
        w.analytic = a(r, c);
        w.differences = best.value;
        w.scale = scale;
      }
    }
  }
  return w;
}

}  // namespace

Eigen::VectorXd row_effect(const Simulation::TangentSample& t) {
  const Eigen::MatrixXd d = 0.5 * (t.forward + t.backward);
  return (d.cwiseAbs() * t.column_scale.asDiagonal()).rowwise().maxCoeff();
}

Eigen::VectorXd judged_effect(const Simulation::TangentSample& t, const Eigen::VectorXd& across) {
  const Eigen::VectorXd own = row_effect(t);
  return (own.array() > 0.0).select(own, across);
}

bool shows_one_percent(const Simulation::TangentSample& t, Eigen::Index r, Eigen::Index c,
                       double effect) {
  const Differenced best = differenced(t, r, c);
  const double scale = std::abs(best.value) + kBlockFloor * effect / t.column_scale[c] +
                       10.0 * best.noise / kTangentTolerance;
  return 0.01 * std::abs(t.analytic(r, c)) > kTangentTolerance * scale;
}

}  // namespace mh::testhost

namespace mh::testhost {
namespace {

std::string describe(const EntryError& w) {
  std::ostringstream msg;
  msg.precision(6);
  msg << "analytic " << w.analytic << ", differences " << w.differences << " (off by " << w.error
      << " of the entry's scale " << w.scale << ", tolerance " << kTangentTolerance << ")";
  return msg.str();
}

std::string tangent_check(const Setup& s, const PluginRegistry& registry) {
  Simulation sim(s.file, registry, s.choices);
  sim.start();
  for (int i = 0; i < 3; ++i) sim.step();
  const TangentComparison t = compare_tangent(sim);
  if (!t.failure.empty()) return t.failure;
  if (!t.ok) return "the analytic tangent disagrees with differences of the residual: " + t.worst;
  return mechanics_check(sim);
}

// z, states and outputs after the run, as bytes.
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

constexpr const char* kNoState = "no state extension: ";

// The check's run started and stepped through the first half of its steps
// (where the snapshot checks save it); returns the whole run's steps.
int start_and_run_half(Simulation& run) {
  run.start();
  const int total =
      static_cast<int>(std::lround((run.settings().t_end - run.time()) / run.settings().dt));
  for (int k = 0; k < total / 2; ++k) run.step();
  return total;
}

// Half the run, saved; the rest of it, then again in a fresh run the state
// is restored into: the two must agree to the last bit, step by step.
std::string state_check(const Setup& s, const PluginRegistry& registry) {
  Simulation run(s.file, registry, s.choices);
  const int total = start_and_run_half(run);
  const int half = total / 2;
  RunState saved;
  try {
    run.save_state(saved);
  } catch (const RunStateError& err) {
    return std::string(kNoState) + err.what();
  }
  const auto shown = [](const Simulation& sim) {
    std::string bytes;
    for (const Eigen::VectorXd* v :
         {&sim.z(), &sim.zd(), &sim.zdd(), &sim.states(), &sim.outputs()})
      bytes.append(reinterpret_cast<const char*>(v->data()),
                   static_cast<size_t>(v->size()) * sizeof(double));
    return bytes;
  };
  std::vector<std::string> after;
  for (int k = half; k < total; ++k) {
    run.step();
    after.push_back(shown(run));
  }
  Simulation fresh(s.file, registry, s.choices);
  fresh.restore_state(saved);
  for (size_t k = 0; k < after.size(); ++k) {
    fresh.step();
    if (shown(fresh) != after[k]) {
      std::ostringstream msg;
      msg << "the run restored from a snapshot at t = " << saved.data.accepted.t
          << " s differs from the run it was saved from at t = " << fresh.time()
          << " s: some state between steps is not in the instance's saved bytes";
      return msg.str();
    }
  }
  return "";
}

constexpr const char* kNoParameters = "no parameters: ";
constexpr const char* kNoSnapshot = "no snapshot: ";

// Each option a component changes in place (monohydra/parameters.h) against
// the same option read at setup: half the run, saved; the option moved by 1 %
// in place, against a fresh instance set up with the moved value and the
// state restored into it. The next step's tangent from differences of the
// residual agrees entry by entry to 1e-6, and the rest of the run to 1e-9 of
// each value, or the instance missed something the value sets (a derived
// constant). A value outside its declared range is refused.
// The residual's derivative with respect to each is differenced by the host
// (no component gives it analytically yet), which the detail says.
// The option `key` of an instance's options set to `value` as the model
// file would write it: a number, or the entry ROW, COLUMN (from 0) of a
// table option, keyed TABLE/ROW/COLUMN (a table valve's flows). False when
// the key names neither.
bool set_option_at_setup(OptionMap& options, const std::string& key, double value) {
  const size_t slash = key.find('/');
  if (slash == std::string::npos) {
    OptionValue v;
    v.number = value;
    v.text = std::to_string(value);
    options[key] = v;
    return true;
  }
  const auto table = options.find(key.substr(0, slash));
  const size_t second = key.find('/', slash + 1);
  if (table == options.end() || table->second.kind != OptionValue::Kind::table ||
      second == std::string::npos)
    return false;
  try {
    const int row = std::stoi(key.substr(slash + 1, second - slash - 1));
    const int column = std::stoi(key.substr(second + 1));
    OptionValue& v = table->second;
    if (row < 0 || row >= v.rows || column < 0 || column >= v.columns) return false;
    v.table[static_cast<size_t>(row) * static_cast<size_t>(v.columns) +
            static_cast<size_t>(column)] = value;
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

std::string parameters_check(const Setup& s, const Subject& who, const PluginRegistry& registry,
                             std::string& detail) {
  std::string instance;
  for (const SubsystemSpec& spec : s.file.subsystems)
    if (spec.type == who.id && instance.empty()) instance = spec.name;
  Simulation run(s.file, registry, s.choices);
  const std::vector<std::string> keys =
      instance.empty() ? std::vector<std::string>{} : run.component_parameter_keys(instance);
  if (keys.empty())
    return std::string(kNoParameters) +
           "it changes none of its options in place (no monohydra/parameters.h): they are read "
           "at its setup";
  const int total = start_and_run_half(run);
  const int half = total / 2;
  RunState saved;
  run.save_state(saved);
  const auto values = [](const Simulation& sim) {
    Eigen::VectorXd v(sim.z().size() + sim.zd().size() + sim.states().size());
    v << sim.z(), sim.zd(), sim.states();
    return v;
  };
  for (const std::string& key : keys) {
    const std::string path = "subsystems/" + instance + "/" + key;
    const Simulation::ParameterRange range = run.component_parameter_range(instance, key);
    const double now = run.component_parameter(instance, key);
    double moved = now != 0.0 ? now * 1.01 : 0.01;
    if (moved > range.upper) moved = now - 0.01 * std::abs(now != 0.0 ? now : 1.0);
    if (moved < range.lower || moved > range.upper) continue;  // a range of one value
    // In place, from the saved state on; and read at setup, the state restored.
    Simulation in_place(s.file, registry, s.choices);
    in_place.restore_state(saved);
    in_place.set_component_parameter(instance, key, moved);
    Setup at_setup = s;
    for (SubsystemSpec& spec : at_setup.file.subsystems)
      if (spec.name == instance) {
        if (!set_option_at_setup(spec.options, key, moved))
          return path + ": a parameter's key names an option, or an entry of a table option " +
                 "(TABLE/ROW/COLUMN), of the model's instance; this one names neither";
      }
    Simulation fresh(at_setup.file, registry, at_setup.choices);
    fresh.restore_state(saved);
    const auto differ = [&](const std::string& what, double a, double b) {
      std::ostringstream msg;
      msg.precision(10);
      msg << path << " set in place to " << moved << " and read at setup give " << a << " and " << b
          << " (" << what << ") at t = " << fresh.time()
          << " s: set_parameter misses something the option sets";
      return msg.str();
    };
    // The next step's tangent from differences of the residual alone (a
    // machine at rest moves no state the option acts on; its derivatives do).
    const Eigen::MatrixXd ta = in_place.central_difference_tangent();
    const Eigen::MatrixXd tb = fresh.central_difference_tangent();
    // Each entry at its own size, with a floor of its row's largest (a row
    // mixes units: a volume's d/dpdot of 1e-10 beside a cylinder's d/dzd).
    for (Eigen::Index r = 0; r < ta.rows(); ++r) {
      const double row = ta.row(r).cwiseAbs().maxCoeff();
      for (Eigen::Index c = 0; c < ta.cols(); ++c)
        if (!(std::abs(ta(r, c) - tb(r, c)) <=
              1e-6 * std::max(std::abs(ta(r, c)), std::abs(tb(r, c))) + 1e-12 * row))
          return differ("the tangent's row " + unknown_name(fresh, static_cast<int>(r)) +
                            ", column " + unknown_name(fresh, static_cast<int>(c)),
                        ta(r, c), tb(r, c));
    }
    for (int k = half; k < total; ++k) {
      in_place.step();
      fresh.step();
    }
    const Eigen::VectorXd a = values(in_place), b = values(fresh);
    for (Eigen::Index i = 0; i < a.size(); ++i)
      if (!(std::abs(a[i] - b[i]) <= 1e-9 * std::max({std::abs(a[i]), std::abs(b[i]), 1e-6})))
        return differ("value " + std::to_string(i + 1) + " of z, zd, states", a[i], b[i]);
    // Outside its range: refused, the value kept.
    for (const double outside :
         {range.upper * 2.0 + 1.0, range.lower - std::abs(range.lower) - 1.0}) {
      if (!std::isfinite(outside) || (outside >= range.lower && outside <= range.upper)) continue;
      bool refused = false;
      try {
        in_place.set_component_parameter(instance, key, outside);
      } catch (const std::invalid_argument&) {
        refused = true;
      }
      if (!refused || in_place.component_parameter(instance, key) != moved)
        return path + ": " + std::to_string(outside) + " is outside its declared range [" +
               std::to_string(range.lower) + ", " + std::to_string(range.upper) + "], yet it was " +
               (refused ? "changed" : "taken");
    }
  }
  detail.clear();
  for (const std::string& key : keys) detail += (detail.empty() ? "" : ", ") + key;
  detail +=
      ": set in place = read at setup; their residual derivatives are differenced by the "
      "host (the component gives none)";
  return "";
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

constexpr const char* kNoBlocks = "no derivative ops: ";

// Each instance of the subject in the model, at each of block_instants,
// every block its ops give against differences of its own evaluate.
std::string subsystem_blocks_check(const Setup& s, const Subject& who,
                                   const PluginRegistry& registry, std::string& detail);

}  // namespace

bool model_uses(const ModelFile& file, const Subject& who) {
  if (who.kind != ComponentKind::subsystem) return true;
  for (const auto& spec : file.subsystems)
    if (spec.type == who.id) return true;
  return false;
}

Setup setup_for(const ModelFile& file, const Subject& who) {
  Setup s{file, {}, {}};
  // The model's own choice keeps its options; another starts from its defaults.
  if (who.kind == ComponentKind::formulation && s.file.formulation.name != who.id)
    s.file.formulation = ComponentChoice{who.id, {}, s.file.formulation.mark};
  if (who.kind == ComponentKind::integrator && s.file.integrator.name != who.id)
    s.file.integrator = ComponentChoice{who.id, {}, s.file.integrator.mark};
  return s;
}

void shorten(Setup& s, int steps) {
  s.choices.t_end = steps * s.choices.dt.value_or(s.file.solver.dt);
  s.file.output = OutputSettings{};
}

TangentComparison compare_tangent(Simulation& sim) {
  TangentComparison out;
  out.tolerance = kTangentTolerance;
  const double dt = sim.settings().dt;
  bool any = false;
  for (const double h : {dt, std::max(kCoarseStep, 10.0 * dt)}) {
    const Simulation::TangentSample t = sim.tangent_sample(h);
    const Eigen::MatrixXd d = 0.5 * (t.forward + t.backward);
    TangentComparison::Sample sample;
    sample.step = h;
    sample.n = static_cast<int>(t.analytic.rows());
    sample.analytic.assign(t.analytic.data(), t.analytic.data() + t.analytic.size());
    sample.differences.assign(d.data(), d.data() + d.size());
    out.samples.push_back(std::move(sample));
    const EntryError w = worst_entry_error(t, nullptr);
    if (w.non_finite) {
      out.failure = "the tangent holds a non-finite entry: row " +
                    unknown_name(sim, static_cast<int>(w.row)) + ", column " +
                    unknown_name(sim, static_cast<int>(w.col));
      return out;
    }
    if (w.compared && (!any || w.error > out.max_error)) {
      any = true;
      out.max_error = w.error;
      out.worst_step = h;
      std::ostringstream msg;
      msg.precision(6);
      msg << "at a step of " << h << " s: row " << unknown_name(sim, static_cast<int>(w.row))
          << ", column " << unknown_name(sim, static_cast<int>(w.col)) << ": " << describe(w);
      out.worst = msg.str();
    }
  }
  out.ok = out.max_error <= kTangentTolerance;
  return out;
}

std::vector<int> block_instants(const Setup& s) {
  const double dt = s.choices.dt.value_or(s.file.solver.dt);
  const long total =
      std::clamp(std::lround(s.file.solver.t_end / dt), 1L, static_cast<long>(kBlockSteps));
  std::vector<int> at;
  if (!s.block_times.empty()) {
    for (const double t : s.block_times) at.push_back(static_cast<int>(std::lround(t / dt)));
  } else {
    for (const long k : {0L, 3L, total / 3, 2 * total / 3, total - 1})
      if (k >= 0 && k < total) at.push_back(static_cast<int>(k));
  }
  std::sort(at.begin(), at.end());
  at.erase(std::unique(at.begin(), at.end()), at.end());
  return at;
}

Effects block_effects(const std::vector<Simulation::DerivativeBlock>& blocks) {
  Effects e;
  for (const Simulation::DerivativeBlock& b : blocks) {
    if (b.sample.forward.size() == 0) continue;
    Eigen::VectorXd& to = b.name.rfind("dF", 0) == 0 ? e.force_rows : e.state_rows;
    const Eigen::VectorXd mine = row_effect(b.sample);
    to = to.size() == 0 ? mine : Eigen::VectorXd(to.cwiseMax(mine));
  }
  return e;
}

BlocksComparison compare_subsystem_blocks(const std::vector<Simulation::DerivativeBlock>& blocks,
                                          const std::string& instance, double t) {
  BlocksComparison out;
  const Effects effects = block_effects(blocks);
  for (const Simulation::DerivativeBlock& b : blocks) {
    if (!b.given) continue;
    const Eigen::VectorXd effect = judged_effect(b.sample, effects.of(b));
    const EntryError w = worst_entry_error(b.sample, nullptr, &effect, &out.noisy);
    out.compared += static_cast<int>(b.sample.analytic.size());
    const auto at = [&] {
      std::ostringstream msg;
      msg.precision(6);
      msg << b.name << " of subsystem '" << instance << "' ";
      return msg.str();
    };
    const auto where = [&] {
      std::ostringstream msg;
      msg.precision(6);
      msg << " at t = " << t << " s: row " << b.rows[static_cast<size_t>(w.row)] << ", column "
          << b.columns[static_cast<size_t>(w.col)];
      return msg.str();
    };
    if (w.non_finite) {
      out.failure = at() + "holds a non-finite entry" + where();
      return out;
    }
    if (w.compared && w.error > kTangentTolerance) {
      out.failure =
          at() + "disagrees with differences of its evaluate" + where() + ": " + describe(w);
      out.worst = w.error;
      return out;
    }
    if (w.compared) out.worst = std::max(out.worst, w.error);
  }
  return out;
}

namespace {

std::string subsystem_blocks_check(const Setup& s, const Subject& who,
                                   const PluginRegistry& registry, std::string& detail) {
  std::vector<std::string> instances;
  for (const SubsystemSpec& spec : s.file.subsystems)
    if (spec.type == who.id) instances.push_back(spec.name);
  const std::vector<int> at = block_instants(s);
  Setup longer = s;
  longer.choices.t_end = (at.back() + 1) * s.choices.dt.value_or(s.file.solver.dt);
  Simulation sim(longer.file, registry, longer.choices);
  sim.start();
  int done = 0, compared = 0, noisy = 0;
  double worst = 0.0;
  std::ostringstream times;
  times.precision(4);
  for (const int step : at) {
    for (; done < step; ++done) sim.step();
    times << (step == at.front() ? "" : ", ") << sim.time();
    for (const std::string& instance : instances) {
      const BlocksComparison c =
          compare_subsystem_blocks(sim.subsystem_blocks(instance), instance, sim.time());
      if (!c.failure.empty()) return c.failure;
      compared += c.compared;
      noisy += c.noisy;
      worst = std::max(worst, c.worst);
    }
  }
  if (compared == 0)
    return std::string(kNoBlocks) +
           "it gives none of jacobian, coupling_jacobian, point_force_jacobian: the host "
           "differences its evaluate";
  std::ostringstream msg;
  msg.precision(3);
  msg << compared << " entry comparisons of " << instances.size()
      << " instance(s) at t = " << times.str() << " s; worst off by " << worst << " of its scale";
  if (noisy > 0)
    msg << "; warning: at " << noisy
        << " of them a nonzero entry's differences were too noisy to show a 1 % error";
  detail = msg.str();
  return "";
}

}  // namespace

Eigen::VectorXd formulation_effect(const Simulation::FormulationBlocks& f) {
  Eigen::VectorXd e = row_effect(f.block[0]);
  for (int b = 1; b < 3; ++b) e = e.cwiseMax(row_effect(f.block[b]));
  return e;
}

std::string compare_formulation_blocks(const Simulation::FormulationBlocks& f, double t,
                                       double worst[3]) {
  const Eigen::VectorXd across = formulation_effect(f);
  for (int b = 0; b < 3; ++b) {
    const Eigen::VectorXd effect = judged_effect(f.block[b], across);
    const EntryError w = worst_entry_error(f.block[b], &f.given, &effect);
    std::ostringstream msg;
    msg.precision(6);
    if (w.non_finite) {
      msg << Simulation::FormulationBlocks::kNames[b] << " holds a non-finite entry at t = " << t
          << " s: row " << w.row + 1 << ", column " << w.col + 1;
      return msg.str();
    }
    if (w.compared && w.error > kTangentTolerance) {
      msg << Simulation::FormulationBlocks::kNames[b]
          << " disagrees with differences of its residual in that argument at t = " << t
          << " s: row " << w.row + 1 << ", column " << w.col + 1 << ": " << describe(w);
      return msg.str();
    }
    if (w.compared) worst[b] = std::max(worst[b], w.error);
  }
  return "";
}

void check_subject(const Subject& who, const std::vector<Setup>& candidates,
                   const PluginRegistry& registry, const Emit& emit) {
  const std::string name = std::string(to_string(who.kind)) + " " + who.id;
  const auto report = [&](const std::string& what, const std::string& failure,
                          const std::string& detail = "") {
    emit(Check{failure.empty() ? Check::Verdict::passed : Check::Verdict::failed,
               name + ": " + what, failure.empty() ? detail : failure});
  };
  const Setup* setup = nullptr;
  std::string cycles;
  for (const Setup& candidate : candidates) {
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
  if (setup == nullptr) return;
  std::ostringstream on;
  on << setup->file.path << ", " << kSteps << " steps of "
     << setup->choices.dt.value_or(setup->file.solver.dt) << " s";
  emit(Check{Check::Verdict::note, name, on.str()});
  report("create/setup/destroy x" + std::to_string(kCycles), cycles);
  if (!cycles.empty()) return;  // the rest needs it created
  Setup counted = *setup;
  const OptionMap* given_options = subject_options(counted, who);
  const std::string tried = "an unknown option and " +
                            std::to_string(given_options != nullptr ? given_options->size() : 0) +
                            " of the model's options made invalid, one at a time";
  report("bad options refused", isolated([&] { return bad_options_check(*setup, who, registry); }),
         tried);
  // An explicit integrator takes no Newton step: there is no tangent to check.
  const std::string method = isolated([&] {
    const Simulation sim(setup->file, registry, setup->choices);
    return std::string(sim.explicit_integration() ? "explicit" : "");
  });
  if (method == "explicit")
    emit(Check{Check::Verdict::skipped,
               name + ": analytic tangent against differences of its residual",
               "an explicit integrator takes no Newton step, so there is no tangent to check"});
  else
    report("analytic tangent against differences of its residual",
           isolated([&] { return tangent_check(*setup, registry); }));
  // A formulation's own blocks, whether or not the host uses them on this
  // model (without mechanics_map it differences the mechanical columns of a
  // model whose subsystems have points, so the check above never sees them).
  if (who.kind == ComponentKind::formulation && method != "explicit") {
    constexpr const char* kPassed = "passed: ";
    const std::string verdict = isolated([&] {
      const std::vector<int> at = block_instants(*setup);
      Setup longer = *setup;
      longer.choices.t_end = (at.back() + 1) * setup->choices.dt.value_or(setup->file.solver.dt);
      Simulation sim(longer.file, registry, longer.choices);
      sim.start();
      double worst[3] = {0.0, 0.0, 0.0};
      std::ostringstream times;
      times.precision(4);
      std::vector<unsigned char> given;
      int done = 0;
      for (const int step : at) {
        for (; done < step; ++done) sim.step();
        times << (step == at.front() ? "" : ", ") << sim.time();
        const Simulation::FormulationBlocks f = sim.formulation_blocks();
        if (f.given.empty())
          return kPassed + std::string("no tangent op: the host differences every column");
        given = f.given;
        std::string failure = compare_formulation_blocks(f, sim.time(), worst);
        if (!failure.empty()) return failure;
      }
      std::ostringstream detail;
      detail.precision(3);
      detail << std::count(given.begin(), given.end(), 1) << " of " << given.size()
             << " columns given, at t = " << times.str()
             << " s; worst entry off by (of its scale) dr/dx " << worst[0] << ", dr/dxd "
             << worst[1] << ", dr/dxdd " << worst[2];
      return kPassed + detail.str();
    });
    const bool passed = verdict.rfind(kPassed, 0) == 0;
    report("its tangent blocks against differences of its residual in x, xd, xdd",
           passed ? "" : verdict, passed ? verdict.substr(std::strlen(kPassed)) : "");
  }
  // A subsystem's own derivative blocks, each in its own units, at several
  // instants: a 1 % error of one entry can hide in the assembled tangent's
  // sums (dR/dy + (2/h) dR/dydot, instances sharing a node).
  if (who.kind == ComponentKind::subsystem && method != "explicit") {
    constexpr const char* kPassed = "passed: ";
    const std::string verdict = isolated([&] {
      std::string detail;
      const std::string failure = subsystem_blocks_check(*setup, who, registry, detail);
      return failure.empty() ? kPassed + detail : failure;
    });
    const std::string what = "its derivative blocks against differences of its evaluate";
    if (verdict.rfind(kNoBlocks, 0) == 0)
      emit(Check{Check::Verdict::skipped, name + ": " + what,
                 verdict.substr(std::strlen(kNoBlocks))});
    else if (verdict.rfind(kPassed, 0) == 0)
      report(what, "", verdict.substr(std::strlen(kPassed)));
    else
      report(what, verdict);
  }
  report("repeated runs bit-identical", isolated([&] {
           const std::string a = fingerprint(*setup, registry);
           const std::string b = fingerprint(*setup, registry);
           return a == b ? std::string() : std::string("two runs of the same model differ");
         }));
  // Parameters changed in place (parameters.h): subsystems only; one
  // without any has no line.
  if (who.kind == ComponentKind::subsystem) {
    constexpr const char* kPassed = "passed: ";
    const std::string verdict = isolated([&] {
      try {
        std::string detail;
        const std::string failure = parameters_check(*setup, who, registry, detail);
        return failure.empty() ? kPassed + detail : failure;
      } catch (const RunStateError& err) {
        return std::string(kNoSnapshot) + err.what();
      }
    });
    const std::string what = "options changed in place match the same options read at setup";
    if (verdict.rfind(kNoSnapshot, 0) == 0)
      emit(Check{Check::Verdict::skipped, name + ": " + what,
                 "the run's snapshot is needed: " + verdict.substr(std::strlen(kNoSnapshot))});
    else if (verdict.rfind(kPassed, 0) == 0)
      report(what, "", verdict.substr(std::strlen(kPassed)));
    else if (verdict.rfind(kNoParameters, 0) != 0)
      report(what, verdict);
  }
  // What a snapshot needs (state.h): a component that keeps state between
  // steps and offers no MH_EXT_STATE is skipped with the reason, one whose
  // saved bytes miss some of it fails.
  const std::string restored = isolated([&] { return state_check(*setup, registry); });
  const std::string state_what = "a snapshot restored into a fresh run repeats its steps";
  if (restored.rfind(kNoState, 0) == 0)
    emit(Check{Check::Verdict::skipped, name + ": " + state_what,
               restored.substr(std::strlen(kNoState))});
  else
    report(state_what, restored);
}

}  // namespace mh::testhost
