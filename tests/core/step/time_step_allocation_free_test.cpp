// The time step allocates nothing (common rule of the project): a counting
// malloc replaces the C library's for this whole test executable, so it sees
// the host's allocations, those of Eigen (std::malloc), of operator new (which
// calls malloc) and those of the plugins the host dlopen's. Built as an
// executable of its own (tests/CMakeLists.txt), never under the sanitizers,
// which replace malloc themselves.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

// glibc's own allocator, which every replacement of malloc may call.
extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t n, size_t size);
void* __libc_realloc(void* p, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void __libc_free(void* p);
}

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

// The replacements: count, then let glibc allocate. Exported from the
// executable (-rdynamic), they take precedence over libc's in every library
// loaded later, the plugins included.
extern "C" {
void* malloc(size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(size_t n, size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, size);
}
void* realloc(void* p, size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, size);
}
void* memalign(size_t alignment, size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(size_t alignment, size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, size_t alignment, size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  void* p = __libc_memalign(alignment, size);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
void free(void* p) {
  __libc_free(p);
}
}

namespace mh {
namespace {

long allocations() {
  return g_allocations.load(std::memory_order_relaxed);
}

// Controls: the counter sees an allocation of this executable, and one made
// inside a library loaded with dlopen (as the plugins are).
TEST(TimeStepAllocationFree, TheCounterSeesAllocationsHereAndInDlopenedLibraries) {
  const long before = allocations();
  std::vector<double> v(100, 1.0);
  EXPECT_GT(allocations(), before);
  EXPECT_EQ(v[99], 1.0);

  void* lib = dlopen(mh::test::paths::allocating_library, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(lib, nullptr) << dlerror();
  using Make = void* (*)(int);
  using Release = void (*)(void*);
  auto* new_block = reinterpret_cast<Make>(dlsym(lib, "mh_fixture_new_block"));
  auto* delete_block = reinterpret_cast<Release>(dlsym(lib, "mh_fixture_delete_block"));
  auto* malloc_block = reinterpret_cast<Make>(dlsym(lib, "mh_fixture_malloc_block"));
  auto* free_block = reinterpret_cast<Release>(dlsym(lib, "mh_fixture_free_block"));
  ASSERT_TRUE(new_block != nullptr && delete_block != nullptr && malloc_block != nullptr &&
              free_block != nullptr);
  const long before_new = allocations();
  void* a = new_block(64);  // operator new of libstdc++, called from the library
  EXPECT_EQ(allocations() - before_new, 1);
  const long before_malloc = allocations();
  void* b = malloc_block(64);  // malloc, called from the library
  EXPECT_EQ(allocations() - before_malloc, 1);
  delete_block(a);
  free_block(b);
  dlclose(lib);
}

struct Case {
  const char* model;
  const char* formulation;
  NewtonKind newton;
  bool line_search = false;
};

std::string name(const Case& c) {
  return std::string(c.model) + " " + c.formulation + " " + to_string(c.newton) +
         (c.line_search ? " line search" : "");
}

void PrintTo(const Case& c, std::ostream* os) {
  *os << name(c);
}

// A few steps size whatever grows on first use (the Newton statistics, the
// linear solver's first factorization); after them, `steps` more steps
// allocate nothing.
void expect_no_allocation(const Case& c) {
  const std::string model = c.model;
  ModelFile file =
      load_model_file(test::source_path(model.rfind("tests/", 0) == 0 ? model : "models/" + model));
  file.solver.newton = c.newton;
  file.solver.line_search = c.line_search;
  Simulation sim(file, test::build_plugins(), RunChoices{c.formulation, "", {}, {}});
  sim.start();
  for (int k = 0; k < 20; ++k) sim.step();
  constexpr int kSteps = 1000;
  long worst = 0;
  int first_allocating = -1;
  for (int k = 0; k < kSteps; ++k) {
    const long before = allocations();
    sim.step();
    const long made = allocations() - before;
    if (made > 0 && first_allocating < 0) first_allocating = k;
    worst = std::max(worst, made);
  }
  EXPECT_EQ(worst, 0) << name(c) << ": step " << 21 + first_allocating << " allocated " << worst
                      << " blocks (the most of " << kSteps << " steps)";
}

// A snapshot saved again into the same RunState reuses its storage: a
// controller that saves at every step allocates nothing either.
TEST(TimeStepAllocationFree, SavingTheRunStateAgainIntoTheSameValueAllocatesNothing) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  ModelFile modified = file;
  modified.solver.newton = NewtonKind::modified;
  for (const ModelFile* f : {&file, static_cast<const ModelFile*>(&modified)}) {
    Simulation sim(*f, test::build_plugins(), RunChoices{"double-step", "", {}, {}});
    sim.start();
    for (int k = 0; k < 20; ++k) sim.step();
    RunState state;
    sim.save_state(state);
    long worst = 0;
    for (int k = 0; k < 100; ++k) {
      sim.step();
      const long before = allocations();
      sim.save_state(state);
      worst = std::max(worst, allocations() - before);
    }
    EXPECT_EQ(worst, 0) << to_string(f->solver.newton);
  }
}

#ifdef MH_HAVE_TEST_FMUS
// Imported FMUs (monohydra-fmu) in the step: the plant with its directional
// derivatives reading a state, the PI without them (differenced tangent)
// reading the plant's output, and a snapshot saved again at every step.
TEST(TimeStepAllocationFree, StepsWithImportedFmusAllocateNothing) {
  const std::string dir = mh::test::paths::fmu_dir;
  const std::string model =
      "units: {length: m, mass: kg, time: s, angle: rad}\nsubsystems:\n"
      "  - {name: lag, type: first-order-lag, input: [[0, 0], [1, 1]], time_constant: 0.2}\n"
      "  - {name: d, type: fmu, fmu: '" +
      dir + "/plant.fmu', u: lag.y, bias_time: 0.5, bias: 0.2, bias_off_time: 0.7005}\n" +
      "  - {name: c, type: fmu, fmu: '" + dir +
      "/pi.fmu', setpoint: 1, measurement: d.y, kp: 2, ki: 1, output_max: 1.5}\n"
      "solver: {dt: 0.001, t_end: 2}\n";
  for (const NewtonKind newton : {NewtonKind::full, NewtonKind::per_step, NewtonKind::modified}) {
    ModelFile file = parse_model_text(model, "fmus.yaml");
    file.solver.newton = newton;
    Simulation sim(file, test::build_plugins());
    sim.start();
    for (int k = 0; k < 20; ++k) sim.step();
    RunState state;
    sim.save_state(state);
    long worst = 0;
    for (int k = 0; k < 1000; ++k) {  // through both time events
      const long before = allocations();
      sim.step();
      sim.save_state(state);
      worst = std::max(worst, allocations() - before);
    }
    EXPECT_EQ(worst, 0) << to_string(newton);
  }
}
#endif

class TimeStepAllocationFreeCase : public ::testing::TestWithParam<Case> {};

TEST_P(TimeStepAllocationFreeCase, StepsAfterTheFirstAllocateNothing) {
  expect_no_allocation(GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    CaseStudies, TimeStepAllocationFreeCase,
    ::testing::Values(Case{"fourbar.yaml", "penalty", NewtonKind::full},
                      Case{"fourbar.yaml", "penalty", NewtonKind::modified},
                      Case{"quickreturn.yaml", "penalty", NewtonKind::full},
                      Case{"quickreturn.yaml", "penalty", NewtonKind::modified},
                      Case{"fourbar.yaml", "double-step", NewtonKind::full},
                      Case{"fourbar.yaml", "double-step", NewtonKind::modified},
                      Case{"quickreturn.yaml", "double-step", NewtonKind::full},
                      Case{"quickreturn.yaml", "double-step", NewtonKind::modified},
                      Case{"double-pendulum.yaml", "open-loop", NewtonKind::full},
                      Case{"double-pendulum.yaml", "open-loop", NewtonKind::modified},
                      Case{"excavator.yaml", "", NewtonKind::full},
                      Case{"fourbar.yaml", "double-step", NewtonKind::per_step},
                      Case{"quickreturn.yaml", "penalty", NewtonKind::per_step},
                      Case{"excavator.yaml", "", NewtonKind::per_step},
                      Case{"double-pendulum.yaml", "open-loop", NewtonKind::articulated},
                      Case{"fourbar.yaml", "penalty", NewtonKind::full, true},
                      Case{"quickreturn.yaml", "double-step", NewtonKind::full, true},
                      // Increments shortened at every valve opening: up to 12 residuals
                      // an iteration.
                      Case{"tests/fixtures/check/stiff-relief.yaml", "", NewtonKind::full, true}),
    [](const ::testing::TestParamInfo<Case>& param) {
      std::string n = name(param.param);
      for (char& ch : n)
        if (std::isalnum(static_cast<unsigned char>(ch)) == 0) ch = '_';
      return n;
    });

}  // namespace
}  // namespace mh
