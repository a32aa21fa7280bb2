// A library that crashes or hangs while being loaded is refused, with the
// reason, and the host lives on (core/src/plugins/plugin_probe.hpp); verdicts are
// cached by path, size, mtime and contents (core/src/plugins/probe_cache.hpp).
#include "../../../core/src/plugins/plugin_probe.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "build_paths.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace mh {
namespace {

const std::string kFaulty = mh::test::paths::faulty_plugin_dir;

// Sets MONOHYDRA_PROBE_CACHE for one test and restores it after.
class ProbeCacheSetting {
 public:
  explicit ProbeCacheSetting(const std::string& value) {
    if (const char* old = std::getenv("MONOHYDRA_PROBE_CACHE"); old != nullptr) old_ = old;
    setenv("MONOHYDRA_PROBE_CACHE", value.c_str(), 1);
  }
  ~ProbeCacheSetting() {
    if (old_.empty())
      unsetenv("MONOHYDRA_PROBE_CACHE");
    else
      setenv("MONOHYDRA_PROBE_CACHE", old_.c_str(), 1);
  }
  ProbeCacheSetting(const ProbeCacheSetting&) = delete;
  ProbeCacheSetting& operator=(const ProbeCacheSetting&) = delete;

 private:
  std::string old_;
};

fs::path scratch(const std::string& name) {
  auto dir =
      fs::temp_directory_path() / ("monohydra-probe-test-" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

using test::load_error;

TEST(PluginProbe, RefusesALibraryThatCrashesInInitNamingTheSignal) {
  const ProbeCacheSetting off("off");
  const std::string path = kFaulty + "/crash_in_init.so";
  EXPECT_EQ(load_error(path), "'" + path + "' crashed with SIGSEGV during probing, in its init");
}

// The probe unloads the library in its child, so its destructors run there
// first: one that crashes is refused, naming the phase, and never runs in the
// host (which would crash at its own exit).
TEST(PluginProbe, ALibraryWhoseDestructorCrashesIsRefusedBeforeTheHostLoadsIt) {
  const std::string path =
      std::string(mh::test::paths::boundary_plugin_dir) + "/crashing_destructor.so";
  EXPECT_EQ(
      load_error(path),
      "'" + path + "' crashed with SIGSEGV during probing, while unloading (its destructors)");
}

TEST(PluginProbe, RefusesAFactoryThatCountsFourBillionComponentsWithoutWalkingThem) {
  const ProbeCacheSetting off("off");
  const std::string path = kFaulty + "/huge_count.so";
  EXPECT_EQ(load_error(path),
            "'" + path + "' claims 4294967295 formulation components (at most 10000)");
}

TEST(PluginProbe, RefusesALibraryCutToHalfItsSize) {
  const ProbeCacheSetting off("off");
  const std::string path = kFaulty + "/truncated_plugin.so";
  EXPECT_EQ(load_error(path),
            "'" + path + "' crashed with SIGBUS during probing, while loading (its constructors)");
}

TEST(PluginProbe, KillsALibraryThatHangsInInitAfterTheTimeLimit) {
  const std::string path = std::string(mh::test::paths::hanging_plugin_dir) + "/hang_in_init.so";
  const auto t0 = std::chrono::steady_clock::now();
  const ProbeVerdict v = probe_library(path, std::chrono::milliseconds(300));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_FALSE(v.usable);
  EXPECT_EQ(v.reason, "timed out after 300 ms during probing, in its init");
  EXPECT_LT(seconds, 5.0);
}

TEST(PluginProbe, ScanOfTheFaultyFolderLoadsTheGoodPluginAndRefusesEachBadOne) {
  const ProbeCacheSetting off("off");
  PluginRegistry r;
  r.scan({kFaulty});
  ASSERT_EQ(r.components().size(), 1u);
  EXPECT_EQ(r.components()[0].id, "crashing-formulation");
  ASSERT_EQ(r.refusals().size(), 3u);
  EXPECT_EQ(r.refusals()[0],
            "'" + kFaulty + "/crash_in_init.so' crashed with SIGSEGV during probing, in its init");
  EXPECT_EQ(r.refusals()[1], "'" + kFaulty +
                                 "/huge_count.so' claims 4294967295 formulation components (at "
                                 "most 10000)");
  EXPECT_EQ(r.refusals()[2], "'" + kFaulty +
                                 "/truncated_plugin.so' crashed with SIGBUS during probing, while "
                                 "loading (its constructors)");
}

TEST(PluginProbe, CachedVerdictIsUsedUntilTheLibraryChanges) {
  const fs::path dir = scratch("cache");
  const fs::path lib = dir / "copy.so";
  fs::copy_file(kFaulty + "/crashing_formulation.so", lib);
  const fs::path cache = dir / "probe-cache";
  const ProbeCacheSetting file(cache.string());
  ASSERT_EQ(load_error(lib.string()), "");  // probed, found usable, remembered

  std::stringstream text;
  text << std::ifstream(cache).rdbuf();
  const std::string header = "monohydra-probe-cache 2\n";
  ASSERT_EQ(text.str().rfind(header, 0), 0u) << text.str();
  const std::string line = text.str().substr(header.size());
  ASSERT_EQ(line.rfind("1\t" + std::to_string(fs::file_size(lib)) + "\t", 0), 0u) << line;
  ASSERT_NE(line.find("\t" + fs::canonical(lib).string() + "\t\n"), std::string::npos) << line;

  // A forged verdict for the same (path, size, mtime) is believed: no probe ran.
  std::string forged = line;
  forged[0] = '0';
  forged.insert(forged.size() - 1, "forged verdict");
  std::ofstream(cache, std::ios::trunc) << header << forged;
  EXPECT_EQ(load_error(lib.string()), "'" + lib.string() + "' forged verdict");
  // ... but not from the cache of an older probe (no header: it tested less).
  std::ofstream(cache, std::ios::trunc) << forged;
  EXPECT_EQ(load_error(lib.string()), "");
  std::ofstream(cache, std::ios::trunc) << header << forged;

  // The same size and mtime with other contents (a rebuild within the
  // mtime's resolution, a copy that kept the time): probed again.
  const auto mtime = fs::last_write_time(lib);
  {
    std::fstream bytes(lib, std::ios::in | std::ios::out | std::ios::binary);
    bytes.seekg(-1, std::ios::end);
    const char last = static_cast<char>(bytes.get());
    bytes.seekp(-1, std::ios::end);
    bytes.put(static_cast<char>(last ^ 1));
  }
  fs::last_write_time(lib, mtime);
  ASSERT_EQ(fs::last_write_time(lib), mtime);  // only the contents tell
  EXPECT_EQ(load_error(lib.string()), "");
  std::ofstream(cache, std::ios::trunc) << header << forged;

  // Once the file changes, its verdict no longer applies: probed again.
  fs::last_write_time(lib, fs::last_write_time(lib) + std::chrono::seconds(1));
  EXPECT_EQ(load_error(lib.string()), "");
}

TEST(PluginProbe, UnwritableCacheIsNoCache) {
  const ProbeCacheSetting file("/proc/monohydra-cannot-write/probe-cache");
  const std::string path = kFaulty + "/crash_in_init.so";
  EXPECT_EQ(load_error(path), "'" + path + "' crashed with SIGSEGV during probing, in its init");
}

// A cache path that is not a regular file is no cache: /dev/zero would be read
// forever, /dev/null replaced by the rename of a save, a FIFO block the open.
TEST(PluginProbe, ACachePathThatIsADeviceOrFifoIsNoCacheAndIsLeftAlone) {
  const fs::path dir = scratch("device-cache");
  const fs::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path link = dir / "zero";
  fs::create_symlink("/dev/zero", link);
  for (const std::string& path :
       {std::string("/dev/null"), std::string("/dev/zero"), fifo.string(), link.string()}) {
    SCOPED_TRACE(path);
    const ProbeCacheSetting file(path);
    const std::string lib = kFaulty + "/crash_in_init.so";
    EXPECT_EQ(load_error(lib), "'" + lib + "' crashed with SIGSEGV during probing, in its init");
  }
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_TRUE(fs::is_character_file("/dev/zero"));
  EXPECT_TRUE(fs::is_fifo(fifo));
}

}  // namespace
}  // namespace mh
