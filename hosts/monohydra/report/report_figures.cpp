#include "report_figures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "control_intervals.hpp"
#include "mechanism_drawing.hpp"
#include "svg_bars.hpp"

namespace mh::cli {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

struct Plotter {
  const Comparison& c;
  const std::vector<PlotInterval>& control_on;
  const std::string& shade_colour;

  PlotSpec spec(const std::string& id, const std::string& title, const std::string& y_label,
                bool log_y = false) const {
    PlotSpec s;
    s.id = id;
    s.title = title;
    s.x_label = "t (s)";
    s.y_label = y_label;
    s.log_y = log_y;
    s.shaded = control_on;
    s.shade_colour = shade_colour;
    char label[64];
    std::snprintf(label, sizeof(label), "control signal on (> %g %% of its range)",
                  100.0 * kControlOnFraction);
    s.shade_label = label;
    return s;
  }

  // Runs that have rows, with their index among all runs (for the dash).
  std::vector<size_t> runs_with_rows() const {
    std::vector<size_t> out;
    for (size_t r = 0; r < c.runs.size(); ++r)
      if (c.runs[r].rows() > 0) out.push_back(r);
    return out;
  }

  // y = scale * column, from row `first` on.
  PlotSeries series(size_t r, const std::string& column, double scale, const std::string& label,
                    const std::string& colour, size_t first = 0) const {
    const RunRecord& run = c.runs[r];
    PlotSeries s;
    s.label = label;
    s.colour = colour;
    s.dash = dash_pattern(r);
    const auto& t = run.values("t");
    const auto& y = run.values(column);
    for (size_t k = first; k < run.rows(); ++k) {
      s.x.push_back(t[k]);
      s.y.push_back(scale * y[k]);
    }
    return s;
  }

  // One series per run of one column, coloured by run.
  std::vector<PlotSeries> per_run(const std::string& column, double scale, size_t first) const {
    std::vector<PlotSeries> out;
    for (size_t r : runs_with_rows())
      out.push_back(series(r, column, scale, c.runs[r].label, palette(r), first));
    return out;
  }
};

// Flow sharing (docs/hydraulics.md, ls-valve-section): the written meter-in
// flow q of every post-compensated section, their sum and each pump's
// delivered flow q, in l/min, for every run; returns the sections drawn.
size_t flow_sharing_panel(const ModelFile& file, const Comparison& c,
                          const std::vector<size_t>& runs, const Plotter& p,
                          std::vector<std::string>& svgs) {
  auto output_column = [](const SubsystemSpec& s, const std::string& local) {
    const auto it = s.output_names.find(local);
    return it == s.output_names.end() ? s.name + "." + local : it->second;  // "": hidden
  };
  std::vector<std::string> sections, pumps;
  for (const SubsystemSpec& s : file.subsystems) {
    const auto compensation = s.options.find("compensation");
    if (s.type == "ls-valve-section" && compensation != s.options.end() &&
        compensation->second.text == "post")
      sections.push_back(output_column(s, "q"));
    else if (s.type == "variable-pump")
      pumps.push_back(output_column(s, "q"));
  }
  constexpr double kToLitresPerMinute = 6e4;
  std::vector<PlotSeries> series;
  size_t drawn = 0;
  for (size_t r : runs) {
    const RunRecord& run = c.runs[r];
    PlotSeries sum;
    size_t k = 0;
    for (const std::string& col : sections) {
      if (col.empty() || run.column(col) < 0) continue;
      PlotSeries q = p.series(r, col, kToLitresPerMinute, col + " " + run.label, palette(k++));
      if (sum.x.empty()) {
        sum = q;
      } else {
        for (size_t i = 0; i < sum.y.size(); ++i) sum.y[i] += q.y[i];
      }
      series.push_back(std::move(q));
    }
    drawn = std::max(drawn, k);
    if (k < 2) continue;  // one section shares with nobody
    sum.label = "sum of the sections " + run.label;
    sum.colour = "#000000";
    series.push_back(std::move(sum));
    for (const std::string& col : pumps)
      if (!col.empty() && run.column(col) >= 0)
        series.push_back(
            p.series(r, col, kToLitresPerMinute, col + " (pump) " + run.label, "#888888"));
  }
  if (drawn < 2) return 0;
  svgs.push_back(svg_plot(
      p.spec("plot-flow-sharing", "Flow sharing: the sections' meter-in flows", "Q (l/min)"),
      series));
  return drawn;
}

}  // namespace

