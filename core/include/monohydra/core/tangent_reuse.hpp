// When the Newton loop (newton_solve.cpp) must assemble and factor the
// tangent anew (solver.newton). `full` factors at every iteration. `per-step`
// (the default) factors once per step, at the integrator's prediction, and
// keeps that factorization for the step's further iterations: its first
// increment is full Newton's, and a later one is a chord step on a tangent a
// step's motion away from exact, so the iteration contracts at a rate of the
// order of the step's own increments. `modified` keeps the factorization
// across steps too, while the iteration contracts fast enough. The
// convergence test stays the increment's (|dx_i| <= tol_i): an iteration that
// contracts at rate theta leaves an error of at most theta / (1 - theta) |dx|,
// so a factorization is kept only while theta <= 1/2, where that bound is
// |dx| itself. `approximate` (solver.newton: articulated) makes a matrix that
// is not the tangent at every iteration, and converges only when its
// increment is far below the tolerance (kApproximateIncrement).
#pragma once

#include <cmath>
#include <cstdint>

#include "monohydra/integrator.h"

namespace mh {

class TangentReuse {
 public:
  // Rate of contraction |dx_k| / |dx_k-1| above which the tangent is refreshed.
  static constexpr double kMaxRate = 0.5;
  // Rate of contraction between two increments on tangents of their step above which
  // the tangent is taken not to be exact (Newton on it converges linearly).
  static constexpr double kExactTangentRate = 0.1;
  // Iterations of one step on one factorization before it is refreshed.
  static constexpr int kMaxIterationsPerTangent = 4;
  // An approximate matrix's iteration converges when its increment is at
  // most this fraction of the tolerance.
  static constexpr double kApproximateIncrement = 1e-4;

  enum class Mode : uint8_t { full, modified, per_step, approximate };

  void set_mode(Mode mode) { mode_ = mode; }
  Mode mode() const { return mode_; }

