// `monohydra fmu`'s FMUs driven by the tests' importer (fmu_importer.hpp)
// through the standard's calling sequence, and compared with `monohydra
// run`: the same numbers at every communication point, FMU states that
// repeat a run to the bit, inputs that move the machine, failures and bad
// calls that return errors with reasons, and descriptions that keep the
// standard's rules.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

// GoogleTest's instance first, so that it outlives the scratch folder's
// cleanup (cli_runner.hpp), which asks it at exit whether every test passed.
static const ::testing::UnitTest* const kUnitTest = ::testing::UnitTest::GetInstance();

#include "../cli_runner.hpp"
#include "build_paths.hpp"
#include "fmu_importer.hpp"
#include "model_description_rules.hpp"

namespace fs = std::filesystem;
using mh::test::Csv;
using mh::test::Fmi2Functions;
using mh::test::Fmi3Functions;
using mh::test::LogRecord;
using mh::test::Unpacked;

namespace {

// An FMU written by `monohydra fmu`, unpacked, its binary loaded on first
// use (so that a test process loads only the engines it drives: LeakSanitizer's
// exit scan fails in a process holding two of them).
struct Exported {
  Unpacked fmu;
  const Fmi3Functions& f() {
    if (!loaded) functions = mh::test::load_fmi3(fmu);
    loaded = true;
    return functions;
  }
  ~Exported() { mh::test::unload(functions.handle); }

 private:
  bool loaded = false;
  Fmi3Functions functions;
};

std::unique_ptr<Exported> export_fmu(const std::string& model, const std::string& name,
                                     const std::string& flags = "") {
  const fs::path dir = mh::test::scratch_dir("fmu-" + name);
  const fs::path file = dir / (name + ".fmu");
  const auto done = mh::test::run_cli("fmu " + model + " --out " + file.string() + " " + flags);
  EXPECT_EQ(done.code, 0) << done.output;
  auto e = std::make_unique<Exported>();
  e->fmu = mh::test::unpack(file, dir / "unpacked");
  return e;
}

// One of the FMUs the build wrote (tests/CMakeLists.txt: mh_test_fmus), unpacked.
std::unique_ptr<Exported> built_fmu(const std::string& name) {
  auto e = std::make_unique<Exported>();
  e->fmu = mh::test::unpack(fs::path(mh::test::paths::exported_fmus) / (name + ".fmu"),
                            mh::test::scratch_dir("fmu-" + name) / "unpacked");
  return e;
}

Csv run_csv(const std::string& model, const std::string& name, const std::string& flags = "") {
  const fs::path csv = mh::test::scratch_dir("run-" + name) / "run.csv";
  const auto done = mh::test::run_cli("run " + model + " --out " + csv.string() + " " + flags);
  EXPECT_EQ(done.code, 0) << done.output;
  return mh::test::read_csv(csv);
}

// One instance of an FMI 3.0 FMU, in Step Mode after initialisation.
class Instance {
 public:
  Instance(Exported& e, LogRecord& log, bool initialise = true) : f_(e.f()) {
    const std::string resources = (e.fmu.dir / "resources").string() + "/";
    handle_ =
        f_.fmi3InstantiateCoSimulation("test", e.fmu.token.c_str(), resources.c_str(), false, false,
                                       false, false, nullptr, 0, &log, mh::test::log_fmi3, nullptr);
    if (handle_ != nullptr && initialise) {
      EXPECT_EQ(f_.fmi3EnterInitializationMode(handle_, false, 0.0, 0.0, false, 0.0), fmi3OK);
      EXPECT_EQ(f_.fmi3ExitInitializationMode(handle_), fmi3OK);
    }
  }
  ~Instance() {
    if (handle_ != nullptr) f_.fmi3FreeInstance(handle_);
  }
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;
  fmi3Instance get() const { return handle_; }
  fmi3Status step(double t, double h) {
    fmi3Boolean event = false, terminate = false, early = false;
    fmi3Float64 last = 0.0;
    return f_.fmi3DoStep(handle_, t, h, true, &event, &terminate, &early, &last);
  }
  std::vector<double> get(const std::vector<fmi3ValueReference>& vrs) {
    std::vector<double> v(vrs.size());
    EXPECT_EQ(f_.fmi3GetFloat64(handle_, vrs.data(), vrs.size(), v.data(), v.size()), fmi3OK);
    return v;
  }
  fmi3Status set(fmi3ValueReference vr, double value) {
    return f_.fmi3SetFloat64(handle_, &vr, 1, &value, 1);
  }

