// The FMU import (monohydra-fmu) on FMUs built from C by the tests
// (fmus/): a first-order plant against its closed form and the trapezoidal
// rule's error, its differenced tangent against its directional derivatives,
// a PI FMU against monohydra-control's pi-controller, a model of the FMU
// alone through `monohydra run`, a time event, snapshots, and each refusal's
// message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "hosts/cli_runner.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

#ifdef MH_HAVE_TEST_FMUS
std::string fmu_file(const std::string& name) {
  return std::string(mh::test::paths::fmu_dir) + "/" + name + ".fmu";
}

// A model of subsystems only (no bodies: key), dt = 1 ms.
std::string fmu_model(const std::string& subsystems, double t_end) {
  return "units: {length: m, mass: kg, time: s, angle: rad}\nsubsystems:\n" + subsystems +
         "solver: {dt: 0.001, t_end: " + std::to_string(t_end) + "}\n";
}

struct FmuRun {
  explicit FmuRun(const std::string& subsystems, double t_end = 5.0)
      : file(parse_model_text(fmu_model(subsystems, t_end), "fmu-model.yaml")),
        sim(std::make_unique<Simulation>(file, test::build_plugins())) {
    sim->start();
  }
  double state(const std::string& name) const {
    const int i = sim->state_index(name);
    EXPECT_GE(i, 0) << name;
    return i < 0 ? NAN : sim->states()[i];
  }
  ModelFile file;
  std::unique_ptr<Simulation> sim;
};

std::string plant(const std::string& name, const std::string& fmu, const std::string& extra = "") {
  return "  - {name: " + name + ", type: fmu, fmu: '" + fmu_file(fmu) + "'" + extra + "}\n";
}

// x' = -x, x(0) = 1 (tau = k = 1, u = 0): x = exp(-t). The trapezoidal rule's
// amplification (1 - h/2)/(1 + h/2) = exp(-h - h^3/12 + ...) leaves the error
// t exp(-t) h^2 / 12 to leading order: at most h^2 / (12 e) = 3.07e-8 at t = 1.
TEST(FmuImport, PlantMatchesItsClosedFormWithinTheTrapezoidalError) {
  FmuRun run(plant("d", "plant"));
  const double h = 0.001;
  double worst = 0.0, worst_y = 0.0;
  while (run.sim->time() < 5.0 - 1e-12) {
    run.sim->step();
    const double t = run.sim->time();
    const double x = run.state("d.x");
    if (t >= 1.0 - 1e-12) worst = std::max(worst, std::abs(x - std::exp(-t)));
    worst_y = std::max(worst_y, std::abs(run.state("d.y") - 2.0 * x));
  }
  const double bound = h * h / (12.0 * std::exp(1.0));
  RecordProperty("worst_error_1_to_5s", test::scientific(worst));
  EXPECT_LT(worst, 1.01 * bound);
  EXPECT_GT(worst, 0.99 * bound);  // it is the trapezoidal rule's own error, not another one
  EXPECT_LT(worst_y, 1e-9);        // the output y = 2 x, an algebraic state
}

