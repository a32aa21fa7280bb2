// The test host's public API (monohydra/testhost.hpp) on the engine: loading,
// the model a component is checked on, runs as time series and the tangent
// comparison. The checks themselves are contract_checks.cpp.
#include "monohydra/testhost.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "build_tree.hpp"
#include "contract_checks.hpp"
#include "isolated_check.hpp"
#include "monohydra/core/input_error.hpp"

namespace fs = std::filesystem;

namespace monohydra::testhost {
namespace {

using mh::ComponentKind;
using mh::ModelFile;
using mh::PluginRegistry;
using mh::testhost::Setup;
using mh::testhost::Subject;

Kind kind_of(ComponentKind k) {
  switch (k) {
    case ComponentKind::formulation:
      return Kind::formulation;
    case ComponentKind::subsystem:
      return Kind::subsystem;
    case ComponentKind::integrator:
      break;
  }
  return Kind::integrator;
}

// The folder this library was loaded from: plugins and models installed
// beside it are found from there, whatever the program that loaded it.
fs::path own_folder() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&check_library), &info) == 0 || info.dli_fname == nullptr)
    return {};
  std::error_code ec;
  const fs::path self = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path() : self.parent_path();
}

std::vector<std::string> default_search_path() {
  std::vector<std::string> path = PluginRegistry::default_search_path();
  const fs::path here = own_folder();
  if (!here.empty()) {
    const fs::path beside = here / "monohydra" / "plugins";
    // After $MONOHYDRA_PLUGIN_PATH, before the executable's and the prefix's.
    size_t env = 0;
    if (const char* e = std::getenv("MONOHYDRA_PLUGIN_PATH"); e != nullptr) {
      std::stringstream ss(e);
      std::string item;
      while (std::getline(ss, item, ':')) env += item.empty() ? 0 : 1;
    }
    path.insert(path.begin() + static_cast<std::ptrdiff_t>(std::min(env, path.size())),
                beside.string());
  }
  return path;
}

std::vector<std::string> models_folders() {
  std::vector<std::string> out;
  const fs::path here = own_folder();
  if (!here.empty())
    out.push_back((here / ".." / "share" / "monohydra" / "models").lexically_normal());
  out.emplace_back(MONOHYDRA_INSTALL_MODELS);
  out.emplace_back(build_tree::source_models);
  return out;
}

// The first folder holding the four-bar: the shipped models.
fs::path shipped_models() {
  std::error_code ec;
  for (const auto& dir : models_folders())
    if (fs::exists(fs::path(dir) / "fourbar.yaml", ec)) return dir;
  return {};
}

// Default fallbacks: the four-bar and the double pendulum for formulations
// and integrators (a closed loop with hydraulics first, then a tree for a
// formulation that handles trees only), every model of the folder smallest
// first for subsystems.
std::vector<std::string> fallback_models(const CheckOptions& options, ComponentKind kind) {
  const fs::path dir =
      options.models_folder.empty() ? shipped_models() : fs::path(options.models_folder);
  if (kind != ComponentKind::subsystem) {
    if (!options.fallback_models.empty()) return options.fallback_models;
    if (dir.empty()) return {};
    return {(dir / "fourbar.yaml").string(), (dir / "double-pendulum.yaml").string()};
  }
  if (dir.empty()) return {};
  std::vector<std::pair<std::uintmax_t, std::string>> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".yaml") found.emplace_back(e.file_size(ec), e.path().string());
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  out.reserve(found.size());
  for (const auto& f : found) out.push_back(f.second);
  return out;
}

// Reads the test's model. Throws mh::InputError.
ModelFile read_model(const Model& model) {
  if (!model.yaml.empty())
    return mh::parse_model_text(model.yaml, model.label.empty() ? "<test model>" : model.label);
  return mh::load_model_file(model.path);
}