 private:
  const Fmi3Functions& f_;
  fmi3Instance handle_ = nullptr;
};

std::vector<fmi3ValueReference> refs(const Unpacked& fmu, const std::vector<std::string>& names) {
  std::vector<fmi3ValueReference> out;
  for (const std::string& n : names) out.push_back(fmu.vr.at(n));
  return out;
}

// Drives `e` from 0 to `t_end` at communication step `h` and compares every
// communication point with the CSV's row at that time: angles to `angle_tol`
// rad, pressures to `pressure_tol` Pa. Returns the points compared.
int compare_with_run(Exported& e, const Csv& csv, double h, double t_end,
                     const std::vector<std::string>& angles,
                     const std::vector<std::string>& pressures, double angle_tol,
                     double pressure_tol) {
  LogRecord log;
  Instance in(e, log);
  std::vector<std::string> names = angles;
  names.insert(names.end(), pressures.begin(), pressures.end());
  const auto vrs = refs(e.fmu, names);
  const std::vector<double>& t_csv = csv["t"];
  std::size_t row = 0;
  int compared = 0;
  double worst_angle = 0.0, worst_pressure = 0.0;
  const long n = std::lround(t_end / h);
  for (long k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) * h;
    if (k > 0) {
      EXPECT_EQ(in.step(static_cast<double>(k - 1) * h, h), fmi3OK) << log.all();
    }
    while (row < t_csv.size() && t_csv[row] < t - 1e-9) ++row;
    if (row == t_csv.size() || std::fabs(t_csv[row] - t) > 1e-9) continue;
    const std::vector<double> v = in.get(vrs);
    for (std::size_t j = 0; j < names.size(); ++j) {
      const double d = std::fabs(v[j] - csv[names[j]][row]);
      (j < angles.size() ? worst_angle : worst_pressure) =
          std::max(j < angles.size() ? worst_angle : worst_pressure, d);
    }
    ++compared;
  }
  std::printf("%d points: largest difference %.3e rad, %.3e Pa\n", compared, worst_angle,
              worst_pressure);
  EXPECT_LE(worst_angle, angle_tol);
  EXPECT_LE(worst_pressure, pressure_tol);
  return compared;
}

class ExportedFmu : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fourbar_ = built_fmu("fourbar").release();
    excavator_ = built_fmu("excavator").release();
  }
  static void TearDownTestSuite() {
    delete fourbar_;
    delete excavator_;
  }
  static Exported* fourbar_;
  static Exported* excavator_;
};
Exported* ExportedFmu::fourbar_ = nullptr;
Exported* ExportedFmu::excavator_ = nullptr;

TEST_F(ExportedFmu, ExportsEveryFunctionOfTheStandard) {
  EXPECT_TRUE(fourbar_->f().missing.empty()) << fourbar_->f().missing.front();
  EXPECT_STREQ(fourbar_->f().fmi3GetVersion(), "3.0");
  const Fmi2Functions f2 = mh::test::load_fmi2(fourbar_->fmu);
  EXPECT_TRUE(f2.missing.empty()) << f2.missing.front();
  EXPECT_STREQ(f2.fmi2GetVersion(), "2.0");
  EXPECT_STREQ(f2.fmi2GetTypesPlatform(), "default");
  mh::test::unload(f2.handle);
}

TEST_F(ExportedFmu, ModelDescriptionKeepsTheStandardsRules) {
  for (const Exported* e : {fourbar_, excavator_}) {
    const auto violations = mh::test::model_description_violations(e->fmu.description);
    std::string text;
    for (const auto& v : violations) text += v + "\n";
    EXPECT_TRUE(violations.empty()) << text;
  }
}

