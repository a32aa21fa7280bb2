#include "build_tree.hpp"

namespace mh::cli::build_tree {

const char* const source_models = MONOHYDRA_SOURCE_MODELS;
const char* const fmu_binary = MONOHYDRA_FMU_BUILD_PATH;
#ifdef MONOHYDRA_MPI_BUILD_PATH
const char* const mpi_transport = MONOHYDRA_MPI_BUILD_PATH;
#else
const char* const mpi_transport = "";
#endif

}  // namespace mh::cli::build_tree