// The FMU without directional derivatives (central differences of its
// functions) runs the same steps: u from a table, tau and k as options.
TEST(FmuImport, DifferencedTangentAgreesWithDirectionalDerivatives) {
  const std::string options = ", u: [[0, 0], [0.5, 0], [1.5, 2], [3, 2]], tau: 0.4, k: 1.5";
  FmuRun run(plant("dd", "plant", options) + plant("fd", "plant_fd", options), 3.0);
  double worst = 0.0;
  while (run.sim->time() < 3.0 - 1e-12) {
    run.sim->step();
    worst = std::max(worst, std::abs(run.state("dd.x") - run.state("fd.x")));
  }
  RecordProperty("worst_difference", test::scientific(worst));
  EXPECT_LT(worst, 1e-10);
  EXPECT_NEAR(run.state("dd.x"), 1.5 * 0.4 * 2.0, 0.05);  // near k tau u
  // Both tangents against the host's central differences of the residual.
  const Eigen::MatrixXd J = run.sim->assembled_tangent();
  const Eigen::MatrixXd J_cd = run.sim->central_difference_tangent();
  ASSERT_EQ(J.rows(), J_cd.rows());
  EXPECT_GT(J_cd.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT((J - J_cd).cwiseAbs().maxCoeff(), 1e-6 * J_cd.cwiseAbs().maxCoeff()) << J << "\n"
                                                                                 << J_cd;
}

// The PI FMU and monohydra-control's pi-controller on one measurement (a
// lag of a table), through the output limits, and a gain reading the FMU's
// output: the FMU's output is a state of the run as the block's is.
TEST(FmuImport, PiControllerMatchesItsNativeTwin) {
  const std::string gains =
      "setpoint: [[0, 0], [0.2, 0], [0.2, 1], [2, 1], [2, -0.5], [4, -0.5]], "
      "measurement: lag.y, kp: 3, ki: 4, output_min: -1, output_max: 1.5, tracking_time: 0.3";
  FmuRun run(
      "  - {name: lag, type: first-order-lag, input: [[0, 0], [1, 0.8], [4, 0.8]], "
      "time_constant: 0.3}\n"
      "  - {name: native, type: pi-controller, " +
          gains +
          "}\n"
          "  - {name: imported, type: fmu, fmu: '" +
          fmu_file("pi") + "', " + gains +
          "}\n"
          "  - {name: g, type: gain, input: imported.u, gain: 2}\n",
      4.0);
  double worst = 0.0, highest = -1e9, lowest = 1e9;
  while (run.sim->time() < 4.0 - 1e-12) {
    run.sim->step();
    worst = std::max({worst, std::abs(run.state("native.u") - run.state("imported.u")),
                      std::abs(run.state("native.i") - run.state("imported.i"))});
    highest = std::max(highest, run.state("imported.u"));
    lowest = std::min(lowest, run.state("imported.u"));
    EXPECT_NEAR(run.state("g.y"), 2.0 * run.state("imported.u"), 1e-9);
  }
  RecordProperty("worst_difference", test::scientific(worst));
  EXPECT_LT(worst, 1e-9);
  EXPECT_DOUBLE_EQ(highest, 1.5);  // both limits were reached
  EXPECT_DOUBLE_EQ(lowest, -1.0);
}

// The boom's position loop (models/fourbar-position-control.yaml) with its
// PI controller replaced by the PI FMU: the sensor's state feeds the FMU's
// input, the FMU's output drives the valve's reference, through the
// mechanics and the hydraulics in one Newton step. Both runs agree.
TEST(FmuImport, PiFmuClosesTheBoomsPositionLoopAsTheNativeBlockDoes) {
  std::ifstream in(test::source_path("models/fourbar-position-control.yaml"));
  std::string native((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string imported = native;
  const auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = imported.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    imported.replace(at, from.size(), to);
  };
  // The native block's Tt defaults to kp / ki = 1.2 s; the FMU's is a parameter.
  replace("    type: pi-controller\n",
          "    type: fmu\n    fmu: '" + fmu_file("pi") + "'\n    tracking_time: 1.2\n");
  replace("    unit: V\n", "");
  const std::string folder = test::source_path("models");
  const ModelFile native_file = parse_model_text(native, "native.yaml", folder);
  const ModelFile imported_file = parse_model_text(imported, "imported.yaml", folder);
  Simulation a(native_file, test::build_plugins()), b(imported_file, test::build_plugins());
  a.start();
  b.start();
  const int stroke = a.state_index("stroke"), command = a.state_index("U_cmd");
  ASSERT_GE(stroke, 0);
  ASSERT_EQ(stroke, b.state_index("stroke"));
  ASSERT_EQ(command, b.state_index("U_cmd"));
  double worst_stroke = 0.0, worst_command = 0.0, highest = 0.0;
  while (a.time() < 6.0 - 1e-9) {
    a.step();
    b.step();
    worst_stroke = std::max(worst_stroke, std::abs(a.states()[stroke] - b.states()[stroke]));
    worst_command = std::max(worst_command, std::abs(a.states()[command] - b.states()[command]));
    highest = std::max(highest, b.states()[command]);
  }
  RecordProperty("worst_stroke_difference", test::scientific(worst_stroke));
  RecordProperty("worst_command_difference", test::scientific(worst_command));
  EXPECT_LT(worst_stroke, 1e-9);    // m
  EXPECT_LT(worst_command, 1e-9);   // V
  EXPECT_DOUBLE_EQ(highest, 10.0);  // the command saturated after the step at 1 s
  EXPECT_NEAR(b.states()[stroke], 0.01, 1e-3);
}

// The plant's bias switches on at bias_time = 0.5 s, a time event the FMU
// announces at its start: the host ends a step there, so x follows
// b + (x(0.5) - b) exp(-(t - 0.5)) with the trapezoidal error only (a
// step late would cost ~ b h = 5e-4).
TEST(FmuImport, TimeEventTakenWhereTheFmuAnnouncesIt) {
  FmuRun run(plant("d", "plant", ", bias_time: 0.5, bias: 0.5"), 3.0);
  double worst = 0.0;
  while (run.sim->time() < 3.0 - 1e-12) {
    run.sim->step();
    const double t = run.sim->time();
    const double exact =
        t <= 0.5 ? std::exp(-t) : 0.5 + (std::exp(-0.5) - 0.5) * std::exp(-(t - 0.5));
    worst = std::max(worst, std::abs(run.state("d.x") - exact));
  }
  RecordProperty("worst_error", test::scientific(worst));
  EXPECT_LT(worst, 1e-7);
}

// The bias switches off at bias_off_time = 1.2505 s, a time event the FMU
// announces only at the first one (not the host's): taken at the first
// step that reaches it, 1.251 s, and the step after it starts from the rate
// before it. The error is about bias (delay + dt / 2) <= 1.5 bias dt.
TEST(FmuImport, LaterTimeEventTakenAtTheStepThatReachesIt) {
  const double bias = 0.5, off = 1.2505, dt = 0.001;
  FmuRun run(plant("d", "plant", ", bias_time: 0.5, bias: 0.5, bias_off_time: 1.2505"), 3.0);
  const double x_off = bias + (std::exp(-0.5) - bias) * std::exp(-(off - 0.5));
  double worst_before = 0.0, worst_after = 0.0;
  while (run.sim->time() < 3.0 - 1e-12) {
    run.sim->step();
    const double t = run.sim->time();
    const double x = run.state("d.x");
    const double on = bias + (std::exp(-0.5) - bias) * std::exp(-(t - 0.5));
    if (t <= 1.25 + 1e-12)
      worst_before = std::max(worst_before, std::abs(x - (t <= 0.5 ? std::exp(-t) : on)));
    if (t >= 1.26) worst_after = std::max(worst_after, std::abs(x - x_off * std::exp(-(t - off))));
  }
  RecordProperty("worst_error_before", test::scientific(worst_before));
  RecordProperty("worst_error_after", test::scientific(worst_after));
  EXPECT_LT(worst_before, 1e-7);
  EXPECT_LT(worst_after, 1.5 * bias * dt);
  EXPECT_GT(worst_after, 1e-5);  // the event was taken (without it x would stay near 0.5)
}

// The FMU reads resources/start.txt through its resourcePath: the folder
// (found by its start.txt, as other test processes unpack FMUs at the same
// time) stays while the instance lives and goes with it.
TEST(FmuImport, ResourcesStayForTheInstanceAndGoWithIt) {
  namespace fs = std::filesystem;
  const auto unpacked_with_resources = [] {
    std::vector<fs::path> found;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::temp_directory_path(), ec))
      if (e.path().filename().string().rfind("monohydra-fmu-", 0) == 0 &&
          fs::exists(e.path() / "resources" / "start.txt", ec))
        found.push_back(e.path());
    return found;
  };
  const std::vector<fs::path> before = unpacked_with_resources();
  fs::path ours;
  {
    FmuRun run(plant("d", "plant_resource"), 1.0);
    EXPECT_EQ(run.state("d.x"), 0.25);
    for (const fs::path& p : unpacked_with_resources())
      if (std::find(before.begin(), before.end(), p) == before.end()) ours = p;
    ASSERT_FALSE(ours.empty()) << "no unpacked folder with resources/start.txt";
    EXPECT_FALSE(fs::exists(ours / "binaries")) << "the loaded binary's folder was kept";
    run.sim->step();
    EXPECT_NEAR(run.state("d.x"), 0.25 * std::exp(-0.001), 1e-9);
  }
  EXPECT_FALSE(fs::exists(ours)) << ours;
}

