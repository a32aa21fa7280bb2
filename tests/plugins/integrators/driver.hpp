// The test harness: loads monohydra-integrators.so through its entry symbol,
// wraps one integrator instance, and drives it on linear test problems
//   A2 xdd + A1 xd + A0 x = f(t)
// by solving each step's equations exactly through the integrator's affine
// map (xd = dxd_dx x + xd_offset, xdd = dxdd_dx x + xdd_offset, per kind):
// a host's Newton iteration on a linear residual, done in one dense solve.
#pragma once

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "build_paths.hpp"
#include "fake_host.hpp"
#include "monohydra/cpp/unknowns.hpp"
#include "monohydra/entry.h"
#include "monohydra/integrator.h"

namespace mh_test {

// The library, opened once for the whole test program.
class IntegratorLibrary {
 public:
  static const IntegratorLibrary& get() {
    static const IntegratorLibrary library;
    return library;
  }
  const mh_integrator_factory* factory() const { return factory_; }
  const mh_plugin_entry* entry() const { return entry_; }

 private:
  IntegratorLibrary() {
    const std::string path = std::string(mh::test::paths::plugin_dir) + "/monohydra-integrators.so";
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle_ == nullptr) throw std::runtime_error("dlopen " + path + ": " + dlerror());
    entry_ = static_cast<const mh_plugin_entry*>(dlsym(handle_, MH_ENTRY_SYMBOL));
    if (entry_ == nullptr) throw std::runtime_error("no mh_entry in " + path);
    if (entry_->init(path.c_str()) == 0) throw std::runtime_error("init failed");
    factory_ =
        static_cast<const mh_integrator_factory*>(entry_->get_factory(MH_INTEGRATOR_FACTORY_ID));
    if (factory_ == nullptr) throw std::runtime_error("no integrator factory");
  }
  // Never closed: the process ends with the tests.
  void* handle_ = nullptr;
  const mh_plugin_entry* entry_ = nullptr;
  const mh_integrator_factory* factory_ = nullptr;
};

// One integrator instance with its host and the host-owned map arrays.
class Integrator {
 public:
  explicit Integrator(const std::string& id, std::map<std::string, double> options = {}) {
    host.numbers = std::move(options);
    const mh_integrator_factory* f = IntegratorLibrary::get().factory();
    api_ = f->create(f, host.api(), id.c_str());
  }
  ~Integrator() {
    if (api_ != nullptr) api_->destroy(api_);
  }
  Integrator(const Integrator&) = delete;
  Integrator& operator=(const Integrator&) = delete;

  const mh_integrator* api() const { return api_; }

  mh_status setup(const std::vector<uint8_t>& kinds, double t0, double dt) {
    kinds_ = kinds;
    const auto n = kinds.size();
    x_predicted.assign(n, 0.0);
    xd_offset.assign(n, 0.0);
    xdd_offset.assign(n, 0.0);
    mh_integrator_problem p{};
    p.struct_size = sizeof(p);
    p.num_unknowns = static_cast<uint32_t>(n);
    p.kinds = kinds_.data();
    p.t0 = t0;
    p.dt = dt;
    return api_->setup(api_, &p);
  }
  mh_status restart(double t, const std::vector<double>& x, const std::vector<double>& xd,
                    const std::vector<double>& xdd) {
    const mh_unknown_values at =
        monohydra::unknown_values(t, x.size(), x.data(), xd.data(), xdd.data());
    return api_->restart(api_, &at);
  }
  mh_status begin_step(double t_next, double h) {
    map = mh_step_map{};
    map.struct_size = sizeof(map);
    map.num_unknowns = static_cast<uint32_t>(kinds_.size());
    map.x_predicted = x_predicted.data();
    map.xd_offset = xd_offset.data();
    map.xdd_offset = xdd_offset.data();
    return api_->begin_step(api_, t_next, h, &map);
  }
  mh_status accept(double t, const std::vector<double>& x, const std::vector<double>& xd,
                   const std::vector<double>& xdd) {
    const mh_unknown_values at =
        monohydra::unknown_values(t, x.size(), x.data(), xd.data(), xdd.data());
    return api_->accept(api_, &at);
  }

  // The map's rate coefficients of unknown i (0 when it has no such rate).
  double dxd_dx(size_t i) const {
    if (kinds_[i] == MH_UNKNOWN_SECOND_ORDER) return map.coefficients.dxd_dx_second;
    if (kinds_[i] == MH_UNKNOWN_FIRST_ORDER) return map.coefficients.dxd_dx_first;
    return 0.0;
  }
  double dxdd_dx(size_t i) const {
    return kinds_[i] == MH_UNKNOWN_SECOND_ORDER ? map.coefficients.dxdd_dx_second : 0.0;
  }
  // The rates the map gives at x (xd, xdd of unknowns without them: 0).
  double xd_at(size_t i, double x) const {
    return kinds_[i] == MH_UNKNOWN_ALGEBRAIC ? 0.0 : dxd_dx(i) * x + xd_offset[i];
  }
  double xdd_at(size_t i, double x) const {
    return kinds_[i] == MH_UNKNOWN_SECOND_ORDER ? dxdd_dx(i) * x + xdd_offset[i] : 0.0;
  }
  const std::vector<uint8_t>& kinds() const { return kinds_; }

