#include "monohydra/core/input_error.hpp"

namespace mh {
namespace {
std::string format_message(const SourceMark& mark, const std::string& field,
                           const std::string& expectation) {
  std::string msg = mark.file.empty() ? std::string("<input>") : mark.file;
  if (mark.line > 0) {
    msg += ":" + std::to_string(mark.line);
    if (mark.column > 0) msg += ":" + std::to_string(mark.column);
  }
  msg += ": ";
  if (!field.empty()) msg += field + ": ";
  msg += expectation;
  return msg;
}
}  // namespace

InputError::InputError(const SourceMark& mark, const std::string& field,
                       const std::string& expectation)
    : std::runtime_error(format_message(mark, field, expectation)), mark_(mark), field_(field) {}

}  // namespace mh
