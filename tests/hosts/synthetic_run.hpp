// Run records made by hand, to test what is computed from them without a
// simulation: the columns a formulation's run would have, filled by formulas.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "run_record.hpp"

namespace mh::test {

struct SyntheticColumn {
  std::string name;
  std::string unit;
  std::function<double(size_t row, double t)> value;
  VariableInfo info = {};  // kind, role and range as a component would declare them
};

// Columns t, z1..zN (rad), `states`, `outputs`, KE, PE, W, drift, phi_norm,
// iters, wall_s over `rows` rows of `dt`; energies and the rest from the
// given functions (zero when empty).
struct SyntheticRun {
  std::string formulation = "synthetic";
  std::string integrator = "trapezoidal";
  size_t rows = 11;
  double dt = 0.1;
  std::vector<std::function<double(size_t, double)>> z;
  std::vector<SyntheticColumn> states;
  std::vector<SyntheticColumn> outputs;
  std::function<double(size_t, double)> KE, PE, W, drift, phi, iters, wall;

  cli::RunRecord make() const {
    cli::RunRecord r;
    r.formulation = formulation;
    r.integrator = integrator;
    r.label = formulation;
    r.dt = dt;
    r.t_end = dt * static_cast<double>(rows - 1);
    auto add = [&](const std::string& name, const std::string& unit,
                   const std::function<double(size_t, double)>& f,
                   VariableInfo info = VariableInfo{}) {
      r.names.push_back(name);
      r.units.push_back(unit);
      if (info.qualified.empty()) info.qualified = name;
      info.name = name;
      info.unit = unit;
      r.info.push_back(info);
      std::vector<double> v;
      for (size_t k = 0; k < rows; ++k) v.push_back(f ? f(k, dt * static_cast<double>(k)) : 0.0);
      r.columns.push_back(v);
    };
    add("t", "s", [](size_t, double t) { return t; });
    for (size_t j = 0; j < z.size(); ++j) add("z" + std::to_string(j + 1), "rad", z[j]);
    r.num_coordinates = static_cast<int>(z.size());
    for (const auto& s : states) add(s.name, s.unit, s.value, s.info);
    r.num_states = static_cast<int>(states.size());
    for (const auto& o : outputs) add(o.name, o.unit, o.value, o.info);
    add("KE", "J", KE);
    add("PE", "J", PE);
    add("W", "J", W);
    add("drift", "J", drift);
    add("phi_norm", "", phi);
    add("iters", "", iters);
    add(cli::kWallColumn, "s", wall);
    return r;
  }
};

}  // namespace mh::test