// A snapshot before the event and one after it: a new run restored from
// either continues to the same bits.
TEST(FmuImport, SnapshotRestoreContinuesIdentically) {
  const std::string model = plant("d", "plant", ", bias_time: 2, bias: 0.5, u: [[0, 0], [4, 1]]");
  for (const double at : {1.0, 3.0}) {
    FmuRun first(model, 4.0);
    while (first.sim->time() < at - 1e-12) first.sim->step();
    const RunState saved = first.sim->save_state();
    while (first.sim->time() < 4.0 - 1e-12) first.sim->step();
    FmuRun second(model, 4.0);
    second.sim->restore_state(saved);
    EXPECT_DOUBLE_EQ(second.sim->time(), at);
    while (second.sim->time() < 4.0 - 1e-12) second.sim->step();
    EXPECT_EQ(first.state("d.x"), second.state("d.x")) << "restored at " << at;
    EXPECT_EQ(first.state("d.y"), second.state("d.y")) << "restored at " << at;
  }
}

TEST(FmuImport, SnapshotOfAnFmuThatCannotSerializeIsRefusedSayingWhy) {
  FmuRun run(plant("d", "plant_fd"), 1.0);
  run.sim->step();
  try {
    (void)run.sim->save_state();
    FAIL() << "a snapshot was taken";
  } catch (const std::exception& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("cannot save or restore its state"), std::string::npos) << what;
    EXPECT_NE(what.find("canSerializeFMUState"), std::string::npos) << what;
  }
}