TEST_F(ExportedFmu, EveryColumnOfRunIsAnOutputWithItsName) {
  const Csv csv = run_csv(mh::test::shipped_model("fourbar.yaml"), "columns", "--t-end 0.01");
  const pugi::xml_node vars =
      fourbar_->fmu.description.child("fmiModelDescription").child("ModelVariables");
  for (const std::string& column : csv.header) {
    const pugi::xml_node v = vars.find_child_by_attribute("Float64", "name", column.c_str());
    ASSERT_TRUE(v) << column;
    EXPECT_STREQ(v.attribute("causality").value(), "output") << column;
  }
  const pugi::xml_node input = vars.find_child_by_attribute("Float64", "name", "valve_command");
  EXPECT_STREQ(input.attribute("causality").value(), "input");
  EXPECT_STREQ(input.attribute("unit").value(), "V");
  EXPECT_DOUBLE_EQ(input.attribute("max").as_double(), 10.0);
  const pugi::xml_node p =
      vars.find_child_by_attribute("Float64", "name", "subsystems.pump.pressure");
  EXPECT_STREQ(p.attribute("causality").value(), "parameter");
  EXPECT_DOUBLE_EQ(p.attribute("start").as_double(), 7.6e6);
  const pugi::xml_node cs =
      fourbar_->fmu.description.child("fmiModelDescription").child("CoSimulation");
  EXPECT_DOUBLE_EQ(cs.attribute("fixedInternalStepSize").as_double(), 1e-3);
  EXPECT_STREQ(cs.attribute("canSerializeFMUState").value(), "true");
}

TEST_F(ExportedFmu, FourbarAtOneMillisecondMatchesMonohydraRun) {
  const Csv csv = run_csv(mh::test::shipped_model("fourbar.yaml"), "fourbar");
  const int compared = compare_with_run(*fourbar_, csv, 1e-3, 10.0, {"z1", "z2", "z3"},
                                        {"p1", "p2", "p3"}, 1e-12, 1e-6);
  EXPECT_EQ(compared, 10001);
}

TEST_F(ExportedFmu, ExcavatorAtTenMillisecondsMatchesMonohydraRun) {
  const Csv csv = run_csv(mh::test::shipped_model("excavator.yaml"), "excavator", "--t-end 10");
  const int compared = compare_with_run(
      *excavator_, csv, 1e-2, 10.0, {"z1", "z2", "z3", "z4", "z5", "z6", "z7", "z8", "z9", "z10"},
      {"p_supply", "p_boom_a", "p_boom_b", "p_arm_a", "p_arm_b", "p_bucket_a", "p_bucket_b",
       "p_slew_a", "p_slew_b"},
      1e-12, 1e-6);
  EXPECT_EQ(compared, 1001);
}

// Runs from the instance's time to `t_end` in steps of h and returns every output there.
std::vector<double> run_to(Instance& in, const Unpacked& fmu, double from, double t_end, double h) {
  const long n = std::lround((t_end - from) / h);
  for (long k = 0; k < n; ++k) EXPECT_EQ(in.step(from + static_cast<double>(k) * h, h), fmi3OK);
  std::vector<fmi3ValueReference> all;
  for (const auto& [name, vr] : fmu.vr) all.push_back(vr);
  return in.get(all);
}

TEST_F(ExportedFmu, StateSavedAt4sAndRestoredRepeatsTheRunBitForBit) {
  LogRecord log;
  Instance in(*fourbar_, log);
  run_to(in, fourbar_->fmu, 0.0, 4.0, 1e-2);
  fmi3FMUState state = nullptr;
  ASSERT_EQ(fourbar_->f().fmi3GetFMUState(in.get(), &state), fmi3OK) << log.all();
  const std::vector<double> first = run_to(in, fourbar_->fmu, 4.0, 10.0, 1e-2);
  ASSERT_EQ(fourbar_->f().fmi3SetFMUState(in.get(), state), fmi3OK) << log.all();
  const std::vector<double> again = run_to(in, fourbar_->fmu, 4.0, 10.0, 1e-2);
  EXPECT_EQ(first, again);  // to the bit
  // Restoring put the run back: the time reads 4 s again.
  ASSERT_EQ(fourbar_->f().fmi3SetFMUState(in.get(), state), fmi3OK);
  EXPECT_DOUBLE_EQ(in.get({fourbar_->fmu.vr.at("time")})[0], 4.0);
  EXPECT_EQ(fourbar_->f().fmi3FreeFMUState(in.get(), &state), fmi3OK);
  EXPECT_EQ(state, nullptr);
}

