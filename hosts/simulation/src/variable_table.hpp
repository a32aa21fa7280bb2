// The values of a run as the API numbers them (simulation.h): coordinates,
// their rates, the states, the outputs, then the inputs. Fixed once the
// model is open and the same for every run of one model, so a batch keeps
// one table for all its runs.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "monohydra/core/model.hpp"
#include "monohydra/core/simulation.hpp"
#include "monohydra/simulation.h"

namespace mh::embed {

// A value of the run as the API numbers it.
struct Variable {
  mhs_kind kind;
  int index;  // into z, zd, states or outputs
  std::string name, qualified, unit;
  double min = 1.0, max = 0.0;  // min > max: no range declared
};

class VariableTable {
 public:
  VariableTable(const Simulation& sim, const Model& model);
  const std::vector<Variable>& list() const { return variables_; }
  int find(const std::string& name) const;  // by name or qualified name; -1 when absent

 private:
  std::vector<Variable> variables_;
  std::unordered_map<std::string, int> by_name_;
};

// Its value in `sim` at the last accepted state.
double value(const Simulation& sim, const Variable& v);

}  // namespace mh::embed
