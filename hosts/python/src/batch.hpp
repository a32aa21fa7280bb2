// monohydra.Batch's engine side (_monohydra._Batch): the C++ layer's Batch
// (monohydra/simulation.hpp) kept thin. Its stepping calls release the GIL
// and take back Python's signals between chunks of steps, so Ctrl-C stops a
// long advance between two steps with KeyboardInterrupt.
#pragma once

#include <pybind11/pybind11.h>

namespace monohydra::python {

void bind_batch(pybind11::module_& m);

}  // namespace monohydra::python
