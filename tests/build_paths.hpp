// Where this build tree put what the tests load and run: the source tree,
// the plugins, the fixtures broken on purpose, the executables. The absolute
// paths are compiled into build_paths.cpp alone (library mh_test_paths), not
// into every test as definitions, so that a test's object is the same in any
// clone and a compiler cache serves it to a clone in another folder.
#pragma once

namespace mh::test::paths {

extern const char* const source_dir;             // the source tree
extern const char* const binary_dir;             // the build tree
extern const char* const executable;             // the built `monohydra`
extern const char* const plugin_dir;             // the shipped plugins, built
extern const char* const fixture_dir;            // tests/fixtures: not plugins, future and old ABIs
extern const char* const sdk20_plugin_dir;       // a plugin of the frozen SDK 2.0
extern const char* const frozen_sdk_plugin_dir;  // one built against frozen 3.0, one 3.2
extern const char* const clash_plugin_dir;       // a library offering penalty's id
extern const char* const check_fixture_dir;      // plugins `check` must fail
extern const char* const faulty_plugin_dir;      // libraries that crash or misbehave
extern const char* const hanging_plugin_dir;     // a library that hangs in init
extern const char* const boundary_plugin_dir;    // ids past the host's limits
extern const char* const sparsity_plugin_dir;    // the sparsity service's fixtures
extern const char* const inverse_dynamics_plugin_dir;  // the inverse dynamics service's caller
extern const char* const fmu_dir;                      // FMUs built from C for the import's tests
extern const char* const exported_fmus;                // FMUs `monohydra fmu` wrote at build time
extern const char* const resume_snapshot;              // the C program that resumes a snapshot
extern const char* const allocating_library;           // the allocation test's control library
extern const char* const examples_dir;                 // examples/ built against the installed SDK
extern const char* const sdk_example_dir;              // sdk/examples/point-load, likewise

}  // namespace mh::test::paths
