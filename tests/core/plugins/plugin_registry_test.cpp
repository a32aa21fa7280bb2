#include "monohydra/core/plugin_registry.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "build_paths.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using test::load_error;

TEST(PluginRegistry, FindsTheBuildsFormulationSubsystemsAndIntegratorsWithTheirAbiVersion) {
  const PluginRegistry& r = test::build_plugins();
  const ComponentInfo& f = r.find(ComponentKind::formulation, "open-loop");
  EXPECT_EQ(f.abi_version.major, MH_ABI_VERSION_MAJOR);
  ASSERT_NE(f.factory, nullptr);
  EXPECT_NE(f.formulation_factory.create, nullptr);
  EXPECT_NE(r.find(ComponentKind::subsystem, "spring-damper").subsystem_factory.create, nullptr);
  EXPECT_NE(r.find(ComponentKind::subsystem, "maxwell").subsystem_factory.create, nullptr);
  EXPECT_NE(r.find(ComponentKind::integrator, "trapezoidal").integrator_factory.create, nullptr);
  EXPECT_TRUE(r.refusals().empty());
}

TEST(PluginRegistry, UnknownComponentErrorListsWhatWasFound) {
  const PluginRegistry& r = test::build_plugins();
  try {
    r.find(ComponentKind::formulation, "lagrange");
    FAIL() << "expected PluginError";
  } catch (const PluginError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("unknown formulation 'lagrange' (found: ", 0), 0u) << msg;
    EXPECT_NE(msg.find("open-loop"), std::string::npos) << msg;
  }
}

// The same plugin installed twice (a byte-identical copy in another folder)
// is one library: its ids are not offered twice.
TEST(PluginRegistry, AByteIdenticalCopyOfALoadedLibraryIsSkipped) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("mh-registry-copy-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::copy_file(std::string(mh::test::paths::plugin_dir) + "/monohydra-penalty.so", dir / "copy.so",
                fs::copy_options::overwrite_existing);
  PluginRegistry r;
  r.scan({mh::test::paths::plugin_dir, dir.string()});
  EXPECT_NO_THROW(r.find(ComponentKind::formulation, "penalty"));
  int offers = 0;
  for (const auto& c : r.components()) offers += c.id == "penalty" ? 1 : 0;
  EXPECT_EQ(offers, 1);
  fs::remove_all(dir);
}

// Two different libraries offering one id: find() refuses to guess, naming
// both, until choose() names one; a choice of a library that does not offer
// the id is refused too.
TEST(PluginRegistry, AnIdOfferedTwiceNeedsAChoiceOfLibrary) {
  const std::string shipped = std::filesystem::weakly_canonical(
      std::string(mh::test::paths::plugin_dir) + "/monohydra-penalty.so");
  const std::string clash = std::string(mh::test::paths::clash_plugin_dir) + "/clashing_ids.so";
  PluginRegistry r;
  r.scan({mh::test::paths::clash_plugin_dir, mh::test::paths::plugin_dir});
  try {
    r.find(ComponentKind::formulation, "penalty");
    FAIL() << "expected PluginError";
  } catch (const PluginError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("formulation 'penalty' is offered by 2 libraries"), std::string::npos)
        << msg;
    EXPECT_NE(msg.find(shipped), std::string::npos) << msg;
    EXPECT_NE(msg.find("clashing_ids.so"), std::string::npos) << msg;
  }
  // The components each offers alone are found without a choice.
  EXPECT_NO_THROW(r.find(ComponentKind::subsystem, "clash-spring"));
  EXPECT_NO_THROW(r.find(ComponentKind::formulation, "double-step"));
  r.choose("penalty", shipped);
  EXPECT_EQ(r.find(ComponentKind::formulation, "penalty").library, shipped);

  PluginRegistry wrong;
  wrong.scan({mh::test::paths::clash_plugin_dir, mh::test::paths::plugin_dir});
  wrong.choose("double-step", clash);
  EXPECT_THROW(wrong.find(ComponentKind::formulation, "double-step"), PluginError);
}

TEST(PluginRegistry, RefusesAFileThatIsNotASharedLibrary) {
  const std::string path = std::string(mh::test::paths::fixture_dir) + "/text_file.so";
  const std::string err = load_error(path);
  EXPECT_NE(err.find("'" + path + "' is not a loadable shared library"), std::string::npos) << err;
  // In the dynamic loader's own words, not an errno.
  EXPECT_NE(err.find("file too short"), std::string::npos) << err;
  EXPECT_EQ(err.find("Bad file descriptor"), std::string::npos) << err;
}

// Ids and versions are quoted in model files, results (JSON) and logs: at
// most 64 bytes of UTF-8 without control characters or spaces.
TEST(PluginRegistry, RefusesAnIdLongerThanTheHostQuotesWithItsLength) {
  const std::string path = std::string(mh::test::paths::boundary_plugin_dir) + "/long_id.so";
  EXPECT_EQ(load_error(path), "'" + path +
                                  "' offers a subsystem component (number 0) whose descriptor "
                                  "cannot be quoted: its id is 1048575 bytes long (at most 64)");
}

TEST(PluginRegistry, RefusesAnIdThatIsNotUtf8NamingTheByte) {
  const std::string path = std::string(mh::test::paths::boundary_plugin_dir) + "/non_utf8_id.so";
  EXPECT_EQ(load_error(path), "'" + path +
                                  "' offers a subsystem component (number 0) whose descriptor "
                                  "cannot be quoted: its id is not valid UTF-8 (byte 7)");
}

