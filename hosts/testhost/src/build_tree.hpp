// The source tree's models/, which a test host running from its build tree
// reads. The path is compiled into build_tree.cpp alone, so that the test
// host's other files compile to the same objects in any clone (a compiler
// cache serves them to a clone in another folder).
#pragma once

namespace monohydra::testhost::build_tree {

extern const char* const source_models;

}  // namespace monohydra::testhost::build_tree