const std::vector<std::string>& report_figure_ids() {
  static const std::vector<std::string> ids = {
      "fig-mechanism", "fig-coordinates", "fig-pressures",   "fig-actuators",  "fig-energies",
      "fig-drift",     "fig-dissipation", "fig-constraints", "fig-iterations", "fig-step-time"};
  return ids;
}

std::vector<ReportFigure> report_figures(const ModelFile& file, const Comparison& c,
                                         const std::vector<PlotInterval>& control_on,
                                         const std::string& shade_colour) {
  const Plotter p{c, control_on, shade_colour};
  const RunRecord* ref = c.reference_run();
  const auto runs = p.runs_with_rows();
  std::vector<ReportFigure> figs;

  // Fig. 6: the mechanism.
  {
    ReportFigure f{"fig-mechanism", "Fig. 6", "The mechanism at every second", "", {}};
    if (ref != nullptr) {
      const auto frames = frames_every_second(*ref);
      f.svgs.push_back(svg_mechanism(file, frames, "drawing-mechanism",
                                     "Positions of the bodies (" + ref->label + ")"));
      f.caption = "The bodies of the " + ref->label + " run at every second, light to dark " +
                  "(a run shorter than 2 s: five instants). Bodies are drawn from their joint " +
                  "point to their other points; squares are bodies centred on their joint; " +
                  "circles on the bodies are joints, open circles cut joints, triangles ground " +
                  "points, dashed lines the ground guides of sliders, orange lines subsystems " +
                  "between two points (e.g. an actuator).";
    }
    figs.push_back(f);
  }

  // Figs. 7a-8a: relative joint coordinates, revolute in degrees and
  // prismatic in metres.
  {
    ReportFigure f{"fig-coordinates", "Figs. 7a and 8a", "Relative joint coordinates", "", {}};
    if (ref != nullptr) {
      for (const bool revolute : {true, false}) {
        std::vector<PlotSeries> series;
        for (size_t r : runs)
          for (int j = 0; j < ref->num_coordinates; ++j) {
            const size_t col = 1 + static_cast<size_t>(j);
            if ((ref->units[col] == "rad") != revolute) continue;
            series.push_back(p.series(r, ref->names[col], revolute ? kRadToDeg : 1.0,
                                      ref->names[col] + " " + c.runs[r].label,
                                      palette(static_cast<size_t>(j))));
          }
        if (series.empty()) continue;
        const std::string id =
            revolute ? "plot-coordinates-revolute" : "plot-coordinates-prismatic";
        f.svgs.push_back(svg_plot(p.spec(id, revolute ? "Revolute joints" : "Prismatic joints",
                                         revolute ? "z (deg)" : "z (m)"),
                                  series));
      }
      f.caption =
          "Colour: the coordinate; line style: the run (solid " + c.runs[runs.front()].label + ").";
    }
    figs.push_back(f);
  }

  // Figs. 7b-8b: pressures.
  {
    ReportFigure f{"fig-pressures", "Figs. 7b and 8b", "Pressures", "", {}};
    if (ref != nullptr && !c.pressures.empty()) {
      std::vector<PlotSeries> series;
      for (size_t r : runs)
        for (size_t k = 0; k < c.pressures.size(); ++k)
          if (c.runs[r].column(c.pressures[k]) >= 0)
            series.push_back(p.series(r, c.pressures[k], 1e-6,
                                      c.pressures[k] + " " + c.runs[r].label, palette(k)));
      f.svgs.push_back(svg_plot(p.spec("plot-pressures", "Pressures", "p (MPa)"), series));
      f.caption = "The states in Pa. Colour: the pressure; line style: the run.";
      // A load-sensing pump: its pressure against the highest load plus its
      // margin, which its compensator holds until the cut-off or the power
      // limit takes over (docs/hydraulics.md, variable-pump).
      for (const SubsystemSpec& s : file.subsystems) {
        const auto margin = s.options.find("margin");
        const auto port_p = s.ports.find("P");
        const auto port_ls = s.ports.find("LS");
        if (s.type != "variable-pump" || margin == s.options.end() || port_p == s.ports.end() ||
            port_ls == s.ports.end())
          continue;
        auto column_of = [&](const std::string& node) {
          const auto it = file.node_columns.find(node);
          return it == file.node_columns.end() ? node : it->second;
        };
        const std::string col_p = column_of(port_p->second.node);
        const std::string col_ls = column_of(port_ls->second.node);
        std::vector<PlotSeries> ls;
        for (size_t r : runs) {
          const RunRecord& run = c.runs[r];
          if (run.column(col_p) < 0 || run.column(col_ls) < 0) continue;
          ls.push_back(p.series(r, col_p, 1e-6, col_p + " " + run.label, palette(0)));
          PlotSeries target = p.series(r, col_ls, 1e-6, "", palette(1));
          for (double& y : target.y) y += 1e-6 * margin->second.number;
          target.label = col_ls + " + margin " + run.label;
          ls.push_back(target);
        }
        if (ls.empty()) continue;
        f.svgs.push_back(
            svg_plot(p.spec("plot-load-sensing-" + s.name,
                            "Load sensing: " + s.name + " against the highest load", "p (MPa)"),
                     ls));
        char text[200];
        std::snprintf(text, sizeof(text),
                      " The last panel: the pump %s's pressure and its LS line's plus its "
                      "%g MPa margin.",
                      s.name.c_str(), 1e-6 * margin->second.number);
        f.caption += text;
      }
    } else {
      f.caption = "This model has no pressures (no written state in Pa): the panel is left out.";
    }
    figs.push_back(f);
  }

  // The actuators: every written output in m (cylinder strokes), in N
  // (their forces) and in W (e.g. a pump's hydraulic power), one plot per unit.
  {
    ReportFigure f{"fig-actuators", "", "Actuator strokes, forces and hydraulic power", "", {}};
    if (ref != nullptr) {
      const size_t first = 1 + static_cast<size_t>(ref->num_coordinates + ref->num_states);
      const size_t last = static_cast<size_t>(std::max(ref->column("KE"), 0));
      struct Panel {
        const char* unit;
        const char* id;
        const char* title;
        const char* y_label;
        double scale;
      };
      const Panel panels[] = {
          {"m", "plot-strokes", "Actuator strokes", "s (m)", 1.0},
          {"N", "plot-forces", "Actuator forces", "F (kN)", 1e-3},
          {"W", "plot-power", "Hydraulic power", "P (kW)", 1e-3},
      };
      for (const Panel& panel : panels) {
        std::vector<PlotSeries> series;
        size_t colour = 0;
        for (size_t col = first; col < last; ++col) {
          if (ref->units[col] != panel.unit) continue;
          for (size_t r : runs)
            if (c.runs[r].column(ref->names[col]) >= 0)
              series.push_back(p.series(r, ref->names[col], panel.scale,
                                        ref->names[col] + " " + c.runs[r].label, palette(colour)));
          ++colour;
        }
        if (!series.empty())
          f.svgs.push_back(svg_plot(p.spec(panel.id, panel.title, panel.y_label), series));
      }
      f.caption = f.svgs.empty()
                      ? "This model writes no outputs in m, N or W (no actuator): the panel is "
                        "left out."
                      : "The written outputs in m, N and W: strokes and forces of the actuators "
                        "and hydraulic power. Colour: the output; line style: the run.";
      const size_t sharing = flow_sharing_panel(file, c, runs, p, f.svgs);
      if (sharing > 0)
        f.caption +=
            " The last panel: flow sharing, the meter-in flow of each of the " +
            std::to_string(sharing) +
            " post-compensated valve sections, their sum and the pump's delivery (l/min): "
            "where the levers ask for more than the pump gives, the sum meets the pump's flow "
            "and every section slows in proportion to its opening.";
    }
    figs.push_back(f);
  }

  // Figs. 9-10: energies, and their balance.
  {
    ReportFigure f{
        "fig-energies", "Figs. 9 and 10", "Kinetic, potential and actuator energy", "", {}};
    std::vector<PlotSeries> series;
    const char* names[] = {"KE", "PE", "W"};
    for (size_t r : runs)
      for (size_t k = 0; k < 3; ++k)
        series.push_back(
            p.series(r, names[k], 1.0, std::string(names[k]) + " " + c.runs[r].label, palette(k)));
    if (!series.empty())
      f.svgs.push_back(svg_plot(p.spec("plot-energies", "Energies", "E (J)"), series));
    f.caption =
        "KE and PE: kinetic and potential energy of the bodies since t = 0; W: the work "
        "done on them by subsystem forces (the actuator). Line style: the formulation.";
    figs.push_back(f);
  }
  {
    ReportFigure f{"fig-drift", "Figs. 9 and 10", "Energy drift", "", {}};
    const auto series = p.per_run("drift", 1.0, 0);
    if (!series.empty())
      f.svgs.push_back(svg_plot(p.spec("plot-drift", "Drift KE + PE - W", "drift (J)"), series));
    f.caption = "drift = KE + PE - W: zero for an exact energy balance.";
    figs.push_back(f);
  }

  // Where the energy goes: what each subsystem dissipated over the run
  // (throttling edges, compensators, reliefs, leakage, friction), beside the
  // work the subsystems did on the bodies.
  {
    ReportFigure f{"fig-dissipation", "", "Where the energy goes", "", {}};
    if (ref != nullptr) {
      std::vector<size_t> order;
      double total = 0.0;
      for (size_t i = 0; i < ref->dissipated.size(); ++i)
        if (ref->dissipated[i] > 0.0) {
          order.push_back(i);
          total += ref->dissipated[i];
        }
      std::stable_sort(order.begin(), order.end(),
                       [&](size_t a, size_t b) { return ref->dissipated[a] > ref->dissipated[b]; });
      // An instance whose component names its parts (MH_ROLE_DISSIPATION_PART:
      // a valve section's edges and compensator) is shown by them, in its colour.
      std::vector<Bar> bars;
      bars.reserve(order.size());
      for (size_t i : order) {
        const std::string prefix = ref->dissipators[i] + ".";
        bool parted = false;
        for (size_t j = 0; j < ref->dissipation_parts.size(); ++j)
          if (ref->dissipation_parts[j].rfind(prefix, 0) == 0) {
            parted = true;
            if (ref->parts_dissipated[j] > 0.0)
              bars.push_back(
                  {ref->dissipation_parts[j], 1e-3 * ref->parts_dissipated[j], palette(i)});
          }
        if (!parted) bars.push_back({ref->dissipators[i], 1e-3 * ref->dissipated[i], palette(i)});
      }
      std::stable_sort(bars.begin(), bars.end(),
                       [](const Bar& a, const Bar& b) { return a.value > b.value; });
      const auto& t = ref->values("t");
      char text[800];
      if (bars.empty()) {
        f.caption =
            "No subsystem of this model reports a dissipation (no energy op, or none "
            "dissipated): the panel is left out.";
      } else {
        f.svgs.push_back(svg_bars(
            {"plot-dissipation", "Energy dissipated by each subsystem (" + ref->label + ")", "kJ"},
            bars));
        std::snprintf(text, sizeof(text),
                      "Each subsystem's dissipated power integrated over the %s run's %g s "
                      "(trapezoidal, per step, as the energy balance integrates their sum): "
                      "%.6g kJ in all, beside W = %.6g kJ of work the subsystems did on the "
                      "bodies and %.6g kJ of kinetic and potential energy gained. Subsystems "
                      "that dissipated nothing are left out; one whose component names the "
                      "parts of its dissipation (a valve section's meter-in and meter-out "
                      "edges, its compensator, its load-sense orifices) is shown by them, "
                      "as instance.part.",
                      ref->label.c_str(), t.empty() ? 0.0 : t.back(), 1e-3 * total,
                      1e-3 * ref->values("W").back(),
                      1e-3 * (ref->values("KE").back() + ref->values("PE").back()));
        f.caption = text;
      }
    }
    figs.push_back(f);
  }

  // Figs. 11-12: constraint violation.
  {
    ReportFigure f{"fig-constraints", "Figs. 11 and 12", "Constraint violation", "", {}};
    if (file.model.cut_joints.empty()) {
      f.caption = "This model has no cut joints: no constraints to violate.";
    } else {
      const auto series = p.per_run("phi_norm", 1.0, 0);
      if (!series.empty())
        f.svgs.push_back(svg_plot(
            p.spec("plot-constraints", "Norm of the constraints", "phi_norm", true), series));
      f.caption =
          "phi_norm: the norm of every cut joint's constraints (the paper shows one "
          "joint), on a log scale; exact zeros are drawn on the bottom of the axis.";
    }
    figs.push_back(f);
  }

  // Figs. 13-14: numerical efficiency.
  {
    ReportFigure f{"fig-iterations", "Figs. 13 and 14", "Newton iterations per step", "", {}};
    const auto series = p.per_run("iters", 1.0, 1);
    if (!series.empty())
      f.svgs.push_back(
          svg_plot(p.spec("plot-iterations", "Newton iterations", "iterations"), series));
    f.caption = "Linear solves per step; each pixel column shows the range of its steps.";
    figs.push_back(f);
  }
  {
    ReportFigure f{"fig-step-time", "Figs. 13 and 14", "Wall time per step", "", {}};
    const auto series = p.per_run(kWallColumn, 1e3, 1);
    if (!series.empty())
      f.svgs.push_back(
          svg_plot(p.spec("plot-step-time", "Wall time per step", "time (ms)"), series));
    f.caption = "Wall time of each step (the wall_s column), measured on this host.";
    figs.push_back(f);
  }
  if (ref == nullptr)
    for (auto& f : figs) f.caption = "No run produced results: nothing to show.";
  return figs;
}

}  // namespace mh::cli
