// The SDK headers give C and C++ translation units the same struct layouts,
// so a plugin written in C and a host written in C++ agree on every field.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "monohydra/inverse_dynamics.h"
#include "monohydra/monohydra.h"
#include "monohydra/sparsity.h"
#include "monohydra/visual.h"

extern "C" {
struct abi_layout {
  const char* name;
  size_t size;
  size_t align;
};
extern const abi_layout mh_c_layouts[];
extern const size_t mh_c_layout_count;
extern const size_t mh_c_offset_host_get_service;
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
      CXX_LAYOUT(mh_unknown_values),
      CXX_LAYOUT(mh_unknown_buffers),
      CXX_LAYOUT(mh_step_begin),
      CXX_LAYOUT(mh_tangent_blocks),
      CXX_LAYOUT(mh_mechanics_map),
      CXX_LAYOUT(mh_coordinate_buffers),
      CXX_LAYOUT(mh_explicit_method),
      CXX_LAYOUT(mh_options_service),
      CXX_LAYOUT(mh_mechanism_service),
      CXX_LAYOUT(mh_outputs_service),
      CXX_LAYOUT(mh_subsystem_setup_service),
      CXX_LAYOUT(mh_unknowns_service),
      CXX_LAYOUT(mh_state_extension),
      CXX_LAYOUT(mh_visual_spec),
      CXX_LAYOUT(mh_visual_service),
      CXX_LAYOUT(mh_sparsity_service),
      CXX_LAYOUT(mh_mechanical_pattern_service),
      CXX_LAYOUT(mh_inverse_dynamics_service),
  };
  ASSERT_EQ(mh_c_layout_count, sizeof(cxx) / sizeof(cxx[0]));
  for (size_t i = 0; i < mh_c_layout_count; ++i) {
    EXPECT_EQ(std::string(mh_c_layouts[i].name), cxx[i].name);
    EXPECT_EQ(mh_c_layouts[i].size, cxx[i].size) << cxx[i].name;
    EXPECT_EQ(mh_c_layouts[i].align, cxx[i].align) << cxx[i].name;
  }
}

TEST(AbiLayout, FunctionTablesKeepTheirFieldOffsets) {
  EXPECT_EQ(mh_c_offset_host_get_service, offsetof(mh_host, get_service));
  EXPECT_EQ(mh_c_offset_formulation_get_extension, offsetof(mh_formulation, get_extension));
  EXPECT_EQ(mh_c_offset_subsystem_get_extension, offsetof(mh_subsystem, get_extension));
}

TEST(AbiLayout, VersionIsThreeOne) {
  const mh_version v = MH_ABI_VERSION_INIT;
  EXPECT_EQ(v.major, 3u);
  EXPECT_EQ(v.minor, 2u);  // 3.1: the signals service, 3.2: its option_signal_port (host.h)
}

// Every instance table begins with the same head (struct_size, descriptor,
// plugin_data, setup, destroy, get_extension), so a host reads any of them
// the same way before it knows the role.
TEST(AbiLayout, EveryInstanceTableBeginsWithTheSameHead) {
  EXPECT_EQ(offsetof(mh_formulation, descriptor), offsetof(mh_subsystem, descriptor));
  EXPECT_EQ(offsetof(mh_formulation, descriptor), offsetof(mh_integrator, descriptor));
  EXPECT_EQ(offsetof(mh_formulation, plugin_data), offsetof(mh_subsystem, plugin_data));
  EXPECT_EQ(offsetof(mh_formulation, plugin_data), offsetof(mh_integrator, plugin_data));
  EXPECT_EQ(offsetof(mh_formulation, setup), offsetof(mh_subsystem, setup));
  EXPECT_EQ(offsetof(mh_formulation, setup), offsetof(mh_integrator, setup));
  EXPECT_EQ(offsetof(mh_formulation, destroy), offsetof(mh_subsystem, destroy));
  EXPECT_EQ(offsetof(mh_formulation, destroy), offsetof(mh_integrator, destroy));
  EXPECT_EQ(offsetof(mh_formulation, get_extension), offsetof(mh_subsystem, get_extension));
  EXPECT_EQ(offsetof(mh_formulation, get_extension), offsetof(mh_integrator, get_extension));
}

// The three factories have one shape, example_model included.
TEST(AbiLayout, TheThreeFactoriesHaveOneShape) {
  EXPECT_EQ(sizeof(mh_formulation_factory), sizeof(mh_subsystem_factory));
  EXPECT_EQ(sizeof(mh_formulation_factory), sizeof(mh_integrator_factory));
  EXPECT_EQ(offsetof(mh_formulation_factory, count), offsetof(mh_subsystem_factory, count));
  EXPECT_EQ(offsetof(mh_formulation_factory, count), offsetof(mh_integrator_factory, count));
  EXPECT_EQ(offsetof(mh_formulation_factory, descriptor),
            offsetof(mh_subsystem_factory, descriptor));
  EXPECT_EQ(offsetof(mh_formulation_factory, descriptor),
            offsetof(mh_integrator_factory, descriptor));
  EXPECT_EQ(offsetof(mh_formulation_factory, create), offsetof(mh_subsystem_factory, create));
  EXPECT_EQ(offsetof(mh_formulation_factory, create), offsetof(mh_integrator_factory, create));
  EXPECT_EQ(offsetof(mh_formulation_factory, example_model),
            offsetof(mh_subsystem_factory, example_model));
  EXPECT_EQ(offsetof(mh_formulation_factory, example_model),
            offsetof(mh_integrator_factory, example_model));
}

// Every array a formulation or an integrator call hands over travels with
// its length: the count precedes the arrays in each view.
TEST(AbiLayout, EveryViewOfTheUnknownsCarriesItsLength) {
  EXPECT_LT(offsetof(mh_unknown_values, num_unknowns), offsetof(mh_unknown_values, x));
  EXPECT_LT(offsetof(mh_unknown_buffers, num_unknowns), offsetof(mh_unknown_buffers, x));
  EXPECT_LT(offsetof(mh_tangent_blocks, num_unknowns), offsetof(mh_tangent_blocks, dr_dx));
  EXPECT_LT(offsetof(mh_mechanics_map, num_unknowns), offsetof(mh_mechanics_map, dz_dx));
  EXPECT_LT(offsetof(mh_coordinate_buffers, num_coordinates), offsetof(mh_coordinate_buffers, z));
  EXPECT_LT(offsetof(mh_step_map, num_unknowns), offsetof(mh_step_map, x_predicted));
  EXPECT_GT(offsetof(mh_subsystem_eval, num_touched), offsetof(mh_subsystem_eval, outputs));
}

// The positions-only modifier of evaluate_mechanics' flags is distinct from
// the three requests.
TEST(AbiLayout, ThePositionsOnlyBitIsDistinctFromTheRequestFlags) {
  EXPECT_EQ(MH_EVAL_DYNAMICS, 0x1u);
  EXPECT_EQ(MH_EVAL_CONSTRAINTS, 0x2u);
  EXPECT_EQ(MH_EVAL_SUBSYSTEMS, 0x4u);
  EXPECT_EQ(MH_EVAL_POSITIONS_ONLY & (MH_EVAL_DYNAMICS | MH_EVAL_CONSTRAINTS | MH_EVAL_SUBSYSTEMS),
            0u);
}
