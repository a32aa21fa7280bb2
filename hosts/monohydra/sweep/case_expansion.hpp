// The cases of a study: each base model with every combination of the
// parameters' values (full factorial, or the i-th value of each taken
// together, or the listed combinations), numbered in that order. Values are
// lists, ranges or seeded random draws from named distributions; the same
// study file gives the same cases on every machine (Boost.Random's
// distributions are the same everywhere, unlike the standard library's).
#pragma once

#include <string>
#include <vector>

#include "study_file.hpp"

namespace mh::cli::sweep {

struct Case {
  int index = 0;     // 0, 1, ... in expansion order: the `case` column
  int model = 0;     // into Study::models
  Overrides values;  // one per varied path, in the order of varied_paths()
};

// The values a parameter takes, in order. Throws InputError.
std::vector<YAML::Node> parameter_values(const Study& study, std::size_t parameter);

// The paths the cases vary, in column order.
std::vector<std::string> varied_paths(const Study& study);

// Every case. Throws InputError (a bad range or distribution, zip lists of
// different lengths).
std::vector<Case> expand_cases(const Study& study);

// A number as the shortest text that reads back to it.
std::string number_text(double value);

}  // namespace mh::cli::sweep
