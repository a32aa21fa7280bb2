// The earth-moving plugin's bucket-soil: a flat blade at constant depth and
// rake against the soil wedge's equilibrium solved here (not the plugin's N
// factors) for three soils, the blade's stop against its closed form and
// its kinetic energy against what the soil took, the edge's bearing
// resistance against Prandtl's factors, a terrain grid against the plane it
// samples, its derivatives where its switches act, and bad options refused
// at their line.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <string>

#include "hosts/cli_runner.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

struct TestSoil {
  const char* name;
  double density, phi, delta, cohesion, adhesion, surcharge;
};

// Loose sand, a soft clay, a dense gravel with a surcharge: the equation's
// four terms each carry one of them.
const TestSoil kSoils[3] = {{"sand", 1600, 30 * kDeg, 20 * kDeg, 0, 0, 0},
                            {"clay", 1900, 12 * kDeg, 8 * kDeg, 30e3, 15e3, 0},
                            {"gravel", 2000, 40 * kDeg, 25 * kDeg, 2e3, 0, 5e3}};

// A blade of width w at rake `rake` on a slide along x, its edge `depth`
// below the ground, thrown forward at v0.
std::string blade_model(const TestSoil& s, double rake, double depth, double mass, double v0,
                        double thickness, double t_end) {
  const double heel_x = -0.3 * std::cos(rake), heel_z = 0.3 * std::sin(rake);
  char text[2048];
  std::snprintf(text, sizeof(text), R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, -9.81]
bodies:
  - {name: blade, parent: ground, joint: {type: prismatic, at: [0, 0, %.17g], axis: [1, 0, 0]},
     mass: %.17g, com: [0, 0, 0], inertia: [10, 10, 10], z0: 0.0, zd0: %.17g}
subsystems:
  - name: soil
    type: bucket-soil
    width: 0.8
    density: %.17g
    friction_angle: %.17g
    interface_friction: %.17g
    cohesion: %.17g
    adhesion: %.17g
    surcharge: %.17g
    edge_thickness: %.17g
    points: {edge: {body: blade, at: [0, 0, 0]}, heel: {body: blade, at: [%.17g, 0, %.17g]},
             side: {body: blade, at: [0, -0.4, 0]}}
formulation: open-loop
solver: {dt: 0.001, t_end: %.17g}
)",
                -depth, mass, v0, s.density, s.phi, s.delta, s.cohesion, s.adhesion, s.surcharge,
                thickness, heel_x, heel_z, t_end);
  return text;
}

struct WedgeForces {
  double p = 0.0, horizontal = 0.0, vertical = 0.0;
};

// The soil wedge ahead of the blade in equilibrium (McKyes 1985, Fig. 4.4):
// its weight and surcharge, cohesion along the failure plane at beta, the
// adhesion along the blade, the blade's resultant Pn (1, tan delta) and the
// failure plane's Rn (1, tan phi) on their normals: two equations for Pn
// and Rn. P = Pn / cos(delta); H and V as the blade bears them.
WedgeForces wedge(const TestSoil& s, double rake, double depth, double width, double beta) {
  const double g = 9.81, cot_sum = 1.0 / std::tan(rake) + 1.0 / std::tan(beta);
  const double weight = 0.5 * s.density * g * width * depth * depth * cot_sum;
  const double surcharge = s.surcharge * width * depth * cot_sum;
  const double cohesion = s.cohesion * width * depth / std::sin(beta);
  const double adhesion = s.adhesion * width * depth / std::sin(rake);
  const double td = std::tan(s.delta), tp = std::tan(s.phi);
  Eigen::Matrix2d a;
  a << std::sin(rake) + td * std::cos(rake), -std::sin(beta) - tp * std::cos(beta),
      std::cos(rake) - td * std::sin(rake), std::cos(beta) - tp * std::sin(beta);
  const Eigen::Vector2d b(
      -adhesion * std::cos(rake) + cohesion * std::cos(beta),
      adhesion * std::sin(rake) + cohesion * std::sin(beta) + weight + surcharge);
  const Eigen::Vector2d pr = a.partialPivLu().solve(b);
  WedgeForces f;
  f.p = pr[0] / std::cos(s.delta);
  f.horizontal = f.p * std::sin(rake + s.delta) + adhesion * std::cos(rake);
  f.vertical = f.p * std::cos(rake + s.delta) - adhesion * std::sin(rake);
  return f;
}

