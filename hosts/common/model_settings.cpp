#include "model_settings.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "monohydra/core/input_error.hpp"
#include "monohydra/core/model_text.hpp"
#include "parameter_path.hpp"

namespace mh::host {
namespace {

bool is_number(const std::string& text) {
  if (text.empty()) return false;
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  std::strtod(begin, &end);
  return end == begin + text.size() && errno != ERANGE;
}

// Where the scalar that starts at `pos` ends: its closing quote, or for a
// plain scalar the first blank, comment or flow indicator (a number, or a
// name without blanks, is all this is asked for; the caller checks that
// the span reads back as the scalar).
std::size_t scalar_end(const std::string& text, std::size_t pos) {
  if (pos >= text.size()) return std::string::npos;
  const char quote = text[pos];
  if (quote == '"' || quote == '\'') {
    for (std::size_t i = pos + 1; i < text.size(); ++i) {
      if (quote == '"' && text[i] == '\\') {
        ++i;
      } else if (text[i] == quote) {
        if (quote == '\'' && i + 1 < text.size() && text[i + 1] == '\'') {
          ++i;  // '' inside single quotes
        } else {
          return i + 1;
        }
      }
    }
    return std::string::npos;
  }
  std::size_t i = pos;
  static const std::string kStops = " \t\r\n,]}#";
  while (i < text.size() && kStops.find(text[i]) == std::string::npos) ++i;
  return i;
}

// The value as the file would write it: a number as given, anything else
// double-quoted so that no character of it can change the file's structure.
std::string scalar_text(const std::string& value) {
  if (is_number(value)) return value;
  std::string out = "\"";
  for (const char c : value) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string described(const PathSetting& s) {
  return s.path + "=" + s.value;
}

}  // namespace

PathSetting parse_setting(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument("expects PATH=VALUE (bodies/boom/mass=250), got '" + text + "'");
  if (eq == 0) throw std::invalid_argument(text + ": the path before '=' is empty");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

SetText apply_settings(const std::string& text, const std::string& label,
                       const std::vector<PathSetting>& settings) {
  SetText out{text, false};
  std::vector<PathSetting> in_tree;  // those the text does not write, set in the tree
  for (const PathSetting& s : settings) {
    YAML::Node value;
    try {
      value = YAML::Load(s.value);
    } catch (const YAML::Exception& err) {
      throw std::invalid_argument(described(s) + ": the value is not one YAML scalar (" + err.msg +
                                  ")");
    }
    if (!value.IsScalar() || s.value.empty())
      throw std::invalid_argument(described(s) + ": expected one value, a number or a name");
    YAML::Node root;
    try {
      root = YAML::Load(out.text);
    } catch (const YAML::Exception& err) {
      throw std::invalid_argument(label + ": not YAML: " + err.what());
    }
    const std::string reason = check_path(root, s.path);
    if (!reason.empty()) throw std::invalid_argument(described(s) + ": " + reason);
    const std::optional<YAML::Node> at = value_at(root, s.path);
    if (at && !at->IsScalar())
      throw std::invalid_argument(described(s) + ": the model writes " +
                                  (at->IsSequence() ? "a list" : "a mapping") + " at " + s.path +
                                  ", not one value");
    if (at && is_number(at->Scalar()) && !is_number(value.Scalar()))
      throw std::invalid_argument(described(s) + ": expected a number (the model writes " +
                                  at->Scalar() + " there), got '" + s.value + "'");
    if (!in_tree.empty() || !at) {
      in_tree.push_back(s);
      continue;
    }
    const auto pos = static_cast<std::size_t>(at->Mark().pos);
    const std::size_t end = scalar_end(out.text, pos);
    bool spliced = false;
    if (end != std::string::npos && end > pos) {
      const std::string span = out.text.substr(pos, end - pos);
      try {
        const YAML::Node again = YAML::Load(span);
        spliced = again.IsScalar() && again.Scalar() == at->Scalar();
      } catch (const YAML::Exception&) {
        spliced = false;
      }
      if (spliced) out.text.replace(pos, end - pos, scalar_text(value.Scalar()));
    }
    if (!spliced) in_tree.push_back(s);
  }
  if (in_tree.empty()) return out;
  YAML::Node root = YAML::Load(out.text);
  for (const PathSetting& s : in_tree) {
    try {
      set_path(root, s.path, YAML::Load(s.value));
    } catch (const std::exception& err) {
      throw std::invalid_argument(described(s) + ": " + err.what());
    }
  }
  YAML::Emitter emitted;
  emitted << root;
  out.text = std::string(emitted.c_str()) + "\n";
  out.rewritten = true;
  return out;
}

ModelFile load_model_file(const std::string& path, const std::vector<PathSetting>& settings) {
  if (settings.empty()) return mh::load_model_file(path);
  const std::string text = read_model_text(path);
  SourceMark mark;
  mark.file = path;
  SetText set;
  try {
    set = apply_settings(text, path, settings);
  } catch (const std::invalid_argument& err) {
    throw InputError(mark, "", std::string("--set ") + err.what());
  }
  std::string all;
  for (const PathSetting& s : settings) all += (all.empty() ? "" : ", ") + described(s);
  std::filesystem::path base = std::filesystem::path(path).parent_path();
  if (base.empty()) base = ".";
  const std::string label = set.rewritten ? path + " (as --set rewrote it)" : path;
  try {
    return parse_model_text(set.text, label, base.string());
  } catch (const InputError& err) {
    // The parser's message, the settings named after it.
    const std::string prefix = InputError(err.mark(), err.field(), "").what();
    const std::string why = std::string(err.what()).substr(prefix.size());
    throw InputError(err.mark(), err.field(), why + " (with --set " + all + ")");
  }
}

}  // namespace mh::host
