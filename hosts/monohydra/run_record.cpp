#include "run_record.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <exception>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/run.hpp"
#include "monohydra/core/run_limits.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "monohydra/host.h"

namespace mh::cli {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The columns of `sim` and their units, in the order a run's CSV (CsvLayout) writes them.
void name_columns(const ModelFile& file, const Simulation& sim, RunRecord& rec) {
  auto add = [&rec](const std::string& name, const std::string& unit,
                    const VariableInfo& info = {}) {
    rec.names.push_back(name);
    rec.units.push_back(unit);
    rec.info.push_back(info);
  };
  add("t", "s");
  const auto& coordinates = sim.coordinate_names();
  for (size_t j = 0; j < coordinates.size(); ++j)
    add(coordinates[j], file.model.bodies[j].joint == JointType::revolute ? "rad" : "m");
  rec.num_coordinates = static_cast<int>(coordinates.size());
  for (const auto& v : sim.state_info()) {
    if (v.name.empty()) continue;
    add(v.name, v.unit, v);
    ++rec.num_states;
  }
  for (const auto& v : sim.output_info())
    if (!v.name.empty()) add(v.name, v.unit, v);
  for (const char* energy : {"KE", "PE", "W", "drift"}) add(energy, "J");
  add("phi_norm", "");
  add("iters", "");
  add(kWallColumn, "s");
  rec.columns.assign(rec.names.size(), {});
}

void record_row(const Simulation& sim, double wall_seconds, RunRecord& rec) {
  size_t c = 0;
  auto push = [&rec, &c](double v) { rec.columns[c++].push_back(v); };
  push(sim.time());
  for (int i = 0; i < sim.z().size(); ++i) push(sim.z()[i]);
  for (int i = 0; i < sim.states().size(); ++i)
    if (!sim.state_names()[static_cast<size_t>(i)].empty()) push(sim.states()[i]);
  for (int i = 0; i < sim.outputs().size(); ++i)
    if (!sim.output_names()[static_cast<size_t>(i)].empty()) push(sim.outputs()[i]);
  for (double v :
       {sim.kinetic_energy(), sim.potential_energy(), sim.work(), sim.drift(), sim.phi_norm()})
    push(v);
  push(static_cast<double>(sim.last_step().iterations));
  push(wall_seconds);
}

// `monohydra run`'s row (its output: columns) with the wall time appended.
void write_row(std::ostream& csv, std::ostringstream& line, const CsvLayout& layout,
               const Simulation& sim, double wall_seconds) {
  line.str("");
  layout.row(line, sim);
  std::string text = line.str();
  text.back() = ',';  // the row's '\n'
  char buf[32];
  text.append(buf, monohydra::write_exact_number(buf, wall_seconds));
  text += '\n';
  csv << text;
}

}  // namespace