// The model's plugins: its plugins: map (each chosen for its id), its
// plugin_paths, then the search path, as `monohydra run` loads them.
void load_model_plugins(const ModelFile& file, PluginRegistry& registry,
                        const std::vector<std::string>& search) {
  for (const auto& [id, library] : file.plugin_libraries) {
    try {
      registry.load(library);
    } catch (const mh::PluginError& err) {
      throw mh::InputError(mh::SourceMark{file.path, 0, 0}, "plugins." + id, err.what());
    }
    registry.choose(id, library);
  }
  std::vector<std::string> folders = file.plugin_paths;
  folders.insert(folders.end(), search.begin(), search.end());
  registry.scan(folders);
}

// The component's declared example model, "" when it declares none. The
// three factories have one shape (ABI 3), so one walk serves them all.
template <class Factory>
std::string example_in(const Factory& f, const void* raw, const std::string& id) {
  if (f.example_model == nullptr || f.count == nullptr || f.descriptor == nullptr) return "";
  const auto* plugin = static_cast<const Factory*>(raw);
  const uint32_t n = f.count(plugin);
  for (uint32_t i = 0; i < n; ++i) {
    const mh_component_descriptor* d = f.descriptor(plugin, i);
    if (d == nullptr || d->id == nullptr || id != d->id) continue;
    const char* text = f.example_model(plugin, i);
    return text != nullptr ? text : "";
  }
  return "";
}

std::string example_model_of(const mh::ComponentInfo& c) {
  switch (c.kind) {
    case ComponentKind::subsystem:
      return example_in(c.subsystem_factory, c.factory, c.id);
    case ComponentKind::formulation:
      return example_in(c.formulation_factory, c.factory, c.id);
    default:
      return example_in(c.integrator_factory, c.factory, c.id);
  }
}

std::string text_or_empty(const char* s) {
  return s != nullptr ? s : "";
}

// The label an example model is named by in errors.
std::string example_label(const Subject& who, const std::string& library) {
  return "the example model of " + std::string(mh::to_string(who.kind)) + " '" + who.id +
         "' (declared by " + fs::path(library).filename().string() + ")";
}

}  // namespace

const char* to_string(Kind kind) {
  switch (kind) {
    case Kind::formulation:
      return "formulation";
    case Kind::subsystem:
      return "subsystem";
    case Kind::integrator:
      break;
  }
  return "integrator";
}

std::vector<double> Series::column(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) throw std::out_of_range("the run has no column '" + name + "'");
  const auto j = static_cast<size_t>(it - names.begin());
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(row[j]);
  return out;
}

bool Series::has(const std::string& name) const {
  return std::find(names.begin(), names.end(), name) != names.end();
}

