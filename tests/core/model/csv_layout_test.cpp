// The rows a run writes (csv_layout.cpp): every column by default, the model
// file's selection in its order, intervals as whole numbers of steps, and
// the real-time columns.
#include "monohydra/core/csv_layout.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "test_support.hpp"

namespace mh {
namespace {

const ModelFile& pendulum() {
  static const ModelFile f = load_model_file(test::source_path("models/double-pendulum.yaml"));
  return f;
}

TEST(CsvLayout, DefaultIsEveryColumnEveryStepAndRealTimeAddsItsTwo) {
  Simulation sim(pendulum(), test::build_plugins());
  const CsvLayout all(sim);
  EXPECT_EQ(all.every_steps(), 1);
  EXPECT_EQ(all.names(), (std::vector<std::string>{"t", "z1", "z2", "KE", "PE", "W", "drift",
                                                   "phi_norm", "iters"}));
  const CsvLayout rt(sim, true);
  EXPECT_EQ(rt.names().back(), "unconverged");
  EXPECT_EQ(rt.names()[rt.names().size() - 2], "late");
}

TEST(CsvLayout, SelectionKeepsItsOrderAndRowsCarryTheSimulationsValues) {
  Simulation sim(pendulum(), test::build_plugins());
  sim.start();
  sim.step();
  OutputSettings out;
  out.columns = {"z2", "t", "iters"};
  out.column_marks.resize(3);
  out.interval = 0.005;
  const CsvLayout layout(sim, out, std::nullopt);
  EXPECT_EQ(layout.every_steps(), 5);
  std::ostringstream row;
  layout.row(row, sim);
  // Shortest round-trip text: the same doubles as printed at full precision.
  std::istringstream in(row.str());
  double z2 = 0, t = 0;
  int iters = 0;
  char comma = 0;
  in >> z2 >> comma >> t >> comma >> iters;
  EXPECT_EQ(z2, sim.z()[1]);
  EXPECT_EQ(t, sim.time());
  EXPECT_EQ(iters, sim.last_step().iterations);
  // The command line's interval overrides the file's.
  EXPECT_EQ(CsvLayout(sim, out, 0.002).every_steps(), 2);
}

TEST(CsvLayout, UnknownColumnsAndFractionalIntervalsAreRefusedWithTheirMark) {
  Simulation sim(pendulum(), test::build_plugins());
  OutputSettings out;
  out.columns = {"t", "p1"};
  out.column_marks = {SourceMark{"m.yaml", 3, 12}, SourceMark{"m.yaml", 3, 15}};
  try {
    CsvLayout(sim, out, std::nullopt);
    FAIL() << "accepted an unknown column";
  } catch (const InputError& e) {
    EXPECT_EQ(e.mark().column, 15);
    EXPECT_EQ(e.field(), "output.columns[1]");
    EXPECT_NE(std::string(e.what()).find("unknown column 'p1' (this run writes: t, z1, z2, KE"),
              std::string::npos)
        << e.what();
  }
  OutputSettings every;
  every.interval = 0.0025;
  every.interval_mark = SourceMark{"m.yaml", 4, 22};
  try {
    CsvLayout(sim, every, std::nullopt);
    FAIL() << "accepted 2.5 steps";
  } catch (const InputError& e) {
    EXPECT_EQ(e.mark().line, 4);
    EXPECT_NE(std::string(e.what()).find("output.interval: expected a whole multiple of the time "
                                         "step dt = 0.001 s, got 0.0025 s (2.5 steps)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(CsvLayout(sim, every, 0.0004), InputError);  // less than one step
}

}  // namespace
}  // namespace mh
