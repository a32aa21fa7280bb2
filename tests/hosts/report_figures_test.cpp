// The report's figures for a hydraulic model (hosts/monohydra/report_figures.cpp),
// before the hydraulic plugins exist: the four-bar with a cylinder and a
// valve in its model file, and runs built by hand with the columns the
// hydraulic four-bar will write (p1..p3, U, s, sdot, Fs).
#include "report_figures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "comparison_table.hpp"
#include "control_intervals.hpp"
#include "mechanism_drawing.hpp"
#include "monohydra/host.h"
#include "report_html.hpp"
#include "synthetic_run.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

ModelFile hydraulic_fourbar() {
  std::ifstream in(source_path("models/fourbar-free.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml.replace(yaml.find("formulation:"), 0,
               "subsystems:\n"
               "  - name: valve\n"
               "    type: valve-4-3\n"
               "    states: {U: U}\n"
               "  - name: cylinder\n"
               "    type: cylinder\n"
               "    points: {a: {body: ground, at: [0, -2, 0]}, b: {body: body3, at: [1, 0, 0]}}\n"
               "    states: {p1: p1, p2: p2, p3: p3}\n"
               "    outputs: {s: s, sdot: sdot, Fs: Fs}\n");
  return parse_model_text(yaml, "fourbar-hydraulic.yaml");
}

// The valve's spool as the valve declares it: a control signal of +-10 V.
VariableInfo control_signal() {
  VariableInfo v;
  v.role = MH_ROLE_CONTROL_SIGNAL;
  v.range_min = -10.0;
  v.range_max = 10.0;
  return v;
}

cli::RunRecord hydraulic_run(const std::string& formulation, double wobble) {
  SyntheticRun s;
  s.formulation = formulation;
  s.rows = 1001;
  s.dt = 0.01;  // 10 s
  const double deg = 3.14159265358979323846 / 180.0;
  s.z = {[wobble, deg](size_t, double t) { return (5.0 + wobble) * std::sin(t) * deg; },
         [deg](size_t, double) { return -135.0 * deg; },
         [deg](size_t, double) { return -45.0 * deg; }};
  auto u = [](size_t k, double) {  // the four-bar's reference signal
    if (k >= 100 && k < 250) return 10.0;
    if (k >= 500 && k < 800) return -10.0;
    return 0.0;
  };
  s.states = {{"p1", "Pa", [](size_t, double t) { return 5.0e6 + 1e5 * t; }},
              {"p2", "Pa", [](size_t, double t) { return 5.0e6 + 2e5 * t; }},
              {"p3", "Pa", [wobble](size_t, double) { return 3.5e6 + wobble; }},
              {"U", "V", u, control_signal()}};
  s.outputs = {{"s", "m", [](size_t, double) { return 1.414; }},
               {"sdot", "m/s", nullptr},
               {"Fs", "N", [](size_t, double) { return 11029.38; }}};
  s.W = [](size_t, double t) { return 100.0 * t; };
  s.phi = [](size_t, double) { return 1e-15; };
  s.iters = [](size_t k, double) { return k == 0 ? 0.0 : 1.0 + static_cast<double>(k % 3 == 0); };
  s.wall = [](size_t, double) { return 2e-5; };
  cli::RunRecord rec = s.make();
  rec.dissipators = {"valve", "cylinder", "relief"};  // J over the run: the relief did nothing
  rec.dissipated = {1500.0, 3000.0 + wobble, 0.0};
  return rec;
}

class HydraulicReport : public ::testing::Test {
 protected:
  HydraulicReport()
      : file(hydraulic_fourbar()),
        c(cli::summarize("four-bar", "fourbar-hydraulic.yaml",
                         {hydraulic_run("double-step", 0.0), hydraulic_run("penalty", 1.0)})),
        open(cli::control_on_intervals(*c.reference_run(),
                                       cli::control_columns(*c.reference_run()))),
        figures(cli::report_figures(file, c, open, "#d8c8f0")) {}
  std::string svgs(const std::string& id) const {
    for (const auto& f : figures)
      if (f.id == id) {
        std::string all;
        for (const auto& s : f.svgs) all += s;
        return all;
      }
    return "";
  }
  ModelFile file;
  cli::Comparison c;
  std::vector<cli::PlotInterval> open;
  std::vector<cli::ReportFigure> figures;
};

TEST_F(HydraulicReport, EveryFigureIsThereInThePapersOrder) {
  ASSERT_EQ(figures.size(), cli::report_figure_ids().size());
  for (size_t i = 0; i < figures.size(); ++i) {
    EXPECT_EQ(figures[i].id, cli::report_figure_ids()[i]);
    EXPECT_FALSE(figures[i].svgs.empty()) << figures[i].id;
  }
}

TEST_F(HydraulicReport, DissipationBarsShowEachSubsystemThatDissipatedLargestFirstInKilojoules) {
  const std::string svg = svgs("fig-dissipation");
  EXPECT_EQ(count(svg, "<rect class=\"bar\""), 2u);  // the relief, at 0 J, is left out
  const size_t cylinder = svg.find("<title>cylinder: 3 kJ</title>");
  const size_t valve = svg.find("<title>valve: 1.5 kJ</title>");
  ASSERT_NE(cylinder, std::string::npos) << svg;
  ASSERT_NE(valve, std::string::npos);
  EXPECT_LT(cylinder, valve);
  for (const auto& f : figures)
    if (f.id == "fig-dissipation") {
      EXPECT_NE(f.caption.find("4.5 kJ in all"), std::string::npos) << f.caption;
    }
}

// A subsystem whose component names the parts of its dissipation is shown by
// them (instance.part), each ranked among the others; one without parts stays whole.
TEST_F(HydraulicReport, ASubsystemsDissipationPartsReplaceItsBar) {
  cli::RunRecord run = hydraulic_run("double-step", 0.0);
  run.dissipation_parts = {"valve.P_meter_in", "valve.P_compensator", "valve.P_load_sense"};
  run.parts_dissipated = {1000.0, 500.0, 0.0};  // the last dissipated nothing: left out
  const cli::Comparison parted = cli::summarize("four-bar", "fourbar-hydraulic.yaml", {run});
  std::string svg;
  for (const auto& f : cli::report_figures(file, parted, open, "#d8c8f0"))
    if (f.id == "fig-dissipation")
      for (const auto& s : f.svgs) svg += s;
  EXPECT_EQ(count(svg, "<rect class=\"bar\""), 3u);
  EXPECT_EQ(svg.find("<title>valve: 1.5 kJ</title>"), std::string::npos) << svg;
  const size_t cylinder = svg.find("<title>cylinder: 3 kJ</title>");
  const size_t meter_in = svg.find("<title>valve.P_meter_in: 1 kJ</title>");
  const size_t compensator = svg.find("<title>valve.P_compensator: 0.5 kJ</title>");
  ASSERT_NE(cylinder, std::string::npos) << svg;
  ASSERT_NE(meter_in, std::string::npos) << svg;
  ASSERT_NE(compensator, std::string::npos) << svg;
  EXPECT_LT(cylinder, meter_in);
  EXPECT_LT(meter_in, compensator);
}

// A load-sensing pump (ports P on p1, LS on p3) adds a panel: its pressure
// and its LS line's plus the margin, for every run.
TEST_F(HydraulicReport, ALoadSensingPumpsPressureIsDrawnAgainstItsLoadPlusItsMargin) {
  ModelFile with_pump = file;
  SubsystemSpec pump;
  pump.name = "pump";
  pump.type = "variable-pump";
  pump.options["margin"].number = 2.5e6;
  pump.ports["P"].node = "p1";
  pump.ports["LS"].node = "ls";
  with_pump.node_columns["ls"] = "p3";  // the LS node is written as p3
  with_pump.subsystems.push_back(pump);
  const auto figs = cli::report_figures(with_pump, c, open, "#d8c8f0");
  const auto f = std::find_if(figs.begin(), figs.end(),
                              [](const cli::ReportFigure& x) { return x.id == "fig-pressures"; });
  ASSERT_NE(f, figs.end());
  ASSERT_EQ(f->svgs.size(), 2u);
  const std::string& svg = f->svgs[1];
  EXPECT_NE(svg.find("id=\"plot-load-sensing-pump\""), std::string::npos);
  EXPECT_EQ(count(svg, "class=\"series\""), 4u);  // p1 and p3 + margin, two runs
  EXPECT_NE(svg.find("p3 + margin double-step"), std::string::npos);
  EXPECT_NE(f->caption.find("2.5 MPa margin"), std::string::npos) << f->caption;
  // Without the pump, the pressures' panel alone.
  EXPECT_EQ(svgs("fig-pressures").find("plot-load-sensing"), std::string::npos);
}

// Two post-compensated sections (their meter-in flows written as s and Fs)
// and a pump (q written as sdot) add the flow-sharing panel: each section,
// their sum and the pump, for every run. One section alone, or sections
// compensated upstream, share nothing: no panel.
TEST_F(HydraulicReport, PostCompensatedSectionsAddAFlowSharingPanel) {
  auto with_sections = [this](const std::vector<std::string>& compensations) {
    ModelFile m = file;
    const char* columns[] = {"s", "Fs"};
    for (size_t i = 0; i < compensations.size(); ++i) {
      SubsystemSpec v;
      v.name = "section" + std::to_string(i);
      v.type = "ls-valve-section";
      v.options["compensation"].kind = OptionValue::Kind::string;
      v.options["compensation"].text = compensations[i];
      v.output_names["q"] = columns[i];
      m.subsystems.push_back(v);
    }
    SubsystemSpec pump;
    pump.name = "pump";
    pump.type = "variable-pump";
    pump.output_names["q"] = "sdot";
    m.subsystems.push_back(pump);
    std::string all, caption;
    for (const auto& f : cli::report_figures(m, c, open, "#d8c8f0"))
      if (f.id == "fig-actuators") {
        for (const auto& svg : f.svgs)
          if (svg.find("id=\"plot-flow-sharing\"") != std::string::npos) all += svg;
        caption = f.caption;
      }
    return std::make_pair(all, caption);
  };
  const auto [svg, caption] = with_sections({"post", "post"});
  ASSERT_FALSE(svg.empty());
  EXPECT_EQ(count(svg, "class=\"series\""), 8u);  // two sections, their sum, the pump; two runs
  EXPECT_NE(svg.find("<title>sum of the sections penalty</title>"), std::string::npos) << svg;
  EXPECT_NE(svg.find("<title>sdot (pump) double-step</title>"), std::string::npos);
  EXPECT_NE(caption.find("each of the 2 post-compensated"), std::string::npos) << caption;
  EXPECT_TRUE(with_sections({"post"}).first.empty());
  EXPECT_TRUE(with_sections({"pre", "pre"}).first.empty());
}

TEST_F(HydraulicReport, PressuresAreTheStatesInPascalOfEveryRunInMegapascal) {
  const std::string svg = svgs("fig-pressures");
  EXPECT_EQ(count(svg, "class=\"series\""), 6u);  // p1..p3 for each run; not U
  EXPECT_NE(svg.find("p (MPa)"), std::string::npos);
  EXPECT_NE(svg.find("<title>p3 penalty</title>"), std::string::npos);
  EXPECT_EQ(svg.find("<title>U "), std::string::npos);
}

TEST_F(HydraulicReport, TimePlotsShadeTheTwoValveOpenings) {
  ASSERT_EQ(open.size(), 2u);
  EXPECT_NEAR(open[0].begin, 1.0, 1e-9);
  EXPECT_NEAR(open[0].end, 2.49, 1e-9);
  EXPECT_NEAR(open[1].begin, 5.0, 1e-9);
  EXPECT_NEAR(open[1].end, 7.99, 1e-9);
  for (const char* id : {"fig-coordinates", "fig-pressures", "fig-energies", "fig-drift",
                         "fig-constraints", "fig-iterations", "fig-step-time"})
    EXPECT_EQ(count(svgs(id), "<rect class=\"shade\""), 2u) << id;
  EXPECT_NE(svgs("fig-drift").find("control signal on (&gt; 1 % of its range)"), std::string::npos);
}

TEST_F(HydraulicReport, MechanismDrawsTheCylinderBetweenItsPointsAtEverySecond) {
  const std::string svg = svgs("fig-mechanism");
  EXPECT_EQ(count(svg, "<g class=\"frame\""), 11u);  // t = 0 .. 10 s
  EXPECT_EQ(count(svg, "<line class=\"element\""), 11u);
  EXPECT_EQ(count(svg, "class=\"cut-joint\""), 11u);  // E
  EXPECT_NE(svg.find(">cylinder</text>"), std::string::npos);
  // G = (0, -2) and O = (0, 0) are ground points; E = (0, -1) too.
  EXPECT_EQ(count(svg, "<polygon points="), 3u);
}

TEST_F(HydraulicReport, ActuatorsShowTheCylindersStrokeAndForceOfEveryRun) {
  const std::string svg = svgs("fig-actuators");
  EXPECT_EQ(count(svg, "<svg xmlns="), 2u);  // strokes, forces; no power (no pump output)
  EXPECT_NE(svg.find("<title>s double-step</title>"), std::string::npos);
  EXPECT_NE(svg.find("<title>Fs penalty</title>"), std::string::npos);
  EXPECT_NE(svg.find("F (kN)"), std::string::npos);
  EXPECT_EQ(svg.find("<title>sdot "), std::string::npos);  // m/s is not a stroke
}

// A 3D model is drawn in three views (side, top, isometric), each with every
// frame; a planar one in its XY plane alone.
TEST(MechanismDrawing, ThreeDimensionalModelsAreDrawnInSideTopAndIsometricViews) {
  const ModelFile excavator = load_model_file(source_path("models/excavator.yaml"));
  const ModelFile fourbar = load_model_file(source_path("models/fourbar.yaml"));
  std::vector<cli::MechanismFrame> frames(2);
  for (auto& f : frames) f.z = Eigen::VectorXd::Zero(10);
  frames[1].t = 1.0;
  const std::string svg = cli::svg_mechanism(excavator, frames, "m", "excavator");
  for (const char* view : {">side view<", ">top view<", ">isometric view<"})
    EXPECT_EQ(count(svg, view), 1u) << view;
  EXPECT_EQ(count(svg, "<g class=\"frame\""), 3u * 2u);
  EXPECT_EQ(count(svg, "<line class=\"element\""), 3u * 2u * 5u);  // five cylinders
  for (auto& f : frames) f.z = Eigen::VectorXd::Zero(3);
  const std::string planar = cli::svg_mechanism(fourbar, frames, "f", "four-bar");
  EXPECT_EQ(count(planar, "class=\"view\""), 0u);
  EXPECT_EQ(count(planar, "<g class=\"frame\""), 2u);
}

TEST_F(HydraulicReport, TheTableComparesEachPressure) {
  const cli::TextTable t = cli::comparison_table(c, nullptr);
  const std::string text = cli::render_text(t);
  for (const char* p : {"max |dp1| from double-step (Pa)", "max |dp2| from double-step (Pa)",
                        "max |dp3| from double-step (Pa)"})
    EXPECT_NE(text.find(p), std::string::npos) << p;
  // p3 of the penalty run is 1 Pa higher throughout.
  for (const auto& row : t.rows) {
    if (row[0] == "max |dp3| from double-step (Pa)") {
      EXPECT_EQ(row[2], "1.000e+00");
    }
  }
}

TEST_F(HydraulicReport, ThePageHoldsEveryFigureAndTheTable) {
  const cli::TextTable t = cli::comparison_table(c, nullptr);
  cli::ReportPage page;
  page.title = "four-bar";
  page.table = &t;
  page.figures = &figures;
  page.csv_files = {"double-step.csv", "penalty.csv"};
  const std::string html = cli::report_html(page);
  for (const auto& id : cli::report_figure_ids())
    EXPECT_NE(html.find("<figure id=\"" + id + "\">"), std::string::npos) << id;
  // One each, two for the coordinates (none prismatic) and the actuators (s, Fs).
  EXPECT_EQ(count(html, "<svg xmlns=\"http://www.w3.org/2000/svg\""), 11u);
  EXPECT_NE(html.find("<table class=\"comparison\">"), std::string::npos);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\"", 0), 0u);
}

}  // namespace
}  // namespace mh::test