CheckReport check_library(const std::string& library, const Model* model,
                          const CheckOptions& options) {
  CheckReport out;
  const auto emit = [&](const Check& c) {
    out.checks.push_back(c);
    if (options.on_check) options.on_check(c);
  };
  // Loading: probed in a child first, then the version, the entry and init.
  PluginRegistry registry;
  try {
    registry.load(library);
  } catch (const mh::PluginError& err) {
    emit({Check::Verdict::failed, "load", err.what()});
    return out;
  }
  std::vector<Subject> subjects;
  std::string canonical;
  for (const auto& c : registry.components()) {
    canonical = c.library;
    subjects.push_back({c.kind, c.id});
  }
  if (subjects.empty()) {
    emit({Check::Verdict::failed, "components",
          "the library offers none (every factory's count is 0 or its factories are missing)"});
    return out;
  }
  out.loaded = true;
  {
    const mh_version v = registry.components().front().abi_version;
    emit({Check::Verdict::passed, "load",
          "ABI " + std::to_string(v.major) + "." + std::to_string(v.minor) + "." +
              std::to_string(v.patch) + " on host ABI " + std::to_string(MH_ABI_VERSION_MAJOR) +
              "." + std::to_string(MH_ABI_VERSION_MINOR) +
              "; its structs read up to their struct_size"});
  }
  for (const auto& c : registry.components()) {
    const mh_component_descriptor* d = c.descriptor;
    std::string bad;
    if (d->struct_size < sizeof(uint32_t) + 5 * sizeof(const char*))
      bad = "descriptor struct_size " + std::to_string(d->struct_size) + " is too small";
    else if (d->name == nullptr || d->version == nullptr || d->version[0] == '\0')
      bad = "descriptor without a name or a version";
    emit({bad.empty() ? Check::Verdict::passed : Check::Verdict::failed,
          std::string(mh::to_string(c.kind)) + " " + c.id + ": descriptor",
          bad.empty() ? std::string("v") + d->version : bad});
  }

  // The rest of the model (other components) from the search path; this
  // library's components win over any other library offering their ids.
  for (const auto& who : subjects) registry.choose(who.id, canonical);
  const std::vector<std::string> search =
      options.search_path.empty() ? default_search_path() : options.search_path;
  std::optional<ModelFile> given;
  if (model != nullptr) {
    try {
      given = read_model(*model);
      load_model_plugins(*given, registry, search);
    } catch (const std::exception& err) {
      out.bad_model = true;
      emit({Check::Verdict::failed, "model", err.what()});
      return out;
    }
  } else {
    registry.scan(search);
  }

  const fs::path library_dir = fs::path(canonical).parent_path();
  for (const auto& who : subjects) {
    const std::string name = std::string(mh::to_string(who.kind)) + " " + who.id;
    std::vector<Setup> setups;
    std::string why;
    if (given) {
      if (mh::testhost::model_uses(*given, who))
        setups.push_back(mh::testhost::setup_for(*given, who));
      else
        why = "'" + given->path + "' does not use it";
    } else {
      const std::string example = example_model_of(registry.find(who.kind, who.id));
      if (!example.empty()) {
        // The component's own example: it must read and use it.
        const std::string label = example_label(who, canonical);
        try {
          const ModelFile file = mh::parse_model_text(example, label, library_dir.string());
          if (mh::testhost::model_uses(file, who))
            setups.push_back(mh::testhost::setup_for(file, who));
          else
            emit({Check::Verdict::failed, name + ": declared example model",
                  label + " does not use it (no subsystem of type '" + who.id + "')"});
        } catch (const std::exception& err) {
          emit({Check::Verdict::failed, name + ": declared example model", err.what()});
        }
        if (setups.empty()) continue;
      } else {
        for (const auto& path : fallback_models(options, who.kind)) {
          try {
            const ModelFile file = mh::load_model_file(path);
            if (!mh::testhost::model_uses(file, who)) continue;
            setups.push_back(mh::testhost::setup_for(file, who));
          } catch (const mh::InputError&) {
            continue;
          }
          // Subsystems: the smallest model that uses it is enough.
          if (who.kind == ComponentKind::subsystem) break;
        }
        if (setups.empty())
          why = who.kind == ComponentKind::subsystem
                    ? "no shipped model uses it and it declares no example model "
                      "(mh_subsystem_factory.example_model): give a model that does "
                      "(monohydra check PLUGIN.so MODEL.yaml)"
                    : "no shipped model was found and it declares no example model";
      }
    }
    if (setups.empty()) {
      emit({Check::Verdict::skipped, name, why});
      continue;
    }
    for (Setup& s : setups) {
      mh::testhost::shorten(s, mh::testhost::kSteps);
      s.block_times = options.at;
    }
    mh::testhost::check_subject(who, setups, registry, emit);
  }
  return out;
}

std::vector<std::string> component_ids(const std::string& library, Kind kind) {
  PluginRegistry registry;
  try {
    registry.load(library);
  } catch (const mh::PluginError& err) {
    throw std::runtime_error(err.what());
  }
  std::vector<std::string> ids;
  for (const auto& c : registry.components())
    if (kind_of(c.kind) == kind) ids.push_back(c.id);
  return ids;
}

struct Host::Impl {
  PluginRegistry registry;
  Subject subject;
  std::string library;
  std::vector<std::string> search;
  std::string version, example;

