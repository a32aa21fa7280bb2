# The examples as a third party gets them: the SDK component installed alone
# into a fresh prefix (headers, CMake package, test host, docs and example
# sources), and each INSTALLED example configured, built and unit-tested
# against that prefix alone.
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
# Under the sanitizers (.ci/sanitize) the installed test host is instrumented:
# an example's test executable must then carry the ASan runtime first, so the
# examples are built with the same flags.
set(sanitize_flags)
if(SANITIZE)
  set(flags "-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined")
  foreach(kind C CXX)
    list(APPEND sanitize_flags "-DCMAKE_${kind}_FLAGS=${flags}")
  endforeach()
  foreach(kind EXE SHARED MODULE)
    list(APPEND sanitize_flags "-DCMAKE_${kind}_LINKER_FLAGS=${flags}")
  endforeach()
  # The same compilers (one ASan runtime in a process), and the SDK's plugin
  # function told so: with clang a module takes the runtime from its host.
  list(APPEND sanitize_flags "-DCMAKE_C_COMPILER=${C_COMPILER}"
       "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}" -DMONOHYDRA_SANITIZE=ON)
  # clang puts UBSan's C++ runtime, which the library's code calls, only into
  # programs linked as C++: the embedding example is a C program.
  if(CXX_COMPILER MATCHES "clang")
    list(TRANSFORM sanitize_flags REPLACE "^(-DCMAKE_EXE_LINKER_FLAGS=.*)$"
         "\\1 -fsanitize-link-c++-runtime -lstdc++")
  endif()
endif()
# This build's compiler cache, when it has one, for the examples too: their
# sources and the headers they include are all under OUT, which reaches the
# compiler relative to itself, so a clone in another folder is served what this
# machine compiled before (the configure and link steps stay, the compiles were
# two thirds of this test's time). A third party's build is the same but
# for the launcher.
set(launcher)
set(cache_env)
if(CCACHE)
  set(launcher -DCMAKE_C_COMPILER_LAUNCHER=${CCACHE} -DCMAKE_CXX_COMPILER_LAUNCHER=${CCACHE})
  set(cache_env ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${OUT} CCACHE_NOHASHDIR=true CCACHE_DEPEND=true
                CCACHE_MAXSIZE=5G)
endif()
get_filename_component(cmake_bin ${CMAKE_COMMAND} DIRECTORY)
set(ctest ${cmake_bin}/ctest)
run(${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${prefix} --component sdk)
foreach(file include/monohydra/testhost.hpp lib/libmonohydra_testhost.so)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "the SDK component does not install ${file} (the test host)")
  endif()
endforeach()
foreach(doc sdk plugin-guide integrators hydraulics formulations model-format)
  if(NOT EXISTS ${prefix}/share/doc/monohydra/${doc}.md)
    message(FATAL_ERROR "the SDK's docs lack share/doc/monohydra/${doc}.md")
  endif()
endforeach()
# The full install holds the shipped plugins, the host's own libraries (the
# sweep's MPI transport, the embedding library and its Python module, the
# binary every exported FMU carries) and
# nothing built for tests (tests/fixtures: broken
# on purpose, never installed).
run(${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${OUT}/full)
file(GLOB_RECURSE libraries RELATIVE ${OUT}/full ${OUT}/full/*.so)
foreach(library ${libraries})
  if(NOT library MATCHES "^lib/monohydra/plugins/monohydra-[a-z-]+\\.so$" AND
     NOT library STREQUAL "lib/monohydra/libmonohydra_sweep_mpi.so" AND
     NOT library STREQUAL "lib/libmonohydra_testhost.so" AND
     NOT library STREQUAL "lib/libmonohydra_simulation.so" AND
     NOT library STREQUAL "lib/monohydra/fmu/monohydra-fmu.so" AND
     NOT library MATCHES "^lib/python3\\.[0-9]+/dist-packages/monohydra/_monohydra\\.[^/]+\\.so$")
    message(FATAL_ERROR "cmake --install installs ${library}, which is not a shipped plugin")
  endif()
endforeach()
if(NOT EXISTS ${OUT}/full/lib/monohydra/plugins/monohydra-penalty.so)
  message(FATAL_ERROR "cmake --install did not install the shipped plugins")
endif()
# The installed command line finds the installed FMU binary and plugins.
run(${OUT}/full/bin/monohydra fmu ${OUT}/full/share/monohydra/models/fourbar.yaml
    --out ${OUT}/installed-fourbar.fmu)
if(NOT EXISTS ${OUT}/installed-fourbar.fmu)
  message(FATAL_ERROR "the installed monohydra fmu wrote no FMU")
endif()
foreach(example accumulator:gas-accumulator lagrange-baumgarte:lagrange-baumgarte point-load:point-load
        rk4:rk4)
  string(REPLACE ":" ";" parts ${example})
  list(GET parts 0 folder)
  list(GET parts 1 library)
  run(${CMAKE_COMMAND} -S ${prefix}/share/doc/monohydra/examples/${folder} -B ${OUT}/build/${folder}
      -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release ${sanitize_flags} ${launcher})
  run(${cache_env} ${CMAKE_COMMAND} --build ${OUT}/build/${folder})
  if(NOT EXISTS ${OUT}/build/${folder}/${library}.so)
    message(FATAL_ERROR "the example ${folder} did not build ${library}.so")
  endif()
  # Its own unit test on the installed test host (point-load has none); the
  # shipped plugins its models use from this build, since the SDK component
  # installs none.
  if(NOT folder STREQUAL "point-load")
    run(${CMAKE_COMMAND} -E env MONOHYDRA_PLUGIN_PATH=${BINARY_DIR}/lib/monohydra/plugins
        ${ctest} --test-dir ${OUT}/build/${folder} --output-on-failure
        --no-tests=error)
  endif()
endforeach()

# The embedding example (a C program on monohydra::simulation) against the
# full install: the library finds the plugins installed beside it, with no
# environment variable (tests/examples/embedding_test.cpp runs it).
run(${CMAKE_COMMAND} -S ${OUT}/full/share/doc/monohydra/examples/embedding -B ${OUT}/build/embedding
    -DCMAKE_PREFIX_PATH=${OUT}/full -DCMAKE_BUILD_TYPE=Release ${sanitize_flags} ${launcher})
run(${cache_env} ${CMAKE_COMMAND} --build ${OUT}/build/embedding)
if(NOT EXISTS ${OUT}/build/embedding/fourbar_embedded)
  message(FATAL_ERROR "the example embedding did not build fourbar_embedded")
endif()