TEST_F(ExportedFmu, SerializedStateContinuesIdenticallyInANewInstance) {
  LogRecord log;
  std::vector<fmi3Byte> bytes;
  std::vector<double> first;
  {
    Instance in(*excavator_, log);
    run_to(in, excavator_->fmu, 0.0, 4.0, 1e-2);
    fmi3FMUState state = nullptr;
    ASSERT_EQ(excavator_->f().fmi3GetFMUState(in.get(), &state), fmi3OK) << log.all();
    size_t size = 0;
    ASSERT_EQ(excavator_->f().fmi3SerializedFMUStateSize(in.get(), state, &size), fmi3OK);
    bytes.resize(size);
    ASSERT_EQ(excavator_->f().fmi3SerializeFMUState(in.get(), state, bytes.data(), size), fmi3OK);
    excavator_->f().fmi3FreeFMUState(in.get(), &state);
    first = run_to(in, excavator_->fmu, 4.0, 6.0, 1e-2);
  }
  Instance fresh(*excavator_, log);
  fmi3FMUState state = nullptr;
  ASSERT_EQ(
      excavator_->f().fmi3DeserializeFMUState(fresh.get(), bytes.data(), bytes.size(), &state),
      fmi3OK)
      << log.all();
  ASSERT_EQ(excavator_->f().fmi3SetFMUState(fresh.get(), state), fmi3OK) << log.all();
  EXPECT_EQ(run_to(fresh, excavator_->fmu, 4.0, 6.0, 1e-2), first);
  excavator_->f().fmi3FreeFMUState(fresh.get(), &state);
  // Damaged bytes are refused with a reason, and nothing is restored.
  bytes[bytes.size() / 2] ^= 0x5a;
  fmi3FMUState damaged = nullptr;
  const fmi3Status s =
      excavator_->f().fmi3DeserializeFMUState(fresh.get(), bytes.data(), bytes.size(), &damaged);
  if (s == fmi3OK) {
    EXPECT_NE(excavator_->f().fmi3SetFMUState(fresh.get(), damaged), fmi3OK);
    excavator_->f().fmi3FreeFMUState(fresh.get(), &damaged);
  } else {
    EXPECT_EQ(s, fmi3Error);
  }
  EXPECT_NE(log.all().find("fmi3"), std::string::npos);
}

TEST_F(ExportedFmu, AnInputDrivenByTheImporterMovesTheBoom) {
  // The cycle keeps the boom valve closed until 1.5 s; the importer opens it
  // from t = 0 one way, then the other: the boom cylinders move each way.
  const auto stroke = refs(excavator_->fmu, {"s_boom_l"});
  const fmi3ValueReference lever = excavator_->fmu.vr.at("boom_command");
  std::vector<double> moved;
  for (const double command : {0.0, 8.0, -8.0}) {
    LogRecord log;
    Instance in(*excavator_, log, false);
    ASSERT_EQ(excavator_->f().fmi3EnterInitializationMode(in.get(), false, 0, 0, false, 0), fmi3OK);
    const double s0 = in.get(stroke)[0];
    ASSERT_EQ(excavator_->f().fmi3ExitInitializationMode(in.get()), fmi3OK);
    if (command != 0.0) {
      ASSERT_EQ(in.set(lever, command), fmi3OK) << log.all();
    }
    run_to(in, excavator_->fmu, 0.0, 1.0, 1e-2);
    moved.push_back(in.get(stroke)[0] - s0);
    EXPECT_DOUBLE_EQ(in.get({lever})[0], command);
  }
  EXPECT_LT(std::fabs(moved[0]), 1e-3);  // the table's closed valve: the boom holds
  EXPECT_GT(std::fabs(moved[1]), 2e-2);  // 2 cm in a second, at least
  EXPECT_GT(std::fabs(moved[2]), 2e-2);
  EXPECT_LT(moved[1] * moved[2], 0.0);  // the other way
}

TEST_F(ExportedFmu, AParameterSetBeforeInitialisationIsTheRunsValue) {
  const fs::path dir = mh::test::scratch_dir("fmu-parameter");
  std::string text = mh::test::read_text(mh::test::shipped_model("fourbar.yaml"));
  const std::string from = "pressure: 7.6e6", to = "pressure: 6.5e6";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), to);
  std::ofstream(dir / "fourbar-6.5MPa.yaml") << text;
  const Csv csv = run_csv((dir / "fourbar-6.5MPa.yaml").string(), "parameter", "--t-end 3");
  LogRecord log;
  Instance in(*fourbar_, log, false);
  ASSERT_EQ(in.set(fourbar_->fmu.vr.at("subsystems.pump.pressure"), 6.5e6), fmi3OK) << log.all();
  ASSERT_EQ(fourbar_->f().fmi3EnterInitializationMode(in.get(), false, 0, 0, false, 0), fmi3OK);
  ASSERT_EQ(fourbar_->f().fmi3ExitInitializationMode(in.get()), fmi3OK) << log.all();
  const auto vrs = refs(fourbar_->fmu, {"z1", "p1", "subsystems.pump.pressure"});
  run_to(in, fourbar_->fmu, 0.0, 3.0, 1e-3);
  const std::vector<double> v = in.get(vrs);
  EXPECT_NEAR(v[0], csv["z1"].back(), 1e-12);
  EXPECT_NEAR(v[1], csv["p1"].back(), 1e-6);
  EXPECT_EQ(v[2], 6.5e6);
  // A fixed parameter is refused once the run is in Step Mode.
  EXPECT_EQ(in.set(fourbar_->fmu.vr.at("subsystems.pump.pressure"), 7e6), fmi3Error);
  EXPECT_NE(log.all().find("fixed"), std::string::npos) << log.all();
}

