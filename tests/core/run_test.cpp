// mh::run never loses or fakes results: a failed write, a stop request and a
// settings error each end the run with a reason, whole rows only, and never
// as completed.
#include "monohydra/core/run.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <sstream>
#include <streambuf>
#include <string>

#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

const char* kPendulum = R"(
units: {length: m, mass: kg, time: s, angle: deg}
bodies:
  - name: rod
    parent: ground
    joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]}
    mass: 1.0
    shape: {type: beam, length: 1.0}
    z0: 30
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// Accepts `capacity` bytes, then fails every write with ENOSPC (a full disk).
class FullDisk : public std::streambuf {
 public:
  explicit FullDisk(std::size_t capacity) : capacity_(capacity) {}
  std::string text;

 protected:
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (text.size() + static_cast<std::size_t>(n) > capacity_) {
      errno = ENOSPC;
      return 0;
    }
    text.append(s, static_cast<std::size_t>(n));
    return n;
  }
  int_type overflow(int_type c) override {
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }

 private:
  std::size_t capacity_;
};

long lines(const std::string& text) {
  return static_cast<long>(std::count(text.begin(), text.end(), '\n'));
}

TEST(Run, FailedWriteStopsTheRunWithTheFileAndReason) {
  const ModelFile file = parse_model_text(kPendulum, "p.yaml");
  Simulation sim(file, test::build_plugins());
  FullDisk disk(4000);
  std::ostream csv(&disk);
  RunOptions options;
  options.csv_name = "out.csv";
  const RunSummary s = run(sim, &csv, options);
  EXPECT_EQ(s.end, RunEnd::write_failed);
  EXPECT_TRUE(s.failed);
  EXPECT_EQ(s.steps_asked, 1000);
  EXPECT_LT(s.steps, 100);  // stopped at once, not after 1000 silent steps
  EXPECT_NE(s.failure.find("of 1000: cannot write the results to 'out.csv': No space left on "
                           "device"),
            std::string::npos)
      << s.failure;
  // Whole rows only: the header, row t = 0 and one per step done but the
  // last, whose row is the write that failed.
  EXPECT_EQ(lines(disk.text), s.steps + 1);
  EXPECT_EQ(disk.text.back(), '\n');
}

TEST(Run, StopFlagEndsTheRunAfterAWholeRow) {
  const ModelFile file = parse_model_text(kPendulum, "p.yaml");
  Simulation sim(file, test::build_plugins());
  std::ostringstream csv;
  volatile std::sig_atomic_t stop = 0;
  RunOptions options;
  options.stop = &stop;
  options.progress = [&stop](double fraction) {
    if (fraction >= 0.1) stop = SIGINT;
  };
  const RunSummary s = run(sim, &csv, options);
  EXPECT_EQ(s.end, RunEnd::interrupted);
  EXPECT_EQ(s.stop_signal, SIGINT);
  EXPECT_EQ(s.steps, 100);
  EXPECT_EQ(s.failure, "stopped at t = 0.1 s, step 100 of 1000");
  EXPECT_EQ(lines(csv.str()), 102);
  EXPECT_EQ(csv.str().back(), '\n');
}

TEST(Run, ZeroStepRunIsNeverCompleted) {
  const ModelFile file = parse_model_text(kPendulum, "p.yaml");
  RunChoices choices;
  choices.t_end = 0.0;
  Simulation sim(file, test::build_plugins(), choices);
  const RunSummary s = run(sim, nullptr);
  EXPECT_EQ(s.end, RunEnd::bad_input);
  EXPECT_EQ(s.steps, 0);
  EXPECT_NE(s.failure.find("t_end / dt = 0 / 0.001 is not a number of steps from 1 to 2^53"),
            std::string::npos)
      << s.failure;
}

TEST(Run, OverflowingStepCountIsNeverCompleted) {
  const ModelFile file = parse_model_text(kPendulum, "p.yaml");
  RunChoices choices;
  choices.t_end = 1e300;
  Simulation sim(file, test::build_plugins(), choices);
  const RunSummary s = run(sim, nullptr);
  EXPECT_EQ(s.end, RunEnd::bad_input);
  EXPECT_TRUE(s.failed);
  EXPECT_EQ(s.steps, 0);
}

TEST(Run, CompletedRunDidEveryStepAsked) {
  const ModelFile file = parse_model_text(kPendulum, "p.yaml");
  RunChoices choices;
  choices.t_end = 0.05;
  Simulation sim(file, test::build_plugins(), choices);
  const RunSummary s = run(sim, nullptr);
  EXPECT_EQ(s.end, RunEnd::completed);
  EXPECT_EQ(s.steps, 50);
  EXPECT_EQ(s.steps_asked, 50);
}

}  // namespace
}  // namespace mh
