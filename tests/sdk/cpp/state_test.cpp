// The C++ helper of the state extension (sdk/include/monohydra/cpp/state.hpp):
// one list of members sizes, saves and loads; wrong lengths and bytes the
// instance refuses leave it as it was, with the reason logged.
#include "monohydra/cpp/state.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "monohydra/formulation.h"

namespace {

std::string g_logged;

void log_line(const mh_host*, mh_log_level, const char* message) {
  g_logged = message;
}

struct Counter {
  const mh_host* host = nullptr;
  double t = 0.0;
  int events = 0;
  bool armed = false;
  std::vector<double> history;
  std::vector<int> order;  // a permutation of 0..size-1 when valid
  template <class Archive>
  void state(Archive& a) {
    a(t);
    a(events);
    a(armed);
    a(history);
    a(order);
  }
  std::string state_loaded() {
    std::vector<char> seen(order.size(), 0);
    for (const int i : order) {
      if (i < 0 || static_cast<size_t>(i) >= order.size() || seen[static_cast<size_t>(i)] != 0)
        return "the order is not a permutation";
      seen[static_cast<size_t>(i)] = 1;
    }
    return "";
  }
};

struct Instance {
  mh_host host{};
  Counter data;
  mh_formulation table{};
  Instance() {
    host.struct_size = sizeof host;
    host.log = log_line;
    data.host = &host;
    data.history = {0.0, 0.0, 0.0};
    data.order = {0, 1};
    table.struct_size = sizeof table;
    table.plugin_data = &data;
  }
};

const mh_state_extension& ext() {
  return *monohydra::state_extension<mh_formulation, Counter>();
}

TEST(StateHelper, SizeIsTheSumOfTheMembersBytes) {
  Instance a;
  EXPECT_EQ(ext().size(&a.table),
            sizeof(double) + sizeof(int) + sizeof(bool) + 3 * sizeof(double) + 2 * sizeof(int));
  EXPECT_EQ(ext().struct_size, sizeof(mh_state_extension));
}

TEST(StateHelper, WhatOneInstanceSavesAnotherLoadsExactly) {
  Instance a, b;
  a.data.t = 0.125;
  a.data.events = 7;
  a.data.armed = true;
  a.data.history = {1.0 / 3.0, -2.5e-300, 4.0};
  a.data.order = {1, 0};
  std::vector<unsigned char> bytes(ext().size(&a.table));
  ASSERT_EQ(ext().save(&a.table, bytes.data(), bytes.size()), MH_OK);
  ASSERT_EQ(ext().load(&b.table, bytes.data(), bytes.size()), MH_OK);
  EXPECT_EQ(b.data.t, 0.125);
  EXPECT_EQ(b.data.events, 7);
  EXPECT_TRUE(b.data.armed);
  EXPECT_EQ(b.data.history, a.data.history);
  EXPECT_EQ(b.data.order, a.data.order);
}

TEST(StateHelper, AWrongLengthIsRefusedWithBothSizesAndChangesNothing) {
  Instance a;
  a.data.t = 2.0;
  std::vector<unsigned char> bytes(ext().size(&a.table) + 1, 0);
  g_logged.clear();
  EXPECT_EQ(ext().load(&a.table, bytes.data(), bytes.size()), MH_ERROR);
  EXPECT_NE(g_logged.find(std::to_string(bytes.size()) + " bytes given, " +
                          std::to_string(bytes.size() - 1) + " expected"),
            std::string::npos)
      << g_logged;
  EXPECT_EQ(a.data.t, 2.0);
  EXPECT_EQ(ext().save(&a.table, nullptr, bytes.size() - 1), MH_ERROR);
}

TEST(StateHelper, BytesTheInstanceRefusesPutTheStateBeforeBackAndSayWhy) {
  Instance a, b;
  b.data.order = {0, 0};  // not a permutation
  b.data.t = 9.0;
  std::vector<unsigned char> bytes(ext().size(&b.table));
  ASSERT_EQ(ext().save(&b.table, bytes.data(), bytes.size()), MH_OK);
  a.data.t = 1.0;
  g_logged.clear();
  EXPECT_EQ(ext().load(&a.table, bytes.data(), bytes.size()), MH_ERROR);
  EXPECT_NE(g_logged.find("the order is not a permutation"), std::string::npos) << g_logged;
  EXPECT_EQ(a.data.t, 1.0);
  EXPECT_EQ(a.data.order, (std::vector<int>{0, 1}));
}

}  // namespace