  // The test's model with this component in it, its plugins loaded.
  Setup setup(const Model& model) {
    const ModelFile file = read_model(model);
    if (!mh::testhost::model_uses(file, subject))
      throw std::runtime_error("the model " + file.path + " does not use subsystem '" + subject.id +
                               "'");
    load_model_plugins(file, registry, search);
    return mh::testhost::setup_for(file, subject);
  }
};

Host::Host(const std::string& library, const std::string& id, std::vector<std::string> search_path)
    : impl_(std::make_unique<Impl>()) {
  try {
    impl_->registry.load(library);
  } catch (const mh::PluginError& err) {
    throw std::runtime_error(err.what());
  }
  for (const auto& c : impl_->registry.components()) {
    if (c.id != id) continue;
    impl_->subject = {c.kind, c.id};
    impl_->library = c.library;
    impl_->version = text_or_empty(c.descriptor->version);
    impl_->example = example_model_of(c);
  }
  if (impl_->library.empty())
    throw std::runtime_error("'" + library + "' offers no component '" + id + "'");
  // It wins over any other library offering the same id.
  impl_->registry.choose(id, impl_->library);
  impl_->search = search_path.empty() ? default_search_path() : std::move(search_path);
}

Host::~Host() = default;

Kind Host::kind() const {
  return kind_of(impl_->subject.kind);
}
const std::string& Host::id() const {
  return impl_->subject.id;
}
std::string Host::version() const {
  return impl_->version;
}
std::string Host::example_model() const {
  return impl_->example;
}

std::string Host::create_destroy(const Model& model, int cycles) const {
  Setup s = impl_->setup(model);
  mh::testhost::shorten(s, 1);
  return mh::testhost::isolated([&] {
    for (int i = 0; i < cycles; ++i) {
      try {
        mh::Simulation sim(s.file, impl_->registry, s.choices);
        sim.start();
      } catch (const std::exception& err) {
        return std::string("cycle ") + std::to_string(i + 1) + ": " + err.what();
      }
    }
    return std::string();
  });
}

Series Host::run(const Model& model, int steps, double dt) const {
  Setup s = impl_->setup(model);
  if (dt > 0.0) s.choices.dt = dt;
  mh::testhost::shorten(s, steps);
  Series out;
  std::optional<mh::Simulation> sim;
  try {
    sim.emplace(s.file, impl_->registry, s.choices);
    sim->start();
  } catch (const std::exception& err) {
    out.status = std::string("setup failed: ") + err.what();
    return out;
  }
  for (const auto& n : sim->coordinate_names()) {
    out.names.push_back(n);
    out.units.emplace_back("");
  }
  for (const auto& n : sim->coordinate_names()) {
    out.names.push_back(n + "_dot");
    out.units.emplace_back("");
  }
  for (const auto& v : sim->state_info()) {
    out.names.push_back(v.qualified);
    out.units.push_back(v.unit);
  }
  for (const auto& v : sim->output_info()) {
    out.names.push_back(v.qualified);
    out.units.push_back(v.unit);
  }
  for (const char* n : {"kinetic_energy", "potential_energy", "stored_energy", "dissipated_energy",
                        "work", "drift"}) {
    out.names.emplace_back(n);
    out.units.emplace_back("J");
  }
  out.names.emplace_back("phi_norm");
  out.units.emplace_back("");
  const auto record = [&] {
    std::vector<double> row;
    row.reserve(out.names.size());
    for (const Eigen::VectorXd* v : {&sim->z(), &sim->zd(), &sim->states(), &sim->outputs()})
      row.insert(row.end(), v->data(), v->data() + v->size());
    for (double e : {sim->kinetic_energy(), sim->potential_energy(), sim->stored_energy(),
                     sim->dissipated_energy(), sim->work(), sim->drift(), sim->phi_norm()})
      row.push_back(e);
    out.time.push_back(sim->time());
    out.rows.push_back(std::move(row));
  };
  record();
  try {
    for (int k = 0; k < steps; ++k) {
      sim->step();
      record();
    }
  } catch (const mh::SimulationError& err) {
    std::ostringstream msg;
    msg << "FAILED at t = " << err.time() << " s, step " << err.step() << ": " << err.reason();
    out.status = msg.str();
    return out;
  } catch (const std::exception& err) {
    out.status = std::string("FAILED: ") + err.what();
    return out;
  }
  out.ok = true;
  out.status = "ok";
  return out;
}

