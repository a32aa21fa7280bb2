// `monohydra check PLUGIN.so [MODEL.yaml]`: loads one plugin library and
// drives every component it offers through its contract, each check in a
// child process so that a crash, an abort or an exception thrown across the
// C boundary is reported as that check's failure rather than ending the host.
// Checks: loading (probe, ABI version and struct-size negotiation, init),
// descriptors, create/setup/destroy cycles, refused bad options, the
// assembled tangent (every analytic block: formulation tangent, subsystem
// jacobian, point_force_jacobian) against forward differences of the plugin's
// own residual, and bit-identical repeated runs. docs/plugin-guide.md.
#pragma once

#include <string>
#include <vector>

namespace mh::cli {

// Exit status: 0 every check passed, 1 one failed, 2 bad arguments.
int check(const std::vector<std::string>& args);

}  // namespace mh::cli
