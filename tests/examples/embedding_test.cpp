// The embedding example (examples/embedding) as a user builds it, against the
// installed prefix alone (build_examples.cmake), run with no plugin path set
// from a folder laid out as the repository root: its CSV is the one
// `monohydra run models/fourbar.yaml` writes, byte for byte, and its
// snapshot halfway repeats the steps after it to the bit (it says so).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "build_paths.hpp"
#include "text_file.hpp"

namespace {

using mh::test::read_text;

std::string output_of(const std::string& command, int& code) {
  std::string out;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return out;
  char buf[4096];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  code = pclose(pipe);
  return out;
}

TEST(EmbeddingExample, ItsCsvIsMonohydraRunsByteForByteWithNoPluginPathSet) {
  const auto root =
      std::filesystem::path(mh::test::paths::binary_dir) / "test-scratch" / "embedding-example";
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root);
  std::filesystem::create_directory_symlink(std::string(mh::test::paths::source_dir) + "/models",
                                            root / "models");
  int code = -1;
  const std::string said =
      output_of("cd '" + root.string() + "' && env -u MONOHYDRA_PLUGIN_PATH " +
                    mh::test::paths::examples_dir + "/embedding/fourbar_embedded",
                code);
  ASSERT_EQ(code, 0) << said;
  EXPECT_NE(said.find("snapshot at t = 5 s: 100 steps after it repeat to the bit"),
            std::string::npos)
      << said;
  const std::string reference = (root / "reference.csv").string();
  const std::string ran = output_of(
      "env -u MONOHYDRA_PLUGIN_PATH " + std::string(mh::test::paths::executable) + " run " +
          mh::test::paths::source_dir + "/models/fourbar.yaml --out " + reference,
      code);
  ASSERT_EQ(code, 0) << ran;
  const std::string embedded = read_text(root / "out" / "embedding" / "fourbar.csv");
  EXPECT_EQ(std::count(embedded.begin(), embedded.end(), '\n'), 10002);
  EXPECT_TRUE(embedded == read_text(reference)) << "the embedded run's CSV differs";
}

}  // namespace
