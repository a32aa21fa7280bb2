#include "build_paths.hpp"

// A path this build does not make (no FMI import, the sanitizers' build
// without the allocation test) is "".
#ifndef MH_FMU_DIR
#define MH_FMU_DIR ""
#endif
#ifndef MH_ALLOCATING_LIBRARY
#define MH_ALLOCATING_LIBRARY ""
#endif

namespace mh::test::paths {

const char* const source_dir = MH_SOURCE_DIR;
const char* const binary_dir = MH_BINARY_DIR;
const char* const executable = MH_EXECUTABLE;
const char* const plugin_dir = MH_PLUGIN_DIR;
const char* const fixture_dir = MH_FIXTURE_DIR;
const char* const sdk20_plugin_dir = MH_SDK20_PLUGIN_DIR;
const char* const frozen_sdk_plugin_dir = MH_FROZEN_SDK_PLUGIN_DIR;
const char* const clash_plugin_dir = MH_CLASH_PLUGIN_DIR;
const char* const check_fixture_dir = MH_CHECK_FIXTURE_DIR;
const char* const faulty_plugin_dir = MH_FAULTY_PLUGIN_DIR;
const char* const hanging_plugin_dir = MH_HANGING_PLUGIN_DIR;
const char* const boundary_plugin_dir = MH_BOUNDARY_PLUGIN_DIR;
const char* const sparsity_plugin_dir = MH_SPARSITY_PLUGIN_DIR;
const char* const inverse_dynamics_plugin_dir = MH_INVERSE_DYNAMICS_PLUGIN_DIR;
const char* const fmu_dir = MH_FMU_DIR;
const char* const exported_fmus = MH_TEST_FMUS;
const char* const resume_snapshot = MH_RESUME_SNAPSHOT;
const char* const allocating_library = MH_ALLOCATING_LIBRARY;
const char* const examples_dir = MH_EXAMPLES_DIR;
const char* const sdk_example_dir = MH_SDK_EXAMPLE_DIR;

}  // namespace mh::test::paths