// An id that runs into unmapped memory: the probe's child measures every
// descriptor text before the host does, so it crashes there and is refused.
TEST(PluginRegistry, AnIdWithoutItsEndIsMeasuredInTheProbeNotInTheHost) {
  const std::string path =
      std::string(mh::test::paths::boundary_plugin_dir) + "/unterminated_id.so";
  EXPECT_EQ(load_error(path), "'" + path +
                                  "' crashed with SIGSEGV during probing, listing its components "
                                  "(get_factory, count, descriptor)");
}

// The model asks for a component a refused library offered: the error says
// which libraries were refused, and why.
TEST(PluginRegistry, AnUnknownComponentErrorNamesTheLibrariesRefusedAndWhy) {
  PluginRegistry r;
  r.scan({mh::test::paths::boundary_plugin_dir});
  try {
    r.find(ComponentKind::subsystem, "faulty-spring");
    FAIL() << "found";
  } catch (const PluginError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("unknown subsystem 'faulty-spring' (found: none; check the plugin "
                        "search path; refused: '"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("/long_id.so' offers a subsystem component (number 0) whose descriptor "
                        "cannot be quoted: its id is 1048575 bytes long (at most 64)"),
              std::string::npos)
        << what;
  }
}

TEST(PluginRegistry, RefusesALibraryWithoutTheEntrySymbol) {
  const std::string path =
      std::string(mh::test::paths::fixture_dir) + "/mh_fixture_not_a_plugin.so";
  EXPECT_EQ(load_error(path), "'" + path +
                                  "' is not a monohydra plugin: it does not export the entry "
                                  "symbol 'mh_entry'");
}

// This host's ABI as the refusals name it, from the SDK header.
const std::string kHostAbi =
    std::to_string(MH_ABI_VERSION_MAJOR) + "." + std::to_string(MH_ABI_VERSION_MINOR);

TEST(PluginRegistry, RefusesAPluginOfAnIncompatibleAbiMajorVersion) {
  const std::string path = std::string(mh::test::paths::fixture_dir) + "/mh_fixture_future_abi.so";
  EXPECT_EQ(load_error(path),
            "'" + path + "' was built for monohydra ABI 99.0, this host speaks ABI " + kHostAbi +
                " (major versions must match: rebuild the plugin against SDK " +
                std::to_string(MH_ABI_VERSION_MAJOR) + ")");
}

TEST(PluginRegistry, RefusesAnAbi1PluginNamingBothVersions) {
  const std::string path = std::string(mh::test::paths::fixture_dir) + "/mh_fixture_major_one.so";
  EXPECT_EQ(load_error(path),
            "'" + path + "' was built for monohydra ABI 1.1, this host speaks ABI " + kHostAbi +
                " (major versions must match: rebuild the plugin against SDK " +
                std::to_string(MH_ABI_VERSION_MAJOR) + ")");
}

// ABI 3 was a break: a plugin of SDK 2.0 (tests/fixtures/sdk20_spring.c,
// built against the frozen 2.0 headers) is refused with both versions and
// where the migration is described, and never called.
TEST(PluginRegistry, RefusesAnSdk2PluginNamingBothVersionsAndTheMigrationSection) {
  const std::string path =
      std::string(mh::test::paths::sdk20_plugin_dir) + "/mh_fixture_sdk20_spring.so";
  EXPECT_EQ(load_error(path),
            "'" + path + "' was built for monohydra ABI 2.0, this host speaks ABI " + kHostAbi +
                " (major versions must match: rebuild the plugin against SDK " +
                std::to_string(MH_ABI_VERSION_MAJOR) +
                "; what changed since ABI 2 and how to port it: \"Migrating a 2.x plugin\" in "
                "docs/sdk.md)");
  PluginRegistry r;
  r.scan({mh::test::paths::sdk20_plugin_dir, mh::test::paths::plugin_dir});
  ASSERT_EQ(r.refusals().size(), 1u);
  EXPECT_THROW(r.find(ComponentKind::subsystem, "sdk20-spring"), PluginError);
}

// The section the refusal names exists in the SDK's guide.
TEST(PluginRegistry, TheMigrationSectionTheRefusalNamesExists) {
  std::ifstream in(test::source_path("docs/sdk.md"));
  const std::string guide((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(guide.find("## Migrating a 2.x plugin"), std::string::npos);
}

TEST(PluginRegistry, ScanRecordsRefusalsAndKeepsGoing) {
  PluginRegistry r;
  r.scan({mh::test::paths::fixture_dir, mh::test::paths::plugin_dir});
  EXPECT_EQ(r.refusals().size(), 4u);
  EXPECT_NO_THROW(r.find(ComponentKind::formulation, "open-loop"));
}

TEST(PluginRegistry, RefusesTheSameComponentIdFromASecondLibrary) {
  PluginRegistry r;
  r.load(std::string(mh::test::paths::plugin_dir) + "/monohydra-mechanics.so");
  // The same file again is a no-op, not a clash.
  EXPECT_NO_THROW(r.load(std::string(mh::test::paths::plugin_dir) + "/monohydra-mechanics.so"));
  EXPECT_EQ(r.components().size(), 2u);
}

}  // namespace
}  // namespace mh
