// What a failed call raises from Python, by what the call was: InputError
// (a model, a name or a value that is wrong: nothing changed) or
// SimulationError (a step that failed), both monohydra.Error (module.cpp
// registers them).
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>

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

// The steps a stepping call takes between two looks at Python's signals:
// at the four-bar's 76 k instructions a step, a few milliseconds.
constexpr uint64_t kStepsBetweenSignals = 100;

// With the GIL released: raises what a signal handler raised
// (KeyboardInterrupt for Ctrl-C), between two steps.
inline void take_signals() {
  const pybind11::gil_scoped_acquire locked;
  if (PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
}

// `steps(k)` for k summing to n, k at most kStepsBetweenSignals, Python's
// signals taken between two calls.
template <class Steps>
void step_in_chunks(uint64_t n, Steps&& steps) {
  while (n > 0) {
    const uint64_t now = n < kStepsBetweenSignals ? n : kStepsBetweenSignals;
    steps(now);
    n -= now;
    if (n > 0) take_signals();
  }
}

// `advance(to)` from `from` to `t` by kStepsBetweenSignals steps of `dt` at
// a time, Python's signals taken between two calls; at least one call (a
// time before the run's is refused there).
template <class Advance>
void advance_in_chunks(double from, double t, double dt, Advance&& advance) {
  const double chunk = static_cast<double>(kStepsBetweenSignals) * dt;
  double now = from;
  do {
    now = now + chunk < t ? now + chunk : t;
    advance(now);
    if (now < t) take_signals();
  } while (now < t);
}

}  // namespace monohydra::python