// A body's mass is tunable: set in Step Mode it acts from that step on, an
// FMU state holds it (restoring one puts the mass back with the run), and
// the same change gives the same run to the bit.
TEST_F(ExportedFmu, ATunableMassSetInStepModeActsAndAStateRestoresItWithTheRun) {
  const Unpacked& fmu = fourbar_->fmu;
  const std::string description = mh::test::read_text(fmu.dir / "modelDescription.xml");
  EXPECT_NE(description.find("name=\"bodies.body3.mass\""), std::string::npos);
  const std::size_t mass_at = description.find("name=\"bodies.body3.mass\"");
  const std::size_t mass_end = description.find("/>", mass_at);
  EXPECT_NE(description.substr(mass_at, mass_end - mass_at).find("variability=\"tunable\""),
            std::string::npos);
  LogRecord log;
  Instance nominal(*fourbar_, log);
  const std::vector<double> unchanged = run_to(nominal, fmu, 0.0, 4.0, 1e-2);

  Instance in(*fourbar_, log);
  run_to(in, fmu, 0.0, 2.0, 1e-2);
  fmi3FMUState at2 = nullptr;
  ASSERT_EQ(fourbar_->f().fmi3GetFMUState(in.get(), &at2), fmi3OK) << log.all();
  const fmi3ValueReference mass = fmu.vr.at("bodies.body3.mass");
  ASSERT_EQ(in.set(mass, 80.0), fmi3OK) << log.all();
  const std::vector<double> heavier = run_to(in, fmu, 2.0, 4.0, 1e-2);
  EXPECT_NE(heavier, unchanged);
  EXPECT_EQ(in.get({mass})[0], 80.0);

  ASSERT_EQ(fourbar_->f().fmi3SetFMUState(in.get(), at2), fmi3OK) << log.all();
  EXPECT_EQ(in.get({mass})[0], 50.0);
  EXPECT_EQ(run_to(in, fmu, 2.0, 4.0, 1e-2), unchanged);  // the state put the mass back

  // Serialized and read back into a new instance, the state carries it too.
  ASSERT_EQ(fourbar_->f().fmi3SetFMUState(in.get(), at2), fmi3OK) << log.all();
  ASSERT_EQ(in.set(mass, 80.0), fmi3OK) << log.all();
  fmi3FMUState heavy = nullptr;
  ASSERT_EQ(fourbar_->f().fmi3GetFMUState(in.get(), &heavy), fmi3OK) << log.all();
  size_t size = 0;
  ASSERT_EQ(fourbar_->f().fmi3SerializedFMUStateSize(in.get(), heavy, &size), fmi3OK);
  std::vector<fmi3Byte> bytes(size);
  ASSERT_EQ(fourbar_->f().fmi3SerializeFMUState(in.get(), heavy, bytes.data(), size), fmi3OK);
  Instance fresh(*fourbar_, log);
  fmi3FMUState read = nullptr;
  ASSERT_EQ(fourbar_->f().fmi3DeserializeFMUState(fresh.get(), bytes.data(), size, &read), fmi3OK)
      << log.all();
  ASSERT_EQ(fourbar_->f().fmi3SetFMUState(fresh.get(), read), fmi3OK) << log.all();
  EXPECT_EQ(fresh.get({mass})[0], 80.0);
  EXPECT_EQ(run_to(fresh, fmu, 2.0, 4.0, 1e-2), heavier);  // to the bit
  // Bytes cut short of the tunable values are not a state of this FMU.
  fmi3FMUState cut = nullptr;
  EXPECT_EQ(fourbar_->f().fmi3DeserializeFMUState(fresh.get(), bytes.data(), 4, &cut), fmi3Error);
  EXPECT_NE(log.all().find("not a state of this FMU"), std::string::npos) << log.all();
  for (fmi3FMUState* s : {&at2, &heavy}) fourbar_->f().fmi3FreeFMUState(in.get(), s);
  fourbar_->f().fmi3FreeFMUState(fresh.get(), &read);
}

