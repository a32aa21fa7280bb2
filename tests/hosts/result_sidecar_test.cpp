// NAME.meta.json beside every result file: valid JSON (read back with
// Boost.PropertyTree's parser) naming the libraries the run used, the model
// file's SHA-256 (checked against coreutils' sha256sum), the command line and
// the settings the run actually used.
#include "result_sidecar.hpp"

#include <gtest/gtest.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <filesystem>
#include <sstream>
#include <string>

#include "build_paths.hpp"
#include "cli_runner.hpp"

namespace {

using mh::test::CliResult;
using mh::test::run_cli;
namespace pt = boost::property_tree;

pt::ptree read_json_file(const std::filesystem::path& path) {
  pt::ptree tree;
  std::istringstream in(mh::test::read_text(path));
  pt::read_json(in, tree);  // throws on anything that is not JSON
  return tree;
}

std::string sha256sum(const std::string& path) {
  const CliResult r = mh::test::run_shell("sha256sum '" + path + "'");
  return r.output.substr(0, r.output.find(' '));
}

// The library of the plugin entry of `kind` and `id`, "" when absent.
std::string library_of(const pt::ptree& meta, const std::string& kind, const std::string& id) {
  for (const auto& [key, entry] : meta.get_child("plugins"))
    if (entry.get<std::string>("kind") == kind && entry.get<std::string>("id") == id)
      return entry.get<std::string>("library");
  return "";
}

TEST(ResultSidecar, RunWritesValidJsonNamingTheLibrariesModelHashAndSettings) {
  const auto dir = mh::test::scratch_dir("sidecar-run");
  const auto csv = dir / "fourbar.csv";
  const std::string model = mh::test::shipped_model("fourbar.yaml");
  const CliResult r = run_cli("run " + model + " --t-end 0.02 --dt 0.002 --out " + csv.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto sidecar = dir / "fourbar.meta.json";
  ASSERT_TRUE(std::filesystem::exists(sidecar)) << r.output;
  pt::ptree meta;
  ASSERT_NO_THROW(meta = read_json_file(sidecar)) << mh::test::read_text(sidecar);
  EXPECT_EQ(meta.get<std::string>("result"), "fourbar.csv");
  EXPECT_FALSE(meta.get<std::string>("monohydra_version").empty());
  EXPECT_EQ(meta.get<std::string>("model.sha256"), sha256sum(model));
  EXPECT_EQ(meta.get<std::string>("model.sha256").size(), 64u);
  EXPECT_NE(meta.get<std::string>("command_line").find("run " + model + " --t-end 0.02"),
            std::string::npos);
  EXPECT_EQ(meta.get<std::string>("settings.formulation"), "double-step");
  EXPECT_EQ(meta.get<std::string>("settings.integrator"), "trapezoidal");
  EXPECT_DOUBLE_EQ(meta.get<double>("settings.dt"), 0.002);
  EXPECT_DOUBLE_EQ(meta.get<double>("settings.t_end"), 0.02);
  EXPECT_EQ(meta.get<int>("settings.max_iterations"), 25);  // the model file's
  EXPECT_EQ(library_of(meta, "formulation", "double-step"),
            std::filesystem::weakly_canonical(std::string(mh::test::paths::plugin_dir) +
                                              "/monohydra-double-step.so")
                .string());
  EXPECT_EQ(library_of(meta, "integrator", "trapezoidal"),
            std::filesystem::weakly_canonical(std::string(mh::test::paths::plugin_dir) +
                                              "/monohydra-integrators.so")
                .string());
  EXPECT_FALSE(library_of(meta, "subsystem", "cylinder").empty());
  EXPECT_NE(r.output.find("provenance:   " + sidecar.string()), std::string::npos) << r.output;
}

TEST(ResultSidecar, EveryCompareCsvGetsOneNamingItsOwnFormulationsLibrary) {
  const auto dir = mh::test::scratch_dir("sidecar-compare");
  const CliResult r = run_cli("compare " + mh::test::shipped_model("fourbar.yaml") +
                              " --t-end 0.01 --report " + dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  for (const std::string f : {"double-step", "penalty"}) {
    const auto sidecar = dir / (f + ".meta.json");
    ASSERT_TRUE(std::filesystem::exists(sidecar)) << f << "\n" << r.output;
    pt::ptree meta;
    ASSERT_NO_THROW(meta = read_json_file(sidecar)) << mh::test::read_text(sidecar);
    EXPECT_EQ(meta.get<std::string>("settings.formulation"), f);
    EXPECT_DOUBLE_EQ(meta.get<double>("settings.t_end"), 0.01);
    EXPECT_EQ(library_of(meta, "formulation", f),
              std::filesystem::weakly_canonical(std::string(mh::test::paths::plugin_dir) +
                                                "/monohydra-" + f + ".so")
                  .string());
  }
}

TEST(ResultSidecar, AnExplicitRunsStabilityCheckIsInItsSidecarAndAnImplicitRunsIsNull) {
  const auto dir = mh::test::scratch_dir("sidecar-stability");
  mh::cli::ResultProvenance p;
  p.model_path = mh::test::shipped_model("fourbar.yaml");
  p.formulation = "double-step";
  p.integrator = "rk4";
  mh::ExplicitStability s;
  s.checks = 2;
  s.unstable = true;
  s.t = 0.5;
  s.step = 501;
  s.h = 1e-3;
  s.amplification = 9984.0;
  s.eigenvalue = {-23060.0, 0.0};
  s.stable_dt = 1.21e-4;
  p.stability = &s;
  const auto result = (dir / "rk4.csv").string();
  ASSERT_TRUE(mh::cli::write_sidecar(result, p));
  pt::ptree meta;
  ASSERT_NO_THROW(meta = read_json_file(dir / "rk4.meta.json"));
  EXPECT_EQ(meta.get<std::string>("settings.explicit_stability"), "warn");
  EXPECT_TRUE(meta.get<bool>("explicit_stability.unstable"));
  EXPECT_EQ(meta.get<int>("explicit_stability.checks"), 2);
  EXPECT_EQ(meta.get<long>("explicit_stability.step"), 501);
  EXPECT_DOUBLE_EQ(meta.get<double>("explicit_stability.amplification"), 9984.0);
  EXPECT_DOUBLE_EQ(meta.get<double>("explicit_stability.stable_dt"), 1.21e-4);
  p.stability = nullptr;  // an implicit run
  ASSERT_TRUE(mh::cli::write_sidecar(result, p));
  ASSERT_NO_THROW(meta = read_json_file(dir / "rk4.meta.json"));
  EXPECT_EQ(meta.get<std::string>("explicit_stability"), "null");
}

TEST(ResultSidecar, ItsPathReplacesTheResultsExtension) {
  EXPECT_EQ(mh::cli::sidecar_path("out/run.csv"), "out/run.meta.json");
  EXPECT_EQ(mh::cli::sidecar_path("results"), "results.meta.json");
}

TEST(ResultSidecar, Sha256OfAKnownTextMatchesTheStandardsVector) {
  // FIPS 180-2's example: SHA-256("abc").
  const auto path = mh::test::scratch_dir("sidecar-sha") / "abc.txt";
  std::ofstream(path) << "abc";
  EXPECT_EQ(mh::cli::file_sha256(path.string()),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(mh::cli::file_sha256((path.parent_path() / "absent").string()), "");
}

}  // namespace