  // Before an iteration: must the tangent be assembled and factored? Always
  // for full Newton; at a step's first iteration for per-step Newton; for
  // both kinds that keep one when there is no factorization, the step's map
  // coefficients (dt, the integrator's method) differ from those it was made
  // at, or the last increments asked for it.
  bool needs_tangent(const mh_step_coefficients& c) const {
    return mode_ == Mode::full || mode_ == Mode::approximate || full_step_ || !valid_ || refresh_ ||
           changed(c.dxd_dx_second, at_.dxd_dx_second) ||
           changed(c.dxdd_dx_second, at_.dxdd_dx_second) ||
           changed(c.dxd_dx_first, at_.dxd_dx_first);
  }
  void factored(const mh_step_coefficients& c) {
    at_ = c;
    valid_ = true;
    refresh_ = false;
    fresh_ = mode_ != Mode::approximate;  // an approximate matrix's increment is never Newton's
    step_tangent_ = fresh_;
    on_this_tangent_ = 0;
    ++factorizations_;
  }
  void begin_step() {
    if (mode_ == Mode::per_step) refresh_ = true;  // a fresh tangent at the prediction
    previous_ = -1.0;
    on_this_tangent_ = 0;
    stale_used_ = false;
    step_tangent_ = false;
    last_on_step_tangent_ = false;
    full_step_ = retry_full_;
    retry_full_ = false;
  }
  // A step that failed on a kept factorization: may it be tried again from
  // its prediction with a fresh tangent at every iteration (full Newton)?
  // Then the next begin_step() starts that attempt.
  bool retry_with_full_newton() {
    // (An approximate matrix has no exact one to fall back on.)
    if (mode_ == Mode::full || mode_ == Mode::approximate || !stale_used_) return false;
    retry_full_ = true;
    invalidate();
    return true;
  }
  // The increment came from a kept factorization and grew: the iteration
  // diverges; the caller undoes it and the next iteration factors anew.
  // (An approximate matrix is made anew at every iteration: undoing would
  // repeat the same increment.)
  bool diverging() const {
    return mode_ != Mode::approximate && !last_fresh_ && previous_increase_;
  }
  // After an iteration's increment, as max_i |dx_i| / tol_i.
  void increment(double worst) {
    ++on_this_tangent_;
    // This increment and the one before on tangents made at this step's iterates.
    const bool both_on_step_tangents = step_tangent_ && last_on_step_tangent_;
    last_on_step_tangent_ = step_tangent_;
    last_fresh_ = fresh_;
    if (!fresh_) stale_used_ = true;
    fresh_ = false;
    previous_increase_ = previous_ > 0.0 && worst > previous_;
    if (previous_increase_ && !last_fresh_) refresh_ = true;  // diverging(): factor anew
    if (previous_ > 0.0) {
      rate_ = worst / previous_;
      rate_of_tangents_ = both_on_step_tangents;
      // A slow rate matters while the iteration has yet to converge; once the
      // increments are within tolerance, converged() weighs it.
      if (rate_ > kMaxRate && worst > 1.0) refresh_ = true;
    }
    if (on_this_tangent_ >= kMaxIterationsPerTangent) refresh_ = true;
    previous_ = worst;
  }
  // Converged: the increment within tolerance and, when it came from a kept
  // factorization, the error bound theta / (1 - theta) |dx| too (theta: the
  // latest rate measured, of this step or an earlier one).
  // A factorization is not trusted to be the exact tangent: Newton on the
  // exact tangent contracts quadratically, and a chord on one made at this
  // step's prediction at a rate of the order of the step's motion, so two
  // successive increments on tangents of this step whose ratio stays above
  // kExactTangentRate say that the matrix is not the residual's derivative
  // (a component's Jacobian is wrong), and the iteration is then held to an
  // approximate matrix's standard. Without it, a spring whose stiffness entries were reported
  // ten times over (tests/fixtures/faulty/faulty_spring.c,
  // FAULT_SCALED_JACOBIAN) met the tolerance at each step with error left
  // that the trapezoidal rule's rates carried on: 2.2e-4 rad from the sound
  // spring's run after 2 s at the default tolerance (full Newton: 8e-15).
  // `quadratic`: whether Newton on the exact tangent contracts
  // quadratically here (not where the residual itself moves between
  // iterations, as an augmented Lagrangian's multipliers do).
  bool converged(double worst, bool quadratic = true) const {
    if (!(worst <= 1.0)) return false;
    // An approximate matrix leaves theta / (1 - theta) of its last increment
    // (theta: its contraction rate, 1e-3 on a swinging double pendulum), and
    // the same error every step, which the trapezoidal rule's rates (2/h,
    // 4/h^2) accumulate in the velocities: its last increment must be far
    // below the tolerance (measured: tests/models/solver_choices_test.cpp).
    if (mode_ == Mode::approximate) return worst <= kApproximateIncrement;
    if (quadratic && tangent_suspect())
      return rate_ < 1.0 && rate_ / (1.0 - rate_) * worst <= kApproximateIncrement;
    if (mode_ == Mode::full || last_fresh_ || rate_ <= kMaxRate) return true;
    return rate_ < 1.0 && rate_ / (1.0 - rate_) * worst <= 1.0;
  }
  // The latest rate came from two tangents of its step and says they are not exact.
  bool tangent_suspect() const { return rate_of_tangents_ && rate_ > kExactTangentRate; }
  double rate() const { return rate_; }
  // A failed step, a restarted integrator, a redefined x: the next iteration
  // factors anew.
  void invalidate() {
    valid_ = false;
    rate_ = 0.0;
    rate_of_tangents_ = false;
  }
  long factorizations() const { return factorizations_; }
  // A factorization is kept for the next step (run_state.cpp saves it):
  // modified Newton's only, as per-step Newton makes a new one at every step.
  bool keeps_factorization() const { return mode_ == Mode::modified && valid_; }

 private:
  // The step h = t_{k+1} - t_k carries round-off from step to step (t = k
  // dt): coefficients within 1e-9 of each other are the same step size.
  static bool changed(double now, double then) {
    return !(std::abs(now - then) <= 1e-9 * std::abs(then));
  }

  Mode mode_ = Mode::full;  // one byte, where a bool `modified` was (run_state_bytes.cpp)
  bool valid_ = false;
  bool refresh_ = false;
  bool full_step_ = false;             // this step factors at every iteration (a retry)
  bool retry_full_ = false;            // the next step is such a retry
  bool stale_used_ = false;            // an increment of this step came from a kept factorization
  bool previous_increase_ = false;     // the last increment was larger than the one before
  bool fresh_ = false;                 // the next increment comes from a new factorization
  bool last_fresh_ = false;            // the last increment came from a new factorization
  bool rate_of_tangents_ = false;      // rate_ is of two increments on tangents of their step
  bool step_tangent_ = false;          // the factorization was made in this step
  bool last_on_step_tangent_ = false;  // the last increment came from one made in this step
  int on_this_tangent_ = 0;            // iterations of this step on the current factorization
  double previous_ = -1.0;             // the last increment of this step
  double rate_ = 0.0;                  // the latest contraction rate measured
  mh_step_coefficients at_{};          // the map's coefficients at the factorization
  long factorizations_ = 0;
};

}  // namespace mh
