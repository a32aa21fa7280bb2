// One open run behind the C API (simulation.h): the opened model (its file
// and plugins, which the simulation refers to for as long as it lives), the
// run's own changes to it, the value table fixed at open, the row layout,
// and what the last call said. Everything a call needs is made at open: a
// step looks nothing up.
#pragma once

#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "opened_model.hpp"
#include "variable_table.hpp"

namespace mh::embed {

// What a run's plugins warned of during one call: the call's MHS_WARNING.
LogSink warnings_into(std::string& warnings);

class Instance {
 public:
  // Throws InputError, PluginError or std::exception naming what is wrong.
  explicit Instance(const OpenRequest& request);
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  Simulation& sim() { return *sim_; }
  const Simulation& sim() const { return *sim_; }
  const std::vector<Variable>& variables() const { return variables_->list(); }
  int find(const std::string& name) const { return variables_->find(name); }
  double value(const Variable& v) const { return embed::value(*sim_, v); }
  const CsvLayout& layout() const { return *layout_; }
  // The row's text (the header when `header`), in a buffer reused call to call.
  const std::string& row_text(bool header) const;

  // A value of the model changed in place (opened_model.hpp's set_parameter).
  void set_parameter(const std::string& path, const std::string& value) {
    embed::set_parameter(*sim_, *opened_, changed_, path, value);
  }

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
  const ModelFile& file() const { return opened_->file; }
  // The model's name in messages: its file's path, or the text's label.
  const std::string& label() const { return opened_->label; }

  // Warnings the plugins logged during the current call (cleared by each call).
  std::string warnings;

 private:
  std::unique_ptr<const OpenedModel> opened_;
  ChangedModel changed_;
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<CsvLayout> layout_;
  std::unique_ptr<VariableTable> variables_;
  mutable std::ostringstream row_stream_;
  mutable std::string row_;
};

}  // namespace mh::embed
