// output: the result columns a run writes and the interval of its rows. The
// names are checked against the run's columns once it is set up
// (csv_layout.cpp): they depend on the plugins.
#include "parser.hpp"

namespace mh::model_file_detail {

OutputSettings Parser::output(const YAML::Node& node) const {
  const MapView map(*this, node, "output", {"interval", "columns"});
  OutputSettings out;
  out.mark = mark(node);
  if (auto interval = map.get("interval")) {
    out.interval = positive(*interval, "output.interval");
    out.interval_mark = mark(*interval);
  }
  if (auto columns = map.get("columns")) {
    if (!columns->IsSequence() || columns->size() == 0)
      fail(*columns, "output.columns",
           "expected a non-empty list of result column names (e.g. [t, z1, KE]), got " +
               describe(*columns));
    std::map<std::string, SourceMark> seen;
    for (std::size_t i = 0; i < columns->size(); ++i) {
      const std::string field = index_field("output.columns", i);
      const std::string name = this->name((*columns)[i], field);
      check_unique(seen, name, (*columns)[i], field, "column");
      out.columns.push_back(name);
      out.column_marks.push_back(mark((*columns)[i]));
    }
  }
  return out;
}

}  // namespace mh::model_file_detail
