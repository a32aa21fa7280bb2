// run --save-state FILE [--at T] and run --resume FILE (hosts/monohydra/
// checkpoint.cpp): a run resumed from a checkpoint writes, from the
// checkpoint's time on, the rows the uninterrupted run wrote, byte for byte;
// a checkpoint of another model, a corrupted one and an --at off the step
// grid are refused with the reason.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "cli_runner.hpp"

namespace mh::test {
namespace {

// The header and the rows from time `t` on of a CSV's text.
std::string rows_from(const std::string& csv, double t) {
  std::istringstream in(csv);
  std::string line, out;
  std::getline(in, line);
  out = line + '\n';
  while (std::getline(in, line))
    if (std::stod(line.substr(0, line.find(','))) >= t - 1e-9) out += line + '\n';
  return out;
}

void expect_resume_continues_bit_for_bit(const std::string& model, const std::string& flags) {
  SCOPED_TRACE(model + flags);
  const auto dir =
      scratch_dir("checkpoint-" + std::to_string(std::hash<std::string>{}(model + flags)));
  const std::string m = shipped_model(model) + flags;
  const CliResult full = run_cli("run " + m + " --out " + (dir / "full.csv").string() +
                                 " --save-state " + (dir / "at4.state").string() + " --at 4");
  ASSERT_EQ(full.code, 0) << full.output;
  EXPECT_NE(full.output.find("state:        " + (dir / "at4.state").string() + " (t = 4 s"),
            std::string::npos)
      << full.output;
  const CliResult resumed = run_cli("run " + m + " --resume " + (dir / "at4.state").string() +
                                    " --out " + (dir / "resumed.csv").string());
  ASSERT_EQ(resumed.code, 0) << resumed.output;
  const std::string tail = rows_from(read_text(dir / "full.csv"), 4.0);
  EXPECT_GT(tail.size(), 1000u);
  EXPECT_EQ(read_text(dir / "resumed.csv"), tail);
}

TEST(RunCheckpoint, ResumedFourBarContinuesBitForBitDoubleStep) {
  expect_resume_continues_bit_for_bit("fourbar.yaml", "");
}

TEST(RunCheckpoint, ResumedFourBarContinuesBitForBitPenalty) {
  expect_resume_continues_bit_for_bit("fourbar.yaml", " --formulation penalty");
}

TEST(RunCheckpoint, ResumedPositionLoopContinuesBitForBit) {
  expect_resume_continues_bit_for_bit("fourbar-position-control.yaml", "");
}

TEST(RunCheckpoint, ACheckpointOfAnotherModelOrCorruptedIsRefusedWithTheReason) {
  const auto dir = scratch_dir("checkpoint-refused");
  const std::string state = (dir / "fourbar.state").string();
  ASSERT_EQ(
      run_cli("run " + shipped_model("fourbar.yaml") + " --t-end 0.01 --save-state " + state).code,
      0);
  const CliResult other =
      run_cli("run " + shipped_model("fourbar-position-control.yaml") + " --resume " + state);
  EXPECT_EQ(other.code, 2) << other.output;
  EXPECT_NE(other.output.find("cannot resume"), std::string::npos) << other.output;
  std::string bytes = read_text(state);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x20);
  std::ofstream(dir / "corrupt.state", std::ios::binary) << bytes;
  const CliResult corrupt = run_cli("run " + shipped_model("fourbar.yaml") + " --resume " +
                                    (dir / "corrupt.state").string());
  EXPECT_EQ(corrupt.code, 2) << corrupt.output;
  EXPECT_NE(corrupt.output.find((dir / "corrupt.state").string()), std::string::npos)
      << corrupt.output;
  const CliResult missing = run_cli("run " + shipped_model("fourbar.yaml") + " --resume " +
                                    (dir / "absent.state").string());
  EXPECT_EQ(missing.code, 2) << missing.output;
  EXPECT_NE(missing.output.find("cannot be read"), std::string::npos) << missing.output;
}

TEST(RunCheckpoint, AnAtOffTheStepGridOrWithoutSaveStateIsAUsageError) {
  const auto dir = scratch_dir("checkpoint-usage");
  const std::string m = shipped_model("fourbar.yaml");
  const CliResult off =
      run_cli("run " + m + " --save-state " + (dir / "s").string() + " --at 4.0005");
  EXPECT_EQ(off.code, 2) << off.output;
  EXPECT_NE(off.output.find("a multiple of dt = 0.001 s"), std::string::npos) << off.output;
  const CliResult beyond =
      run_cli("run " + m + " --save-state " + (dir / "s").string() + " --at 11");
  EXPECT_EQ(beyond.code, 2) << beyond.output;
  const CliResult alone = run_cli("run " + m + " --at 4");
  EXPECT_EQ(alone.code, 2) << alone.output;
  EXPECT_NE(alone.output.find("--at applies to --save-state only"), std::string::npos)
      << alone.output;
}

}  // namespace
}  // namespace mh::test
