/* The SDK compiles as plain C11, and its structs have the layout this file
 * records; abi_layout_test.cpp checks C++ sees the same layout. */
#include <stddef.h>

#include "monohydra/constrained.h"
#include "monohydra/inverse_dynamics.h"
#include "monohydra/monohydra.h"
#include "monohydra/parameters.h"
#include "monohydra/sparsity.h"
#include "monohydra/visual.h"

#define LAYOUT(T) \
  { #T, sizeof(T), _Alignof(T) }

typedef struct abi_layout {
  const char* name;
  size_t size;
  size_t align;
} abi_layout;

/* Interface structs begin with struct_size (or the version, for the entry). */
_Static_assert(offsetof(mh_host, struct_size) == 0, "mh_host starts with struct_size");
_Static_assert(offsetof(mh_formulation, struct_size) == 0, "struct_size first");
_Static_assert(offsetof(mh_subsystem, struct_size) == 0, "struct_size first");
_Static_assert(offsetof(mh_integrator, struct_size) == 0, "struct_size first");
_Static_assert(offsetof(mh_plugin_entry, abi_version) == 0, "entry starts with its version");
_Static_assert(sizeof(mh_status) == sizeof(int), "status is an int-sized enum");

const abi_layout mh_c_layouts[] = {
    LAYOUT(mh_version),
    LAYOUT(mh_component_descriptor),
    LAYOUT(mh_plugin_entry),
    LAYOUT(mh_mech_info),
    LAYOUT(mh_mech_request),
    LAYOUT(mh_mech_result),
    LAYOUT(mh_port_spec),
    LAYOUT(mh_host),
    LAYOUT(mh_formulation),
    LAYOUT(mh_formulation_factory),
    LAYOUT(mh_subsystem_eval),
    LAYOUT(mh_subsystem),
    LAYOUT(mh_subsystem_factory),
    LAYOUT(mh_integrator),
    LAYOUT(mh_integrator_factory),
    LAYOUT(mh_step_map),
    LAYOUT(mh_step_coefficients),
    LAYOUT(mh_state_spec),
    LAYOUT(mh_output_spec),
    LAYOUT(mh_unknown_spec),
    LAYOUT(mh_mech_derivatives_request),
    LAYOUT(mh_mech_derivatives),
    LAYOUT(mh_unknown_values),
    LAYOUT(mh_unknown_buffers),
    LAYOUT(mh_step_begin),
    LAYOUT(mh_tangent_blocks),
    LAYOUT(mh_mechanics_map),
    LAYOUT(mh_coordinate_buffers),
    LAYOUT(mh_explicit_method),
    LAYOUT(mh_options_service),
    LAYOUT(mh_mechanism_service),
    LAYOUT(mh_outputs_service),
    LAYOUT(mh_subsystem_setup_service),
    LAYOUT(mh_unknowns_service),
    LAYOUT(mh_state_extension),
    LAYOUT(mh_visual_spec),
    LAYOUT(mh_visual_service),
    LAYOUT(mh_sparsity_service),
    LAYOUT(mh_mechanical_pattern_service),
    LAYOUT(mh_inverse_dynamics_service),
};
const size_t mh_c_layout_count = sizeof(mh_c_layouts) / sizeof(mh_c_layouts[0]);
const size_t mh_c_offset_host_get_service = offsetof(mh_host, get_service);
const size_t mh_c_offset_formulation_get_extension = offsetof(mh_formulation, get_extension);
const size_t mh_c_offset_subsystem_get_extension = offsetof(mh_subsystem, get_extension);
