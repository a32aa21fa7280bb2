#include "instance.hpp"

#include <limits>
#include <optional>
#include <stdexcept>

#include "model_settings.hpp"
#include "monohydra/core/run_limits.hpp"
#include "parameter_direction.hpp"

namespace mh::embed {

LogSink warnings_into(std::string& warnings) {
  return [&warnings](mh_log_level level, const std::string& source, const std::string& text) {
    if (level < MH_LOG_WARNING) return;
    if (!warnings.empty()) warnings += '\n';
    warnings += source + ": " + text;
  };
}

Instance::Instance(const OpenRequest& request)
    : opened_(std::make_unique<const OpenedModel>(request)), changed_(*opened_) {
  sim_ = std::make_unique<Simulation>(opened_->file, opened_->registry, opened_->choices,
                                      warnings_into(warnings));
  layout_ = std::make_unique<CsvLayout>(*sim_, opened_->file.output, std::nullopt);
  check_column_names(opened_->file, *sim_);
  variables_ = std::make_unique<VariableTable>(*sim_, opened_->file.model);
}

ParameterDirection Instance::parameter(const std::string& path) const {
  return host::parameter_direction(changed_.text, opened_->label, opened_->base_dir, opened_->file,
                                   path);
}

void Instance::track_sensitivities(const std::vector<std::string>& paths) {
  std::vector<ParameterDirection> directions;
  directions.reserve(paths.size());
  for (const std::string& path : paths) directions.push_back(parameter(path));
  sim_->track_sensitivities(directions);
}

double Instance::sensitivity(const Variable& v, int j) const {
  switch (v.kind) {
    case MHS_COORDINATE:
      return sim_->coordinate_sensitivities()(v.index, j);
    case MHS_COORDINATE_RATE:
      return sim_->coordinate_rate_sensitivities()(v.index, j);
    case MHS_STATE:
      return sim_->state_sensitivities()(v.index, j);
    case MHS_OUTPUT:
      if (sim_->output_differentiated(v.index)) return sim_->output_sensitivities()(v.index, j);
      break;
    default:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

const std::string& Instance::row_text(bool header) const {
  row_stream_.str("");
  if (header)
    layout_->header(row_stream_);
  else
    layout_->row(row_stream_, *sim_);
  row_ = row_stream_.str();
  return row_;
}

}  // namespace mh::embed
