// The SDK's C++ helper (monohydra/cpp/subsystem_component.hpp): optional
// operations found at compile time, exceptions turned into logged errors at
// the boundary, the factory over a list of components, and the struct_size
// check for fields of a later minor ABI; the spec builders; the formulation
// helper's guard (monohydra/cpp/formulation_plugin.hpp).
#include <gtest/gtest.h>

#include <cstddef>
#include <stdexcept>
#include <string>

#include "fake_host.hpp"
#include "monohydra/cpp/formulation_plugin.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/subsystem_component.hpp"

namespace mh::test {
namespace {

int g_alive = 0;  // instances of the classes below not yet destroyed

class Minimal {
 public:
  static const mh_component_descriptor kDescriptor;
  explicit Minimal(const mh_host* host) : host_(host) { ++g_alive; }
  ~Minimal() { --g_alive; }
  Minimal(const Minimal&) = delete;
  Minimal& operator=(const Minimal&) = delete;
  mh_status setup() {
    const mh_state_spec x = monohydra::state_spec("x", "m", 1.0, 1e-6);
    return monohydra::subsystem_setup(host_).add_state(host_, &x, &x_);
  }
  mh_status evaluate(const mh_subsystem_eval& eval) const {
    eval.residual[x_] += eval.ydot[x_] + 2.0 * eval.y[x_];
    return MH_OK;
  }

