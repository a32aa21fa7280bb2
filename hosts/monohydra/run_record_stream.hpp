// A RunRecord as bytes, for the pipe from a run's child process to compare:
// doubles are copied bit for bit, so the parent holds exactly the numbers the
// child computed, and a stream cut by a crash still gives every whole row.
#pragma once

#include <string>

#include "run_record.hpp"

namespace mh::cli {

// Appends the record's description (everything but the columns' values).
// `final` marks the end of the run: a stream without it was cut.
void append_record_description(std::string& out, const RunRecord& rec, bool final);
// Appends the values of row `row`.
void append_record_row(std::string& out, const RunRecord& rec, size_t row);

struct DecodedRecord {
  RunRecord record;
  bool complete = false;  // the final description arrived
};
// Decodes what append_record_* wrote, up to the last whole message.
DecodedRecord decode_record_stream(const std::string& bytes);

}  // namespace mh::cli
