// Where the shipped models (and the paper's reference numbers beside them) are
// found: an installed tree's share/monohydra/models, the install prefix's, or
// the source tree's models/ when running from a build tree.
#pragma once

#include <string>

namespace mh::cli {

// The path of models/<name> in the first of those folders that holds it, or
// "models/<name>" (relative to the working directory) when none does.
std::string shipped_model(const std::string& name);

}  // namespace mh::cli
