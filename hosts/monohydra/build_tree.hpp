// Where this build tree put what the command line looks for before it is
// installed: the source tree's models, the FMU binary, sweep's MPI transport.
// The absolute paths are compiled into build_tree.cpp alone, so that every
// other file of the host compiles to the same object in any clone and a
// compiler cache serves it to a clone in another folder.
#pragma once

namespace mh::cli::build_tree {

extern const char* const source_models;  // <source>/models
extern const char* const fmu_binary;     // the built monohydra-fmu.so
extern const char* const mpi_transport;  // the built libmonohydra_sweep_mpi.so; "" without MPI

}  // namespace mh::cli::build_tree
