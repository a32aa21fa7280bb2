#include "study_file.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "parameter_path.hpp"

namespace fs = std::filesystem;

namespace mh::cli::sweep {
namespace {

const std::vector<std::string> kScalarMetrics = {
    "peak_drift",      "drift_percent", "max_phi_norm", "newton_iterations",
    "mean_iterations", "steps",         "cpu_time"};

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  SourceMark mark(const YAML::Node& node) const {
    SourceMark m;
    m.file = file_;
    const YAML::Mark y = node.Mark();
    if (!y.is_null() && y.line >= 0) {
      m.line = y.line + 1;
      m.column = y.column + 1;
    }
    return m;
  }
  [[noreturn]] void fail(const YAML::Node& node, const std::string& field,
                         const std::string& expectation) const {
    throw InputError(mark(node), field, expectation);
  }
  std::string text(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar() || node.Scalar().empty()) fail(node, field, "expected a non-empty text");
    return node.Scalar();
  }
  void keys(const YAML::Node& map, const std::string& field,
            const std::vector<std::string>& allowed) const {
    if (!map.IsMap()) fail(map, field, "expected a mapping");
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(kv.first, field.empty() ? key : field + "/" + key,
             "unknown key (expected one of: " + list + ")");
      }
    }
  }
  // A parameter value: a scalar (number or text).
  YAML::Node scalar_value(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(node, field, "expected a single value (a number or a name)");
    return node;
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

Overrides read_overrides(const Reader& r, const YAML::Node& map, const std::string& field,
                         const Study& study) {
  if (!map.IsMap()) r.fail(map, field, "expected a mapping of model paths to values");
  Overrides out;
  for (const auto& kv : map) {
    const std::string path = kv.first.Scalar();
    const std::string f = field + "/" + path;
    for (const auto& m : study.models) {
      const std::string why = host::check_path(m.tree, path);
      if (!why.empty()) r.fail(kv.first, f, "not a value of model " + m.name + ": " + why);
    }
    out.emplace_back(path, r.scalar_value(kv.second, f));
  }
  return out;
}

MetricSpec read_metric(const Reader& r, const YAML::Node& node, const std::string& field) {
  MetricSpec m;
  m.mark = r.mark(node);
  if (node.IsScalar()) {
    m.kind = node.Scalar();
    if (std::find(kScalarMetrics.begin(), kScalarMetrics.end(), m.kind) == kScalarMetrics.end())
      r.fail(node, field,
             "unknown metric '" + m.kind +
                 "' (expected peak_drift, drift_percent, max_phi_norm, newton_iterations, "
                 "mean_iterations, steps, cpu_time, {max: COLUMN}, {min: COLUMN}, "
                 "{final: COLUMN} or {error: COLUMN, reference: NAME})");
    m.header = m.kind == "peak_drift" ? "peak_drift_J" : m.kind;
    return m;
  }
  if (!node.IsMap()) r.fail(node, field, "expected a metric name or {max|min|final|error: COLUMN}");
  for (const char* kind : {"max", "min", "final", "error"}) {
    if (node[kind]) {
      m.kind = kind;
      m.column = r.text(node[kind], field + "/" + kind);
    }
  }
  if (m.kind.empty()) r.fail(node, field, "expected one of max, min, final or error: COLUMN");
  if (m.kind == "error") {
    r.keys(node, field, {"error", "reference"});
    if (!node["reference"]) r.fail(node, field, "an error metric needs reference: NAME");
    m.reference = r.text(node["reference"], field + "/reference");
    m.header = "error_" + m.column + "_" + m.reference;
  } else {
    r.keys(node, field, {m.kind});
    m.header = m.kind + "_" + m.column;
  }
  return m;
}

}  // namespace