// `monohydra run` on a model of the FMU alone, its fmu: relative to the model
// file: the column d.x holds the solution.
TEST(FmuImport, ModelOfAnFmuAloneRunsThroughTheCommandLine) {
  const std::filesystem::path dir = test::scratch_root() / "fmu-alone";
  std::filesystem::create_directories(dir / "fmus");
  std::filesystem::copy_file(fmu_file("plant"), dir / "fmus" / "plant.fmu",
                             std::filesystem::copy_options::overwrite_existing);
  {
    std::ofstream out(dir / "alone.yaml");
    out << "units: {length: m, mass: kg, time: s, angle: rad}\n"
           "subsystems:\n  - {name: d, type: fmu, fmu: fmus/plant.fmu}\n"
           "solver: {dt: 0.001, t_end: 2}\n";
  }
  const test::CliResult r = test::run_cli(
      "run " + (dir / "alone.yaml").string() + " --out " + (dir / "out.csv").string(), "", "/");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(dir / "out.csv");
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  EXPECT_EQ(header.rfind("t,d.x,d.y,", 0), 0u) << header;
  const double x = std::stod(last.substr(last.find(',') + 1));
  EXPECT_NEAR(x, std::exp(-2.0), 1e-7) << last;
}

// Each FMU that cannot be run is refused at setup, with the model file, the
// field, the FMU's path and what is wrong.
void expect_refused(const std::string& fmu_path, const std::string& reason) {
  try {
    FmuRun run("  - {name: d, type: fmu, fmu: '" + fmu_path + "'}\n", 1.0);
    FAIL() << fmu_path << " was accepted";
  } catch (const std::exception& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("fmu-model.yaml:3"), std::string::npos) << what;
    EXPECT_NE(what.find("subsystem 'd' (fmu) option 'fmu'"), std::string::npos) << what;
    EXPECT_NE(what.find(fmu_path), std::string::npos) << what;
    EXPECT_NE(what.find(reason), std::string::npos) << what;
  }
}

TEST(FmuImport, RefusesAMissingFile) {
  expect_refused(std::string(mh::test::paths::fmu_dir) + "/absent.fmu", "it does not exist");
}
TEST(FmuImport, RefusesAFileThatIsNotAZip) {
  expect_refused(fmu_file("not_a_zip"), "it is not a zip archive");
}
TEST(FmuImport, RefusesAnFmuWithoutABinaryForThisPlatform) {
  expect_refused(fmu_file("no_binary"), "no binary for this platform (no binaries/x86_64-linux/");
}
TEST(FmuImport, RefusesAnFmi2Fmu) {
  expect_refused(fmu_file("version2"), "it is an FMI 2.0 FMU (fmiVersion=\"2.0\")");
}
TEST(FmuImport, RefusesACoSimulationOnlyFmu) {
  expect_refused(fmu_file("cs_only"), "Co-Simulation FMU only (no <ModelExchange>)");
}
TEST(FmuImport, RefusesAWrongInstantiationToken) {
  expect_refused(fmu_file("wrong_token"),
                 "instantiationToken of its modelDescription.xml ({plant-0})");
}
TEST(FmuImport, RefusesABinaryThatLacksAFunction) {
  expect_refused(fmu_file("missing_function"),
                 "lacks functions the import calls: "
                 "fmi3GetContinuousStateDerivatives");
}
TEST(FmuImport, RefusesStateEvents) {
  expect_refused(fmu_file("state_events"), "it has state events (1 event indicators)");
}
#endif

TEST(ModelOfSubsystemsOnly, ModelWithNeitherBodiesNorSubsystemsIsRefused) {
  try {
    (void)parse_model_text("units: {length: m, mass: kg, time: s, angle: rad}\n", "empty.yaml");
    FAIL() << "an empty model was accepted";
  } catch (const std::exception& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("empty.yaml:1"), std::string::npos) << what;
    EXPECT_NE(what.find("bodies"), std::string::npos) << what;
    EXPECT_NE(what.find("found neither"), std::string::npos) << what;
  }
}

// A signal chain without bodies runs with open-loop and penalty alike.
TEST(ModelOfSubsystemsOnly, RunsWithOpenLoopAndPenalty) {
  for (const char* formulation : {"open-loop", "penalty"}) {
    const ModelFile file = parse_model_text(
        std::string("units: {length: m, mass: kg, time: s, angle: rad}\nsubsystems:\n"
                    "  - {name: lag, type: first-order-lag, input: [[0, 1], [1, 1]], "
                    "time_constant: 0.5}\nformulation: ") +
            formulation + "\nsolver: {dt: 0.001, t_end: 1}\n",
        "chain.yaml");
    Simulation sim(file, test::build_plugins());
    sim.start();
    while (sim.time() < 1.0 - 1e-12) sim.step();
    EXPECT_NEAR(sim.states()[sim.state_index("lag.y")], 1.0 - std::exp(-2.0), 1e-6) << formulation;
  }
}

}  // namespace
}  // namespace mh
