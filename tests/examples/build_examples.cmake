# The examples as a third party gets them: the SDK component installed alone
# into a fresh prefix (headers, CMake package, docs and example sources), and
# each INSTALLED example configured and built against that prefix alone.
foreach(var BINARY_DIR OUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "build_examples.cmake: ${var} is not set")
  endif()
endforeach()
file(REMOVE_RECURSE ${OUT})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()
set(prefix ${OUT}/prefix)
run(${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${prefix} --component sdk)
foreach(doc sdk plugin-guide integrators hydraulics formulations model-format)
  if(NOT EXISTS ${prefix}/share/doc/monohydra/${doc}.md)
    message(FATAL_ERROR "the SDK's docs lack share/doc/monohydra/${doc}.md")
  endif()
endforeach()
# The full install holds the shipped plugins, the host's own libraries (the
# sweep's MPI transport) and nothing built for tests (tests/fixtures: broken
# on purpose, never installed).
run(${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${OUT}/full)
file(GLOB_RECURSE libraries RELATIVE ${OUT}/full ${OUT}/full/*.so)
foreach(library ${libraries})
  if(NOT library MATCHES "^lib/monohydra/plugins/monohydra-[a-z-]+\\.so$" AND
     NOT library STREQUAL "lib/monohydra/libmonohydra_sweep_mpi.so")
    message(FATAL_ERROR "cmake --install installs ${library}, which is not a shipped plugin")
  endif()
endforeach()
if(NOT EXISTS ${OUT}/full/lib/monohydra/plugins/monohydra-penalty.so)
  message(FATAL_ERROR "cmake --install did not install the shipped plugins")
endif()
foreach(example accumulator:gas-accumulator lagrange-baumgarte:lagrange-baumgarte point-load:point-load
        rk4:rk4)
  string(REPLACE ":" ";" parts ${example})
  list(GET parts 0 folder)
  list(GET parts 1 library)
  run(${CMAKE_COMMAND} -S ${prefix}/share/doc/monohydra/examples/${folder} -B ${OUT}/build/${folder}
      -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release)
  run(${CMAKE_COMMAND} --build ${OUT}/build/${folder})
  if(NOT EXISTS ${OUT}/build/${folder}/${library}.so)
    message(FATAL_ERROR "the example ${folder} did not build ${library}.so")
  endif()
endforeach()
