#include "build_tree.hpp"

namespace monohydra::testhost::build_tree {

const char* const source_models = MONOHYDRA_SOURCE_MODELS;

}  // namespace monohydra::testhost::build_tree
