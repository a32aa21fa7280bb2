// compare runs each formulation in a forked child: a plugin that crashes
// (SIGSEGV in its residual, an abort) ends its own run only, and the rows it
// had computed and every other run's results stay.
#pragma once

#include "run_record.hpp"

namespace mh::cli {

// record_run in a child process, whose record comes back through a pipe row
// by row (run_record_stream.hpp). A child killed by a signal gives a failed
// record with `crashed_by` set, the failure "crashed (SIGSEGV) after t = 0.1
// s" and the rows it had sent. A stop signal this process receives is passed
// on to the child, which stops after its current row. Falls back to
// record_run in this process when it cannot fork.
RunRecord record_run_isolated(const ModelFile& file, const PluginRegistry& registry,
                              const std::string& formulation, const std::string& integrator,
                              RecordOptions options);

}  // namespace mh::cli