Study load_study(const std::string& path) {
  Study study;
  study.path = path;
  Reader r(path);
  SourceMark file_mark;
  file_mark.file = path;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(file_mark, "", "cannot read the study file: no such regular file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    SourceMark m = file_mark;
    if (!e.mark.is_null()) m.line = e.mark.line + 1;
    throw InputError(m, "", "malformed YAML: " + e.msg);
  }
  if (!root.IsMap())
    throw InputError(file_mark, "", "expected a mapping (models, parameters, ...)");
  r.keys(root, "",
         {"name", "models", "seed", "set", "parameters", "combine", "cases", "references",
          "metrics", "plots"});
  study.name = root["name"] ? r.text(root["name"], "name") : fs::path(path).stem().string();
  const fs::path base = fs::path(path).parent_path();

  const YAML::Node models = root["models"];
  if (!models || !models.IsSequence() || models.size() == 0)
    throw InputError(models ? r.mark(models) : file_mark, "models",
                     "expected a non-empty list of model files ({name: N, file: F} or F)");
  for (std::size_t i = 0; i < models.size(); ++i) {
    const std::string field = "models[" + std::to_string(i) + "]";
    const YAML::Node item = models[i];
    BaseModel m;
    std::string file;
    if (item.IsScalar()) {
      file = item.Scalar();
    } else {
      r.keys(item, field, {"name", "file"});
      if (!item["file"]) r.fail(item, field, "expected file: MODEL.yaml");
      file = r.text(item["file"], field + "/file");
      if (item["name"]) m.name = r.text(item["name"], field + "/name");
    }
    const fs::path p = fs::path(file).is_absolute() ? fs::path(file) : base / file;
    m.path = p.lexically_normal().string();
    if (m.name.empty()) m.name = p.stem().string();
    for (const auto& other : study.models)
      if (other.name == m.name) r.fail(item, field, "a second model named '" + m.name + "'");
    try {
      if (!fs::is_regular_file(m.path, ec)) throw YAML::BadFile(m.path);
      m.tree = YAML::LoadFile(m.path);
    } catch (const YAML::Exception& e) {
      r.fail(item, field, "cannot read the model file '" + m.path + "': " + e.msg);
    }
    study.models.push_back(std::move(m));
  }

  if (root["seed"]) {
    try {
      study.seed = root["seed"].as<std::uint64_t>();
    } catch (const YAML::Exception&) {
      r.fail(root["seed"], "seed", "expected a non-negative integer");
    }
  }
  if (root["set"]) study.set = read_overrides(r, root["set"], "set", study);

  if (root["parameters"]) {
    const YAML::Node params = root["parameters"];
    if (!params.IsMap())
      r.fail(params, "parameters", "expected a mapping of model paths to values");
    for (const auto& kv : params) {
      ParameterSpec p;
      p.path = kv.first.Scalar();
      p.mark = r.mark(kv.first);
      p.values = kv.second;
      for (const auto& m : study.models) {
        const std::string why = host::check_path(m.tree, p.path);
        if (!why.empty())
          r.fail(kv.first, "parameters/" + p.path, "not a value of model " + m.name + ": " + why);
      }
      study.parameters.push_back(p);
    }
  }
  if (root["combine"]) {
    study.combine = r.text(root["combine"], "combine");
    if (study.combine != "factorial" && study.combine != "zip")
      r.fail(root["combine"], "combine", "expected factorial or zip");
  }
  if (root["cases"]) {
    const YAML::Node cases = root["cases"];
    if (!cases.IsSequence() || cases.size() == 0)
      r.fail(cases, "cases", "expected a non-empty list of {path: value, ...}");
    if (!study.parameters.empty())
      r.fail(cases, "cases", "give either parameters (combined) or cases (listed), not both");
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const std::string field = "cases[" + std::to_string(i) + "]";
      Overrides o = read_overrides(r, cases[i], field, study);
      for (const auto& [p, v] : o)
        if (std::find(study.listed_paths.begin(), study.listed_paths.end(), p) ==
            study.listed_paths.end())
          study.listed_paths.push_back(p);
      study.listed.push_back(std::move(o));
    }
  }
  if (root["references"]) {
    const YAML::Node refs = root["references"];
    if (!refs.IsMap()) r.fail(refs, "references", "expected a mapping NAME: {path: value, ...}");
    for (const auto& kv : refs) {
      const std::string name = kv.first.Scalar();
      study.references[name] = read_overrides(r, kv.second, "references/" + name, study);
    }
  }
  if (root["metrics"]) {
    const YAML::Node list = root["metrics"];
    if (!list.IsSequence()) r.fail(list, "metrics", "expected a list of metrics");
    for (std::size_t i = 0; i < list.size(); ++i) {
      MetricSpec m = read_metric(r, list[i], "metrics[" + std::to_string(i) + "]");
      if (m.kind == "cpu_time") continue;  // every table has cpu_s
      if (m.kind == "error" && study.references.count(m.reference) == 0)
        throw InputError(m.mark, "metrics[" + std::to_string(i) + "]/reference",
                         "no reference run named '" + m.reference + "' in references");
      study.metrics.push_back(m);
    }
  } else {
    for (const char* kind : {"peak_drift", "max_phi_norm", "newton_iterations"}) {
      MetricSpec m;
      m.kind = kind;
      m.header = m.kind == "peak_drift" ? "peak_drift_J" : m.kind;
      study.metrics.push_back(m);
    }
  }
  if (root["plots"]) {
    const YAML::Node list = root["plots"];
    if (!list.IsSequence()) r.fail(list, "plots", "expected a list of {x: COLUMN, y: COLUMN}");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string field = "plots[" + std::to_string(i) + "]";
      const YAML::Node item = list[i];
      r.keys(item, field, {"x", "y", "log_x", "log_y", "title", "model"});
      if (!item["x"] || !item["y"]) r.fail(item, field, "expected x: COLUMN and y: COLUMN");
      PlotRequest p;
      p.mark = r.mark(item);
      p.x = r.text(item["x"], field + "/x");
      p.y = r.text(item["y"], field + "/y");
      p.log_x = item["log_x"] && item["log_x"].as<bool>(false);
      p.log_y = item["log_y"] && item["log_y"].as<bool>(false);
      p.title = item["title"] ? item["title"].Scalar() : p.y + " against " + p.x;
      if (item["model"]) {
        p.model = r.text(item["model"], field + "/model");
        bool known = false;
        for (const auto& m : study.models) known = known || m.name == p.model;
        if (!known) r.fail(item["model"], field + "/model", "no model named '" + p.model + "'");
      }
      study.plots.push_back(p);
    }
  }
  return study;
}

}  // namespace mh::cli::sweep
