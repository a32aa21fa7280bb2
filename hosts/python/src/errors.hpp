// What a failed call raises from Python, by what the call was: InputError
// (a model, a name or a value that is wrong: nothing changed) or
// SimulationError (a step that failed), both monohydra.Error (module.cpp
// registers them).
#pragma once

#include "monohydra/simulation.hpp"

namespace monohydra::python {

// The exception a failed call raises, by what the call was.
struct InputError : monohydra::Error {
  explicit InputError(const monohydra::Error& e) : monohydra::Error(e) {}
};
struct SimulationError : monohydra::Error {
  explicit SimulationError(const monohydra::Error& e) : monohydra::Error(e) {}
};

template <class Call>
auto as_input(Call&& call) {
  try {
    return call();
  } catch (const monohydra::Error& e) {
    throw InputError(e);
  }
}

template <class Call>
auto as_run(Call&& call) {
  try {
    return call();
  } catch (const monohydra::Error& e) {
    throw SimulationError(e);
  }
}

}  // namespace monohydra::python
