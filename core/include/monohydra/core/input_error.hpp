// Errors in what a user wrote: they name the file, line, field and what was
// expected, so a bad model never reaches the solver.
#pragma once

#include <stdexcept>
#include <string>

namespace mh {

// Where something was written in an input file; line and column are 1-based,
// 0 when unknown.
struct SourceMark {
  std::string file;
  int line = 0;
  int column = 0;
};

class InputError : public std::runtime_error {
 public:
  // Message: "FILE:LINE:COL: FIELD: EXPECTATION" (line/column left out when 0).
  InputError(const SourceMark& mark, const std::string& field, const std::string& expectation);
  const SourceMark& mark() const { return mark_; }
  const std::string& field() const { return field_; }

 private:
  SourceMark mark_;
  std::string field_;
};

}  // namespace mh