 private:
  const mh_host* host_;
  int32_t x_ = -1;
};
const mh_component_descriptor Minimal::kDescriptor{
    sizeof(mh_component_descriptor), "minimal", "Minimal", "tests", "1.0.0", "x' + 2 x = 0"};

class Full : public Minimal {
 public:
  static const mh_component_descriptor kDescriptor;
  using Minimal::Minimal;
  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double* d_dydot) const {
    d_dy[0] = 2.0;
    d_dydot[0] = 1.0;
    return MH_OK;
  }
  mh_status energy(const mh_subsystem_eval&, double& stored, double& dissipation) const {
    stored = 3.0;
    dissipation = 4.0;
    return MH_OK;
  }
  mh_status accept(const mh_subsystem_eval&) {
    ++accepted;
    return MH_OK;
  }
  const void* extension(const char* id) const {
    return std::string(id) == "full/1" ? &kDescriptor : nullptr;
  }
  int accepted = 0;
};
const mh_component_descriptor Full::kDescriptor{
    sizeof(mh_component_descriptor), "full", "Full", "tests", "1.0.0", "every optional op"};

class Throwing {
 public:
  static const mh_component_descriptor kDescriptor;
  explicit Throwing(const mh_host*) {}
  mh_status setup() { throw std::runtime_error("the option file is on fire"); }
  mh_status evaluate(const mh_subsystem_eval&) { throw 42; }
};
const mh_component_descriptor Throwing::kDescriptor{
    sizeof(mh_component_descriptor), "throwing", "Throwing", "tests", "1.0.0", "throws"};

class ThrowingConstructor {
 public:
  static const mh_component_descriptor kDescriptor;
  explicit ThrowingConstructor(const mh_host*) { throw std::invalid_argument("no, thanks"); }
  mh_status setup() { return MH_OK; }
  mh_status evaluate(const mh_subsystem_eval&) { return MH_OK; }
};
const mh_component_descriptor ThrowingConstructor::kDescriptor{
    sizeof(mh_component_descriptor), "throwing-constructor", "", "tests", "1.0.0", ""};

const monohydra::SubsystemComponent kComponents[] = {monohydra::subsystem_component<Minimal>(),
                                                     monohydra::subsystem_component<Full>()};
constexpr monohydra::SubsystemFactory kFactory(kComponents);

// Destroys an instance at the end of a scope.
struct Destroy {
  const mh_subsystem* s;
  ~Destroy() {
    if (s != nullptr) s->destroy(s);
  }
};

// A component with point_force_jacobian (a point-less stand-in: the
// adapter only has to find it and pass the call through).
class WithPointJacobian : public Minimal {
 public:
  static const mh_component_descriptor kDescriptor;
  using Minimal::Minimal;
  mh_status point_force_jacobian(const mh_subsystem_eval&, double* dF_dp, double* dF_dv) const {
    dF_dp[0] = 5.0;
    dF_dv[0] = 6.0;
    return MH_OK;
  }
};
const mh_component_descriptor WithPointJacobian::kDescriptor{
    sizeof(mh_component_descriptor), "point-jacobian", "", "tests", "1.0.0", ""};

TEST(SdkSubsystemComponent, PointForceJacobianIsInTheTableOnlyWhenTheClassHasOne) {
  FakeNetwork net;
  FakeHost host(net);
  const mh_subsystem* with = monohydra::SubsystemAdapter<WithPointJacobian>::create(&host.table);
  const mh_subsystem* without = monohydra::SubsystemAdapter<Minimal>::create(&host.table);
  ASSERT_NE(with, nullptr);
  ASSERT_NE(without, nullptr);
  const Destroy guard_with{with}, guard_without{without};
  EXPECT_EQ(without->point_force_jacobian, nullptr);
  ASSERT_NE(with->point_force_jacobian, nullptr);
  Evaluation e(net);
  const mh_subsystem_eval rec = e.record();
  double dF_dp = 0.0, dF_dv = 0.0;
  EXPECT_EQ(with->point_force_jacobian(with, &rec, &dF_dp, &dF_dv), MH_OK);
  EXPECT_EQ(dF_dp, 5.0);
  EXPECT_EQ(dF_dv, 6.0);
}

TEST(SdkSubsystemComponent, AbsentOptionalOperationsAreNullInTheTable) {
  FakeNetwork net;
  FakeHost host(net);
  const mh_subsystem* minimal = monohydra::SubsystemAdapter<Minimal>::create(&host.table);
  ASSERT_NE(minimal, nullptr);
  const Destroy guard{minimal};
  EXPECT_EQ(minimal->struct_size, sizeof(mh_subsystem));
  EXPECT_EQ(minimal->descriptor, &Minimal::kDescriptor);
  EXPECT_EQ(minimal->jacobian, nullptr);
  EXPECT_EQ(minimal->energy, nullptr);
  EXPECT_EQ(minimal->accept, nullptr);
  ASSERT_NE(minimal->get_extension, nullptr);
  EXPECT_EQ(minimal->get_extension(minimal, "full/1"), nullptr);
  ASSERT_EQ(minimal->setup(minimal), MH_OK);
  Evaluation e(net);
  e.y[0] = 1.5;
  e.ydot[0] = 0.5;
  ASSERT_EQ(e.run(minimal), MH_OK);
  EXPECT_EQ(e.residual[0], 0.5 + 3.0);
}

TEST(SdkSubsystemComponent, PresentOptionalOperationsAreFoundAndCalled) {
  FakeNetwork net;
  FakeHost host(net);
  const mh_subsystem* full = monohydra::SubsystemAdapter<Full>::create(&host.table);
  ASSERT_NE(full, nullptr);
  const Destroy guard{full};
  ASSERT_EQ(full->setup(full), MH_OK);
  ASSERT_NE(full->jacobian, nullptr);
  ASSERT_NE(full->energy, nullptr);
  ASSERT_NE(full->accept, nullptr);
  Evaluation e(net);
  const mh_subsystem_eval rec = e.record();
  double d_dy = 0.0, d_dydot = 0.0, stored = 0.0, dissipation = 0.0;
  EXPECT_EQ(full->jacobian(full, &rec, &d_dy, &d_dydot), MH_OK);
  EXPECT_EQ(d_dy, 2.0);
  EXPECT_EQ(d_dydot, 1.0);
  EXPECT_EQ(full->energy(full, &rec, &stored, &dissipation), MH_OK);
  EXPECT_EQ(stored, 3.0);
  EXPECT_EQ(dissipation, 4.0);
  EXPECT_EQ(full->accept(full, &rec), MH_OK);
  EXPECT_EQ(full->get_extension(full, "full/1"), &Full::kDescriptor);
  EXPECT_EQ(full->get_extension(full, "other/1"), nullptr);
}

TEST(SdkSubsystemComponent, DestroyReleasesTheObject) {
  FakeNetwork net;
  FakeHost host(net);
  const int before = g_alive;
  const mh_subsystem* s = monohydra::SubsystemAdapter<Minimal>::create(&host.table);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(g_alive, before + 1);
  s->destroy(s);
  EXPECT_EQ(g_alive, before);
}

TEST(SdkSubsystemComponent, ExceptionsBecomeLoggedErrorsAtTheBoundary) {
  FakeNetwork net;
  FakeHost host(net);
  const mh_subsystem* s = monohydra::SubsystemAdapter<Throwing>::create(&host.table);
  ASSERT_NE(s, nullptr);
  const Destroy guard{s};
  EXPECT_EQ(s->setup(s), MH_ERROR);
  ASSERT_EQ(host.logs.size(), 1u);
  EXPECT_EQ(host.logs[0], "setup: the option file is on fire");
  Evaluation e(net);
  EXPECT_EQ(e.run(s), MH_ERROR);
  ASSERT_EQ(host.logs.size(), 2u);
  EXPECT_EQ(host.logs[1], "evaluate: unknown C++ exception");
}

TEST(SdkSubsystemComponent, ConstructorThatThrowsMakesCreateReturnNullAfterLogging) {
  FakeNetwork net;
  FakeHost host(net);
  EXPECT_EQ(monohydra::SubsystemAdapter<ThrowingConstructor>::create(&host.table), nullptr);
  ASSERT_EQ(host.logs.size(), 1u);
  EXPECT_EQ(host.logs[0], "creating the instance: no, thanks");
  EXPECT_EQ(monohydra::SubsystemAdapter<ThrowingConstructor>::create(nullptr), nullptr);
}

TEST(SdkSubsystemComponent, FactoryListsCreatesByIdAndAnswersOnlyItsFactoryId) {
  const mh_subsystem_factory* f = kFactory.api();
  EXPECT_EQ(f->struct_size, sizeof(mh_subsystem_factory));
  ASSERT_EQ(f->count(f), 2u);
  EXPECT_EQ(f->descriptor(f, 0), &Minimal::kDescriptor);
  EXPECT_EQ(f->descriptor(f, 1), &Full::kDescriptor);
  EXPECT_EQ(f->descriptor(f, 2), nullptr);
  FakeNetwork net;
  FakeHost host(net);
  const mh_subsystem* full = f->create(f, &host.table, "full");
  ASSERT_NE(full, nullptr);
  const Destroy guard{full};
  EXPECT_EQ(full->descriptor, &Full::kDescriptor);
  EXPECT_EQ(f->create(f, &host.table, "nothing"), nullptr);
  ASSERT_EQ(host.logs.size(), 1u);
  EXPECT_EQ(host.logs[0], "nothing: no such component in this library");
  EXPECT_EQ(f->create(f, &host.table, nullptr), nullptr);
  EXPECT_EQ(kFactory.get_factory(MH_SUBSYSTEM_FACTORY_ID), f);
  EXPECT_EQ(kFactory.get_factory(MH_FORMULATION_FACTORY_ID), nullptr);
  EXPECT_EQ(kFactory.get_factory(nullptr), nullptr);
}

TEST(SdkSubsystemComponent, HasFieldComparesTheTablesStructSize) {
  mh_mechanism_service mech{};
  mech.struct_size = sizeof(mh_mechanism_service);
  EXPECT_TRUE(MONOHYDRA_HAS_FIELD(mh_mechanism_service, &mech, mech_derivatives));
  // A table that ends before its last field (as a 3.0 table would before a
  // field a later 3.x appends).
  mech.struct_size = static_cast<uint32_t>(offsetof(mh_mechanism_service, mech_derivatives));
  EXPECT_FALSE(MONOHYDRA_HAS_FIELD(mh_mechanism_service, &mech, mech_derivatives));
  EXPECT_TRUE(MONOHYDRA_HAS_FIELD(mh_mechanism_service, &mech, evaluate_mechanics));
}

TEST(SdkSpecs, FillStructSizeAndLeaveRoleAndRangeEmpty) {
  const mh_state_spec state = monohydra::state_spec("p", "Pa", 1e5, 1e-2);
  EXPECT_EQ(state.struct_size, sizeof(mh_state_spec));
  EXPECT_STREQ(state.name, "p");
  EXPECT_STREQ(state.unit, "Pa");
  EXPECT_EQ(state.initial, 1e5);
  EXPECT_EQ(state.abs_tolerance, 1e-2);
  EXPECT_EQ(state.role, nullptr);
  EXPECT_EQ(state.range_min, 0.0);
  EXPECT_EQ(state.range_max, 0.0);
  const mh_output_spec output = monohydra::output_spec("repartitions", "", MH_OUTPUT_COUNTER);
  EXPECT_EQ(output.struct_size, sizeof(mh_output_spec));
  EXPECT_EQ(output.kind, static_cast<uint32_t>(MH_OUTPUT_COUNTER));
  EXPECT_EQ(output.role, nullptr);
  EXPECT_EQ(monohydra::output_spec("s", "m").kind, static_cast<uint32_t>(MH_OUTPUT_SIGNAL));
  const mh_unknown_spec unknown =
      monohydra::unknown_spec("z1", "rad", MH_UNKNOWN_SECOND_ORDER, 1e-7);
  EXPECT_EQ(unknown.struct_size, sizeof(mh_unknown_spec));
  EXPECT_EQ(unknown.kind, static_cast<uint32_t>(MH_UNKNOWN_SECOND_ORDER));
  EXPECT_EQ(unknown.abs_tolerance, 1e-7);
}

// The formulation helper's guard: an exception in an op is logged with the
// op's name and becomes MH_ERROR; one in the constructor makes create fail.
struct FormulationState {
  const mh_host* host = nullptr;
  int calls = 0;
};
struct ThrowingFormulationState {
  ThrowingFormulationState() { throw std::runtime_error("no memory for Eigen"); }
  const mh_host* host = nullptr;
};

TEST(SdkFormulationPlugin, GuardedOpLogsTheOpsNameAndReturnsError) {
  FakeNetwork net;
  FakeHost host(net);
  mh_formulation ops{};
  ops.struct_size = sizeof(mh_formulation);
  const mh_formulation* f = monohydra::create_formulation<FormulationState>(&host.table, ops);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(monohydra::guarded_op<FormulationState>(f, "begin_step",
                                                    [](FormulationState& s) {
                                                      ++s.calls;
                                                      return MH_OK;
                                                    }),
            MH_OK);
  EXPECT_EQ(
      monohydra::guarded_op<FormulationState>(
          f, "residual", [](FormulationState&) -> mh_status { throw std::runtime_error("boom"); }),
      MH_ERROR);
  EXPECT_EQ(monohydra::guarded_op<FormulationState>(
                f, "accept", [](FormulationState&) -> mh_status { throw 7; }),
            MH_ERROR);
  EXPECT_EQ(static_cast<const FormulationState*>(f->plugin_data)->calls, 1);
  ASSERT_EQ(host.logs.size(), 2u);
  EXPECT_EQ(host.logs[0], "residual: boom");
  EXPECT_EQ(host.logs[1], "accept: unknown C++ exception");
  monohydra::destroy_formulation<FormulationState>(f);

  EXPECT_EQ(monohydra::create_formulation<ThrowingFormulationState>(&host.table, ops), nullptr);
  ASSERT_EQ(host.logs.size(), 3u);
  EXPECT_EQ(host.logs[2], "creating the formulation: no memory for Eigen");
}

}  // namespace
}  // namespace mh::test
