// The record a run's child sends to compare comes back bit for bit, and a
// stream cut by a crash still gives every whole row (run_record_stream.hpp).
#include "run_record_stream.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "same_bits.hpp"
#include "stability_text.hpp"

namespace mh::cli {
namespace {

RunRecord two_row_record() {
  RunRecord rec;
  rec.label = "penalty";
  rec.formulation = "penalty";
  rec.integrator = "trapezoidal";
  rec.dt = 0.001;
  rec.t_end = 0.3;
  rec.names = {"t", "z1", "wall_s"};
  rec.units = {"s", "rad", "s"};
  rec.info.resize(3);
  rec.info[1].name = "z1";
  rec.info[1].qualified = "body1.z1";
  rec.info[1].kind = 2;
  rec.info[1].range_min = -1.5;
  rec.info[1].range_max = 0.1;
  rec.num_coordinates = 1;
  rec.csv_path = "/tmp/x.csv";
  rec.columns = {{0.0, 0.1}, {-0.0, 1.0 / 3.0}, {std::numeric_limits<double>::denorm_min(), 1e308}};
  return rec;
}

using mh::test::same_bits;

std::string stream_of(const RunRecord& rec) {
  std::string bytes;
  append_record_description(bytes, rec, false);
  for (size_t k = 0; k < rec.rows(); ++k) append_record_row(bytes, rec, k);
  return bytes;
}

TEST(RunRecordStream, ACompleteRecordComesBackBitForBit) {
  RunRecord rec = two_row_record();
  rec.failed = true;
  rec.failure = "t = 0.1 s, step 100: no convergence";
  rec.failure_time = 0.1;
  std::string bytes = stream_of(rec);
  rec.dissipators = {"valve", "spring"};  // known at the end: in the final description
  rec.dissipated = {12.5, 1.0 / 3.0};
  rec.dissipation_parts = {"valve.P_meter_in", "valve.P_compensator"};
  rec.parts_dissipated = {10.0, 2.5 + 1e-13};
  append_record_description(bytes, rec, true);
  const DecodedRecord d = decode_record_stream(bytes);
  EXPECT_TRUE(d.complete);
  EXPECT_EQ(d.record.label, "penalty");
  EXPECT_EQ(d.record.integrator, "trapezoidal");
  EXPECT_TRUE(d.record.failed);
  EXPECT_EQ(d.record.failure, "t = 0.1 s, step 100: no convergence");
  ASSERT_TRUE(d.record.failure_time.has_value());
  EXPECT_TRUE(same_bits(*d.record.failure_time, 0.1));
  EXPECT_EQ(d.record.names, rec.names);
  EXPECT_EQ(d.record.units, rec.units);
  EXPECT_EQ(d.record.info[1].qualified, "body1.z1");
  EXPECT_EQ(d.record.info[1].kind, 2u);
  EXPECT_TRUE(same_bits(d.record.info[1].range_min, -1.5));
  EXPECT_EQ(d.record.num_coordinates, 1);
  EXPECT_EQ(d.record.csv_path, "/tmp/x.csv");
  EXPECT_EQ(d.record.dissipators, rec.dissipators);
  ASSERT_EQ(d.record.dissipated.size(), 2u);
  EXPECT_TRUE(same_bits(d.record.dissipated[1], 1.0 / 3.0));
  EXPECT_EQ(d.record.dissipation_parts, rec.dissipation_parts);
  ASSERT_EQ(d.record.parts_dissipated.size(), 2u);
  EXPECT_TRUE(same_bits(d.record.parts_dissipated[1], 2.5 + 1e-13));
  ASSERT_EQ(d.record.columns.size(), 3u);
  for (size_t c = 0; c < 3; ++c) {
    ASSERT_EQ(d.record.columns[c].size(), 2u);
    for (size_t k = 0; k < 2; ++k)
      EXPECT_TRUE(same_bits(d.record.columns[c][k], rec.columns[c][k])) << c << ", " << k;
  }
}

TEST(RunRecordStream, TheExplicitStabilityCheckComesBackAndReadsAsCompareSaysIt) {
  RunRecord rec = two_row_record();
  rec.integrator = "rk4";
  ExplicitStability& s = rec.stability;
  s.checks = 3;
  s.unstable = true;
  s.t = 0.25;
  s.step = 251;
  s.h = 1e-3;
  s.amplification = 9984.25;
  s.eigenvalue = {-23060.0, -12.5};
  s.stable_dt = 1.21e-4;
  s.cpu_seconds = 1.5e-4;
  s.skipped = 1;
  std::string bytes = stream_of(rec);
  append_record_description(bytes, rec, true);
  const ExplicitStability d = decode_record_stream(bytes).record.stability;
  EXPECT_EQ(d.checks, 3);
  EXPECT_TRUE(d.unstable);
  EXPECT_EQ(d.step, 251);
  EXPECT_EQ(d.skipped, 1);
  for (const auto& [a, b] : {std::pair{d.t, s.t},
                             {d.h, s.h},
                             {d.amplification, s.amplification},
                             {d.eigenvalue.real(), s.eigenvalue.real()},
                             {d.eigenvalue.imag(), s.eigenvalue.imag()},
                             {d.stable_dt, s.stable_dt},
                             {d.cpu_seconds, s.cpu_seconds}})
    EXPECT_TRUE(same_bits(a, b)) << a << " vs " << b;
  EXPECT_EQ(stability_text(d),
            "unstable: dt = 1 ms, |R| = 9984 (lambda = -2.306e+04 - 12.5i 1/s, at t = 0.25 s), "
            "stable below ~ 0.121 ms");
  EXPECT_EQ(stability_cost_text(d), "3 checks, 1 skipped (a rate solve failed), 0.15 ms CPU");
  rec.stability = ExplicitStability{};  // an implicit run: nothing to say
  EXPECT_EQ(stability_text(rec.stability), "");
}

TEST(RunRecordStream, AStreamCutInsideARowKeepsTheWholeRowsBeforeIt) {
  const RunRecord rec = two_row_record();
  const std::string bytes = stream_of(rec);
  const DecodedRecord d = decode_record_stream(bytes.substr(0, bytes.size() - 5));
  EXPECT_FALSE(d.complete);
  ASSERT_EQ(d.record.rows(), 1u);
  EXPECT_TRUE(same_bits(d.record.columns[1][0], -0.0));
  EXPECT_EQ(d.record.label, "penalty");
}

}  // namespace
}  // namespace mh::cli