  FakeHost host;
  mh_step_map map{};
  std::vector<double> x_predicted, xd_offset, xdd_offset;

 private:
  const mh_integrator* api_ = nullptr;
  std::vector<uint8_t> kinds_;
};

// A2 xdd + A1 xd + A0 x = f(t), n unknowns, matrices row-major n x n.
struct LinearProblem {
  std::vector<uint8_t> kinds;
  std::vector<double> A2, A1, A0;
  std::function<void(double t, double* f)> f;
  size_t n() const { return kinds.size(); }
};

struct State {
  double t = 0.0;
  std::vector<double> x, xd, xdd;
};

// Solves A z = b in place (Gaussian elimination, partial pivoting); A row-major.
inline void solve_dense(std::vector<double> A, std::vector<double>& b) {
  const size_t n = b.size();
  for (size_t k = 0; k < n; ++k) {
    size_t p = k;
    for (size_t i = k + 1; i < n; ++i)
      if (std::abs(A[i * n + k]) > std::abs(A[p * n + k])) p = i;
    if (A[p * n + k] == 0.0) throw std::runtime_error("singular step matrix");
    if (p != k) {
      for (size_t j = 0; j < n; ++j) std::swap(A[k * n + j], A[p * n + j]);
      std::swap(b[k], b[p]);
    }
    for (size_t i = k + 1; i < n; ++i) {
      const double l = A[i * n + k] / A[k * n + k];
      if (l == 0.0) continue;
      for (size_t j = k; j < n; ++j) A[i * n + j] -= l * A[k * n + j];
      b[i] -= l * b[k];
    }
  }
  for (size_t k = n; k-- > 0;) {
    double s = b[k];
    for (size_t j = k + 1; j < n; ++j) s -= A[k * n + j] * b[j];
    b[k] = s / A[k * n + k];
  }
}

// One step of length h from `s` (the integrator's last accepted or restarted
// state): map, exact solve of the linear equations at t + h, accept.
inline State step(Integrator& integ, const LinearProblem& p, const State& s, double h) {
  const size_t n = p.n();
  const double t_next = s.t + h;
  if (integ.begin_step(t_next, h) != MH_OK) throw std::runtime_error("begin_step failed");
  // (A2 D2 + A1 D1 + A0) x = f - A2 o2 - A1 o1
  std::vector<double> K(n * n), b(n);
  p.f(t_next, b.data());
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      K[i * n + j] =
          p.A2[i * n + j] * integ.dxdd_dx(j) + p.A1[i * n + j] * integ.dxd_dx(j) + p.A0[i * n + j];
      b[i] -= p.A2[i * n + j] * integ.xdd_at(j, 0.0) + p.A1[i * n + j] * integ.xd_at(j, 0.0);
    }
  solve_dense(K, b);
  State next;
  next.t = t_next;
  next.x = b;
  next.xd.resize(n);
  next.xdd.resize(n);
  for (size_t i = 0; i < n; ++i) {
    next.xd[i] = integ.xd_at(i, next.x[i]);
    next.xdd[i] = integ.xdd_at(i, next.x[i]);
  }
  if (integ.accept(t_next, next.x, next.xd, next.xdd) != MH_OK)
    throw std::runtime_error("accept failed");
  return next;
}

// Runs from s0 with the steps `hs`, calling `each` after every step.
inline State run(Integrator& integ, const LinearProblem& p, const State& s0,
                 const std::vector<double>& hs,
                 const std::function<void(const State&)>& each = nullptr) {
  if (integ.setup(p.kinds, s0.t, hs.front()) != MH_OK) throw std::runtime_error("setup failed");
  if (integ.restart(s0.t, s0.x, s0.xd, s0.xdd) != MH_OK) throw std::runtime_error("restart failed");
  State s = s0;
  for (double h : hs) {
    s = step(integ, p, s, h);
    if (each) each(s);
  }
  return s;
}

inline std::vector<double> uniform_steps(double t_end, double h) {
  return std::vector<double>(static_cast<size_t>(std::lround(t_end / h)), h);
}

// The integrators of the library and the options each test runs them with.
struct Case {
  const char* id;
  std::map<std::string, double> options;
};
inline std::vector<Case> all_cases() {
  return {{"trapezoidal", {}},
          {"generalized-alpha", {}},
          {"generalized-alpha", {{"rho_inf", 0.0}}},
          {"generalized-alpha", {{"rho_inf", 0.5}}},
          {"bdf2", {}}};
}
inline std::string name(const Case& c) {
  std::string s = c.id;
  for (const auto& o : c.options) s += " " + o.first + "=" + std::to_string(o.second);
  return s;
}

}  // namespace mh_test