TEST_F(ExportedFmu, BadCallsReturnErrorsAndSayWhy) {
  const Fmi3Functions& f = fourbar_->f();
  fmi3ValueReference vr = 2;
  double value = 0.0;
  EXPECT_EQ(f.fmi3GetFloat64(nullptr, &vr, 1, &value, 1), fmi3Error);
  EXPECT_EQ(f.fmi3DoStep(nullptr, 0, 1e-3, true, nullptr, nullptr, nullptr, nullptr), fmi3Error);
  EXPECT_EQ(f.fmi3EnterInitializationMode(nullptr, false, 0, 0, false, 0), fmi3Error);
  f.fmi3FreeInstance(nullptr);  // ignored

  LogRecord log;
  const std::string resources = (fourbar_->fmu.dir / "resources").string() + "/";
  EXPECT_EQ(
      f.fmi3InstantiateCoSimulation("x", "{not-the-token}", resources.c_str(), false, false, false,
                                    false, nullptr, 0, &log, mh::test::log_fmi3, nullptr),
      nullptr);
  EXPECT_NE(log.all().find("instantiation token"), std::string::npos) << log.all();
  EXPECT_EQ(f.fmi3InstantiateModelExchange("x", fourbar_->fmu.token.c_str(), resources.c_str(),
                                           false, false, &log, mh::test::log_fmi3),
            nullptr);
  EXPECT_NE(log.all().find("Co-Simulation only"), std::string::npos);
  EXPECT_EQ(f.fmi3InstantiateCoSimulation("x", fourbar_->fmu.token.c_str(), "/no/such/folder/",
                                          false, false, false, false, nullptr, 0, &log,
                                          mh::test::log_fmi3, nullptr),
            nullptr);
  EXPECT_NE(log.all().find("/no/such/folder/"), std::string::npos) << log.all();

  log.messages.clear();
  Instance in(*fourbar_, log, false);
  ASSERT_NE(in.get(), nullptr) << log.all();
  EXPECT_EQ(f.fmi3GetFloat64(in.get(), &vr, 1, &value, 1), fmi3Error);  // before initialisation
  EXPECT_NE(log.all().find("Instantiated"), std::string::npos) << log.all();
  EXPECT_EQ(in.step(0.0, 1e-3), fmi3Error);
  EXPECT_NE(log.all().find("not in Step Mode"), std::string::npos) << log.all();
  EXPECT_EQ(f.fmi3EnterInitializationMode(in.get(), false, 0, 1.0, false, 0), fmi3Error);
  EXPECT_NE(log.all().find("starts at t = 0"), std::string::npos) << log.all();
  ASSERT_EQ(f.fmi3EnterInitializationMode(in.get(), false, 0, 0, false, 0), fmi3OK);
  EXPECT_EQ(f.fmi3EnterInitializationMode(in.get(), false, 0, 0, false, 0), fmi3Error);
  ASSERT_EQ(f.fmi3ExitInitializationMode(in.get()), fmi3OK);

  log.messages.clear();
  const fmi3ValueReference unknown = 99999;
  EXPECT_EQ(f.fmi3GetFloat64(in.get(), &unknown, 1, &value, 1), fmi3Error);
  EXPECT_NE(log.all().find("99999"), std::string::npos) << log.all();
  EXPECT_EQ(in.set(fourbar_->fmu.vr.at("z1"), 1.0), fmi3Error);
  EXPECT_NE(log.all().find("output"), std::string::npos);
  EXPECT_EQ(in.set(fourbar_->fmu.vr.at("valve_command"), NAN), fmi3Error);
  EXPECT_EQ(in.step(0.0, 1.5e-3), fmi3Error);
  EXPECT_NE(log.all().find("multiple"), std::string::npos) << log.all();
  EXPECT_EQ(in.step(0.5, 1e-3), fmi3Error);
  EXPECT_NE(log.all().find("not the FMU's time"), std::string::npos) << log.all();
  EXPECT_EQ(f.fmi3GetInt32(in.get(), &vr, 1, nullptr, 1), fmi3Error);
  EXPECT_EQ(f.fmi3GetFloat64(in.get(), &vr, 1, &value, 2), fmi3Error);
  EXPECT_EQ(f.fmi3GetFloat64(in.get(), nullptr, 1, &value, 1), fmi3Error);
  // None of that changed the run: it steps on from t = 0.
  EXPECT_EQ(in.step(0.0, 1e-3), fmi3OK) << log.all();
  EXPECT_EQ(f.fmi3Terminate(in.get()), fmi3OK);
  EXPECT_EQ(in.step(1e-3, 1e-3), fmi3Error);
  EXPECT_EQ(f.fmi3Reset(in.get()), fmi3OK);
  EXPECT_EQ(f.fmi3EnterInitializationMode(in.get(), false, 0, 0, false, 0), fmi3OK);
}