TangentComparison Host::tangent(const Model& model, int steps_before) const {
  Setup s = impl_->setup(model);
  mh::testhost::shorten(s, steps_before + 1);
  TangentComparison out;
  out.tolerance = mh::testhost::kTangentTolerance;
  try {
    mh::Simulation sim(s.file, impl_->registry, s.choices);
    sim.start();
    for (int i = 0; i < steps_before; ++i) sim.step();
    return mh::testhost::compare_tangent(sim);
  } catch (const std::exception& err) {
    out.failure = err.what();
  }
  return out;
}

CheckReport Host::check(const Model& model) const {
  CheckReport out;
  out.loaded = true;
  Setup s;
  try {
    s = impl_->setup(model);
  } catch (const std::exception& err) {
    out.bad_model = true;
    out.checks.push_back({Check::Verdict::failed, "model", err.what()});
    return out;
  }
  mh::testhost::shorten(s, mh::testhost::kSteps);
  mh::testhost::check_subject(impl_->subject, {s}, impl_->registry,
                              [&](const Check& c) { out.checks.push_back(c); });
  return out;
}

namespace {

using mh::Simulation;

// Host::planted_errors' account: each entry of each block planted in, in
// turn, at each instant; seen when its block then failed the comparison,
// judgeable where a 1 % error is above the differences' own error.
class PlantedAccount {
 public:
  // Every entry of `t` (its `given` columns; null: all) whose effect on its
  // row is above the comparison's floor (not a rounding residue of a
  // structural zero: 1e-16 where a double pendulum's Coriolis term has no
  // d/dzd_2, whose 1 % nobody could see). `planted(e)`: the block's analytic
  // matrix with entry e's error planted through the op; `fails()`: whether
  // the comparison fails with it in place of t's own.
  template <class Planted, class Fails>
  void plant(Simulation::TangentSample& t, const std::vector<unsigned char>* given,
             const Eigen::VectorXd& effect, const std::string& block,
             const std::vector<std::string>* rows, const std::vector<std::string>* columns,
             Planted&& planted, Fails&& fails) {
    const Eigen::MatrixXd analytic = t.analytic;
    for (Eigen::Index e = 0; e < analytic.size(); ++e) {
      const Eigen::Index r = e % analytic.rows(), c = e / analytic.rows();
      if (given != nullptr && (*given)[static_cast<size_t>(c)] == 0) continue;
      if (!(std::abs(analytic(r, c)) * t.column_scale[c] > mh::testhost::kBlockFloor * effect[r]))
        continue;
      const auto named = [](const std::vector<std::string>* names, Eigen::Index i) {
        return names != nullptr ? (*names)[static_cast<size_t>(i)] : std::to_string(i + 1);
      };
      Seen& k = seen_[block + ": row " + named(rows, r) + ", column " + named(columns, c)];
      t.analytic = planted(e);
      k.seen = k.seen || fails();
      t.analytic = analytic;
      k.judged = k.judged || mh::testhost::shows_one_percent(t, r, c, effect[r]);
    }
  }
  PlantedErrors result() const {
    PlantedErrors out;
    out.planted = static_cast<int>(seen_.size());
    for (const auto& [key, k] : seen_)
      if (!k.seen) (k.judged ? out.missed : out.too_noisy).push_back(key);
    return out;
  }

