// Whether an explicit integrator's step is within its stability bound
// (docs/integrators.md). The run linearises the rates it solves for at a
// state (their map from the integrated state, by differences of its own rate
// solve), takes the eigenvalues lambda of that map, and asks the integrator
// plugin itself what one step does to the linear test equation y' = lambda y:
// its amplification factor R(h lambda), from its own stage operations, so any
// explicit integrator is judged by its own formula, not by RK4's. A mode the
// step amplifies more than the exact flow does (|R(h lambda)| > max(1,
// |exp(h lambda)|)) grows without bound: the run is unstable, however bounded
// its first seconds look.
#pragma once

#include <complex>
#include <initializer_list>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "monohydra/integrator.h"

namespace mh {

// solver.explicit_stability and --explicit-stability: what an unstable
// explicit step does to the run. warn (the default) notes it in the summary
// and the result's sidecar and goes on, so a comparison can show the failure;
// error stops the run with the time, the step and the reason; off skips the
// check.
enum class ExplicitStabilityPolicy { off, warn, error };
// Inline: the model-file parser uses them, and the loader's fuzzer links the
// parser without the engine.
inline const char* to_string(ExplicitStabilityPolicy policy) {  // "off", "warn", "error"
  switch (policy) {
    case ExplicitStabilityPolicy::off:
      return "off";
    case ExplicitStabilityPolicy::error:
      return "error";
    default:
      return "warn";
  }
}
// "off", "warn" or "error"; false for anything else.
inline bool parse_explicit_stability(const std::string& text, ExplicitStabilityPolicy& policy) {
  for (const auto p : {ExplicitStabilityPolicy::off, ExplicitStabilityPolicy::warn,
                       ExplicitStabilityPolicy::error})
    if (text == to_string(p)) {
      policy = p;
      return true;
    }
  return false;
}

// What the run's checks found: the worst one (the largest excess
// |R| / max(1, |exp(h lambda)|)) and the smallest stable step seen.
struct ExplicitStability {
  int checks = 0;                   // 0: an implicit integrator, or the check is off
  bool unstable = false;            // some check found a mode the step amplifies
  double t = 0.0;                   // s: the state of the worst check
  long step = 0;                    // the step it preceded
  double h = 0.0;                   // s: that step
  double amplification = 1.0;       // |R(h lambda)| of its worst mode
  std::complex<double> eigenvalue;  // 1/s: that mode's lambda
  // s: the largest h at which every mode of every check is stable (a
  // bisection on h with the same amplification factor); infinity when no h
  // up to 2^40 dt is unstable (every mode at rest).
  double stable_dt = std::numeric_limits<double>::infinity();
  double cpu_seconds = 0.0;  // all checks together (process CPU time)
  int skipped = 0;           // checks whose rate solve failed at a perturbed state
};

// The stability check's margin: |R| may exceed the exact flow's growth by
// this fraction (round-off in the differenced rates) before a mode counts
// as amplified.
constexpr double kAmplificationTolerance = 1e-6;

// R(h lambda) of one explicit integrator by its own stage operations: an
// instance of its own, set up for two first-order unknowns u carrying y =
// u0 + i u1 (y' = lambda y is u' = [[Re, -Im], [Im, Re]] u), restarted at
// u = (1, 0) and stepped once by h: u = (Re R, Im R). Exact for every linear
// one-step method whose first-order formula is the same for every unknown.
class StageAmplification {
 public:
  // Takes `instance` (an explicit integrator not yet set up; destroyed here).
  explicit StageAmplification(const mh_integrator* instance);
  ~StageAmplification();
  StageAmplification(const StageAmplification&) = delete;
  StageAmplification& operator=(const StageAmplification&) = delete;

  // Throws std::runtime_error when the plugin fails an operation.
  std::complex<double> factor(std::complex<double> lambda, double h);
  // |R(h lambda)| / max(1, |exp(h lambda)|): above 1 + kAmplificationTolerance
  // the step amplifies the mode more than the exact flow does.
  double excess(std::complex<double> lambda, double h);
  // The largest h at which no eigenvalue's excess is above the tolerance:
  // from h0 doubled (or halved) to a bracket, then bisected to 1e-4
  // relative; infinity when none is unstable up to 2^40 h0.
  double largest_stable_step(const std::vector<std::complex<double>>& eigenvalues, double h0);

 private:
  void set_up(double h);
  const mh_integrator* self_;
  mh_integrator ops_{};
  mh_explicit_method stages_{};  // its explicit method's operations
  double setup_h_ = 0.0;
};

}  // namespace mh
