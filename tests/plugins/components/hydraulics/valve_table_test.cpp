// The table valve (valve-table; plugins/components/hydraulics/flow_map.hpp, spool.hpp):
// through a fake host, a table made from the orifice formula gives valve-4-3's
// rows exactly at any state (also between and beyond its points); a measured
// table comes back exactly at its points, bilinearly in the flow coefficient
// between them and as sqrt(dp) beyond the last drop; the jacobian against
// central differences; and bad tables refused with the row named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "plugins/fake_host.hpp"

namespace mh::test {
namespace {

constexpr double kCvd = 2.138e-8, kTau = 4.547e-3, kPtr = 2e5;
const std::vector<double> kReference = {0, 0, 1, 0, 1, 10, 2.5, 10, 2.5, 0, 5, 0, 5, -10};

double orifice(double dp) {
  if (std::abs(dp) < kPtr) return std::sqrt(kPtr) * dp / kPtr;
  return (dp > 0 ? 1.0 : -1.0) * std::sqrt(std::abs(dp));
}

// Rows [u, dp, Q] on the grid u x dp with Q = f(u, dp).
template <class F>
std::vector<double> grid(const std::vector<double>& us, const std::vector<double>& dps, F f) {
  std::vector<double> rows;
  for (double u : us)
    for (double dp : dps) rows.insert(rows.end(), {u, dp, f(u, dp)});
  return rows;
}

struct Valve {
  FakeNetwork net;
  FakeHost host;
  std::unique_ptr<Instance> instance;
  mh_status status = MH_ERROR;
  Valve(const std::string& id, const std::vector<double>& table) : host(net, "valve") {
    host.numbers = {{"time_constant", kTau}};
    if (id == "valve-4-3") host.numbers["flow_coefficient"] = kCvd;
    if (!table.empty()) host.tables["flow_table"] = {3u, table};
    host.tables["reference"] = {2u, kReference};
    host.port_nodes = {{"P", "supply"}, {"T", "return"}, {"A", "n1"}, {"B", "n3"}};
    instance = std::make_unique<Instance>(id, host);
    status = instance->setup();
  }
  Evaluation at(double u, double pp, double pt, double pa, double pb, double t = 1.2) const {
    Evaluation e(net);
    e.t = t;
    e.y[static_cast<size_t>(host.port("P").index)] = pp;
    e.y[static_cast<size_t>(host.port("T").index)] = pt;
    e.y[static_cast<size_t>(host.port("A").index)] = pa;
    e.y[static_cast<size_t>(host.port("B").index)] = pb;
    e.y[static_cast<size_t>(host.state("U"))] = u;
    e.ydot[static_cast<size_t>(host.state("U"))] = 300.0;
    return e;
  }
  // The flow P -> A (U >= 0) or A -> T (U < 0): what leaves A's row, sign-adjusted.
  double flow_a(double u, double pa, double pp = 20e6, double pt = 0.0) const {
    Evaluation e = at(u, pp, pt, pa, 1e6);
    EXPECT_EQ(e.run(*instance), MH_OK);
    const double leaving_a = e.residual[static_cast<size_t>(host.port("A").index)];
    return u >= 0.0 ? -leaving_a : leaving_a;  // P -> A enters A; A -> T leaves it
  }
};

const std::vector<double> kSpools = {1, 2.5, 5, 7.5, 10};      // V
const std::vector<double> kDrops = {5e5, 1e6, 2e6, 5e6, 1e7};  // Pa
std::vector<double> orifice_table() {
  return grid(kSpools, kDrops, [](double u, double dp) { return kCvd * u * std::sqrt(dp); });
}

TEST(ValveTable, TableFromTheOrificeFormulaGivesValve43sRowsEverywhere) {
  Valve table("valve-table", orifice_table()), orifice_valve("valve-4-3", {});
  ASSERT_EQ(table.status, MH_OK) << table.host.all_logs();
  ASSERT_EQ(orifice_valve.status, MH_OK) << orifice_valve.host.all_logs();
  EXPECT_EQ(table.host.state_record("U").role, MH_ROLE_CONTROL_SIGNAL);
  EXPECT_EQ(table.host.time_events, orifice_valve.host.time_events);
  double worst = 0.0;
  // Spools on and between the grid, both signs; drops inside, below (laminar too) and beyond it.
  for (double u : {0.0, 0.3, 1.0, 3.7, -6.2, 10.0, -0.01}) {
    for (double pa : {19.99e6, 19.9e6, 17e6, 12.3e6, 2e6, 0.05e6}) {
      for (double t : {0.5, 1.0, 3.0}) {
        Evaluation a = table.at(u, 20e6, 1e5, pa, 4e6, t),
                   b = orifice_valve.at(u, 20e6, 1e5, pa, 4e6, t);
        ASSERT_EQ(a.run(*table.instance), MH_OK);
        ASSERT_EQ(b.run(*orifice_valve.instance), MH_OK);
        for (size_t i = 0; i < a.residual.size(); ++i)
          worst = std::max(worst, std::abs(a.residual[i] - b.residual[i]) /
                                      std::max(1e-9, std::abs(b.residual[i])));
        EXPECT_EQ(a.outputs[0], b.outputs[0]);  // U_ref
      }
    }
  }
  EXPECT_LT(worst, 1e-12);
  std::printf(
      "[ measured ] valve-table from the orifice formula vs valve-4-3: max relative "
      "difference %.3g\n",
      worst);
}

// A measured-looking characteristic: progressive in the spool (overlap, then
// opening faster), a little less than sqrt in the pressure drop.
double measured(double u, double dp) {
  return 3e-9 * std::pow(u, 1.6) * std::pow(dp, 0.45);
}

TEST(ValveTable, ReproducesTheTablePointsAndInterpolatesBetweenThem) {
  Valve v("valve-table", grid(kSpools, kDrops, measured));
  ASSERT_EQ(v.status, MH_OK) << v.host.all_logs();
  for (double u : kSpools) {
    for (double dp : kDrops) {
      EXPECT_NEAR(v.flow_a(u, 20e6 - dp), measured(u, dp), 1e-12 * measured(u, dp))
          << u << " " << dp;
      EXPECT_NEAR(v.flow_a(-u, dp, 20e6, 0.0), measured(u, dp), 1e-12 * measured(u, dp));  // A->T
    }
  }
  // Between points: bilinear in K = Q / sqrt(dp).
  const double u = 3.0, dp = 3e6;
  const double wu = (u - 2.5) / 2.5, wd = (dp - 2e6) / 3e6;
  auto k = [](double uu, double d) { return measured(uu, d) / std::sqrt(d); };
  const double k_expected = (1 - wu) * ((1 - wd) * k(2.5, 2e6) + wd * k(2.5, 5e6)) +
                            wu * ((1 - wd) * k(5, 2e6) + wd * k(5, 5e6));
  EXPECT_NEAR(v.flow_a(u, 20e6 - dp), k_expected * std::sqrt(dp), 1e-12 * measured(u, dp));
  // Below the first spool position: linear to zero flow at U = 0 (closed centre).
  EXPECT_NEAR(v.flow_a(0.5, 19e6), 0.5 * measured(1.0, 1e6), 1e-12 * measured(1.0, 1e6));
  EXPECT_EQ(v.flow_a(0.0, 19e6), 0.0);
}

TEST(ValveTable, ExtrapolatesAsTheSquareRootOfThePressureDropBeyondTheTable) {
  Valve v("valve-table", grid(kSpools, kDrops, measured));
  ASSERT_EQ(v.status, MH_OK);
  for (double u : {2.5, 6.0}) {
    const double at_last = v.flow_a(u, 30e6 - 1e7, 30e6);
    const double beyond = v.flow_a(u, 40e6 - 4e7, 40e6);  // 4x the last drop
    EXPECT_NEAR(beyond, 2.0 * at_last, 1e-12 * at_last) << u;
  }
  // Below the first drop: the same K, orifice law (laminar below p_tr).
  const double k = measured(5.0, 5e5) / std::sqrt(5e5);
  EXPECT_NEAR(v.flow_a(5.0, 20e6 - 3e5), k * std::sqrt(3e5), 1e-12 * k * std::sqrt(3e5));
  EXPECT_NEAR(v.flow_a(5.0, 20e6 - 1e5), k * orifice(1e5), 1e-12 * k * std::sqrt(1e5));
}

TEST(ValveTable, AnalyticJacobianMatchesCentralDifferencesOffTheGridLines) {
  Valve v("valve-table", grid(kSpools, kDrops, measured));
  ASSERT_EQ(v.status, MH_OK);
  double worst = 0.0;
  for (double u : {0.4, 3.3, -4.1, 8.8, 11.0}) {
    worst = std::max(worst, jacobian_error(*v.instance, v.at(u, 20e6, 1e5, 16.3e6, 3.3e6)));
    worst = std::max(worst, jacobian_error(*v.instance, v.at(u, 20e6, 1e5, 19.93e6, 0.13e6)));
    worst = std::max(worst, jacobian_error(*v.instance, v.at(u, 20e6, 1e5, 21.5e6, 4e6)));
  }
  EXPECT_LT(worst, 1e-6);
  std::printf("[ measured ] valve-table jacobian max relative error %.3g\n", worst);
}

TEST(ValveTable, EdgesDissipateQTimesDpNeverNegative) {
  Valve v("valve-table", grid(kSpools, kDrops, measured));
  ASSERT_EQ(v.status, MH_OK);
  ASSERT_NE(v.instance->api()->energy, nullptr);
  for (double u : {-7.0, -0.5, 0.0, 2.0, 9.0}) {
    for (double pa : {-1e6, 3e6, 15e6, 25e6}) {  // flows either way through each edge
      Evaluation e = v.at(u, 20e6, 1e5, pa, 6e6);
      const mh_subsystem_eval rec = e.record();
      double stored = -1, dissipation = -1;
      ASSERT_EQ(v.instance->api()->energy(v.instance->api(), &rec, &stored, &dissipation), MH_OK);
      EXPECT_EQ(stored, 0.0);
      EXPECT_GE(dissipation, 0.0) << u << " " << pa;
    }
  }
  // One edge open at U = 2 V with P -> A only (B = T): the dissipation is Q_PA (p_P - p_A).
  Evaluation e = v.at(2.0, 20e6, 1e5, 15e6, 1e5);
  const mh_subsystem_eval rec = e.record();
  double stored = 0, dissipation = 0;
  ASSERT_EQ(v.instance->api()->energy(v.instance->api(), &rec, &stored, &dissipation), MH_OK);
  EXPECT_NEAR(dissipation, v.flow_a(2.0, 15e6) * 5e6, 1e-9 * dissipation);
}

TEST(ValveTable, BadTablesAreRefusedNamingTheRow) {
  struct Case {
    std::vector<double> table;
    const char* says;
  };
  const std::vector<Case> cases = {
      {{}, "rows [spool (V), pressure drop (Pa), flow (m^3/s)]"},
      {{1, 1e6, 1e-4, 1, 5e5, 2e-4}, "pressure drops of one spool position increasing (row 2)"},
      {{1, 1e6, 1e-4, 1, 2e6, 2e-4, 2, 1e6, 3e-4}, "a full grid"},
      {{1, 1e6, 1e-4, 2, 1e6, 2e-4, 1.5, 1e6, 3e-4}, "spool positions increasing"},
      {{1, 1e6, 1e-4, 1, 2e6, 2e-4, 2, 1e6, 3e-4, 2, 3e6, 4e-4}, "pressure drop"},
      {{1, 1e6, -1e-4}, "flow >= 0"},
      {{0, 1e6, 1e-5, 1, 1e6, 2e-4}, "zero flow at spool 0"},
      {{0, 1e6, 0.0}, "at least one spool position above 0"},
  };
  for (const Case& c : cases) {
    Valve v("valve-table", c.table);
    EXPECT_EQ(v.status, MH_ERROR) << c.says;
    if (c.table.empty()) continue;  // a missing table is the host's (required option)
    ASSERT_EQ(v.host.option_errors, std::vector<std::string>{"flow_table"}) << c.says;
    EXPECT_NE(v.host.expected[0].find(c.says), std::string::npos) << v.host.expected[0];
  }
}

}  // namespace
}  // namespace mh::test