int RunRecord::column(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

const std::vector<double>& RunRecord::values(const std::string& name) const {
  const int c = column(name);
  if (c < 0) throw std::out_of_range("no column '" + name + "' in the run " + label);
  return columns[static_cast<size_t>(c)];
}

RunRecord record_run(const ModelFile& file, const PluginRegistry& registry,
                     const std::string& formulation, const std::string& integrator,
                     const RecordOptions& options) {
  RunRecord rec;
  rec.formulation = formulation.empty() ? file.formulation.name : formulation;
  rec.integrator = integrator.empty() ? file.integrator.name : integrator;
  rec.label = rec.formulation;
  std::unique_ptr<Simulation> sim;
  try {
    // The settings are checked before any plugin reads them (the output's
    // size once the columns are known, below).
    const StepOverrides& o = options.overrides;
    check_run_settings(file, o.applied_to(file.solver), o.limits, 0, o.origins());
    sim = std::make_unique<Simulation>(
        file, registry,
        RunChoices{formulation, integrator, options.overrides.dt, options.overrides.t_end},
        options.log);
  } catch (const std::exception& err) {
    rec.failed = true;
    rec.failure = err.what();
    return rec;
  }
  rec.dt = sim->settings().dt;
  rec.t_end = sim->settings().t_end;
  name_columns(file, *sim, rec);
  long total = 0;
  std::unique_ptr<CsvLayout> layout;
  try {
    check_column_names(file, *sim);
    // The model file's output: rows every every_steps() steps and the CSV's
    // columns, as `run` writes them (the rows kept in memory keep every
    // column: the table is computed from them).
    layout = std::make_unique<CsvLayout>(*sim, file.output, std::nullopt);
    // Every row kept is in memory too: count it like a CSV.
    total = check_run_settings(file, sim->settings(), options.overrides.limits, rec.names.size(),
                               options.overrides.origins(), layout->every_steps());
  } catch (const InputError& err) {
    rec.failed = true;
    rec.failure = err.what();
    return rec;
  }

  std::ofstream csv;
  if (!options.csv_path.empty()) {
    csv.open(options.csv_path);
    if (!csv) {
      rec.failed = true;
      rec.failure = "cannot write '" + options.csv_path + "'";
      return rec;
    }
    rec.csv_path = options.csv_path;
  }
  std::ostringstream line;
  try {
    auto t0 = Clock::now();
    sim->start();
    double wall = seconds_since(t0);
    record_row(*sim, wall, rec);
    if (options.on_row) options.on_row(rec);
    if (csv.is_open()) {
      line.str("");
      layout->header(line);
      std::string header = line.str();
      header.pop_back();  // the header's '\n'
      csv << header << ',' << kWallColumn << '\n';
      write_row(csv, line, *layout, *sim, wall);
      csv.flush();
    }
    // The breakdown of the dissipated energy, outside the steps' wall time.
    rec.dissipators = sim->subsystem_names();
    rec.dissipated.assign(rec.dissipators.size(), 0.0);
    std::vector<double> power_k(rec.dissipators.size()), power(rec.dissipators.size());
    sim->dissipation_powers(power_k.data());
    std::vector<size_t> part_outputs;  // the outputs of role dissipation-part
    for (size_t i = 0; i < sim->output_info().size(); ++i)
      if (sim->output_info()[i].role == MH_ROLE_DISSIPATION_PART) {
        part_outputs.push_back(i);
        rec.dissipation_parts.push_back(sim->output_info()[i].qualified);
      }
    rec.parts_dissipated.assign(part_outputs.size(), 0.0);
    std::vector<double> part_k(part_outputs.size());
    for (size_t j = 0; j < part_outputs.size(); ++j)
      part_k[j] = sim->outputs()[static_cast<Eigen::Index>(part_outputs[j])];
    const long report_every = std::max(1L, total / 100);
    const long every = layout->every_steps();
    double wall_since_row = 0.0;  // the steps since the last row kept
    for (long k = 0; k < total; ++k) {
      if (options.stop != nullptr && *options.stop != 0) {
        rec.stopped_by = static_cast<int>(*options.stop);
        rec.failed = true;
        rec.failure = "interrupted at t = " + std::to_string(sim->time()) + " s, step " +
                      std::to_string(k) + " of " + std::to_string(total);
        rec.failure_time = sim->time();
        break;
      }
      const double t_k = sim->time();
      t0 = Clock::now();
      sim->step();
      wall_since_row += seconds_since(t0);
      sim->dissipation_powers(power.data());
      const double h = sim->time() - t_k;
      for (size_t i = 0; i < power.size(); ++i)
        rec.dissipated[i] += 0.5 * h * (power_k[i] + power[i]);
      power_k.swap(power);
      for (size_t j = 0; j < part_outputs.size(); ++j) {
        const double p = sim->outputs()[static_cast<Eigen::Index>(part_outputs[j])];
        rec.parts_dissipated[j] += 0.5 * h * (part_k[j] + p);
        part_k[j] = p;
      }
      if ((k + 1) % every == 0) {
        record_row(*sim, wall_since_row, rec);
        if (options.on_row) options.on_row(rec);
        if (csv.is_open()) {
          write_row(csv, line, *layout, *sim, wall_since_row);
          csv.flush();  // the rows before a crash stay on disk
          if (!csv) throw std::runtime_error("cannot write '" + options.csv_path + "'");
        }
        wall_since_row = 0.0;
      }
      if (options.progress && (k + 1) % report_every == 0)
        options.progress(static_cast<double>(k + 1) / static_cast<double>(total));
    }
    if (csv.is_open() && !csv.flush())
      throw std::runtime_error("cannot write '" + options.csv_path + "'");
    rec.stability = sim->explicit_stability();
  } catch (const SimulationError& err) {
    rec.stability = sim->explicit_stability();
    rec.failed = true;
    rec.failure = err.what();
    rec.failure_time = err.time();
  } catch (const std::exception& err) {  // e.g. the initial assembly
    rec.failed = true;
    rec.failure = err.what();
  }
  return rec;
}

}  // namespace mh::cli
