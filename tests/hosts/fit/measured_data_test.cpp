// The measured data `fit` reads (hosts/monohydra/fit/measured_data.cpp):
// samples at their own rates with empty fields where none was taken, and
// every malformed file refused naming its line and column.
#include "measured_data.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "hosts/cli_runner.hpp"
#include "monohydra/core/input_error.hpp"

namespace {

std::string file_with(const std::string& name, const std::string& text) {
  const auto path = mh::test::scratch_dir("measured-" + name) / "data.csv";
  std::ofstream(path) << text;
  return path.string();
}

// The message of the refusal, or "" when the file is read.
std::string refusal(const std::string& name, const std::string& text) {
  try {
    mh::cli::read_measured_data(file_with(name, text));
  } catch (const mh::InputError& err) {
    return err.what();
  }
  return "";
}

TEST(MeasuredData, ColumnsAtTheirOwnRatesKeepEmptyFieldsAsSamplesNotTaken) {
  const auto data = mh::cli::read_measured_data(
      file_with("rates", "t,z1,p1\n0,0.5,1e6\n0.001,0.25,\n0.002, 0.125 ,\n0.01,,2e6\n"));
  ASSERT_EQ(data.names, (std::vector<std::string>{"z1", "p1"}));
  ASSERT_EQ(data.t.size(), 4U);
  EXPECT_DOUBLE_EQ(data.values[0][2], 0.125);
  EXPECT_TRUE(std::isnan(data.values[1][1]));
  EXPECT_DOUBLE_EQ(data.values[1][3], 2e6);
  EXPECT_EQ(data.count(0), 3U);
  EXPECT_EQ(data.count(1), 2U);
}

TEST(MeasuredData, AFileWithoutTimeFirstIsRefusedAtItsHeader) {
  EXPECT_NE(refusal("no-t", "time,z1\n0,1\n").find("data.csv:1:1: header: `t`"), std::string::npos);
}

TEST(MeasuredData, TimesThatDoNotIncreaseAreRefusedAtTheirLine) {
  EXPECT_NE(refusal("order", "t,z1\n0,1\n0.2,1\n0.1,1\n").find("data.csv:4:1: t: a time after"),
            std::string::npos);
}

TEST(MeasuredData, NanAndTextInAFieldAreRefusedNamingTheColumn) {
  EXPECT_NE(refusal("nan", "t,z1,p1\n0,1,2\n0.1,nan,2\n").find("data.csv:3:2: z1: a finite number"),
            std::string::npos);
  EXPECT_NE(refusal("text", "t,z1,p1\n0,1,2\n0.1,1,high\n").find("data.csv:3:3: p1:"),
            std::string::npos);
  EXPECT_NE(refusal("inf", "t,z1\n0,inf\n").find("z1: a finite number"), std::string::npos);
}

TEST(MeasuredData, RowsWithAnotherFieldCountNamesTwiceAndEmptyColumnsAreRefused) {
  EXPECT_NE(refusal("fields", "t,z1\n0,1,2\n").find("data.csv:2: row: 2 fields"),
            std::string::npos);
  EXPECT_NE(refusal("twice", "t,z1,z1\n0,1,2\n").find("z1: one column of this name"),
            std::string::npos);
  EXPECT_NE(refusal("empty-column", "t,z1,p1\n0,1,\n0.1,2,\n").find("p1: at least one sample"),
            std::string::npos);
  EXPECT_NE(refusal("no-rows", "t,z1\n").find("at least one row"), std::string::npos);
  EXPECT_NE(refusal("empty", "").find("the file is empty"), std::string::npos);
}

}  // namespace
