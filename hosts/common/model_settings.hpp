// Values set by path over a model file (run --set PATH=VALUE): each replaces
// the scalar the file writes at that path in the file's own text, so every
// line keeps its number and a value the parser refuses is reported at the
// line of the file that held it. A path the file does not write (a solver
// setting or a component option left at its default) is added to the tree,
// and the tree written anew.
#pragma once

#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"

namespace mh::host {

struct PathSetting {
  std::string path;   // as parameter_path.hpp addresses values: bodies/boom/mass
  std::string value;  // its text, as the model file would write it
};

// "PATH=VALUE" into a setting; std::invalid_argument without '=' or a path.
PathSetting parse_setting(const std::string& text);

struct SetText {
  std::string text;
  bool rewritten = false;  // the tree was written anew: lines differ from the file's
};

// `text` (a model file's, named `label` in errors) with every setting
// applied in order. Refused with std::invalid_argument that starts with
// PATH=VALUE: a
// path the model has no value at, a path to a list or mapping, a value that
// is not one scalar, and text where the file writes a number.
SetText apply_settings(const std::string& text, const std::string& label,
                       const std::vector<PathSetting>& settings);

// The model file at `path` with `settings` applied (none: load_model_file).
// Throws InputError naming the file: a refused setting as
// "FILE: --set PATH=VALUE: why", and the parser's refusal of the result with
// "(with --set PATH=VALUE, ...)" after it; while the settings only replace
// values the file writes, the parser's line numbers are the file's.
ModelFile load_model_file(const std::string& path, const std::vector<PathSetting>& settings);

}  // namespace mh::host