// The wedge that fails first: P least over the admissible beta, by a scan of
// 20000 angles and a ternary search in the best one's neighbours.
WedgeForces failing_wedge(const TestSoil& s, double rake, double depth, double width) {
  const double top = kPi - rake - s.delta - s.phi;
  const int n = 20000;
  int best = 1;
  for (int i = 1; i < n; ++i)
    if (wedge(s, rake, depth, width, top * i / n).p <
        wedge(s, rake, depth, width, top * best / n).p)
      best = i;
  double lo = top * (best - 1) / n, hi = top * (best + 1) / n;
  for (int k = 0; k < 200; ++k) {
    const double a = lo + (hi - lo) / 3.0, b = hi - (hi - lo) / 3.0;
    (wedge(s, rake, depth, width, a).p < wedge(s, rake, depth, width, b).p ? hi : lo) =
        (wedge(s, rake, depth, width, a).p < wedge(s, rake, depth, width, b).p ? b : a);
  }
  return wedge(s, rake, depth, width, 0.5 * (lo + hi));
}

double output(const Simulation& sim, const std::string& name) {
  const int i = sim.output_index(name);
  EXPECT_GE(i, 0) << name;
  return i < 0 ? NAN : sim.outputs()[i];
}

TEST(BucketSoil, AFlatBladeAtConstantDepthAndRakeMeetsTheWedgesEquilibriumForThreeSoils) {
  const double rake = 35 * kDeg, depth = 0.15;
  for (const TestSoil& s : kSoils) {
    const WedgeForces hand = failing_wedge(s, rake, depth, 0.8);
    const ModelFile file =
        parse_model_text(blade_model(s, rake, depth, 1e4, 1.0, 0.0, 0.1), "blade.yaml");
    Simulation sim(file, test::build_plugins());
    sim.start();
    for (int i = 0; i < 100; ++i) {
      sim.step();
      EXPECT_NEAR(output(sim, "soil.Fh"), hand.horizontal, 1e-9 * hand.horizontal) << s.name;
      EXPECT_NEAR(output(sim, "soil.Fv"), hand.vertical, 1e-9 * std::abs(hand.vertical)) << s.name;
    }
    EXPECT_NEAR(output(sim, "soil.rake"), rake, 1e-12) << s.name;
    EXPECT_NEAR(output(sim, "soil.depth"), depth, 1e-12) << s.name;
    // The slide bears the vertical force; the horizontal one decelerates the
    // blade at H / m, its speed falling linearly.
    EXPECT_NEAR((1.0 - sim.zd()[0]) / 0.1 * 1e4, hand.horizontal, 1e-8 * hand.horizontal) << s.name;
  }
}

