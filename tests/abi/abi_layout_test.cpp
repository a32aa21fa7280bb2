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
      CXX_LAYOUT(mh_version),
      CXX_LAYOUT(mh_component_descriptor),
      CXX_LAYOUT(mh_plugin_entry),
      CXX_LAYOUT(mh_mech_info),
      CXX_LAYOUT(mh_mech_request),
      CXX_LAYOUT(mh_mech_result),
      CXX_LAYOUT(mh_port_spec),
      CXX_LAYOUT(mh_host),
      CXX_LAYOUT(mh_formulation),
      CXX_LAYOUT(mh_formulation_factory),
      CXX_LAYOUT(mh_subsystem_eval),
      CXX_LAYOUT(mh_subsystem),
      CXX_LAYOUT(mh_subsystem_factory),
      CXX_LAYOUT(mh_integrator),
      CXX_LAYOUT(mh_integrator_factory),
      CXX_LAYOUT(mh_step_map),
      CXX_LAYOUT(mh_step_coefficients),
      CXX_LAYOUT(mh_state_spec),
      CXX_LAYOUT(mh_output_spec),
      CXX_LAYOUT(mh_unknown_spec),
      CXX_LAYOUT(mh_mech_derivatives_request),
      CXX_LAYOUT(mh_mech_derivatives),
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

TEST(AbiLayout, VersionIsTwoFive) {
  const mh_version v = MH_ABI_VERSION_INIT;
  EXPECT_EQ(v.major, 2u);
  EXPECT_EQ(v.minor, 5u);
}

// ABI 2.5 added a modifier bit of evaluate_mechanics' flags, no field: it is
// distinct from every flag of 2.0, whose values stand.
TEST(AbiLayout, MinorFiveAddsThePositionsOnlyBitBesideTheTwoZeroFlags) {
  EXPECT_EQ(MH_EVAL_DYNAMICS, 0x1u);
  EXPECT_EQ(MH_EVAL_CONSTRAINTS, 0x2u);
  EXPECT_EQ(MH_EVAL_SUBSYSTEMS, 0x4u);
  EXPECT_EQ(MH_EVAL_POSITIONS_ONLY & (MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS | MH_EVAL_SUBSYSTEMS),
            0u);
}

// ABI 2.1 only appended: every 2.0 field keeps its offset (the frozen 2.0
// headers' sizes, recorded by abi_layout_sdk20.c), the new ones follow.
extern "C" {
extern const size_t mh_sdk20_sizeof_host;
extern const size_t mh_sdk20_sizeof_subsystem;
extern const size_t mh_sdk20_sizeof_formulation;
extern const size_t mh_sdk20_sizeof_integrator;
extern const size_t mh_sdk20_sizeof_subsystem_factory;
extern const size_t mh_sdk20_offset_host_evaluate;
extern const size_t mh_sdk20_offset_subsystem_get_extension;
}

TEST(AbiLayout, MinorOneAppendsAfterEveryTwoZeroField) {
  EXPECT_EQ(offsetof(mh_host, evaluate_mechanics), mh_sdk20_offset_host_evaluate);
  EXPECT_EQ(offsetof(mh_host, mech_derivatives), mh_sdk20_sizeof_host);
  EXPECT_EQ(sizeof(mh_host), mh_sdk20_sizeof_host + sizeof(void*));
  EXPECT_EQ(offsetof(mh_subsystem, get_extension), mh_sdk20_offset_subsystem_get_extension);
  EXPECT_EQ(offsetof(mh_subsystem, point_force_jacobian), mh_sdk20_sizeof_subsystem);
}

// ABI 2.2 appended mechanics_map at the end of mh_formulation (unchanged in
// 2.1) and coupling_jacobian at the end of mh_subsystem: every field before
// keeps its offset.
TEST(AbiLayout, MinorTwoAppendsOneOpToFormulationsAndOneToSubsystems) {
  EXPECT_EQ(offsetof(mh_formulation, mechanics_map), mh_sdk20_sizeof_formulation);
  EXPECT_EQ(sizeof(mh_formulation), mh_sdk20_sizeof_formulation + sizeof(void*));
  // and coupling_jacobian right after 2.1's point_force_jacobian in mh_subsystem.
  EXPECT_EQ(offsetof(mh_subsystem, coupling_jacobian), mh_sdk20_sizeof_subsystem + sizeof(void*));
  EXPECT_EQ(sizeof(mh_subsystem), mh_sdk20_sizeof_subsystem + 2 * sizeof(void*));
}

// ABI 2.3 appended the explicit stage operations at the end of mh_integrator
// (unchanged from 2.0 to 2.2): every 2.0 field keeps its offset, and an
// integrator of an older SDK reads them as 0 / NULL (implicit).
TEST(AbiLayout, MinorThreeAppendsTheExplicitStagesToIntegrators) {
  EXPECT_EQ(offsetof(mh_integrator, num_stages), mh_sdk20_sizeof_integrator);
  EXPECT_GT(offsetof(mh_integrator, stage_state), offsetof(mh_integrator, num_stages));
  EXPECT_EQ(offsetof(mh_integrator, stage_rates),
            offsetof(mh_integrator, stage_state) + sizeof(void*));
  EXPECT_EQ(offsetof(mh_integrator, finish_step),
            offsetof(mh_integrator, stage_rates) + sizeof(void*));
  EXPECT_EQ(sizeof(mh_integrator), offsetof(mh_integrator, finish_step) + sizeof(void*));
}

// ABI 2.4 appended example_model at the end of mh_subsystem_factory
// (unchanged from 2.0 to 2.3): a factory of an older SDK ends before it and
// reads it as NULL ("declares no example model").
TEST(AbiLayout, MinorFourAppendsTheExampleModelToSubsystemFactories) {
  EXPECT_EQ(offsetof(mh_subsystem_factory, example_model), mh_sdk20_sizeof_subsystem_factory);
  EXPECT_EQ(sizeof(mh_subsystem_factory), mh_sdk20_sizeof_subsystem_factory + sizeof(void*));
}
