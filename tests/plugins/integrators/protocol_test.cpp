// What every integrator of the library owes the host: the factory's listing,
// restart forgetting the history, and refusing bad calls with a logged reason.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "problems.hpp"

namespace mh_test {
namespace {

TEST(Library, ListsTrapezoidalFirstThenGeneralizedAlphaAndBdf2) {
  const IntegratorLibrary& lib = IntegratorLibrary::get();
  EXPECT_EQ(lib.entry()->abi_version.major, MH_ABI_VERSION_MAJOR);
  EXPECT_EQ(lib.entry()->get_factory("monohydra.formulation-factory/2"), nullptr);
  const mh_integrator_factory* f = lib.factory();
  ASSERT_EQ(f->count(f), 3u);
  EXPECT_STREQ(f->descriptor(f, 0)->id, "trapezoidal");
  EXPECT_STREQ(f->descriptor(f, 1)->id, "generalized-alpha");
  EXPECT_STREQ(f->descriptor(f, 2)->id, "bdf2");
  EXPECT_EQ(f->descriptor(f, 3), nullptr);
  for (const char* id : {"trapezoidal", "generalized-alpha", "bdf2"}) {
    Integrator integ(id);
    ASSERT_NE(integ.api(), nullptr) << id;
    EXPECT_EQ(integ.api()->struct_size, sizeof(mh_integrator));
    EXPECT_NE(integ.api()->begin_step, nullptr);  // an implicit method: a map, no stages
    EXPECT_EQ(integ.api()->explicit_method, nullptr);
    EXPECT_STREQ(integ.api()->descriptor->id, id);
    EXPECT_EQ(integ.api()->get_extension(integ.api(), "anything/1"), nullptr);
  }
  FakeHost host;
  EXPECT_EQ(f->create(f, host.api(), "runge-kutta"), nullptr);
  ASSERT_EQ(host.logs.size(), 1u);
  EXPECT_NE(host.logs[0].find("runge-kutta"), std::string::npos);
}

// After a restart, a step uses only the state given there: its map equals
// that of a fresh instance restarted from the same state, bit for bit.
TEST(Restart, TheNextStepUsesOnlyTheRestartState) {
  const Mixed mixed;
  const State r{0.37, {0.2, -1.0, 4.0}, {1.5, 0.25, 0.0}, {-6.0, 0.0, 0.0}};
  for (const Case& c : all_cases()) {
    Integrator used(c.id, c.options), fresh(c.id, c.options);
    run(used, mixed.problem(), mixed.initial(), uniform_steps(0.3, 0.01));
    ASSERT_EQ(used.restart(r.t, r.x, r.xd, r.xdd), MH_OK);
    ASSERT_EQ(fresh.setup(mixed.problem().kinds, r.t, 0.01), MH_OK);
    ASSERT_EQ(fresh.restart(r.t, r.x, r.xd, r.xdd), MH_OK);
    for (int k = 0; k < 3; ++k) {  // and so do the steps after it
      const double h = k == 0 ? 0.004 : 0.01;
      ASSERT_EQ(used.begin_step(r.t + h, h), MH_OK);
      ASSERT_EQ(fresh.begin_step(r.t + h, h), MH_OK);
      const mh_step_coefficients &a = used.map.coefficients, &b = fresh.map.coefficients;
      EXPECT_EQ(a.struct_size, b.struct_size) << name(c);
      EXPECT_EQ(a.h, b.h) << name(c);
      EXPECT_EQ(a.dxd_dx_second, b.dxd_dx_second) << name(c);
      EXPECT_EQ(a.dxdd_dx_second, b.dxdd_dx_second) << name(c);
      EXPECT_EQ(a.dxd_dx_first, b.dxd_dx_first) << name(c);
      EXPECT_EQ(used.x_predicted, fresh.x_predicted) << name(c);
      EXPECT_EQ(used.xd_offset, fresh.xd_offset) << name(c);
      EXPECT_EQ(used.xdd_offset, fresh.xdd_offset) << name(c);
      const std::vector<double> x{0.21 + k, -0.9, 3.9};
      const std::vector<double> xd{used.xd_at(0, x[0]), used.xd_at(1, x[1]), 0.0};
      const std::vector<double> xdd{used.xdd_at(0, x[0]), 0.0, 0.0};
      ASSERT_EQ(used.accept(r.t + h, x, xd, xdd), MH_OK);
      ASSERT_EQ(fresh.accept(r.t + h, x, xd, xdd), MH_OK);
    }
  }
}

// A failed step is abandoned: begin_step again starts from the last accept.
TEST(Restart, AnAbandonedStepLeavesTheHistoryAlone) {
  for (const Case& c : all_cases()) {
    Integrator integ(c.id, c.options);
    ASSERT_EQ(integ.setup({MH_UNKNOWN_SECOND_ORDER, MH_UNKNOWN_FIRST_ORDER}, 0.0, 0.01), MH_OK);
    ASSERT_EQ(integ.restart(0.0, {1.0, 2.0}, {0.5, -1.0}, {-3.0, 0.0}), MH_OK);
    ASSERT_EQ(integ.begin_step(0.01, 0.01), MH_OK);
    const std::vector<double> first = integ.xdd_offset, first_xd = integ.xd_offset;
    ASSERT_EQ(integ.begin_step(0.02, 0.02), MH_OK);  // abandoned and retried
    ASSERT_EQ(integ.begin_step(0.01, 0.01), MH_OK);
    EXPECT_EQ(integ.xdd_offset, first) << name(c);
    EXPECT_EQ(integ.xd_offset, first_xd) << name(c);
  }
}

TEST(Protocol, RefusesBadCallsAndNonFiniteValuesWithALoggedReason) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const Case& c : all_cases()) {
    Integrator integ(c.id, c.options);
    const auto refused = [&](mh_status st, const char* what) {
      EXPECT_EQ(st, MH_ERROR) << name(c) << ": " << what;
      EXPECT_FALSE(integ.host.logs.empty()) << name(c) << ": " << what;
      integ.host.logs.clear();
    };
    const std::vector<uint8_t> kinds{MH_UNKNOWN_SECOND_ORDER, MH_UNKNOWN_ALGEBRAIC};
    refused(integ.api()->setup(integ.api(), nullptr), "no problem");
    refused(integ.setup({MH_UNKNOWN_SECOND_ORDER, 7}, 0.0, 0.01), "kind 7");
    refused(integ.setup(kinds, 0.0, 0.0), "dt = 0");
    refused(integ.setup(kinds, nan, 0.01), "t0 NaN");
    mh_integrator_problem small{};
    small.struct_size = 8;
    refused(integ.api()->setup(integ.api(), &small), "struct_size 8");
    refused(integ.restart(0.0, {1.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}), "restart before setup");

    ASSERT_EQ(integ.setup(kinds, 0.0, 0.01), MH_OK);
    refused(integ.begin_step(0.01, 0.01), "begin_step before restart");
    refused(integ.restart(0.0, {nan, 0.0}, {0.0, 0.0}, {0.0, 0.0}), "restart x NaN");
    refused(integ.restart(0.0, {1.0, 0.0}, {inf, 0.0}, {0.0, 0.0}), "restart xd inf");
    refused(integ.restart(inf, {1.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}), "restart t inf");
    ASSERT_EQ(integ.restart(0.0, {1.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}), MH_OK);
    refused(integ.accept(0.01, {1.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}), "accept before begin_step");
    refused(integ.begin_step(0.01, 0.0), "h = 0");
    refused(integ.begin_step(0.01, -0.01), "h < 0");
    refused(integ.begin_step(0.01, nan), "h NaN");
    refused(integ.begin_step(nan, 0.01), "t_next NaN");
    refused(integ.api()->begin_step(integ.api(), 0.01, 0.01, nullptr), "no map");
    mh_step_map no_arrays{};
    no_arrays.struct_size = sizeof(no_arrays);
    refused(integ.api()->begin_step(integ.api(), 0.01, 0.01, &no_arrays), "NULL arrays");
    ASSERT_EQ(integ.begin_step(0.01, 0.01), MH_OK);
    refused(integ.accept(0.01, {nan, 0.0}, {0.0, 0.0}, {0.0, 0.0}), "accept x NaN");
    refused(integ.accept(0.01, {1.0, 0.0}, {0.0, 0.0}, {-inf, 0.0}), "accept xdd -inf");
    EXPECT_EQ(integ.accept(0.01, {1.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}), MH_OK) << name(c);
  }
}

}  // namespace
}  // namespace mh_test
