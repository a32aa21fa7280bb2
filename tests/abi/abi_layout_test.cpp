// The SDK headers give C and C++ translation units the same struct layouts,
// so a plugin written in C and a host written in C++ agree on every field.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "monohydra/monohydra.h"

extern "C" {
struct abi_layout {
  const char* name;
  size_t size;
  size_t align;
};
extern const abi_layout mh_c_layouts[];
extern const size_t mh_c_layout_count;
extern const size_t mh_c_offset_host_evaluate;
extern const size_t mh_c_offset_formulation_get_extension;
extern const size_t mh_c_offset_subsystem_get_extension;
}

#define CXX_LAYOUT(T) \
  { #T, sizeof(T), alignof(T) }

TEST(AbiLayout, CAndCxxSeeTheSameSizesAndAlignments) {
  const abi_layout cxx[] = {
      CXX_LAYOUT(mh_version),           CXX_LAYOUT(mh_component_descriptor),
      CXX_LAYOUT(mh_plugin_entry),      CXX_LAYOUT(mh_mech_info),
      CXX_LAYOUT(mh_mech_request),      CXX_LAYOUT(mh_mech_result),
      CXX_LAYOUT(mh_port_spec),         CXX_LAYOUT(mh_host),
      CXX_LAYOUT(mh_formulation),       CXX_LAYOUT(mh_formulation_factory),
      CXX_LAYOUT(mh_subsystem_eval),    CXX_LAYOUT(mh_subsystem),
      CXX_LAYOUT(mh_subsystem_factory),
  };
  ASSERT_EQ(mh_c_layout_count, sizeof(cxx) / sizeof(cxx[0]));
  for (size_t i = 0; i < mh_c_layout_count; ++i) {
    EXPECT_EQ(std::string(mh_c_layouts[i].name), cxx[i].name);
    EXPECT_EQ(mh_c_layouts[i].size, cxx[i].size) << cxx[i].name;
    EXPECT_EQ(mh_c_layouts[i].align, cxx[i].align) << cxx[i].name;
  }
}

TEST(AbiLayout, FunctionTablesKeepTheirFieldOffsets) {
  EXPECT_EQ(mh_c_offset_host_evaluate, offsetof(mh_host, evaluate_mechanics));
  EXPECT_EQ(mh_c_offset_formulation_get_extension, offsetof(mh_formulation, get_extension));
  EXPECT_EQ(mh_c_offset_subsystem_get_extension, offsetof(mh_subsystem, get_extension));
}

TEST(AbiLayout, VersionIsOneOne) {
  const mh_version v = MH_ABI_VERSION_INIT;
  EXPECT_EQ(v.major, 1u);
  EXPECT_EQ(v.minor, 1u);
}

// ABI 1.1 only appended: every 1.0 field keeps its offset, the new ones follow.
TEST(AbiLayout, MinorOneAppendsHostServicesAfterEveryOneZeroField) {
  EXPECT_GT(offsetof(mh_host, add_port), offsetof(mh_host, add_output));
  EXPECT_GT(offsetof(mh_host, point_position), offsetof(mh_host, add_port));
  EXPECT_GT(offsetof(mh_host, add_time_event), offsetof(mh_host, point_position));
  EXPECT_EQ(sizeof(mh_host), offsetof(mh_host, add_time_event) + sizeof(void*));
}
