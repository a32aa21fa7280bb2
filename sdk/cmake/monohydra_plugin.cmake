# monohydra_add_plugin(TARGET source...)
# Builds a monohydra plugin: a MODULE library against the SDK headers whose
# only exported symbol is the entry `mh_entry` (linker version script), with
# hidden visibility and no undefined symbols (CMake >= 3.17). Used by monohydra's own plugins
# and, from the installed SDK, by third parties alike.
function(monohydra_add_plugin target)
  add_library(${target} MODULE ${ARGN})
  target_link_libraries(${target} PRIVATE monohydra::sdk)
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    C_VISIBILITY_PRESET hidden
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  target_link_options(${target} PRIVATE
    -Wl,--version-script=${CMAKE_CURRENT_FUNCTION_LIST_DIR}/plugin.map)
  # In monohydra's own sanitizer builds (MONOHYDRA_SANITIZE,
  # MONOHYDRA_SANITIZE_THREAD) with clang, a module is not linked against the
  # sanitizers' runtime: the instrumented executable that dlopens it provides
  # those symbols, so --no-undefined would fail there. GCC links the runtime
  # into the module and keeps the check.
  if(NOT ((MONOHYDRA_SANITIZE OR MONOHYDRA_SANITIZE_THREAD) AND
          (CMAKE_C_COMPILER_ID MATCHES "Clang" OR CMAKE_CXX_COMPILER_ID MATCHES "Clang")))
    target_link_options(${target} PRIVATE -Wl,--no-undefined)
  endif()
endfunction()