TEST(FailingFmu, ANewtonFailureInDoStepIsAnErrorWithTheEnginesMessage) {
  // One Newton iteration per step cannot close the four-bar's loop once it moves.
  const fs::path dir = mh::test::scratch_dir("fmu-failing");
  std::string text = mh::test::read_text(mh::test::shipped_model("fourbar.yaml"));
  const std::string from = "max_iterations: 25";
  text.replace(text.find(from), from.size(), "max_iterations: 1");
  std::ofstream(dir / "one-iteration.yaml") << text;
  const auto run = mh::test::run_cli("run " + (dir / "one-iteration.yaml").string() + " --out " +
                                     (dir / "run.csv").string());
  ASSERT_EQ(run.code, 1) << run.output;
  const auto e = export_fmu((dir / "one-iteration.yaml").string(), "failing-export");
  LogRecord log;
  Instance in(*e, log);
  fmi3FMUState start = nullptr;
  ASSERT_EQ(e->f().fmi3GetFMUState(in.get(), &start), fmi3OK);
  fmi3Status s = fmi3OK;
  double t = 0.0, last = -1.0;
  for (; t < 10.0 && s == fmi3OK; t += 0.01) {
    fmi3Boolean event = false, terminate = false, early = false;
    s = e->f().fmi3DoStep(in.get(), t, 0.01, true, &event, &terminate, &early, &last);
  }
  EXPECT_EQ(s, fmi3Error);
  EXPECT_LT(t, 10.0);
  EXPECT_GE(last, t - 0.01 - 1e-9);  // the last accepted state, inside the failed step
  EXPECT_LT(last, t);
  // The run's own failure message ("... at t = ..., step ...: why") reaches the log.
  const std::string why = run.output.substr(run.output.find("simulation failed at ") + 21);
  const std::string first_line = why.substr(0, why.find('\n'));
  EXPECT_NE(log.all().find("fmi3DoStep"), std::string::npos) << log.all();
  EXPECT_NE(log.all().find(first_line.substr(first_line.find(':') + 2, 30)), std::string::npos)
      << "log:\n"
      << log.all() << "run said: " << first_line;
  // The failed run takes no step until a state is set; then it goes on.
  EXPECT_EQ(in.step(last, 0.01), fmi3Error);
  ASSERT_EQ(e->f().fmi3SetFMUState(in.get(), start), fmi3OK) << log.all();
  EXPECT_EQ(in.step(0.0, 0.01), fmi3OK) << log.all();
  e->f().fmi3FreeFMUState(in.get(), &start);
}

