// One open run behind the C API (simulation.h): the model file, its
// plugins and the simulation, which refers to both for as long as it lives,
// the value table fixed at open, the row layout, and what the last call
// said. Everything a call needs is made at open: a step looks nothing up.
#pragma once

#include <memory>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/run_state.hpp"
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

// What a setting chooses as the command line's flags do; the rest are
// paths into the model's tree.
struct OpenRequest {
  std::string path;                   // the model file ("" when from text)
  std::string text, label, base_dir;  // the model's text, when not from a file
  std::vector<std::pair<std::string, std::string>> settings;
};

class Instance {
 public:
  // Throws InputError, PluginError or std::exception naming what is wrong.
  explicit Instance(const OpenRequest& request);
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  Simulation& sim() { return *sim_; }
  const Simulation& sim() const { return *sim_; }
  const std::vector<Variable>& variables() const { return variables_; }
  int find(const std::string& name) const;  // -1 when absent
  double value(const Variable& v) const;
  const CsvLayout& layout() const { return *layout_; }
  // The row's text (the header when `header`), in a buffer reused call to call.
  const std::string& row_text(bool header) const;

  // A value of the model changed in place, before start or between steps
  // (mhs_set_parameter): a body's mass, centre of mass or inertia, or
  // gravity, by its path as settings address it ("bodies/body3/mass",
  // "bodies/body3/com/0", "gravity/1"), the value as the model file would
  // write it (in its units). The model file's parser reads the changed text,
  // so a value is checked and derived (an inertia from a shape) as when
  // opening. Throws std::invalid_argument naming the path; nothing changes.
  void set_parameter(const std::string& path, const std::string& value);

  // Forward sensitivities (mhs_track_sensitivities) with respect to the
  // values at `paths`, before start; std::invalid_argument naming what is
  // refused. Then d(v)/d(parameter j) at the accepted state (NaN for a value
  // without one).
  void track_sensitivities(const std::vector<std::string>& paths);
  int num_sensitivities() const { return sim_->num_sensitivities(); }
  double sensitivity(const Variable& v, int j) const;

  // A parameter by its path, as sensitivities and filters take it;
  // std::invalid_argument naming the path.
  ParameterDirection parameter(const std::string& path) const;
  const ModelFile& file() const { return file_; }
  // The model's name in messages: its file's path, or the text's label.
  const std::string& label() const { return label_; }

  // Warnings the plugins logged during the current call (cleared by each call).
  std::string warnings;

 private:
  void make_variables();

  std::string text_;  // the model's text with every setting so far
  std::string label_, base_dir_;

  ModelFile file_;
  PluginRegistry registry_;
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<CsvLayout> layout_;
  std::vector<Variable> variables_;
  std::unordered_map<std::string, int> by_name_;
  mutable std::ostringstream row_stream_;
  mutable std::string row_;
};

}  // namespace mh::embed