// Thrown at 1 m/s, the blade stops where the constant H has taken its
// momentum, t = m v0 / H (to within the creep at the speed scale), and the
// soil has taken its kinetic energy.
TEST(BucketSoil, AThrownBladeStopsWhenTheCuttingForceHasTakenItsMomentumAndEnergy) {
  const TestSoil& sand = kSoils[0];
  const double rake = 35 * kDeg, depth = 0.1, mass = 200.0;
  const WedgeForces hand = failing_wedge(sand, rake, depth, 0.8);
  const double t_stop = mass * 1.0 / hand.horizontal;
  const ModelFile file =
      parse_model_text(blade_model(sand, rake, depth, mass, 1.0, 0.0, t_stop + 0.3), "blade.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  double t_slow = -1.0;  // when the speed first falls below 0.05 m/s
  while (sim.time() < t_stop + 0.3 - 1e-9) {
    sim.step();
    if (t_slow < 0.0 && sim.zd()[0] < 0.05) t_slow = sim.time();
  }
  EXPECT_NEAR(t_slow, mass * 0.95 / hand.horizontal, 2e-3);
  EXPECT_LT(std::abs(sim.zd()[0]), 0.05);
  const double kinetic = 0.5 * mass * (1.0 - sim.zd()[0] * sim.zd()[0]);
  EXPECT_NEAR(sim.dissipated_energy(), kinetic, 1e-6 * kinetic);
}

// Pushed along its own blade, the edge's end bears w t (c N_c + gamma d N_q)
// with Prandtl's and Reissner's factors.
TEST(BucketSoil, TheEdgePushedAlongItsBladeBearsThePrandtlReissnerCapacity) {
  const TestSoil& clay = kSoils[1];
  const double rake = 35 * kDeg, depth = 0.15, t = 0.03;
  const ModelFile file =
      parse_model_text(blade_model(clay, rake, depth, 1e4, 1.0, t, 0.05), "blade.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  sim.step();
  const double phi = clay.phi;
  const double nq = std::exp(kPi * std::tan(phi)) * std::pow(std::tan(kPi / 4 + phi / 2), 2);
  const double nc = (nq - 1.0) / std::tan(phi);
  const double bearing = 0.8 * t * (clay.cohesion * nc + clay.density * 9.81 * depth * nq);
  EXPECT_NEAR(output(sim, "soil.Fp"), bearing, 1e-9 * bearing);
}

// A 300 kg bucket on a pivot, thrown at 3 rad/s through the air into a
// cohesive sand, where gravity keeps pushing it on until the soil holds it:
// its edge enters the ground (the depth band), its rake comes down through
// the upper limit's band (80 to 75 degrees) and it stalls (the speed scale).
constexpr const char* kSwing = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, -9.81]
bodies:
  - {name: bucket, parent: ground, joint: {type: revolute, at: [0, 0, 0.6], axis: [0, -1, 0]},
     mass: 300.0, com: [0, 0, -0.5], inertia: [20, 20, 20], z0: -1.0, zd0: 3.0}
subsystems:
  - {name: sand, type: bucket-soil, width: 1.0, density: 1700, friction_angle: 0.55,
     interface_friction: 0.35, cohesion: 5000, adhesion: 2000, edge_thickness: 0.02,
     points: {edge: {body: bucket, at: [0, 0, -0.8]}, heel: {body: bucket, at: [-0.3, 0, -0.6]},
              side: {body: bucket, at: [0, -0.5, -0.8]}}}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

TEST(BucketSoil, ASwingingBucketEntersTheGroundAndStallsInOneNewtonIterationAStep) {
  const ModelFile file = parse_model_text(kSwing, "swing.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  double z_held = 0.0, depth_max = 0.0;
  long iterations = 0, steps = 0;
  while (sim.time() < 1.0 - 1e-9) {
    sim.step();
    iterations += sim.last_step().iterations;
    ++steps;
    depth_max = std::max(depth_max, output(sim, "sand.depth"));
    if (std::abs(sim.time() - 0.3) < 1e-9) z_held = sim.z()[0];
  }
  EXPECT_GT(depth_max, 0.1);
  // Held: from 0.3 s to 1 s it creeps by less than 0.01 rad (1 cm/s at the edge at most).
  EXPECT_LT(std::abs(sim.z()[0] - z_held), 0.01);
  EXPECT_GT(output(sim, "sand.Fh"), 100.0);  // the soil holds it against gravity
  EXPECT_LT(static_cast<double>(iterations) / static_cast<double>(steps), 1.05);
}

// Its force's derivatives against differences of its own force where the
// smooth switches act (the edge at the surface at 0.08 s, the rake in its
// limit's band before it, the stall after 0.2 s).
TEST(BucketSoil, ItsDerivativesMatchDifferencesWhereItEntersTheGroundAndWhereItStalls) {
  const auto path = test::scratch_dir("bucket-soil") / "swing.yaml";
  std::ofstream(path) << kSwing;
  const test::CliResult r = test::run_cli(
      "check " + std::string(test::paths::plugin_dir) + "/monohydra-earthmoving.so " +
      path.string() + " --at 0.05,0.075,0.078,0.08,0.082,0.09,0.1,0.15,0.2,0.21,0.22,0.23,0.5");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("ok    subsystem bucket-soil: its derivative blocks against "
                          "differences of its evaluate"),
            std::string::npos)
      << r.output;
}

// The blade model on a terrain instead of the plane z = 0: `grid` holds
// the lines that replace "    edge_thickness: ...".
std::string on_terrain(const std::string& model, const std::string& grid) {
  const size_t at = model.find("    edge_thickness:");
  EXPECT_NE(at, std::string::npos);
  std::string text = model;
  if (at != std::string::npos) text.insert(at, grid);
  return text;
}

// A blade on a slide pushed into a stiff clay by a cylinder whose pump (0.1
// l/s) a relief valve limits at 10 MPa: the soil's passive force (25.7 kN)
// exceeds what the cylinder can push (19.5 kN), so it stalls. In the same Newton step
// the pump's flow splits between the relief valve and the creep the speed
// scale lets through, the cylinder's force equals the soil's mobilised
// resistance, and the pressure holds where the relief valve passes what is
// left: about one iteration a step, none failed.
TEST(BucketSoil, AStalledCylinderHoldsTheReliefPressureWhileTheSoilHoldsItsBlade) {
  const TestSoil stiff_clay{"stiff clay", 1900, 12 * kDeg, 8 * kDeg, 200e3, 50e3, 0};
  const double rake = std::atan2(0.17, 0.25), depth = 0.1, area = 0.25 * kPi * 0.05 * 0.05;
  const std::string model = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, -9.81]
bodies:
  - {name: blade, parent: ground, joint: {type: prismatic, at: [0, 0, -0.1], axis: [1, 0, 0]},
     mass: 500.0, com: [0, 0, 0], inertia: [10, 10, 10], z0: 0.0}
subsystems:
  - {name: pump, type: flow-source, ports: {p: n}, flow: 1e-4}
  - {name: line, type: volume, ports: {p: n}, volume: 1e-4, bulk_modulus: 1e9,
     fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
  - {name: relief, type: relief-valve, ports: {P: n, T: tank}, cracking_pressure: 10e6,
     override_pressure: 5e5, nominal_flow: 1e-4, outputs: {q: q_relief}}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
  - {name: cyl, type: cylinder, ports: {A: n, B: tank}, piston_diameter: 0.05,
     rod_diameter: 0.025, length: 1.5, chamber_bulk_modulus: 31500e6,
     fluid_bulk_modulus: 1500e6, efficiency: 0.95,
     points: {a: {body: ground, at: [-2, 0, -0.1]}, b: {body: blade, at: [0, 0, 0]}}}
  - {name: soil, type: bucket-soil, width: 1.0, density: 1900, friction_angle: 0.20943951023931953,
     interface_friction: 0.13962634015954636, cohesion: 200e3, adhesion: 50e3, edge_thickness: 0,
     points: {edge: {body: blade, at: [0, 0, 0]}, heel: {body: blade, at: [-0.25, 0, 0.17]},
              side: {body: blade, at: [0, -0.5, 0]}}}
nodes: {n: p, tank: null}
formulation: open-loop
solver: {dt: 0.001, t_end: 2}
)";
  const ModelFile file = parse_model_text(model, "stall.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  long iterations = 0, steps = 0;
  while (sim.time() < 2.0 - 1e-9) {
    sim.step();  // throws if a step fails: none may
    iterations += sim.last_step().iterations;
    ++steps;
  }
  EXPECT_LT(static_cast<double>(iterations) / static_cast<double>(steps), 1.1);
  const double full = failing_wedge(stiff_clay, rake, depth, 1.0).horizontal;
  const double push = output(sim, "cyl.Fs"), held = output(sim, "soil.Fh");
  EXPECT_GT(full, 1.2 * push);           // the soil could hold more than the cylinder pushes
  EXPECT_NEAR(held, push, 1e-3 * push);  // quasi-static creep: the forces balance
  // The creep: the mobilised fraction tanh(v / 0.01)^2 = H / H_full.
  const double creep = 0.01 * std::atanh(std::sqrt(held / full));
  EXPECT_NEAR(sim.zd()[0], creep, 1e-6);
  // The pump's flow: what the relief valve passes and what the creep takes.
  EXPECT_NEAR(output(sim, "q_relief") + area * sim.zd()[0], 1e-4, 1e-9);
  // The pressure where the relief valve passes that flow, between its
  // cracking and full-open pressures (10 and 10.5 MPa over the tank's 0.1).
  const double p = sim.states()[sim.state_index("p")];
  EXPECT_GT(p, 10.1e6);
  EXPECT_LT(p, 10.6e6);
}

// A 5 x 4 grid 0.5 m apart from (-1, -1) of the plane z = 0.1 - 0.05 x +
// 0.02 y: between its points and beyond its last column along the slide the
// edge's depth is the plane's, exactly (Catmull-Rom reproduces a plane; the
// border continues its slope).
TEST(BucketSoil, ATerrainGridOfAPlaneGivesThePlanesDepthBetweenItsPoints) {
  std::string rows;
  for (int j = 0; j < 4; ++j) {
    rows += j == 0 ? "    terrain_heights: [[" : ", [";
    for (int i = 0; i < 5; ++i) {
      const double x = -1.0 + 0.5 * i, y = -1.0 + 0.5 * j;
      rows += (i == 0 ? "" : ", ") + std::to_string(0.1 - 0.05 * x + 0.02 * y);
    }
    rows += "]";
  }
  rows += "]\n";
  const std::string grid =
      "    terrain_size: [5, 4]\n    terrain_spacing: 0.5\n"
      "    terrain_origin: [-1, -1]\n" +
      rows;
  const ModelFile file = parse_model_text(
      on_terrain(blade_model(kSoils[0], 35 * kDeg, 0.1, 1e4, 1.0, 0.0, 0.8), grid), "blade.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  double worst = 0.0;
  while (sim.time() < 0.8 - 1e-9) {
    sim.step();
    const double x = sim.z()[0];  // the edge's x; its y is 0, its z -0.1
    worst = std::max(worst, std::abs(output(sim, "soil.depth") - (0.1 - 0.05 * x + 0.1)));
  }
  EXPECT_GT(sim.z()[0], 0.7);  // past the grid's last column at x = 1
  EXPECT_LT(worst, 1e-12);
}

// On bumps (a 7 x 3 grid of heights up to 0.12 m apart), the swinging
// bucket's force still has the derivatives of its own values: the terrain's
// slope is in them.
TEST(BucketSoil, ItsDerivativesOnABumpyTerrainMatchDifferences) {
  std::string model = kSwing;
  const std::string grid =
      ", terrain_size: [7, 3], terrain_spacing: 0.25, terrain_origin: [-0.75, -0.25],\n"
      "     terrain_heights: [[0, 0.05, -0.04, 0.08, -0.02, 0.06, 0],\n"
      "                       [0.02, -0.03, 0.07, -0.05, 0.04, -0.01, 0.03],\n"
      "                       [0, 0.04, -0.02, 0.06, 0.01, 0.02, 0]]";
  const size_t at = model.find(", edge_thickness: 0.02");
  ASSERT_NE(at, std::string::npos);
  model.insert(at, grid);
  const auto path = test::scratch_dir("bucket-soil") / "bumps.yaml";
  std::ofstream(path) << model;
  const test::CliResult r =
      test::run_cli("check " + std::string(test::paths::plugin_dir) + "/monohydra-earthmoving.so " +
                    path.string() + " --at 0.06,0.07,0.08,0.09,0.1,0.12,0.15,0.2,0.3");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("ok    subsystem bucket-soil: its derivative blocks"), std::string::npos)
      << r.output;
}

std::string setup_error(const std::string& text) {
  try {
    const ModelFile file = parse_model_text(text, "blade.yaml");
    Simulation sim(file, test::build_plugins());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The model with option `key`'s line set to `value`.
std::string with(const std::string& model, const std::string& key, const std::string& value) {
  std::string text = model;
  const size_t at = text.find("    " + key + ": ");
  EXPECT_NE(at, std::string::npos) << key;
  if (at != std::string::npos)
    text.replace(at, text.find('\n', at) - at, "    " + key + ": " + value);
  return text;
}

TEST(BucketSoil, BadSoilOrGeometryIsRefusedAtItsLineSayingWhatWasExpected) {
  const std::string model = blade_model(kSoils[1], 35 * kDeg, 0.1, 100.0, 1.0, 0.0, 0.1);
  const struct {
    const char *key, *value, *expected;
  } cases[] = {
      {"density", "0",
       "blade.yaml:10:14: subsystem 'soil' (bucket-soil) option 'density': expected a positive "
       "soil density (kg/m^3), got '0'"},
      {"cohesion", "-1", "option 'cohesion': expected a non-negative cohesion"},
      {"friction_angle", "1.5708",
       "option 'friction_angle': expected an internal friction angle phi with 0 <= phi < pi/2"},
      {"interface_friction", "0.3",
       "option 'interface_friction': expected a soil-metal friction angle delta with 0 <= delta "
       "<= friction_angle"},
      {"width", "0", "option 'width': expected a positive cutting width (m)"},
  };
  for (const auto& c : cases) {
    const std::string err = setup_error(with(model, c.key, c.value));
    EXPECT_NE(err.find(c.expected), std::string::npos) << c.key << ": " << err;
  }
  const struct {
    const char *grid, *expected;
  } terrains[] = {
      {"    terrain_size: [1, 5]\n    terrain_spacing: 0.5\n    terrain_heights: [[0], [0], [0], "
       "[0], [0]]\n",
       "option 'terrain_size': expected [nx, ny]: whole numbers of grid points along x and y, each "
       "at least 2 (a grid of at least one cell)"},
      {"    terrain_size: [2, 3]\n    terrain_spacing: 0.5\n    terrain_heights: [[0, 0], [0, "
       "0]]\n",
       "option 'terrain_heights': expected 3 rows (terrain_size's ny) of 2 finite heights (m)"},
      {"    terrain_size: [2, 2]\n    terrain_spacing: 0\n    terrain_heights: [[0, 0], [0, "
       "0]]\n",
       "option 'terrain_spacing': expected a positive distance between the terrain's grid points"},
      {"    terrain_size: [2, 2]\n    terrain_spacing: 1\n    terrain_heights: [[0, 0], [0, "
       "0]]\n    ground_level: 0\n",
       "option 'ground_level': expected either a ground_level or a terrain (terrain_size), not "
       "both"},
  };
  for (const auto& t : terrains) {
    const std::string err = setup_error(on_terrain(model, t.grid));
    EXPECT_NE(err.find(t.expected), std::string::npos) << t.grid << ": " << err;
  }
  // A heel on the edge leaves the blade without a direction.
  const size_t heel = model.find("heel: {body: blade, at: [");
  ASSERT_NE(heel, std::string::npos);
  std::string flat = model;
  flat.replace(heel, flat.find("]}", heel) + 2 - heel, "heel: {body: blade, at: [0, 0, 0]}");
  const std::string err = setup_error(flat);
  EXPECT_NE(err.find("a heel point at least 1 mm from the edge"), std::string::npos) << err;
}

}  // namespace
}  // namespace mh