TEST(Fmi2Fmu, GivesTheRunOfTheFmi3Fmu) {
  const fs::path dir = mh::test::scratch_dir("fmu-v2");
  const Unpacked fmu =
      mh::test::unpack(fs::path(mh::test::paths::exported_fmus) / "fourbar2.fmu", dir / "unpacked");
  EXPECT_STREQ(fmu.description.child("fmiModelDescription").attribute("fmiVersion").value(), "2.0");
  const auto violations = mh::test::model_description_violations(fmu.description);
  EXPECT_TRUE(violations.empty()) << violations.front();
  const Fmi2Functions f = mh::test::load_fmi2(fmu);
  LogRecord log;
  const fmi2CallbackFunctions callbacks{mh::test::log_fmi2, nullptr, nullptr, nullptr, &log};
  const std::string uri = "file://" + (fmu.dir / "resources").string();
  fmi2Component c = f.fmi2Instantiate("v2", fmi2CoSimulation, fmu.token.c_str(), uri.c_str(),
                                      &callbacks, fmi2False, fmi2False);
  ASSERT_NE(c, nullptr) << log.all();
  EXPECT_EQ(f.fmi2Instantiate("v2", fmi2ModelExchange, fmu.token.c_str(), uri.c_str(), &callbacks,
                              fmi2False, fmi2False),
            nullptr);
  ASSERT_EQ(f.fmi2SetupExperiment(c, fmi2False, 0, 0, fmi2False, 0), fmi2OK);
  ASSERT_EQ(f.fmi2EnterInitializationMode(c), fmi2OK);
  ASSERT_EQ(f.fmi2ExitInitializationMode(c), fmi2OK);
  for (int k = 0; k < 2000; ++k) ASSERT_EQ(f.fmi2DoStep(c, k * 1e-3, 1e-3, fmi2True), fmi2OK);
  const std::vector<fmi2ValueReference> vrs = {fmu.vr.at("z1"), fmu.vr.at("p2"), fmu.vr.at("s")};
  std::vector<double> v2(3);
  ASSERT_EQ(f.fmi2GetReal(c, vrs.data(), vrs.size(), v2.data()), fmi2OK);
  const fmi2ValueReference unknown = 99999;
  EXPECT_EQ(f.fmi2GetReal(c, &unknown, 1, v2.data()), fmi2Error);
  EXPECT_NE(log.all().find("99999"), std::string::npos) << log.all();
  f.fmi2FreeInstance(c);
  mh::test::unload(f.handle);

  const Csv csv = run_csv(mh::test::shipped_model("fourbar.yaml"), "v2", "--t-end 2");
  EXPECT_EQ(v2[0], csv["z1"].back());  // the same engine, the same bits
  EXPECT_EQ(v2[1], csv["p2"].back());
  EXPECT_EQ(v2[2], csv["s"].back());
}

TEST(FmuContents, TheBinaryFindsEveryLibraryItNeedsInsideTheFmu) {
  const fs::path dir = mh::test::scratch_dir("fmu-contents");
  const Unpacked fmu =
      mh::test::unpack(fs::path(mh::test::paths::exported_fmus) / "fourbar.fmu", dir / "unpacked");
  const fs::path bin = fmu.dir / "binaries" / "x86_64-linux";
  EXPECT_TRUE(fs::is_regular_file(fmu.dir / "resources" / "model.yaml"));
  EXPECT_TRUE(fs::is_regular_file(fmu.dir / "resources" / "plugins" / "monohydra-hydraulics.so"));
  const auto ldd =
      mh::test::run_shell("env -u LD_LIBRARY_PATH ldd " + (bin / "fourbar.so").string());
  ASSERT_EQ(ldd.code, 0) << ldd.output;
  EXPECT_EQ(ldd.output.find("not found"), std::string::npos) << ldd.output;
  EXPECT_EQ(ldd.output.find("libmonohydra"), std::string::npos) << ldd.output;
  // Every library beyond the C and C++ runtimes resolves to the FMU's own copy.
  std::istringstream lines(ldd.output);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("=>") == std::string::npos) continue;
    const bool system =
        line.find("libc.so") != std::string::npos || line.find("libm.so") != std::string::npos ||
        line.find("libstdc++") != std::string::npos || line.find("libgcc_s") != std::string::npos ||
        line.find("san.so") != std::string::npos || line.find("linux-vdso") != std::string::npos;
    if (!system) {
      EXPECT_NE(line.find(bin.string()), std::string::npos) << line;
    }
  }
}

TEST(FmuCommand, RefusesBadUsageWithAReason) {
  const fs::path dir = mh::test::scratch_dir("fmu-usage");
  auto r = mh::test::run_cli("fmu " + mh::test::shipped_model("fourbar.yaml"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
  r = mh::test::run_cli("fmu " + mh::test::shipped_model("fourbar.yaml") + " --out " +
                        (dir / "x.fmu").string() + " --fmi-version 4");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("3 or 2"), std::string::npos) << r.output;
  std::ofstream(dir / "bad.yaml") << "units: {length: m, mass: kg, time: s, angle: deg}\n"
                                     "bodies: 3\n";
  r = mh::test::run_cli("fmu " + (dir / "bad.yaml").string() + " --out " +
                        (dir / "y.fmu").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("bad.yaml:2"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "y.fmu"));
}

}  // namespace
