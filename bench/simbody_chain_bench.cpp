// The peer of chains_bench.cpp's open chain: the same N beams (0.1 m, 1 kg,
// centre of mass at mid-length, m l^2 / 12 about the transverse axes), pinned
// tip to tip about z, 1 degree apart, under gravity -9.81 m/s^2 along y, in
// Simbody 3.7 with its Verlet integrator at the same fixed 1 ms (and at a
// quarter of it: a second-order method's error / 16, for a ratio at matched
// accuracy). Both run in
// mh_bench, one process, so the ratio of their CPU times per step carries from
// one machine to another where the times do not. Built only when Simbody is
// installed (Debian libsimbody-dev).
//
// Accuracy beside the cost: each benchmark reports the energy error after one
// simulated second, |E(1 s) - E(0)| in J (energy_error_1s), for Simbody here
// and for monohydra's chain in chains_bench.cpp, so that the ratio compares
// runs of comparable accuracy.
#include <Simbody.h>
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace mh::bench {
namespace {

struct SimbodyChain {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::Force::Gravity gravity{forces, matter, -SimTK::YAxis, 9.81};
  SimTK::State state;
  std::unique_ptr<SimTK::VerletIntegrator> integrator;
  double energy0 = 0.0;

  double dt;

  SimbodyChain(int n, double step) : dt(step) {
    const double m = 1.0, l = 0.1;
    const SimTK::Vec3 com(0.5 * l, 0.0, 0.0);
    // Central inertia of a slender beam along x, shifted to the body frame at its hinge.
    const SimTK::Inertia about_com(SimTK::Vec3(0.0, m * l * l / 12.0, m * l * l / 12.0));
    const SimTK::Body::Rigid body(
        SimTK::MassProperties(m, com, about_com.shiftFromMassCenter(com, m)));
    SimTK::MobilizedBody parent = matter.Ground();
    std::vector<SimTK::MobilizedBody::Pin> pins;
    for (int j = 0; j < n; ++j) {
      const SimTK::Vec3 at = j == 0 ? SimTK::Vec3(0) : SimTK::Vec3(l, 0.0, 0.0);
      pins.emplace_back(parent, SimTK::Transform(at), body, SimTK::Transform());
      parent = pins.back();
    }
    system.realizeTopology();
    state = system.getDefaultState();
    for (auto& pin : pins) pin.setAngle(state, 1.0 * SimTK::Pi / 180.0);
    system.realize(state, SimTK::Stage::Dynamics);
    energy0 = system.calcEnergy(state);
    integrator = std::make_unique<SimTK::VerletIntegrator>(system);
    integrator->setFixedStepSize(dt);
    integrator->initialize(state);
  }

  double time() const { return integrator->getTime(); }
  void step() { integrator->stepBy(dt); }
  double energy_error() {
    SimTK::State s = integrator->getState();
    system.realize(s, SimTK::Stage::Dynamics);
    return std::abs(system.calcEnergy(s) - energy0);
  }
};

void step_simbody_chain(benchmark::State& state, int n, double dt) {
  auto chain = std::make_unique<SimbodyChain>(n, dt);
  double steps = 0, energy_error = -1;
  for (auto _ : state) {
    if (chain->time() >= 1.0 - 1e-9) {  // a new run (untimed): the same motion again
      state.PauseTiming();
      energy_error = chain->energy_error();
      chain = std::make_unique<SimbodyChain>(n, dt);
      state.ResumeTiming();
    }
    chain->step();
    steps += 1;
  }
  state.counters["steps"] = steps / static_cast<double>(state.iterations());
  state.counters["us_per_step"] =
      benchmark::Counter(steps * 1e-6, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  // Negative when no simulated second was completed: the accuracy is unknown, not zero.
  state.counters["energy_error_1s"] = energy_error;
}

const int registered = [] {
  // Names: simbody/chain/N/dt in us.
  for (int dt_us : {1000, 250})
    for (int n : {4, 16, 64, 256, 1024}) {
      const std::string name = "simbody/chain/" + std::to_string(n) + "/" + std::to_string(dt_us);
      benchmark::RegisterBenchmark(name.c_str(), [n, dt_us](benchmark::State& s) {
        step_simbody_chain(s, n, 1e-6 * dt_us);
      })->Unit(benchmark::kMicrosecond);
    }
  return 0;
}();

}  // namespace
}  // namespace mh::bench