 private:
  struct Seen {
    bool seen = false, judged = false;
  };
  std::map<std::string, Seen> seen_;  // by entry, in order
};

// The run of `s` to each instant of its blocks' comparison, `at_instant`
// called there; the run's failure or "".
template <class AtInstant>
std::string each_instant(Setup& s, const PluginRegistry& registry, AtInstant&& at_instant) {
  const std::vector<int> at = mh::testhost::block_instants(s);
  s.choices.t_end = (at.back() + 1) * s.choices.dt.value_or(s.file.solver.dt);
  s.file.output = mh::OutputSettings{};
  try {
    Simulation sim(s.file, registry, s.choices);
    sim.start();
    int done = 0;
    for (const int step : at) {
      for (; done < step; ++done) sim.step();
      std::string failure = at_instant(sim);
      if (!failure.empty()) return failure;
    }
  } catch (const std::exception& err) {
    return err.what();
  }
  return "";
}

}  // namespace

PlantedErrors Host::planted_errors(const Model& model, double factor) const {
  if (impl_->subject.kind == ComponentKind::integrator) {
    PlantedErrors out;
    out.failure =
        "planted errors are of a subsystem's derivative blocks or a formulation's "
        "tangent blocks; '" +
        impl_->subject.id + "' is an integrator";
    return out;
  }
  Setup s = impl_->setup(model);
  PlantedAccount account;
  std::string failure;
  if (impl_->subject.kind == ComponentKind::formulation) {
    // Its tangent blocks dr/dx, dr/dxd, dr/dxdd in the columns it gives.
    failure = each_instant(s, impl_->registry, [&](Simulation& sim) -> std::string {
      Simulation::FormulationBlocks f = sim.formulation_blocks();
      const Eigen::VectorXd across = mh::testhost::formulation_effect(f);
      double worst[3] = {0.0, 0.0, 0.0};
      std::string unplanted = mh::testhost::compare_formulation_blocks(f, sim.time(), worst);
      if (!unplanted.empty()) return "unplanted: " + unplanted;
      for (int b = 0; b < 3; ++b) {
        const char* block = mh::Simulation::FormulationBlocks::kNames[b];
        account.plant(
            f.block[b], &f.given, mh::testhost::judged_effect(f.block[b], across), block, nullptr,
            nullptr,
            [&](Eigen::Index e) {
              sim.plant_derivative_error("", block, static_cast<long>(e), factor);
              Eigen::MatrixXd a = sim.formulation_blocks(false).block[b].analytic;
              sim.plant_derivative_error("", block, static_cast<long>(e), 1.0);
              return a;
            },
            [&] {
              return !mh::testhost::compare_formulation_blocks(f, sim.time(), worst).empty();
            });
      }
      return "";
    });
  } else {
    // Each instance's derivative blocks, as its ops give them.
    std::vector<std::string> instances;
    for (const mh::SubsystemSpec& spec : s.file.subsystems)
      if (spec.type == impl_->subject.id) instances.push_back(spec.name);
    failure = each_instant(s, impl_->registry, [&](Simulation& sim) -> std::string {
      for (const std::string& instance : instances) {
        std::vector<Simulation::DerivativeBlock> blocks = sim.subsystem_blocks(instance);
        const mh::testhost::Effects effects = mh::testhost::block_effects(blocks);
        const auto fails = [&] {
          return !mh::testhost::compare_subsystem_blocks(blocks, instance, sim.time())
                      .failure.empty();
        };
        if (fails())
          return "unplanted: " +
                 mh::testhost::compare_subsystem_blocks(blocks, instance, sim.time()).failure;
        for (Simulation::DerivativeBlock& b : blocks) {
          if (!b.given) continue;
          account.plant(
              b.sample, nullptr, mh::testhost::judged_effect(b.sample, effects.of(b)),
              b.name + " of subsystem '" + instance + "'", &b.rows, &b.columns,
              [&](Eigen::Index e) {
                sim.plant_derivative_error(instance, b.name, static_cast<long>(e), factor);
                Eigen::MatrixXd a;
                for (const auto& again : sim.subsystem_blocks(instance, false))
                  if (again.name == b.name) a = again.sample.analytic;
                sim.plant_derivative_error(instance, b.name, static_cast<long>(e), 1.0);
                return a;
              },
              fails);
        }
      }
      return "";
    });
  }
  PlantedErrors out = account.result();
  out.failure = failure;
  return out;
}

}  // namespace monohydra::testhost
