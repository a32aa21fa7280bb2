#include "case_studies.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "monohydra/core/input_error.hpp"
#include "shipped_models.hpp"

namespace fs = std::filesystem;

namespace mh::cli {
namespace {

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& field,
                         const std::string& expectation) const {
    SourceMark m;
    m.file = file_;
    if (node.IsDefined() && !node.Mark().is_null()) {
      m.line = node.Mark().line + 1;
      m.column = node.Mark().column + 1;
    }
    throw InputError(m, field, expectation);
  }

  // Rejects keys outside `allowed`.
  void keys(const YAML::Node& map, const std::string& field,
            const std::set<std::string>& allowed) const {
    if (!map.IsMap()) fail(map, field, "expected a mapping");
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      if (allowed.count(key) == 0) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(kv.first, field + "." + key,
             "unknown key '" + key + "' (expected one of: " + list + ")");
      }
    }
  }

  std::string text(const YAML::Node& map, const std::string& key, const std::string& field,
                   bool required) const {
    const YAML::Node node = map[key];
    if (!node.IsDefined()) {
      if (required) fail(map, field + "." + key, "missing (required)");
      return "";
    }
    if (!node.IsScalar() || node.Scalar().empty())
      fail(node, field + "." + key, "expected a non-empty string");
    return node.Scalar();
  }

  std::optional<double> number(const YAML::Node& map, const std::string& key,
                               const std::string& field) const {
    const YAML::Node node = map[key];
    if (!node.IsDefined()) return std::nullopt;
    if (node.IsScalar() && node.Tag() != "!") {
      try {
        size_t used = 0;
        const double v = std::stod(node.Scalar(), &used);
        if (used == node.Scalar().size() && std::isfinite(v)) return v;
      } catch (const std::exception&) {
      }
    }
    fail(node, field + "." + key, "expected a finite number, got '" + node.Scalar() + "'");
  }

  PaperNumbers paper(const YAML::Node& node, const std::string& field) const {
    PaperNumbers p;
    if (!node.IsDefined()) return p;
    keys(node, field,
         {"source", "platform", "integrator", "max_actuator_work", "peak_drift",
          "peak_drift_percent", "peak_drift_time", "runs"});
    p.source = text(node, "source", field, false);
    p.platform = text(node, "platform", field, false);
    p.integrator = text(node, "integrator", field, true);
    p.max_actuator_work = number(node, "max_actuator_work", field);
    p.peak_drift = number(node, "peak_drift", field);
    p.peak_drift_percent = number(node, "peak_drift_percent", field);
    p.peak_drift_time = number(node, "peak_drift_time", field);
    const YAML::Node runs = node["runs"];
    if (runs.IsDefined()) {
      if (!runs.IsMap()) fail(runs, field + ".runs", "expected a mapping formulation: numbers");
      for (const auto& kv : runs) {
        const std::string f = field + ".runs." + kv.first.Scalar();
        keys(kv.second, f, {"avg_iterations", "max_iterations", "total_seconds", "coordinates"});
        PaperRun r;
        r.formulation = kv.first.Scalar();
        r.coordinates = text(kv.second, "coordinates", f, false);
        r.avg_iterations = number(kv.second, "avg_iterations", f);
        r.max_iterations = number(kv.second, "max_iterations", f);
        r.total_seconds = number(kv.second, "total_seconds", f);
        p.runs.push_back(r);
      }
    }
    return p;
  }

  CaseStudy study(const YAML::Node& node, const std::string& field, const fs::path& dir) const {
    keys(node, field,
         {"name", "model", "report", "formulations", "control_shading", "newton", "paper"});
    CaseStudy s;
    s.name = text(node, "name", field, true);
    const fs::path model = text(node, "model", field, true);
    s.model_path = (model.is_absolute() ? model : dir / model).lexically_normal().string();
    s.report_dir = text(node, "report", field, true);
    const YAML::Node fs_node = node["formulations"];
    if (!fs_node.IsSequence() || fs_node.size() == 0)
      fail(fs_node.IsDefined() ? fs_node : node, field + ".formulations",
           "expected a non-empty list of formulation names");
    for (const auto& f : fs_node) {
      if (!f.IsScalar() || f.Scalar().empty())
        fail(f, field + ".formulations", "expected a formulation name");
      s.formulations.push_back(f.Scalar());
    }
    s.control_shading = text(node, "control_shading", field, false);
    if (s.control_shading.empty()) s.control_shading = "#d8c8f0";
    const bool hex =
        s.control_shading.size() == 7 && s.control_shading[0] == '#' &&
        s.control_shading.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos;
    if (!hex)
      fail(node["control_shading"], field + ".control_shading", "expected a colour #rrggbb");
    const std::string newton = text(node, "newton", field, false);
    if (!newton.empty()) {
      for (NewtonKind kind : {NewtonKind::full, NewtonKind::per_step, NewtonKind::modified,
                              NewtonKind::articulated, NewtonKind::automatic})
        if (newton == to_string(kind)) s.newton = kind;
      if (!s.newton)
        fail(node["newton"], field + ".newton",
             "expected auto, full, per-step, modified or articulated (as a model file's "
             "solver.newton), got '" +
                 newton + "'");
    }
    s.paper = paper(node["paper"], field + ".paper");
    return s;
  }

 private:
  std::string file_;
};

}  // namespace

const PaperRun* PaperNumbers::run(const std::string& formulation,
                                  const std::string& with_integrator) const {
  if (with_integrator != integrator) return nullptr;
  for (const auto& r : runs)
    if (r.formulation == formulation) return &r;
  return nullptr;
}

std::string case_studies_path() {
  const char* env = std::getenv("MONOHYDRA_CASE_STUDIES");
  if (env != nullptr && *env != '\0') return env;
  return shipped_model("paper-reference.yaml");
}

std::vector<CaseStudy> load_case_studies(const std::string& path) {
  const Reader reader(path);
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(SourceMark{path, 0, 0}, "case studies", "cannot open the file");
  } catch (const YAML::Exception& err) {
    throw InputError(SourceMark{path, err.mark.line + 1, err.mark.column + 1}, "case studies",
                     err.msg);
  }
  reader.keys(root, "case_studies", {"case_studies"});
  const YAML::Node list = root["case_studies"];
  if (!list.IsSequence() || list.size() == 0)
    reader.fail(list.IsDefined() ? list : root, "case_studies",
                "expected a non-empty list of case studies");
  const fs::path dir = fs::path(path).parent_path();
  std::vector<CaseStudy> out;
  for (size_t i = 0; i < list.size(); ++i)
    out.push_back(reader.study(list[i], "case_studies[" + std::to_string(i) + "]", dir));
  return out;
}

const CaseStudy* find_case_study(const std::vector<CaseStudy>& studies,
                                 const std::string& model_path) {
  std::error_code ec;
  for (const auto& s : studies)
    if (fs::equivalent(s.model_path, model_path, ec) && !ec) return &s;
  return nullptr;
}

}  // namespace mh::cli
