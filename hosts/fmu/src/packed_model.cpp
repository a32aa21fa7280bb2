#include "packed_model.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

namespace mh::fmu {

namespace {

std::uint64_t fnv1a(const std::string& text, std::uint64_t seed) {
  std::uint64_t h = seed;
  for (unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

// A scalar that is a whole number ("1.5e6", "-3"), as strtod reads it.
bool as_number(const YAML::Node& node, double& value) {
  if (!node.IsScalar()) return false;
  const std::string& text = node.Scalar();
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

// Each scalar number of the named items of `list` (subsystems:, bodies:).
void add_items(const YAML::Node& list, const char* key, std::vector<FmuVariable>& out) {
  if (!list || !list.IsSequence()) return;
  for (const YAML::Node& item : list) {
    if (!item.IsMap() || !item["name"] || !item["name"].IsScalar()) continue;
    const std::string item_name = item["name"].Scalar();
    for (const auto& field : item) {
      const std::string option = field.first.as<std::string>();
      double value = 0.0;
      if (option == "name" || !as_number(field.second, value)) continue;
      FmuVariable v;
      v.causality = Causality::parameter;
      v.name = std::string(key) + "." + item_name + "." + option;
      v.path = std::string(key) + "/" + item_name + "/" + option;
      v.start = value;
      // A body's mass changes between steps (mhs_set_parameter); the other
      // options are read when the model is set up.
      v.tunable = std::string(key) == "bodies" && option == "mass";
      v.description = "the model file's " + v.path + " (its units: the model's units:)" +
                      (v.tunable ? "; tunable: set between steps, the run goes on with it" : "");
      out.push_back(std::move(v));
    }
  }
}

}  // namespace

std::string instantiation_token(const std::string& model_text) {
  const std::uint64_t a = fnv1a(model_text, 0xcbf29ce484222325ULL);
  const std::uint64_t b = fnv1a(model_text, 0x84222325cbf29ce4ULL);
  char text[48];
  std::snprintf(text, sizeof(text), "{%08x-%04x-%04x-%04x-%012llx}", static_cast<unsigned>(a >> 32),
                static_cast<unsigned>((a >> 16) & 0xffff), static_cast<unsigned>(a & 0xffff),
                static_cast<unsigned>(b >> 48),
                static_cast<unsigned long long>(b & 0xffffffffffffULL));
  return text;
}

std::vector<FmuVariable> numeric_options(const std::string& model_text) {
  const YAML::Node root = YAML::Load(model_text);
  std::vector<FmuVariable> out;
  add_items(root["bodies"], "bodies", out);
  add_items(root["subsystems"], "subsystems", out);
  const YAML::Node formulation = root["formulation"];
  if (formulation && formulation.IsMap()) {
    for (const auto& field : formulation) {
      const std::string option = field.first.as<std::string>();
      double value = 0.0;
      if (option == "name" || !as_number(field.second, value)) continue;
      FmuVariable v;
      v.causality = Causality::parameter;
      v.name = "formulation." + option;
      v.path = "formulation/" + option;
      v.start = value;
      v.description = "the formulation's option " + option;
      out.push_back(std::move(v));
    }
  }
  return out;
}

std::vector<FmuVariable> variable_table(mhs_simulation* sim, const std::string& model_text) {
  std::vector<FmuVariable> table;
  FmuVariable time;
  time.causality = Causality::independent;
  time.name = "time";
  time.unit = "s";
  time.description = "the run's time";
  table.push_back(time);

  uint32_t columns = 0;
  if (mhs_row_size(sim, &columns) != MHS_OK) throw std::runtime_error(mhs_message(sim));
  for (uint32_t c = 0; c < columns; ++c) {
    const char* name = nullptr;
    if (mhs_row_name(sim, c, &name) != MHS_OK) throw std::runtime_error(mhs_message(sim));
    FmuVariable v;
    v.causality = Causality::output;
    v.name = name;
    v.index = c;
    v.description = "the column " + v.name + " of monohydra run";
    uint32_t found = 0;
    if (mhs_find(sim, name, &found) == MHS_OK) {
      mhs_variable_info info{};
      info.struct_size = sizeof(info);
      if (mhs_variable(sim, found, &info) == MHS_OK) {
        v.unit = info.unit;
        v.description += std::string(" (") + info.qualified + ")";
      }
    } else if (v.name == "t") {
      v.unit = "s";
    } else if (v.name == "KE" || v.name == "PE" || v.name == "W") {
      v.unit = "J";  // the energy balance's columns (docs/model-format.md, Output)
    }
    table.push_back(std::move(v));
  }

  uint32_t count = 0;
  if (mhs_variable_count(sim, &count) != MHS_OK) throw std::runtime_error(mhs_message(sim));
  for (uint32_t i = 0; i < count; ++i) {
    mhs_variable_info info{};
    info.struct_size = sizeof(info);
    if (mhs_variable(sim, i, &info) != MHS_OK) throw std::runtime_error(mhs_message(sim));
    if (info.kind != MHS_INPUT) continue;
    FmuVariable v;
    v.causality = Causality::input;
    v.name = info.name;
    v.unit = info.unit;
    v.min = info.min;
    v.max = info.max;
    v.index = i;
    v.description = "the model's input " + v.name + " (its table while not set)";
    if (mhs_get(sim, &i, 1, &v.start) != MHS_OK) throw std::runtime_error(mhs_message(sim));
    table.push_back(std::move(v));
  }

  for (FmuVariable& v : numeric_options(model_text)) table.push_back(std::move(v));

  std::unordered_set<std::string> names;
  for (std::size_t k = 0; k < table.size(); ++k) {
    table[k].value_reference = static_cast<std::uint32_t>(k);
    if (!names.insert(table[k].name).second)
      throw std::runtime_error("two of the FMU's variables would be called '" + table[k].name +
                               "': rename a column, an input or an item of the model");
  }
  return table;
}

PackedModel read_packed_model(const std::string& resources_dir) {
  std::string dir = resources_dir;
  if (!dir.empty() && dir.back() != '/') dir += '/';
  PackedModel p;
  p.model_path = dir + kModelFile;
  p.model_text = read_text(p.model_path);
  const std::string settings_path = dir + kSettingsFile;
  if (std::ifstream(settings_path).good()) {
    p.settings_text = read_text(settings_path);
    try {
      const YAML::Node root = YAML::Load(p.settings_text);
      for (const YAML::Node& s : root["settings"])
        p.settings.emplace_back(s["path"].as<std::string>(), s["value"].as<std::string>());
    } catch (const YAML::Exception& e) {
      throw std::runtime_error(settings_path + ": " + e.what() +
                               " (expected settings: a list of {path, value})");
    }
  }
  p.token = instantiation_token(p.model_text + "\n---\n" + p.settings_text);
  return p;
}

std::vector<mhs_setting> api_settings(const PackedModel& packed) {
  std::vector<mhs_setting> out;
  for (const auto& [path, value] : packed.settings) out.push_back({path.c_str(), value.c_str()});
  return out;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace mh::fmu
