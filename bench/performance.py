#!/usr/bin/python3
"""Regenerates docs/performance.md and docs/performance-chains.svg from
measurements on this machine: one command, every number.

  bench/performance.py [--build build] [--repetitions 3] [--quick]
                       [--no-profile] [--json FILE]
  bench/performance.py --chains [--build build] [--repetitions 3] [--json FILE]

It runs build/bin/mh_bench (Google Benchmark, JSON output; medians of
--repetitions runs, CPU time), fits log-log slopes to the chain and tree
curves, draws them as SVG, profiles a case study and chains with valgrind
--tool=callgrind on build/bin/mh_profile (inclusive costs from
callgrind_annotate), and writes the page. Python 3 from Debian, no pip.
--json reuses an earlier mh_bench JSON instead of running it (each run keeps
its own as BUILD/performance.json); --quick runs one repetition and leaves
out the N = 256 chain. --chains measures only the chains and trees
(--benchmark_filter='chain|tree') and prints their table and fitted slopes
(all N, and over N >= 33 for the large end), and which Newton the default
configuration runs on each, instead of writing the page.

The default configuration is KLU and solver.newton: auto, which runs
per-step Newton (one tangent a step) on the case studies, the excavator and
the trees, and articulated Newton on long chains (mh_bench measures the
chains and trees under auto and articulated Newton too);
full Newton, the paper's method, is measured beside per-step throughout.
"""

import argparse
import datetime
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The paper's Matlab, CPU seconds for 10 s (docs/results.md, the paper's Sect. 6).
PAPER_SECONDS = {
    ("fourbar", "double-step"): 27.45,
    ("fourbar", "penalty"): 21.54,
    ("quickreturn", "double-step"): 29.03,
    ("quickreturn", "penalty"): 28.47,
}
# main at 047c70c, measured the same way before this work (medians, CPU).
BASELINE_CASES = {
    ("fourbar", "double-step"): 204.0,
    ("fourbar", "penalty"): 213.0,
    ("quickreturn", "double-step"): 369.0,
    ("quickreturn", "penalty"): 354.0,
}
BASELINE_CHAIN_US = {4: 8.2, 8: 28.0, 16: 126.0, 32: 459.0, 64: 2270.0}
TARGET_CASE_MS = 20.0
TARGET_CHAIN_US = {64: 150.0, 256: 5000.0}
SIMULATED_SECONDS = 10.0  # of each case-study run

# Profile categories: regular expressions on callgrind's function names.
# Inclusive costs, so they nest: the tangent's differences call the residual.
PROFILE_CATEGORIES = [
    ("Newton residual (r(x), every call)", [r"mh::Simulation::Engine::residual\("]),
    ("tangent assembly", [r"mh::Simulation::Engine::assemble_tangent\("]),
    ("factorization and solve", [r"mh::\w+Solver::factor\(", r"mh::\w+Solver::solve\("]),
    ("projections (penalty, Eqs. 20-21)", [r"Projector::(project_\w+|factorize)\("]),
    ("dependent coordinates (double-step)", [r"DependentCoordinates::solve\("]),
    ("output (CSV rows)", [r"mh::CsvLayout::row\(", r"write_checked\("]),
]
PROFILE_TOTAL = r"mh::run\(mh::Simulation&, std::ostream\*, mh::RunOptions const&\)"
# The Newton kinds the benchmarks measure, the default's first: solver.newton:
# auto runs per-step Newton on the case studies, the excavator and the trees
# (articulated Newton on long chains: CHAIN_NEWTONS, below); full
# Newton is the paper's method (models/paper-reference.yaml, newton: full).
NEWTON_KINDS = ("per-step", "full", "modified")
DEFAULT_NEWTON = "per-step"
# The chains and trees are measured under the default, auto (articulated
# Newton on the chains from N = 8, per-step elsewhere), and articulated
# Newton (no tangent: an O(N) solve) besides the kinds above.
CHAIN_NEWTONS = ("auto", "articulated") + NEWTON_KINDS
PROFILES = [
    # label, mh_profile arguments: per-step Newton unless the label says otherwise
    ("four-bar, double-step, 2 s, CSV every step",
     ["fourbar.yaml", "double-step", "2", "every-step", "per-step"]),
    ("four-bar, penalty, 2 s, CSV every step",
     ["fourbar.yaml", "penalty", "2", "every-step", "per-step"]),
    ("chain N = 8, 0.2 s, no CSV", ["chain:8", "open-loop", "0.2", "none", "per-step"]),
    ("chain N = 64, 0.02 s, no CSV", ["chain:64", "open-loop", "0.02", "none", "per-step"]),
    ("chain N = 256, 0.003 s, no CSV", ["chain:256", "open-loop", "0.003", "none", "per-step"]),
    ("tree N = 129, 0.01 s, no CSV", ["tree:129", "open-loop", "0.01", "none", "per-step"]),
    ("four-bar, double-step, full Newton, 2 s, CSV every step",
     ["fourbar.yaml", "double-step", "2", "every-step", "full"]),
    ("four-bar, double-step, modified Newton, 2 s, CSV every 10 ms",
     ["fourbar.yaml", "double-step", "2", "10ms", "modified"]),
    ("chain N = 64, modified Newton, 0.02 s, no CSV",
     ["chain:64", "open-loop", "0.02", "none", "modified"]),
]


def run(cmd, **kw):
    print("+ " + " ".join(cmd), file=sys.stderr)
    return subprocess.run(cmd, check=True, **kw)


def machine():
    model = "unknown CPU"
    cpus = "?"
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            key, _, value = line.partition(":")
            if key.strip() == "Model name":
                model = value.strip()
            elif key.strip() == "CPU(s)":
                cpus = value.strip()
    except (OSError, subprocess.CalledProcessError):
        pass
    return model, cpus


def git_head():
    try:
        return subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def run_bench(build, repetitions, quick, only=None):
    exe = os.path.join(build, "bin", "mh_bench")
    if not os.path.exists(exe):
        sys.exit("performance.py: %s not found: configure with -DMONOHYDRA_BENCH=ON and build" % exe)
    fd, out = tempfile.mkstemp(suffix=".json")
    os.close(fd)
    cmd = [exe, "--benchmark_out=" + out, "--benchmark_out_format=json",
           "--benchmark_format=console"]
    if repetitions > 1:
        cmd += ["--benchmark_repetitions=%d" % repetitions,
                "--benchmark_report_aggregates_only=true"]
    if quick:
        cmd += ["--benchmark_filter=-/256$"]
    elif only:
        cmd += ["--benchmark_filter=" + only]
    run(cmd, stdout=sys.stderr)
    with open(out) as f:
        data = json.load(f)
    # Kept beside the build: `--json build/performance.json` redraws the page
    # without measuring again.
    shutil.move(out, os.path.join(build, "performance.json"))
    return data


def to_us(entry, key):
    scale = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}[entry.get("time_unit", "ns")]
    return entry[key] * scale


def results(data):
    """name -> {'cpu_us': ..., counters...}: medians when repeated, else the one run."""
    out = {}
    for e in data.get("benchmarks", []):
        if e.get("run_type") == "aggregate" and e.get("aggregate_name") != "median":
            continue
        name = re.sub(r"/iterations:\d+$", "", e.get("run_name", e["name"]))
        name = re.sub(r"_median$", "", name)
        if e.get("error_occurred"):
            out[name] = {"error": e.get("error_message", "failed")}
            continue
        r = {k: v for k, v in e.items() if isinstance(v, (int, float))}
        r["cpu_us"] = to_us(e, "cpu_time")
        out[name] = r
    return out


def fmt(v, digits=3):
    if v is None:
        return "—"
    if v == 0:
        return "0"
    mag = math.floor(math.log10(abs(v)))
    decimals = max(0, digits - 1 - mag)
    return ("%." + str(decimals) + "f") % v


def fit_slope(points):
    """Least-squares slope of log(y) over log(x)."""
    pts = [(math.log(x), math.log(y)) for x, y in points if x > 0 and y > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else None


def curve(res, kind, linear, newton):
    pts = []
    for name, r in res.items():
        parts = name.split("/")
        if len(parts) == 4 and parts[:3] == [kind, linear, newton] and "cpu_us" in r:
            pts.append((int(parts[3]), r["cpu_us"], r))
    return sorted(pts)


def svg_plot(series, path):
    """Log-log plot of (N, us per step) series: [(label, colour, dash, points, slope)],
    dash an SVG stroke-dasharray ("" for a solid line)."""
    W, H, L, R, T, B = 720, 480, 70, 250, 20, 50
    xs = [p[0] for s in series for p in s[3]] or [1, 10]
    ys = [p[1] for s in series for p in s[3]] + list(TARGET_CHAIN_US.values())
    x0, x1 = math.log10(min(xs)), math.log10(max(xs))
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    if x1 <= x0:
        x1 = x0 + 1

    def px(x):
        return L + (math.log10(x) - x0) / (x1 - x0) * (W - L - R)

    def py(y):
        return H - B - (math.log10(y) - y0) / (y1 - y0) * (H - T - B)

    o = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" '
         'font-family="sans-serif" font-size="12">' % (W, H),
         '<rect width="100%" height="100%" fill="white"/>']
    for e in range(int(y0), int(y1) + 1):
        y = py(10 ** e)
        o.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (L, y, W - R, y))
        label = ["1 us", "10 us", "100 us", "1 ms", "10 ms", "100 ms", "1 s", "10 s"][e] \
            if 0 <= e <= 7 else "1e%d us" % e
        o.append('<text x="%d" y="%.1f" text-anchor="end">%s</text>' % (L - 6, y + 4, label))
    n = 1
    while n <= max(xs):
        if n >= min(xs):
            x = px(n)
            o.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#eee"/>' % (x, T, x, H - B))
            o.append('<text x="%.1f" y="%d" text-anchor="middle">%d</text>' % (x, H - B + 16, n))
        n *= 2
    o.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="black"/>'
             % (L, T, W - L - R, H - T - B))
    o.append('<text x="%d" y="%d" text-anchor="middle">bodies N</text>' % ((L + W - R) / 2, H - 12))
    o.append('<text x="16" y="%d" transform="rotate(-90 16 %d)" text-anchor="middle">'
             'CPU time per step (dt = 1 ms)</text>' % ((T + H - B) / 2, (T + H - B) / 2))
    for n, us in TARGET_CHAIN_US.items():
        if min(xs) <= n <= max(xs):
            o.append('<path d="M%.1f %.1f l-6 -6 l12 0 z" fill="red"/>' % (px(n), py(us)))
    ly = T + 10
    for label, colour, dash, pts, slope in series:
        if not pts:
            continue
        d = " ".join("%s%.1f %.1f" % ("M" if i == 0 else "L", px(x), py(y))
                     for i, (x, y) in enumerate((p[0], p[1]) for p in pts))
        o.append('<path d="%s" fill="none" stroke="%s" stroke-width="2"%s/>'
                 % (d, colour, ' stroke-dasharray="%s"' % dash if dash else ""))
        for p in pts:
            o.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"/>' % (px(p[0]), py(p[1]), colour))
        o.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2"%s/>'
                 % (W - R + 10, ly, W - R + 34, ly, colour,
                    ' stroke-dasharray="%s"' % dash if dash else ""))
        o.append('<text x="%d" y="%d">%s, slope %s</text>' % (W - R + 40, ly + 4, label, fmt(slope, 2)))
        ly += 20
    o.append('<path d="M%d %d l-6 -6 l12 0 z" fill="red"/>' % (W - R + 22, ly + 4))
    o.append('<text x="%d" y="%d">targets (chain)</text>' % (W - R + 40, ly + 4))
    o.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(o) + "\n")


# Exclusive instruction counts per time step of the case studies (modified
# Newton, no output), grouped by kernel: the budget that 20 ms per 10 s has to
# fit. Differences of two runs (1 s and 3 s) over the 2000 steps between them,
# so loading and start-up cancel (bench/instructions_per_step.sh does the same
# for the total).
BUDGET_CASES = [("fourbar", "double-step"), ("fourbar", "penalty"),
                ("quickreturn", "double-step"), ("quickreturn", "penalty")]
BUDGET_GROUPS = [
    ("kinematics (positions, velocities)", [r"mh::forward_kinematics\(", r"mh::forward_velocities\(",
                                            r"AngleAxis", r"sincos", r"mh::kinematics_at|Engine::kinematics_at\("]),
    ("M' and Q' (Eq. 12)", [r"mh::mass_matrix_and_forces\(", r"mh::reset_applied_forces\(",
                           r"mh::apply_point_force\("]),
    ("constraints (Phi, Phi_z, velocity term)", [r"evaluate_constraint", r"mh::point_\w+\(",
                                                 r"mh::angular_jacobian\(", r"mh::body_\w+\(",
                                                 r"constraints_at_kinematics"]),
    ("K and C (penalty's projections, tangents)", [r"dynamics_derivatives", r"mechanics_derivatives", r"fill_columns",
                                                   r"vary_body_residual", r"variation_z",
                                                   r"variation_zd", r"body_state", r"point_force",
                                                   r"motion_cross", r"is_ancestor"]),
    ("subsystems (hydraulics)", [r"evaluate_subsystems", r"hyd::", r"SubsystemAdapter"]),
    ("formulation's own algebra (LU of Phi_z^d, R_z, projections)",
     [r"double_step::", r"mh_penalty::", r"Projector", r"PartialPivLU", r"partial_lu", r"FullPivLU",
      r"general_matrix_vector", r"general_matrix_matrix", r"triangular_solve"]),
    ("Newton, KLU, integrator map", [r"klu_", r"KluSolver", r"newton_solve", r"rates_of",
                                    r"Engine::residual\(", r"integ::"]),
]


def step_budget(build):
    """Instructions per step by kernel group, for the four case studies (modified Newton)."""
    if shutil.which("valgrind") is None or shutil.which("callgrind_annotate") is None:
        return None
    exe = os.path.join(build, "bin", "mh_profile")
    out_rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for model, form in BUDGET_CASES:
            per = []
            for t in ("1", "3"):
                out = os.path.join(tmp, "cg." + t)
                run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out, exe,
                     model + ".yaml", form, t, "none", "modified"],
                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=tmp)
                text = subprocess.run(["callgrind_annotate", "--inclusive=no", "--threshold=100",
                                       "--auto=no", out], capture_output=True, text=True,
                                      check=True).stdout
                costs = {}
                for line in text.splitlines():
                    m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)$", line)
                    if m:
                        costs[m.group(2)] = int(m.group(1).replace(",", ""))
                per.append(costs)
            steps = 2000.0
            diff = {f: (per[1].get(f, 0) - per[0].get(f, 0)) / steps for f in per[1]}
            total = next((v for f, v in diff.items() if f.startswith("PROGRAM TOTALS")), None)
            groups = [0.0] * len(BUDGET_GROUPS)
            for f, v in diff.items():
                if f.startswith("PROGRAM TOTALS"):
                    continue
                for i, (_, pats) in enumerate(BUDGET_GROUPS):
                    if any(re.search(p, f) for p in pats):
                        groups[i] += v
                        break
            out_rows.append((model, form, total, groups))
        # The instruction rate: one whole 10 s run's instructions over the
        # bench's CPU time for it (four-bar, double-step, modified Newton).
        out = os.path.join(tmp, "cg.10")
        run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out, exe,
             "fourbar.yaml", "double-step", "10", "none", "modified"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=tmp)
        text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100",
                               "--auto=no", out], capture_output=True, text=True, check=True).stdout
        whole = next((int(m.group(1).replace(",", "")) for line in text.splitlines()
                      for m in [re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)$", line)]
                      if m and re.search(PROFILE_TOTAL, m.group(2))), None)
    return out_rows, whole


def budget_section(budget, res, why="valgrind missing"):
    if not budget:
        return "Not measured (%s)." % why
    rows, whole = budget
    head = ("| case (modified Newton) | instructions per step | residuals per step | "
            + " | ".join(g[0] for g in BUDGET_GROUPS) + " | other |")
    lines = [head, "|---" * (len(BUDGET_GROUPS) + 4) + "|"]
    for model, form, total, groups in rows:
        r = res.get("case/%s/%s/trapezoidal/klu/modified" % (model, form), {})
        other = total - sum(groups) if total else None
        cells = ["%.1fk (%.0f %%)" % (g / 1e3, 100.0 * g / total) for g in groups] if total else []
        lines.append("| %s, %s | %s | %s | %s | %s |" % (
            model, form, "{:,.0f}".format(total) if total else "—",
            fmt(r.get("residuals_per_step")), " | ".join(cells),
            "%.1fk (%.0f %%)" % (other / 1e3, 100.0 * other / total) if total else "—"))
    cpu = res.get("case/fourbar/double-step/trapezoidal/klu/modified", {}).get("cpu_us")
    if whole and cpu:
        rate = whole / (cpu * 1e3)  # per ns
        lines += ["", "Instruction rate: a whole 10 s run of the four-bar, double-step, modified "
                  "Newton, is %s instructions (`mh::run`) in the bench's %s ms of CPU: %.1f "
                  "instructions per ns, so 2 us per step is about %.0fk instructions per step." % (
                      "{:,}".format(whole), fmt(cpu / 1e3), rate, 2.0 * rate)]
    return "\n".join(lines)


def profile(build):
    if shutil.which("valgrind") is None or shutil.which("callgrind_annotate") is None:
        return None, "valgrind is not installed (apt-get install valgrind)"
    exe = os.path.join(build, "bin", "mh_profile")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, args in PROFILES:
            out = os.path.join(tmp, "callgrind.out")
            try:
                run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out, exe] + args,
                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=tmp)
            except subprocess.CalledProcessError as err:  # the run failed: said, not fatal
                rows.append(("%s (failed: exit %d)" % (label, err.returncode), None,
                             [None] * len(PROFILE_CATEGORIES)))
                continue
            text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100",
                                   "--auto=no", out], capture_output=True, text=True,
                                  check=True).stdout
            costs = []
            for line in text.splitlines():
                m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)$", line)
                if m:
                    costs.append((int(m.group(1).replace(",", "")), m.group(2)))
            total = next((c for c, f in costs if re.search(PROFILE_TOTAL, f)), None)
            shares = []
            for name, patterns in PROFILE_CATEGORIES:
                found = [c for c, f in costs if any(re.search(p, f) for p in patterns)]
                shares.append(100.0 * sum(found) / total if found and total else None)
            rows.append((label, total, shares))
    return rows, None


def case_table(res):
    lines = ["| model | formulation | integrator | ms per 10 s | us per step | Newton its/step "
             "| tangents/step | kinematics passes/step | real-time factor | x the paper's Matlab "
             "| full Newton: ms per 10 s (its/step, tangents/step) | full Newton's time over "
             "per-step's |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, r in sorted(res.items()):
        p = name.split("/")
        if len(p) != 6 or p[0] != "case" or p[4:] != ["klu", DEFAULT_NEWTON]:
            continue
        lines.append(case_row(p, r, res.get("/".join(p[:5] + ["full"]), {})))
    return "\n".join(lines)


def kin(r):
    for k, v in r.items():
        if "kin" in k.lower():
            return v
    return None


def case_row(p, r, full):
    """One per-step run, with its full-Newton twin (where measured) beside it."""
    beside = "— | —"
    if "cpu_us" in full:
        beside = "%s (%s, %s) | %s" % (
            fmt(full["cpu_us"] / 1e3), fmt(full.get("its_per_step")),
            fmt(full.get("tangents_per_step")),
            "%.2f" % (full["cpu_us"] / r["cpu_us"]) if "cpu_us" in r else "—")
    elif "error" in full:
        beside = "failed: %s | —" % full["error"]
    if "error" in r:
        return "| %s | %s | %s | failed: %s | | | | | | | %s |" % (
            p[1], p[2], p[3], r["error"], beside)
    ms = r["cpu_us"] / 1e3
    paper = PAPER_SECONDS.get((p[1], p[2]))
    return "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
        p[1], p[2], p[3], fmt(ms), fmt(r.get("us_per_step")), fmt(r.get("its_per_step")),
        fmt(r.get("tangents_per_step")), fmt(kin(r)), fmt(SIMULATED_SECONDS / (ms / 1e3)),
        fmt(paper / (ms / 1e3)) if paper else "—", beside)


def solver_table(res):
    combos = [(l, n) for n in NEWTON_KINDS for l in ("klu", "umfpack", "dense")]
    head = "| case (trapezoidal) | " + " | ".join(
        "%s, %s%s" % (l, n, " (default)" if (l, n) == ("klu", DEFAULT_NEWTON) else "")
        for l, n in combos) + " |"
    lines = [head, "|---" * (len(combos) + 1) + "|"]
    for model, form in sorted(PAPER_SECONDS):
        cells = []
        for l, n in combos:
            r = res.get("case/%s/%s/trapezoidal/%s/%s" % (model, form, l, n), {})
            cells.append("%s ms (%s its, %s tangents)" % (
                fmt(r["cpu_us"] / 1e3), fmt(r.get("its_per_step")), fmt(r.get("tangents_per_step")))
                         if "cpu_us" in r else "—")
        lines.append("| %s, %s | %s |" % (model, form, " | ".join(cells)))
    for kind in ("chain", "tree"):
        ns = sorted({p[0] for l, n in combos for p in curve(res, kind, l, n)})
        for N in ns:
            cells = []
            for l, n in combos:
                r = res.get("%s/%s/%s/%d" % (kind, l, n, N), {})
                cells.append("%s us" % fmt(r["cpu_us"]) if "cpu_us" in r else "—")
            lines.append("| %s N = %d (per step) | %s |" % (kind, N, " | ".join(cells)))
    return "\n".join(lines)


def best_choice(res):
    """The linear solvers and Newton kinds on the case studies, fastest first
    (sum of the four runs, ms)."""
    totals = {}
    for l in ("klu", "umfpack", "dense"):
        for n in NEWTON_KINDS:
            vals = [res.get("case/%s/%s/trapezoidal/%s/%s" % (m, f, l, n), {}).get("cpu_us")
                    for m, f in PAPER_SECONDS]
            if all(v is not None for v in vals):
                totals[(l, n)] = sum(vals) / 1e3
    return sorted(totals.items(), key=lambda kv: kv[1])


def output_table(res):
    lines = ["| case | no CSV | CSV every step | CSV every 10 ms | cost, every step | cost, 10 ms |",
             "|---|---|---|---|---|---|"]
    for model, form in sorted(PAPER_SECONDS):
        base = "output/%s/%s/" % (model, form)
        none, every, ten = (res.get(base + k, {}).get("cpu_us") for k in ("none", "every-step", "10ms"))
        if none is None:
            continue

        def pct(v):
            return "%+.1f %%" % (100.0 * (v - none) / none) if v is not None else "—"
        lines.append("| %s, %s | %s ms | %s ms | %s ms | %s | %s |" % (
            model, form, fmt(none / 1e3), fmt(every / 1e3 if every else None),
            fmt(ten / 1e3 if ten else None), pct(every), pct(ten)))
    return "\n".join(lines)


def chain_table(res):
    series = [(kind, "klu", n) for kind in ("chain", "tree") for n in CHAIN_NEWTONS]
    lines = ["| mechanism | Newton | N | us per step | its/step | tangents/step |",
             "|---|---|---|---|---|---|"]
    for kind, l, n in series:
        for N, us, r in curve(res, kind, l, n):
            lines.append("| %s | %s | %d | %s | %s | %s |" % (
                kind, n, N, fmt(us), fmt(r.get("its_per_step")), fmt(r.get("tangents_per_step"))))
    return "\n".join(lines)


def targets(res):
    out = []
    for (model, form), paper in sorted(PAPER_SECONDS.items()):
        t = {n: res.get("case/%s/%s/trapezoidal/klu/%s" % (model, form, n), {}).get("cpu_us")
             for n in NEWTON_KINDS}
        measured = [v for v in t.values() if v is not None]
        if not measured:
            continue
        best = min(measured) / 1e3
        verdict = "met" if best <= TARGET_CASE_MS else "missed by %.1fx" % (best / TARGET_CASE_MS)
        out.append("- %s, %s: %s ms per 10 s at best (%s; baseline %s ms): target %g ms %s." % (
            model, form, fmt(best),
            ", ".join("%s %s" % (n, fmt(t[n] / 1e3 if t[n] else None)) for n in NEWTON_KINDS),
            fmt(BASELINE_CASES[(model, form)]), TARGET_CASE_MS, verdict))
    for N, goal in sorted(TARGET_CHAIN_US.items()):
        vals = [r["cpu_us"] for n in CHAIN_NEWTONS
                for r in [res.get("chain/klu/%s/%d" % (n, N), {})] if "cpu_us" in r]
        if not vals:
            out.append("- chain N = %d: not measured (run without --quick)." % N)
            continue
        best = min(vals)
        verdict = "met" if best <= goal else "missed by %.1fx" % (best / goal)
        out.append("- chain N = %d: %s us per step at best: target %s us %s." % (
            N, fmt(best), fmt(goal), verdict))
    best64 = {}
    for n in CHAIN_NEWTONS:
        vals = [res.get("chain/%s/%s/64" % (l, n), {}).get("cpu_us") for l in ("klu", "auto")]
        vals = [v for v in vals if v is not None]
        if vals:
            best64[n] = min(vals)
    holds = [n for n in CHAIN_NEWTONS if n in best64 and best64[n] <= TARGET_CHAIN_US[64]]
    for n, what in (("auto", "the default: articulated Newton on this chain"),
                    ("per-step", "one tangent a step"),
                    ("full", "a fresh tangent every iteration")):
        if n in best64:
            out.append("- chain N = 64 with %s Newton (%s): %s us per step at best (KLU or auto): "
                       "%s." % (n, what, fmt(best64[n]),
                                "met" if best64[n] <= TARGET_CHAIN_US[64] else
                                "missed by %.1fx" % (best64[n] / TARGET_CHAIN_US[64])))
    if best64:
        out.append("- chain N = 64: the target holds with %s." % (
            " and ".join("%s Newton" % k for k in holds) if holds
            else "none of the Newton kinds measured"))
    for (model, form) in sorted(PAPER_SECONDS):
        for n in NEWTON_KINDS:
            r = res.get("case/%s/%s/trapezoidal/klu/%s" % (model, form, n), {})
            k = kin(r)
            if k is not None:
                out.append("- kinematics passes per step, %s, %s, %s Newton: %s (target at most 6) "
                           "%s." % (model, form, n, fmt(k), "met" if k <= 6.0 else "missed"))
    tree = curve(res, "tree", "klu", DEFAULT_NEWTON)
    slope = fit_slope([(p[0], p[1]) for p in tree])
    if slope is not None:
        out.append("- tree of bounded depth, %s Newton: cost grows as N^%s (target: linear, N^1) "
                   "%s." % (DEFAULT_NEWTON, fmt(slope, 2), "met" if slope <= 1.15 else "missed"))
    return "\n".join(out)


def profile_section(rows, why):
    if rows is None:
        return "Not measured: %s." % why
    head = "| run | instructions (run()) | " + " | ".join(c[0] for c in PROFILE_CATEGORIES) + " |"
    lines = [head, "|---" * (len(PROFILE_CATEGORIES) + 2) + "|"]
    for label, total, shares in rows:
        cells = ["%.1f %%" % s if s is not None else "—" for s in shares]
        lines.append("| %s | %s | %s |" % (label, "{:,}".format(total) if total else "—",
                                          " | ".join(cells)))
    return "\n".join(lines)


def largest_shares(rows):
    if not rows:
        return "not profiled"
    out = []
    for label, _, shares in rows:
        named = sorted(((v, PROFILE_CATEGORIES[i][0]) for i, v in enumerate(shares)
                        if v is not None), reverse=True)[:2]
        if named:
            out.append("%s: %s" % (label, ", ".join("%s %.0f %%" % (n, v) for v, n in named)))
    return "; ".join(out) or "no category found"


def chains_report(res, defaults=None):
    """Every chain and tree series measured: us per step by N, and log-log
    slopes; the Newton kinds in CHAIN_NEWTONS's order (the default's first)
    and, with `defaults` ({(kind, N): Newton kind}, default_newtons()), the
    kind the default configuration runs on each."""
    linears = ("klu", "auto", "umfpack", "dense")

    def order(key):
        kind, l, n = key
        return (kind, CHAIN_NEWTONS.index(n) if n in CHAIN_NEWTONS else len(CHAIN_NEWTONS), n,
                linears.index(l) if l in linears else len(linears), l)
    series = sorted({tuple(name.split("/")[:3]) for name in res
                     if name.split("/")[0] in ("chain", "tree") and len(name.split("/")) == 4},
                    key=order)
    lines = ["| series | N: us per step (its/step, tangents/step) | slope, all N | slope, N >= 33 |",
             "|---|---|---|---|"]
    for kind, l, n in series:
        pts = curve(res, kind, l, n)
        cells = ", ".join("%d: %s (%s, %s)" % (N, fmt(us), fmt(r.get("its_per_step")),
                                                fmt(r.get("tangents_per_step")))
                          for N, us, r in pts)
        large = fit_slope([(p[0], p[1]) for p in pts if p[0] >= 33])
        lines.append("| %s/%s/%s | %s | %s | %s |" % (
            kind, l, n, cells, fmt(fit_slope([(p[0], p[1]) for p in pts]), 2), fmt(large, 2)))
    failed = ["%s: %s" % (name, r["error"]) for name, r in sorted(res.items()) if "error" in r]
    if defaults:
        lines += ["", "The default configuration (solver.newton: auto, as each run on each "
                  "mechanism reported its choice) runs, " + default_kinds_text(defaults) + "."]
    return "\n".join(lines + (["", "failed: " + "; ".join(failed)] if failed else []))


def default_kinds_text(defaults):
    """'on the chains, per-step Newton at N = 2, 4 and articulated Newton at
    N = 8, ...; on the trees, per-step Newton at N = ...'."""
    out = []
    for kind in ("chain", "tree"):
        by_kind = {}
        for (k, n), newton in sorted(defaults.items()):
            if k == kind:
                by_kind.setdefault(newton or "unknown (the run failed)", []).append(n)
        if by_kind:
            out.append("on the %ss, %s" % (kind, " and ".join(
                "%s Newton at N = %s" % (newton, ", ".join(str(n) for n in ns))
                for newton, ns in sorted(by_kind.items(), key=lambda kv: kv[1][0]))))
    return "; ".join(out) or "not determined"


# The speed issue's measurements (docs/performance.md "## Targets"): every
# count is callgrind's, so it carries from one machine to another; the times
# beside them are this machine's.
RUN_CASES = [  # model, formulation, from, to (s), target instructions per step
    ("fourbar", "double-step", 1.0, 2.0, 20e3),
    ("fourbar", "penalty", 1.0, 2.0, 20e3),
    ("quickreturn", "double-step", 1.0, 2.0, 25e3),
    ("quickreturn", "penalty", 1.0, 2.0, 25e3),
    ("excavator", "double-step", 2.0, 3.0, 60e3),
    ("excavator", "penalty", 2.0, 3.0, 60e3),
]
CYCLE_SECONDS = 22.0  # models/excavator.yaml's digging cycle
BIG_CHAIN = 2000
BIG_CHAIN_TARGET = 0.5e9  # instructions per step
BIG_CHAIN_STEPS = 3
# The big chain under callgrind: articulated Newton (what the default, auto,
# runs on it), per-step Newton with KLU (the default linear solver) and
# modified Newton with auto (dense LU), the fastest tangent-based kind.
BIG_CHAIN_RUNS = (("articulated", "klu"), ("per-step", "klu"), ("modified", "auto"))
TREE_SLOPE_TARGET = 1.05
SIMBODY_N = [4, 16, 64, 256, 1024]
# The parts of a step (inclusive costs, step_split): the tangent's assembly,
# the linear solver's factorization, the residual calls (the tangent's forward
# differences call it too) and the subsystems' evaluations in them.
SPLIT_TANGENT = r"mh::Simulation::Engine::assemble_tangent\("
SPLIT_FACTOR = r"mh::\w+Solver::factor\("
SPLIT_RESIDUAL = r"mh::Simulation::Engine::residual\("
SPLIT_SUBSYSTEMS = r"mh::Simulation::Engine::evaluate_subsystems\("
# The formulation's own work after each iterate and each step (e.g. penalty's
# projections, Eqs. 20-21): its iteration_done and accept.
SPLIT_FORMULATION = r"::(iteration_done|accept)\(mh_formulation const\*"
ANNOTATE_LINE = re.compile(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+([<>*])\s+(.*)$")


def callgrind_summaries(cmd, directory, extra=()):
    """Runs cmd under callgrind, one output file per process (and per dump)
    in directory; returns stdout and {file name: (trigger, instructions)}."""
    os.makedirs(directory, exist_ok=True)
    out = subprocess.run(["valgrind", "--tool=callgrind", "--trace-children=yes",
                          "--callgrind-out-file=" + os.path.join(directory, "cg.%p")]
                         + list(extra) + cmd, capture_output=True, text=True, check=True,
                         cwd=directory).stdout
    files = {}
    for name in os.listdir(directory):
        if not name.startswith("cg."):
            continue
        trigger, total = "", None
        with open(os.path.join(directory, name), errors="replace") as f:
            for line in f:
                if line.startswith("desc: Trigger:"):
                    trigger = line.split(":", 2)[2].strip()
                elif line.startswith("summary:"):
                    total = int(line.split()[1])
        if total is not None:
            files[name] = (trigger, total)
    return out, files


def annotate_tree(path):
    """callgrind_annotate --inclusive=yes --tree=both of one output file:
    {function: {"cost": inclusive, "calls": calls from every caller,
    "callees": {callee: (inclusive cost of those calls, calls)}}}."""
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--tree=both",
                           "--threshold=100", "--auto=no", path], capture_output=True, text=True,
                          check=True).stdout
    funcs = {}
    block = []

    def flush():
        star = next((b for b in block if b[1] == "*"), None)
        if star is not None:
            f = funcs.setdefault(star[2], {"cost": 0, "calls": 0, "callees": {}})
            f["cost"] = star[0]
            for cost, kind, name, calls in block:
                if kind == "<":
                    f["calls"] += calls
                elif kind == ">":
                    c, n = f["callees"].get(name, (0, 0))
                    f["callees"][name] = (c + cost, n + calls)
        del block[:]

    for line in text.splitlines():
        m = ANNOTATE_LINE.match(line)
        if m:
            name = m.group(3)
            count = re.search(r" \(([\d,]+)x\)", name)
            calls = int(count.group(1).replace(",", "")) if count else 0
            name = re.sub(r" \([\d,]+x\)", "", name).strip()
            block.append((int(m.group(1).replace(",", "")), m.group(2), name, calls))
        elif not line.strip():
            flush()
    flush()
    return funcs


def inclusive(funcs, pattern):
    """Inclusive cost and calls of the functions matching pattern (not of the
    lambdas defined in them, whose names contain theirs: nested costs)."""
    found = [f for name, f in funcs.items() if re.search(pattern, name) and "{lambda" not in name]
    return sum(f["cost"] for f in found), sum(f["calls"] for f in found)


def called_within(funcs, caller, callee):
    """Cost and calls of callee's calls made directly by caller."""
    cost = calls = 0
    for name, f in funcs.items():
        if re.search(caller, name):
            for other, (c, n) in f["callees"].items():
                if re.search(callee, other):
                    cost += c
                    calls += n
    return cost, calls


def short_name(name):
    """callgrind's 'file:function(args) [object]' as 'Class::function'."""
    name = re.sub(r" \[[^\]]*\]$", "", name)
    m = re.match(r"^(.*?[^:]):([^:].*)$", name)
    name = m.group(2) if m else name
    name = name.replace("(anonymous namespace)::", "").split("(")[0]
    return "::".join(name.split("::")[-2:])


def largest_exclusive(path):
    """The function with the most exclusive instructions in one output file."""
    text = subprocess.run(["callgrind_annotate", "--inclusive=no", "--threshold=100", "--auto=no",
                           path], capture_output=True, text=True, check=True).stdout
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)$", line)
        if m and "PROGRAM TOTALS" not in m.group(2):
            return short_name(m.group(2)), int(m.group(1).replace(",", ""))
    return None, 0


def newton_of(summary):
    """The Newton kind `monohydra run`'s summary names ('solver: klu, per-step
    Newton, ...' or 'solver: articulated Newton, ...')."""
    m = re.search(r"^solver:\s+(?:[\w-]+, )?([\w-]+) Newton", summary, re.M)
    return m.group(1) if m else None


def run_instructions(build, tmp, model, form, t1, t2):
    """`monohydra run`'s instructions per step between t1 and t2: two runs,
    every forked process counted, so start-up cancels. No solver option is
    given: the default configuration, whose Newton kind the summary names."""
    exe = os.path.join(build, "bin", "monohydra")
    counts, kinds = [], set()
    for t in (t1, t2):
        d = tempfile.mkdtemp(dir=tmp)
        out, files = callgrind_summaries(
            [exe, "run", os.path.join(ROOT, "models", model + ".yaml"), "--formulation", form,
             "--t-end", "%g" % t, "--output-interval", "0.01", "--out", os.path.join(d, "r.csv")],
            d)
        steps = int(re.search(r"^steps:\s+(\d+)", out, re.M).group(1))
        counts.append((sum(v for _, v in files.values()), steps))
        kinds.add(newton_of(out) or "?")
    return {"instructions": (counts[1][0] - counts[0][0]) / float(counts[1][1] - counts[0][1]),
            "newton": "/".join(sorted(kinds))}


def run_ips(v):
    """run_instructions' count (a bare number in targets JSON of before per-step)."""
    return v["instructions"] if isinstance(v, dict) else v


def step_costs(build, tmp, what, form, t1, t2, newton=DEFAULT_NEWTON, linear="klu", every=1,
               count=True, annotate=False):
    """mh_step_costs: this machine's mean and largest step time (native), and
    under callgrind each step's (or each `every` steps') instructions alone;
    with annotate, the share of the last dump's instructions in the linear
    solver's factorization."""
    exe = os.path.join(build, "bin", "mh_step_costs")
    args = [exe, what, form, "%g" % t1, "%g" % t2, newton, linear, str(every)]
    native = subprocess.run(args, capture_output=True, text=True, check=True,
                            cwd=tmp).stdout
    r = {k: float(v) for k, v in re.findall(r"^(\w+) (\S+)$", native, re.M)}
    if count:
        d = tempfile.mkdtemp(dir=tmp)
        _, files = callgrind_summaries(args, d, ["--instr-atstart=no"])
        dumps = sorted((int(t.split()[-1]), v, name) for name, (t, v) in files.items()
                       if re.match(r"Client Request: step \d+$", t))
        r["dumps"] = [v for _, v, _ in dumps]
        r["mean_instructions"] = sum(r["dumps"]) / r["steps"] if r["steps"] else None
        r["worst_instructions"] = max(r["dumps"]) if every == 1 and r["dumps"] else None
        if annotate and dumps and dumps[-1][1]:
            factor, _ = inclusive(annotate_tree(os.path.join(d, dumps[-1][2])), SPLIT_FACTOR)
            r["factor_share"] = factor / float(dumps[-1][1])
    return r


def step_split(build, tmp, what, form, t1, t2, newton=DEFAULT_NEWTON, linear="klu"):
    """Where a step's instructions go: mh_step_costs under callgrind with one
    dump for the whole window t1-t2 (no output), its inclusive costs per step:
    the tangents' assembly and factorization, the residual calls outside the
    tangent (each Newton iteration's and the converged iterate's), the
    subsystems' evaluations (in every residual call), the formulation's own
    work after each iterate and step, and the rest; calls per step; the
    largest exclusive function."""
    exe = os.path.join(build, "bin", "mh_step_costs")
    args = [exe, what, form, "%g" % t1, "%g" % t2, newton, linear]
    native = subprocess.run(args, capture_output=True, text=True, check=True, cwd=tmp).stdout
    steps = int(re.search(r"^steps (\d+)$", native, re.M).group(1))
    d = tempfile.mkdtemp(dir=tmp)
    _, files = callgrind_summaries(args + [str(steps)], d, ["--instr-atstart=no"])
    name = next(n for n, (t, _) in files.items() if t == "Client Request: step %d" % (steps - 1))
    path = os.path.join(d, name)
    funcs = annotate_tree(path)
    total = float(files[name][1])
    tangent, tangents = inclusive(funcs, SPLIT_TANGENT)
    factor, factors = inclusive(funcs, SPLIT_FACTOR)
    residual, residual_calls = inclusive(funcs, SPLIT_RESIDUAL)
    in_tangent, fd_calls = called_within(funcs, SPLIT_TANGENT, SPLIT_RESIDUAL)
    subsystems, _ = inclusive(funcs, SPLIT_SUBSYSTEMS)
    formulation, _ = inclusive(funcs, SPLIT_FORMULATION)
    top, top_cost = largest_exclusive(path)
    n = float(steps)
    return {"steps": steps, "newton": newton, "total": total / n, "tangents": tangents / n,
            "tangent": tangent / n, "factors": factors / n, "factor": factor / n,
            "residual_calls": (residual_calls - fd_calls) / n, "fd_calls": fd_calls / n,
            "residuals": (residual - in_tangent) / n, "subsystems": subsystems / n,
            "formulation": formulation / n,
            "rest": (total - tangent - factor - (residual - in_tangent) - formulation) / n,
            "top": top, "top_share": top_cost / total if total else None}


def real_time_line(build, tmp, form):
    """`monohydra run --real-time` on the excavator's whole cycle at 1 ms."""
    exe = os.path.join(build, "bin", "monohydra")
    out = subprocess.run([exe, "run", os.path.join(ROOT, "models", "excavator.yaml"),
                          "--formulation", form, "--real-time", "--out",
                          os.path.join(tmp, "rt-%s.csv" % form)],
                         capture_output=True, text=True, check=True).stdout
    m = re.search(r"deadlines missed: (\d+) of (\d+) steps \(([\d.e+-]+) %\), worst ([\d.e+-]+) ms "
                  r"late, mean ([\d.e+-]+) ms late", out)
    u = re.search(r"accepted unconverged: (\d+) steps", out)
    return {"missed": int(m.group(1)), "steps": int(m.group(2)), "worst_late_ms": float(m.group(4)),
            "mean_late_ms": float(m.group(5)), "unconverged": int(u.group(1)) if u else None,
            "newton": newton_of(out)}


def default_newtons(build, res):
    """{(kind, N): the Newton kind the default configuration (solver.newton:
    auto) runs on the bench's chain or tree of N bodies}, for every N that
    mh_bench measured: one step of `mh_profile chain:N` (the same generated
    mechanism), which names the kind its run resolved (None where it failed)."""
    exe = os.path.join(build, "bin", "mh_profile")
    out = {}
    mechanisms = sorted({(p[0], int(p[3])) for p in (name.split("/") for name in res)
                         if len(p) == 4 and p[0] in ("chain", "tree") and p[3].isdigit()})
    for kind, n in mechanisms:
        try:
            said = subprocess.run([exe, "%s:%d" % (kind, n), "open-loop", "0.001", "none", "auto"],
                                  capture_output=True, text=True, check=True).stdout
            m = re.search(r"Newton iterations, ([\w-]+) Newton", said)
            out[(kind, n)] = m.group(1) if m else None
        except (OSError, subprocess.CalledProcessError):
            out[(kind, n)] = None
    return out


def issue_measurements(build):
    """Every callgrind count and real-time run of the Targets section; the
    callgrind runs go two at a time (one per core), after the timed benchmarks."""
    import concurrent.futures as cf
    if shutil.which("valgrind") is None:
        return None
    tmp = tempfile.mkdtemp(prefix="mh-perf-")
    try:
        # Real time first, alone on the machine: its deadlines are wall clock.
        rt = {f: real_time_line(build, tmp, f) for f in ("double-step", "penalty")}
        jobs = {}
        with cf.ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
            # The longest first: the whole cycles, one dump per simulated second.
            for f in ("double-step", "penalty"):
                jobs[("cycle", f)] = pool.submit(step_costs, build, tmp, "excavator.yaml", f, 0.0,
                                                 CYCLE_SECONDS, DEFAULT_NEWTON, "klu", 1000)
            for newton, linear in BIG_CHAIN_RUNS:
                # Per-step Newton factors at every step: its last step's share
                # of factorization is the N^3 of the page's prose.
                jobs[("big", newton, linear)] = pool.submit(
                    step_costs, build, tmp, "chain:%d" % BIG_CHAIN, "open-loop", 0.0,
                    BIG_CHAIN_STEPS * 1e-3, newton, linear, annotate=newton == DEFAULT_NEWTON)
            for model, form, t1, t2, _ in RUN_CASES:
                jobs[("run", model, form)] = pool.submit(run_instructions, build, tmp, model, form,
                                                         t1, t2)
                jobs[("steps", model, form)] = pool.submit(step_costs, build, tmp, model + ".yaml",
                                                           form, t1, t2)
                for newton in (DEFAULT_NEWTON, "full"):
                    jobs[("split", model, form, newton)] = pool.submit(
                        step_split, build, tmp, model + ".yaml", form, t1, t2, newton)
        out = {k: v.result() for k, v in jobs.items()}
        out["real_time"] = rt
        return out
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def verdict(value, target, unit=""):
    if value is None:
        return "not measured"
    return "met" if value <= target else "missed by %.1fx" % (value / target)


def span(values, form=None, sep=" to "):
    """'a to b' of the smallest and largest value as formatted ('a' when they read the same)."""
    form = form or fmt
    vals = sorted(v for v in values if v is not None)
    if not vals:
        return "—"
    a, b = form(vals[0]), form(vals[-1])
    return a if a == b else a + sep + b


def kilo(v):
    return "%sk" % fmt(v / 1e3) if v is not None else "—"


def ratio_of(a, b, k=1.0):
    """a's CPU time over k times b's, None unless both were measured."""
    return a["cpu_us"] / (k * b["cpu_us"]) if "cpu_us" in a and "cpu_us" in b else None


def energy_error(r):
    e = r.get("energy_error_1s")
    return None if e is None or e < 0 else e


def simbody_rows(res):
    """For each N against Simbody: ours with the default (auto, KLU), full
    Newton (KLU), the fastest Newton kind and linear solver measured, Simbody
    at 1 ms and 0.25 ms."""
    rows = []
    for n in SIMBODY_N:
        cands = [((l, k), res.get("chain/%s/%s/%d" % (l, k, n), {})) for l in ("klu", "auto")
                 for k in CHAIN_NEWTONS]
        (fl, fk), fast = min(cands, key=lambda c: c[1].get("cpu_us", float("inf")))
        rows.append({"n": n, "default": res.get("chain/klu/auto/%d" % n, {}),
                     "full": res.get("chain/klu/full/%d" % n, {}), "fast": fast,
                     "fast_name": "%s, %s" % (fl, fk) if "cpu_us" in fast else "—",
                     "sb": res.get("simbody/chain/%d/1000" % n, {}),
                     "sq": res.get("simbody/chain/%d/250" % n, {})})
    return rows


def split_table(m):
    """A step's instructions by part (step_split), per-step and full Newton."""
    L = ["| case | Newton | instructions per step | tangents per step | the tangents' assembly "
         "and factorization | residual calls per step | the residual calls | the subsystems' "
         "evaluations (in every residual call) | the formulation's own work after each iterate "
         "and step | the rest (linear solves, integrator, step) |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    for model, form, t1, t2, _ in RUN_CASES:
        for newton in (DEFAULT_NEWTON, "full"):
            s = m.get(("split", model, form, newton))
            if not s:
                continue
            tot = s["total"]

            def part(v):
                return "%s (%.0f %%)" % (kilo(v), 100.0 * v / tot) if tot else "—"
            calls = fmt(s["residual_calls"])
            if s["fd_calls"] > 0:
                calls += " (and %s in the tangent's differences)" % fmt(s["fd_calls"])
            L.append("| %s, %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                model, form, newton, "{:,.0f}".format(tot), fmt(s["tangents"]),
                part(s["tangent"] + s["factor"]), calls, part(s["residuals"]),
                part(s["subsystems"]), part(s.get("formulation", 0.0)), part(s["rest"])))
    return "\n".join(L)


def issue_targets(m, res, defaults=None):
    """The Targets section: each of the speed issue's targets, met or by how much missed."""
    if m is None:
        return "Not measured (valgrind missing)."
    defaults = defaults or {}
    runs = [m[("run", c[0], c[1])] for c in RUN_CASES]
    kinds = sorted({(r.get("newton") if isinstance(r, dict) else None) or "not recorded"
                    for r in runs})
    L = ["### The case studies and the excavator: instructions per step",
         "",
         "`monohydra run MODEL --formulation F --output-interval 0.01` under callgrind, every "
         "forked process counted, the difference of two end times over the steps between them "
         "(the default configuration, no solver option: KLU and %s Newton, as the runs' "
         "summaries said). Worst step: `bench/step_costs.cpp` (`mh_step_costs`, %s Newton, KLU) "
         "over the same window, each step's instructions alone (callgrind, one dump per step) and "
         "its CPU time on this machine (steady clock, a run without valgrind)." % (
             " and ".join(kinds), DEFAULT_NEWTON),
         "",
         "| case | window | instructions per step | target | verdict | mean step | worst step: "
         "instructions | worst step: time | at t (s), Newton iterations |",
         "|---|---|---|---|---|---|---|---|---|"]
    for model, form, t1, t2, target in RUN_CASES:
        ips = run_ips(m[("run", model, form)])
        s = m[("steps", model, form)]
        L.append("| %s, %s | %g-%g s | %s | %s | %s | %s us | %s | %s us | %s, %d |" % (
            model, form, t1, t2, "{:,.0f}".format(ips), "{:,.0f}".format(target),
            verdict(ips, target), fmt(s["mean_us"]), "{:,}".format(s["worst_instructions"]),
            fmt(s["worst_us"]), fmt(s["worst_at"]), s["worst_iterations"]))
    rt_kinds = sorted({m["real_time"][f].get("newton") or "not recorded"
                       for f in ("double-step", "penalty")})
    L += ["",
          "The excavator's whole %g s cycle (`mh_step_costs excavator.yaml F 0 %g %s klu 1000`: "
          "%s Newton, KLU, no output; instructions of every simulated second; real time: "
          "`monohydra run --real-time`, the default configuration, %s Newton):" % (
              CYCLE_SECONDS, CYCLE_SECONDS, DEFAULT_NEWTON, DEFAULT_NEWTON, " and ".join(rt_kinds)),
          "",
          "| formulation | instructions per step, whole cycle | cheapest second | dearest second "
          "| mean step | worst step (time) | at t (s) | real time at 1 ms: deadlines missed | "
          "worst and mean lateness | accepted unconverged |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for f in ("double-step", "penalty"):
        c = m[("cycle", f)]
        per_s = [v / 1000.0 for v in c["dumps"]]
        dear = max(range(len(per_s)), key=lambda i: per_s[i]) if per_s else None
        cheap = min(range(len(per_s)), key=lambda i: per_s[i]) if per_s else None
        rt = m["real_time"][f]
        L.append("| %s | %s | %s (%d-%d s) | %s (%d-%d s) | %s us | %s ms | %s | %d of %d (%.2f %%) | "
                 "%s ms, %s ms | %s |" % (
                     f, "{:,.0f}".format(c["mean_instructions"]),
                     "{:,.0f}".format(per_s[cheap]), cheap, cheap + 1,
                     "{:,.0f}".format(per_s[dear]), dear, dear + 1, fmt(c["mean_us"]),
                     fmt(c["worst_us"] / 1e3), fmt(c["worst_at"]), rt["missed"], rt["steps"],
                     100.0 * rt["missed"] / rt["steps"], fmt(rt["worst_late_ms"]),
                     fmt(rt["mean_late_ms"]), rt["unconverged"]))
    if any(("split", c[0], c[1], DEFAULT_NEWTON) in m for c in RUN_CASES):
        L += ["",
              "Where a step's instructions go, the same windows: `mh_step_costs MODEL F T1 T2 NEWTON "
              "klu STEPS` under callgrind, one dump for the window (no output, so a little below "
              "`monohydra run`'s counts above), inclusive costs per step from `callgrind_annotate "
              "--tree=both`: the tangents (`assemble_tangent` and the linear solver's `factor`), "
              "the residual calls outside the tangent (`Engine::residual`: each Newton iteration's "
              "and the converged iterate's evaluation), the subsystems' evaluations "
              "(`evaluate_subsystems`, part of the residual calls), the formulation's own work "
              "after each iterate and each step (its `iteration_done` and `accept`: penalty's "
              "projections, Eqs. 20-21) and the rest. %s Newton, the default, beside full Newton, "
              "the paper's." % DEFAULT_NEWTON.capitalize(),
              "",
              split_table(m)]
    # Chains against Simbody.
    L += ["", "### Chains against Simbody", ""]
    rows = simbody_rows(res)
    if not any("cpu_us" in r["sb"] for r in rows):
        L.append("Not measured: mh_bench was built without Simbody (apt-get install "
                 "libsimbody-dev, configure again).")
    else:
        L += ["The chain of N beams in both, one process (`mh_bench`, CPU time per step, medians): "
              "monohydra's open-loop formulation with the trapezoidal rule and Simbody 3.7's "
              "`VerletIntegrator`, both at a fixed 1 ms (`bench/simbody_chain_bench.cpp`). Ours "
              "in the default configuration (KLU, `solver.newton: auto`), with full Newton (the "
              "paper's) and with the fastest Newton kind and linear solver measured; the last "
              "column names the Newton kind the default runs on that chain, as the run itself "
              "said (`mh_profile`). Ratio: ours over Simbody's, "
              "below 1 is ahead. Accuracy: the energy error after one simulated second, "
              "|E(1 s) - E(0)| (J), where the benchmark completed one; Simbody at 0.25 ms (a "
              "quarter of the step, four steps per ours) for the ratio at matched accuracy.",
              "",
              "| N | ours: the default | ours: klu, full | ours: fastest | Simbody, 1 ms | "
              "ratio, the default | ratio, fastest | energy error: ours (fastest), Simbody 1 ms, "
              "Simbody 0.25 ms | ratio, fastest, against Simbody at 0.25 ms (4 steps) | the "
              "default runs |",
              "|---|---|---|---|---|---|---|---|---|---|"]

        def ratio(a, b, k=1.0):
            v = ratio_of(a, b, k)
            return "%.2f" % v if v is not None else "—"

        def err(r):
            e = energy_error(r)
            return "%.2g" % e if e is not None else "—"

        for r in rows:
            L.append("| %d | %s us | %s us | %s us (%s) | %s us | %s | %s | %s, %s, %s | %s | %s |" % (
                r["n"], fmt(r["default"].get("cpu_us")), fmt(r["full"].get("cpu_us")),
                fmt(r["fast"].get("cpu_us")), r["fast_name"], fmt(r["sb"].get("cpu_us")),
                ratio(r["default"], r["sb"]), ratio(r["fast"], r["sb"]), err(r["fast"]),
                err(r["sb"]), err(r["sq"]), ratio(r["fast"], r["sq"], 4.0),
                defaults.get(("chain", r["n"])) or "—"))
    # The big chain and the tree.
    L += ["", "### The %d-body chain and the tree of bounded depth" % BIG_CHAIN, ""]
    for newton, linear in BIG_CHAIN_RUNS:
        b = m[("big", newton, linear)]
        what = ("no tangent: an articulated-body factorization of M' an iteration"
                if newton == "articulated" else "the first factors the tangent")
        L.append("- chain of %d bodies, %s Newton, %s: %s instructions per step (the mean of its "
                 "first %d steps, each counted alone; %s), %s s per step here: target %s, %s." % (
                     BIG_CHAIN, newton, linear, "{:,.0f}".format(b["mean_instructions"]),
                     BIG_CHAIN_STEPS, what, fmt(b["mean_us"] / 1e6), "{:.1e}".format(BIG_CHAIN_TARGET),
                     verdict(b["mean_instructions"], BIG_CHAIN_TARGET)))
    for k in CHAIN_NEWTONS:
        tree = curve(res, "tree", "klu", k)
        slope = fit_slope([(p[0], p[1]) for p in tree])
        L.append("- tree of bounded depth, %s, N = %s: cost grows as N^%s: target N^%s, %s." % (
            "auto Newton (the default)" if k == "auto" else k + " Newton", ", ".join(str(p[0]) for p in tree), fmt(slope, 3), TREE_SLOPE_TARGET,
            "met" if slope is not None and slope <= TREE_SLOPE_TARGET else
            ("missed" if slope is not None else "not measured")))
    return "\n".join(L)


def missed_title(label, ratios, targets):
    """'Case studies, 6.7x to 7.9x over 20k and 25k' (or what is met)."""
    goal = " and ".join("%gk" % (t / 1e3) for t in sorted(set(targets)))
    missed = [r for r in ratios if r > 1.0]
    if not missed:
        return "%s: met (%s)" % (label, goal)
    text = "%s, %s over %s" % (label, span(missed, lambda v: "%.1fx" % v,
                                             " and " if len(missed) == 2 else " to "), goal)
    if len(missed) < len(ratios):
        text += " (%d of %d met)" % (len(ratios) - len(missed), len(ratios))
    return text


def in_the_way(m, res, defaults=None):
    """What stands in the way of each target: the Targets section's reading,
    every number from this run's measurements."""
    head = ["### What stands in the way", ""]
    if m is None:
        return "\n".join(head + ["Not measured (valgrind missing)."])
    defaults = defaults or {}
    cases = [c for c in RUN_CASES if c[0] != "excavator"]
    excavator = [c for c in RUN_CASES if c[0] == "excavator"]
    split = {(c[0], c[1], n): m.get(("split", c[0], c[1], n)) for c in RUN_CASES
             for n in (DEFAULT_NEWTON, "full")}
    if not all(split.values()):
        return "\n".join(head + ["Not measured: the step's split by part (step_split) is missing "
                                 "from the Targets measurements (an earlier --targets-json?)."])
    head.append("Read from this run's measurements above: `monohydra run`'s instructions per "
                "step, their split by part (`mh_step_costs` under callgrind) and mh_bench's times.")
    head.append("")
    L = []

    def over(c):
        return run_ips(m[("run", c[0], c[1])]) / c[4]

    # The case studies.
    sp = [split[(c[0], c[1], DEFAULT_NEWTON)] for c in cases]
    fu = [split[(c[0], c[1], "full")] for c in cases]
    tangent = [s["tangent"] + s["factor"] for s in sp]
    per_call = [s["residuals"] / s["residual_calls"] for s in sp if s["residual_calls"]]
    fd = [s["fd_calls"] for s in sp]
    t_over = [t / c[4] for t, c in zip(tangent, cases)]
    r_over = [s["residuals"] / c[4] for s, c in zip(sp, cases)]
    if min(t_over) > 1.0 and min(r_over) > 1.0:
        gap = ("each alone costs more than the target, so 20k needs both a tangent made less "
               "often than once a step, or for much less, and residuals %s cheaper" %
               span(r_over, lambda v: "%.1fx" % v))
    else:
        gap = "together they are %s the target" % span(
            [(t + s["residuals"]) / c[4] for t, s, c in zip(tangent, sp, cases)],
            lambda v: "%.1fx" % v)
    first = sp[0]
    L.append(
        "- **%s.** Per-step Newton, the default, factors %s tangents a step and calls the "
        "residual %s times (each Newton iteration's and the converged iterate's evaluation%s). "
        "Of its %s instructions a step (`mh_step_costs`, no output: the split above), the "
        "tangent's assembly and factorization take %s (%s %%) and the residual calls %s (%s %%, "
        "%s a call); the formulation's own work after each iterate and step %s (penalty's "
        "projections: %s on penalty), the rest (linear solves, the integrator) %s. The tangent "
        "alone is %s the target and the residual calls alone %s: %s. No function holds more "
        "than %s %% of a step exclusive (%s, %s: `%s`): the cost is spread over the kernels. "
        "Full Newton, the paper's method, factors %s tangents a step for %s instructions. "
        "Modified Newton keeps one factorization across steps, but it must tighten Newton's "
        "tolerance to 1e-13 to hold a free mechanism's energy, and then it costs what full "
        "Newton costs (the default configuration, above)." % (
            missed_title("Case studies", [over(c) for c in cases], [c[4] for c in cases]),
            span([s["tangents"] for s in sp]), span([s["residual_calls"] for s in sp]),
            "" if max(fd) == 0 else "; %s more in the tangent's forward differences" % span(fd),
            span([s["total"] for s in sp], kilo), span(tangent, kilo),
            span([100.0 * t / s["total"] for t, s in zip(tangent, sp)], lambda v: "%.0f" % v),
            span([s["residuals"] for s in sp], kilo),
            span([100.0 * s["residuals"] / s["total"] for s in sp], lambda v: "%.0f" % v),
            span(per_call, kilo), span([s.get("formulation", 0.0) for s in sp], kilo),
            span([s.get("formulation", 0.0) for c, s in zip(cases, sp) if c[1] == "penalty"],
                 kilo),
            span([s["rest"] for s in sp], kilo),
            span(t_over, lambda v: "%.1fx" % v), span(r_over, lambda v: "%.1fx" % v), gap,
            "%.0f" % (100.0 * max(s["top_share"] or 0 for s in sp)), cases[0][0], cases[0][1],
            first["top"], span([s["tangents"] for s in fu]), span([s["total"] for s in fu], kilo)))

    # Worst steps.
    st = [m[("steps", c[0], c[1])] for c in cases]
    ratio_i = [s["worst_instructions"] / s["mean_instructions"] for s in st]
    ratio_t = [s["worst_us"] / s["mean_us"] for s in st]
    mean_its = [res.get("case/%s/%s/trapezoidal/klu/%s" % (c[0], c[1], DEFAULT_NEWTON), {})
                .get("its_per_step") for c in cases]
    ex = [m[("steps", c[0], c[1])] for c in excavator]
    ex_spread = [100.0 * (s["worst_instructions"] / s["mean_instructions"] - 1.0) for s in ex]
    ex_sp = [split[(c[0], c[1], DEFAULT_NEWTON)] for c in excavator]
    L.append(
        "- **Worst steps.** A case study's dearest step is %s its mean in instructions. Its "
        "slowest step takes %s the mean step's time (%s us), with %s Newton iterations, where "
        "the window's steps average %s residual calls (each iteration's and the converged "
        "iterate's; over the whole 10 s, %s iterations a step, mh_bench)%s. The excavator's "
        "dearest step is within %s %% of its mean in instructions (%s residual calls and %s "
        "tangents a step)." % (
            span(ratio_i, lambda v: "%.2fx" % v), span(ratio_t, lambda v: "%.1fx" % v),
            span([s["mean_us"] for s in st]),
            span([float(s["worst_iterations"]) for s in st], lambda v: "%d" % v),
            span([s["residual_calls"] for s in sp]), span(mean_its),
            ": more than its instructions account for, the clock's and the cache's share of so "
            "short a step" if min(ratio_t) > max(ratio_i) else "",
            span(ex_spread, lambda v: "%.1f" % v), span([s["residual_calls"] for s in ex_sp]),
            span([s["tangents"] for s in ex_sp])))

    # The excavator.
    ex_fu = [split[(c[0], c[1], "full")] for c in excavator]
    rt = m["real_time"]
    by_form = {c[1]: s for c, s in zip(excavator, ex_sp)}
    pen = ""
    if "penalty" in by_form and "double-step" in by_form:
        p, d = by_form["penalty"], by_form["double-step"]
        pen = (" Penalty adds its projections (the formulation's own work after each iterate "
               "and step: %s a step, against double-step's %s) and calls the residual %s times a "
               "step, double-step %s." % (
                   kilo(p.get("formulation", 0.0)), kilo(d.get("formulation", 0.0)),
                   fmt(p["residual_calls"]), fmt(d["residual_calls"])))
    L.append(
        "- **%s.** The same parts as the case studies' steps, each dearer: the tangent's "
        "assembly and factorization %s (%s %%) and the residual calls %s (%s %%), %s a call, of "
        "which the subsystems' evaluations take %s %%.%s Full Newton, the paper's method, costs "
        "%s instructions a step here. At 1 ms in real time it misses %.2f %% (double-step) and "
        "%.2f %% (penalty) of its deadlines on this machine, each by at most %s ms." % (
            missed_title("Excavator", [over(c) for c in excavator], [c[4] for c in excavator]),
            span([s["tangent"] + s["factor"] for s in ex_sp], kilo),
            span([100.0 * (s["tangent"] + s["factor"]) / s["total"] for s in ex_sp],
                 lambda v: "%.0f" % v),
            span([s["residuals"] for s in ex_sp], kilo),
            span([100.0 * s["residuals"] / s["total"] for s in ex_sp], lambda v: "%.0f" % v),
            span([s["residuals"] / s["residual_calls"] for s in ex_sp if s["residual_calls"]],
                 kilo),
            span([100.0 * s["subsystems"] / s["residuals"] for s in ex_sp if s["residuals"]],
                 lambda v: "%.0f" % v),
            pen, span([s["total"] for s in ex_fu], kilo),
            100.0 * rt["double-step"]["missed"] / rt["double-step"]["steps"],
            100.0 * rt["penalty"]["missed"] / rt["penalty"]["steps"],
            fmt(max(rt[f]["worst_late_ms"] for f in ("double-step", "penalty")))))

    # Chains against Simbody.
    rows = [r for r in simbody_rows(res) if "cpu_us" in r["sb"]]
    big = {(n, l): m[("big", n, l)] for n, l in BIG_CHAIN_RUNS}
    share = big.get((DEFAULT_NEWTON, "klu"), {}).get("factor_share")
    articulated = sorted(n for (k, n), v in defaults.items() if k == "chain" and v == "articulated")
    if rows:
        rd = [(r["n"], ratio_of(r["default"], r["sb"])) for r in rows]
        rf = [(r["n"], ratio_of(r["fast"], r["sb"]), r["fast_name"]) for r in rows]
        rq = [(r["n"], ratio_of(r["fast"], r["sq"], 4.0)) for r in rows]

        def behind_from(pairs):
            ns = [p[0] for p in pairs if p[1] is not None and p[1] > 1.0]
            return "N = %d" % ns[0] if ns else ""

        def ns_text(ns):
            return "N = " + ", ".join(str(n) for n in ns) if ns else "no N measured"
        ahead_d = [n for n, v in rd if v is not None and v < 1.0]
        ahead_f = [(n, v, name) for n, v, name in rf if v is not None and v < 1.0]
        ahead_q = [(n, v) for n, v in rq if v is not None and v < 1.0]
        errs = [(r["n"], energy_error(r["fast"]), energy_error(r["sq"])) for r in rows]
        both = [e for e in errs if e[1] is not None and e[2] is not None]
        unknown = [n for n, ours, _ in errs if ours is None]
        last = rf[-1]
        behind = (behind_from(rd), behind_from([(n, v) for n, v, _ in rf]))
        title = ("ahead at every N measured, the default and the fastest"
                 if behind == ("", "") else "behind from %s (the default) and %s (fastest)" % (
                     behind[0] or "no N", behind[1] or "no N"))
        text = ("- **Chains against Simbody, %s.** "
                "A serial chain's tangent in relative coordinates is dense: its factorization "
                "costs N^3%s, and its blocks N^2; the default does not form it on these chains "
                "from N = 8 but solves Newton's system by the articulated-body recursion, O(N) a "
                "solve and about twice the iterations. Simbody's Verlet is explicit and O(N) per "
                "step, one force evaluation a step. With the default we are ahead at %s, with the "
                "fastest kind measured at %s" % (
                    title,
                    " (%.0f %% of a step of the %d-body chain, per-step Newton with KLU, "
                    "callgrind)" % (100.0 * share, BIG_CHAIN) if share is not None else "",
                    ns_text(ahead_d), ns_text([n for n, _, _ in ahead_f])))
        if ahead_f:
            text += " (%s)" % "; ".join("%d: %s %.2f" % (n, name.replace(", ", "/"), v)
                                        for n, v, name in ahead_f)
        text += ". Set against Simbody at a quarter of the step, the fastest is ahead at %s" % (
            ns_text([n for n, _ in ahead_q]))
        if ahead_q:
            text += " (%s)" % "; ".join("%d: %.2f" % (n, v) for n, v in ahead_q)
        if both:
            n, ours, sq = both[-1]
            text += ("; at N = %d Simbody's energy error at that step is %.2g J against our "
                     "%.2g J" % (n, sq, ours))
        if unknown:
            text += ("; at %s our benchmark completed no simulated second, so its error is not "
                     "known" % ns_text(unknown))
        if last[1] is not None:
            text += ". At N = %d the fastest is %.1fx Simbody's time" % (last[0], last[1])
        text += "."
        compared = [n for n in articulated if n in [r["n"] for r in rows]]
        if compared:
            text += (" The default chose articulated Newton on the chains of %s (the run's own "
                     "report)." % ns_text(compared))
        L.append(text)

    # The big chain.
    b_over = [(n, l, big[(n, l)]["mean_instructions"] / BIG_CHAIN_TARGET)
              for n, l in BIG_CHAIN_RUNS]
    title = "The %d-body chain: %s against %s instructions a step" % (
        BIG_CHAIN, " and ".join("%s (%s, %s)" % ("met" if v <= 1.0 else "%.1fx over" % v, n, l)
                                for n, l, v in b_over), "{:.1e}".format(BIG_CHAIN_TARGET))
    shares = ["%.0f %% of a step with %s Newton and %s" % (
        100.0 * big[(n, l)]["factor_share"], n, l)
        for n, l in BIG_CHAIN_RUNS if big[(n, l)].get("factor_share") is not None]
    text = ("- **%s.** With a tangent, the same N^3%s. Articulated Newton forms no tangent: "
            "it solves Newton's system by the articulated-body recursion, O(N) a solve "
            "(`solver.newton: articulated`, `docs/model-format.md`)." % (
                title, ": the factorization is " + " and ".join(shares) if shares else ""))
    kind = defaults.get(("chain", BIG_CHAIN))
    if kind:
        text += " The default runs %s Newton on this chain (the run's own report)." % kind
    L.append(text)

    # Trees.
    slopes = {k: fit_slope([(p[0], p[1]) for p in curve(res, "tree", "klu", k)])
              for k in CHAIN_NEWTONS}
    d = slopes[DEFAULT_NEWTON]
    trees = sorted((n, v) for (k, n), v in defaults.items() if k == "tree")
    all_default = trees and all(v == DEFAULT_NEWTON for _, v in trees)
    L.append("- **Trees of bounded depth: %s.** The cost grows as N^%s with per-step Newton%s, "
             "N^%s with full, N^%s with modified and N^%s with articulated Newton (target "
             "N^%s)." % (
                 "not measured" if d is None else "met" if d <= TREE_SLOPE_TARGET else "missed",
                 fmt(d, 3), " (the default's choice on every tree measured, the run's own report)"
                 if all_default else "", fmt(slopes["full"], 3), fmt(slopes["modified"], 3),
                 fmt(slopes["articulated"], 3), TREE_SLOPE_TARGET))
    return "\n".join(head + L)


def default_config(res, m, defaults=None):
    """The Targets section's "The default configuration": which Newton the
    default runs where, why per-step, and what it costs beside full Newton."""
    defaults = defaults or {}
    runs = sorted({m[k].get("newton") for k in (m or {}) if k[0] == "run"
                   and isinstance(m[k], dict) and m[k].get("newton")})
    articulated = sorted(n for (k, n), v in defaults.items() if k == "chain" and v == "articulated")
    per_step_chains = sorted(n for (k, n), v in defaults.items()
                             if k == "chain" and v == "per-step")
    trees = sorted(n for (k, n), v in defaults.items() if k == "tree" and v == "per-step")
    where = ("the case studies and the excavator (`monohydra run` named %s Newton for the runs "
             "of the table below)" % " and ".join(runs) if runs else
             "the case studies and the excavator")
    if trees:
        where += ", the trees"
    if per_step_chains:
        where += " and the chains of N = %s" % ", ".join(str(n) for n in per_step_chains)
    text = ("Per-step Newton is the default: `solver.newton: auto` runs it on %s%s. It is the "
            "fastest Newton kind there that passes every accuracy test: it gives full "
            "Newton's trajectories on the case studies with one tangent per step "
            "(`tests/models/solver_choices_test.cpp`, "
            "`PerStepNewtonGivesFullNewtonsCaseStudyTrajectoriesWithOneTangentPerStep`) and holds "
            "the free four-bar's energy as full Newton does at the shipped tolerance "
            "(`ModifiedNewtonNeedsARoundOffToleranceToHoldAFreeFourBarsEnergy`)." % (
                where, "; on the chains of N = %s it chose articulated Newton (no tangent, an O(N) "
                "solve; `docs/model-format.md`)" % ", ".join(str(n) for n in articulated)
                if articulated else ""))
    pairs = []
    for model, form in sorted(PAPER_SECONDS):
        p = res.get("case/%s/%s/trapezoidal/klu/%s" % (model, form, DEFAULT_NEWTON), {})
        f = res.get("case/%s/%s/trapezoidal/klu/full" % (model, form), {})
        if "cpu_us" in p and "cpu_us" in f:
            pairs.append((p, f))
    if pairs:
        text += (" On the four case studies (mh_bench, KLU, trapezoidal, 10 s) it takes %s of full "
                 "Newton's CPU time, at %s tangents and %s iterations a step against full "
                 "Newton's %s and %s." % (
                     span([p["cpu_us"] / f["cpu_us"] for p, f in pairs], lambda v: "%.2f" % v),
                     span([p.get("tangents_per_step") for p, _ in pairs]),
                     span([p.get("its_per_step") for p, _ in pairs]),
                     span([f.get("tangents_per_step") for _, f in pairs]),
                     span([f.get("its_per_step") for _, f in pairs])))
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--repetitions", type=int, default=3)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-profile", action="store_true")
    ap.add_argument("--json", help="an mh_bench JSON to use instead of running it")
    ap.add_argument("--targets-json", help="the Targets section's counts from an earlier run "
                    "(BUILD/performance-targets.json) instead of measuring them again")
    ap.add_argument("--chains", action="store_true",
                    help="measure the chains and trees only and print their table")
    ap.add_argument("--copied-only", action="store_true",
                    help="refresh only the sections copied from docs/sweeps.md and "
                    "docs/batches.md in the existing page, measuring nothing")
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "performance.md"))
    ap.add_argument("--svg", default=os.path.join(ROOT, "docs", "performance-chains.svg"))
    a = ap.parse_args()
    a.build = os.path.abspath(a.build)
    if a.copied_only:
        refresh_copied(a.out)
        return

    if a.json:
        with open(a.json) as f:
            data = json.load(f)
    else:
        data = run_bench(a.build, 1 if a.quick else a.repetitions, a.quick,
                         "chain|tree" if a.chains else None)
    res = results(data)
    if a.chains:
        print(chains_report(res, default_newtons(a.build, res)))
        return
    rows, why = (None, "left out (--no-profile)") if a.no_profile else profile(a.build)
    budget = None if a.no_profile else step_budget(a.build)
    if a.targets_json:
        with open(a.targets_json) as f:
            measured = {tuple(k.split("|")): v for k, v in json.load(f).items()}
    else:
        measured = issue_measurements(a.build)
        if measured is not None:
            with open(os.path.join(a.build, "performance-targets.json"), "w") as f:
                json.dump({"|".join(k) if isinstance(k, tuple) else k: v
                           for k, v in measured.items()}, f)
    if measured is not None and ("real_time",) in measured:
        measured["real_time"] = measured.pop(("real_time",))
    # Which Newton the default runs on each chain and tree measured.
    defaults = default_newtons(a.build, res)

    series = []
    dashes = {"auto": "", "articulated": "1 2", "per-step": "8 2 2 2", "full": "6 4",
              "modified": "2 3"}
    for kind, colour in (("chain", "#1f77b4"), ("tree", "#2ca02c")):
        for n in CHAIN_NEWTONS:
            pts = curve(res, kind, "klu", n)
            slope = fit_slope([(p[0], p[1]) for p in pts])
            series.append(("%s, %s Newton" % (kind, n), colour, dashes[n], pts, slope))
    svg_plot(series, a.svg)
    slopes = []
    for label, _, _, pts, slope in series:
        tail = fit_slope([(p[0], p[1]) for p in pts[-3:]])
        slopes.append("| %s | %s | %s |" % (label, fmt(slope, 2), fmt(tail, 2)))

    model, cpus = machine()
    ctx = data.get("context", {})
    ranking = best_choice(res)
    fastest_note = ("; the fastest Newton kind on the case studies, the ranking above"
                    if ranking and ranking[0][0][1] == "modified" else "")
    iterations = [res.get("case/%s/%s/trapezoidal/klu/%s" % (m, f, n), {}).get("its_per_step")
                  for m, f in PAPER_SECONDS for n in NEWTON_KINDS]
    base_chain = ", ".join("N = %d: %s us" % (n, fmt(v)) for n, v in sorted(BASELINE_CHAIN_US.items()))
    page = """# Performance

Generated by `bench/performance.py` (do not edit by hand: run
`bench/performance.py` from the source tree after building with
`-DMONOHYDRA_BENCH=ON`; it regenerates every number here and
`performance-chains.svg`). Commit {head}, {date}.

**Machine:** a {cpus}-core VM, `lscpu` model "{model}": times are CPU time
(Google Benchmark's `cpu_time`, median of {reps} repetitions), Release, one
thread, no output unless said. mh_bench's own context: {ncpu} CPUs at {mhz}
MHz{scaling}. Whatever else runs on the machine while it measures is said
here by hand when it matters: on 2026-12-05 nothing else ran beside the
timed benchmarks and the real-time runs (the callgrind counts ran two at a
time after them; the real-time runs were repeated alone on the idle machine
afterwards, and those are the numbers here). Repeated runs of the same
case-study benchmark differ by up to about 5 % between medians of 3. The
real-time runs' misses are this VM's pauses, not the Newton kind: three
runs of the double-step cycle with per-step Newton missed 856, 974 and
1025 of 22000 deadlines, one with full Newton in between 611 (on
2026-12-04 full Newton missed 18); a pause of 20 ms makes the next 20
steps late, each cut at its deadline and accepted unconverged, and the
cycle's worst step outside real time takes 1.2 ms with one Newton
iteration. The baseline below (047c70c) was
timed on 2026-12-01 on another VM (an Intel Xeon): its milliseconds do not
compare with this page's; the instruction counts do.

## Targets: instructions per step

What the speed issue asks, each target met or by how much it is missed.
Instruction counts are callgrind's (they agree to the digit between
machines whose times differ 2x); times are this machine's.

### The default configuration

{default_config}

Modified Newton, which keeps its factorization across steps, is not the
default: tried as the default (the measurements of de31dcd), it failed 28
tests, 20 of them physics: the energy and constraint bounds of the free
mechanisms, the formulations' agreement on the four-bar, the quick-return
and both excavators. On the free four-bar (double-step, 10 s) its peak
energy drift is 47.7 J at the shipped tol_position = 1e-7, against full
Newton's 0.0126 J. It needs 1e-13 to match, and there it costs what full
Newton costs: 54.7k against 55.2k instructions per step
(`tests/models/solver_choices_test.cpp`,
`ModifiedNewtonNeedsARoundOffToleranceToHoldAFreeFourBarsEnergy`;
`docs/model-format.md`, `newton`).

The paper's comparison (`monohydra` with no arguments, `monohydra compare`
on a case-study model) runs full Newton, the paper's method, a tangent at
every iteration (Eq. 37; `newton: full` in `models/paper-reference.yaml`),
so that its iteration counts stand beside the paper's; full Newton is
measured beside per-step throughout this page.

{issue_targets}

{in_the_way}

## Case studies (10 s at dt = 1 ms, KLU, per-step Newton: the default)

{case_table}

Real-time factor: simulated 10 s over the CPU time. The paper's Matlab
took {paper} s (four-bar double-step, four-bar penalty, quick-return
double-step, quick-return penalty; with full Newton, the paper's method).
Kinematics passes: passes of the kinematics per step
(`Simulation::counters()`; target at most 6). The last two columns: the
same run with full Newton (trapezoidal only), and its CPU time over
per-step's.

## Linear solvers and Newton kinds

`solver: {{linear: klu|umfpack|dense, newton: per-step|full|modified}}`
(`docs/model-format.md`; the default `newton: auto` is per-step Newton on
the case studies and trees, articulated Newton on long chains: the chains
and trees below measure both). Case studies: ms per 10 s (Newton iterations
and tangents factored per step); chains and trees: CPU time per step.

{solver_table}

Fastest on the four case studies together (sum of the four runs): {ranking}.
KLU stays the default: it refactors with the pivots it chose first, which
is what large sparse tangents need; dense LU pays off only for small ones,
and UMFPACK makes a new numeric factorization (and allocates) each time.
Per-step Newton, the default, gives full Newton's trajectories with one
tangent per step (`tests/models/solver_choices_test.cpp`,
`PerStepNewtonGivesFullNewtonsCaseStudyTrajectoriesWithOneTangentPerStep`).
Modified Newton gives them within the tolerances (the same file:
coordinates within 1e-7 rad of full Newton over 10 s), but not a free
mechanism's energy at the default tolerance (the default configuration,
above): it is an option, not the default.

## Output cost

The same case-study runs writing their CSV to `/dev/null` (formatting and
writes, no disk), every step and every 10 ms (`--output-interval 0.01`), in
the models' default configuration (KLU, per-step Newton). Target: at most
5 % with a 10 ms interval.

{output_table}

## Chains and trees

The open chain of N beams (0.1 m, 1 kg) and a tree of bounded depth (one
base beam and (N - 1)/2 arms of two beams on its tip), open-loop
formulation, trapezoidal, dt = 1 ms, KLU: the default, `solver.newton:
auto` (solid), articulated Newton (dots; no tangent, the linear solver
unused), per-step Newton (dash-dots), full Newton (dashes) and modified
Newton (short dashes). For articulated Newton "tangents/step" counts the
articulated-body factorizations of M', one an iteration. The default
configuration (as each run reported its choice) runs, {chain_defaults}.
Plot: `performance-chains.svg` (log-log, with the fitted slopes; red marks:
the chain targets).

![chains and trees](performance-chains.svg)

| series | slope over all N | slope over the last three N |
|---|---|---|
{slopes}

{chain_table}

## Earlier targets (milliseconds per 10 s)

The first speed work's targets, in this machine's milliseconds:

{targets}

Where the time goes (the profile below, the two largest inclusive shares
of each profiled run): {largest}.

### What stands in the way of 20 ms per 10 s

20 ms for 10 000 steps is 2 us per step. The budget below is modified
Newton's (one factorization kept across steps{fastest_note}), the floor of
the Newton kinds: its cost is almost all residual calls, about three per
step (Newton's iterations plus the evaluation of the converged iterate,
which the step accepts), and each residual runs the semirecursive
kinematics, M' and Q', the constraints and the hydraulics once or twice.
The default, per-step Newton, adds a tangent a step to it (the split by
part in the Targets section above). Exclusive instructions per step by
kernel (callgrind, 1 s to 3 s of each run, `bench/performance.py`):

{budget}

No one kernel holds the time: each is a few hundred instructions per body
per call (a 3D kinematics pass is about 2.5k instructions for the
four-bar's three bodies, M' and Q' about 2.2k, scalar SSE2 code as the
Release build compiles it), called about ten times per step; at the rate
measured above, 2 us per step leaves a third to a quarter of the
instructions the case studies now take. Closing that gap needs
fewer calls per step rather than faster kernels. The converged iterate's
evaluation stays (it makes the accepted state consistent: double-step's
dependent coordinates, the rates, the outputs), so two residual calls per
step is the floor and the lever is a predictor good enough for one Newton
iteration per step (the paper's Taylor predictor of Eq. 34 leaves
{iterations} iterations here; a third-order extrapolation tried here cut them by 3-13 % only,
pressures set the count); and for penalty, the projections' K and C
(Eqs. 20-21) without a recursion of their own each step.

## Profile

`valgrind --tool=callgrind` of `build/bin/mh_profile` (one run of a model,
CSV to /dev/null when said; per-step Newton and KLU unless said, on the
chains too, where the default runs articulated Newton), inclusive
instruction counts from
`callgrind_annotate --inclusive=yes`, as a share of `mh::run`. Inclusive
costs nest: the tangent's forward differences call the residual, and the
double-step's residual solves its dependent coordinates, so the columns do
not add up to 100 %. "—": no such function in the run (or inlined).

{profile}

## Baseline (main at 047c70c, before this work)

Measured on this machine with the same benchmarks the same day (medians,
CPU): four-bar double-step 204 ms per 10 s, four-bar penalty 213 ms,
quick-return double-step 369 ms, quick-return penalty 354 ms; the chain per
step {base_chain}.

{copied}""".format(
        head=git_head(), date=datetime.date.today().isoformat(), cpus=cpus, model=model,
        reps=max([e.get("repetitions", 1) for e in data.get("benchmarks", [])] or [1]), ncpu=ctx.get("num_cpus", "?"),
        mhz=ctx.get("mhz_per_cpu", "?"),
        scaling=", CPU scaling on" if ctx.get("cpu_scaling_enabled") else "",
        case_table=case_table(res), paper=", ".join(
            "%g" % PAPER_SECONDS[k] for k in [("fourbar", "double-step"), ("fourbar", "penalty"),
                                              ("quickreturn", "double-step"),
                                              ("quickreturn", "penalty")]),
        solver_table=solver_table(res),
        ranking=", ".join("%s/%s %s ms" % (l, n, fmt(v)) for (l, n), v in ranking) or "—",
        output_table=output_table(res), slopes="\n".join(slopes), chain_table=chain_table(res),
        issue_targets=issue_targets(measured, res, defaults),
        in_the_way=in_the_way(measured, res, defaults),
        default_config=default_config(res, measured, defaults),
        chain_defaults=default_kinds_text(defaults), fastest_note=fastest_note,
        iterations=span(iterations, sep="-"),
        targets=targets(res), largest=largest_shares(rows),
        budget=budget_section(budget, res,
                              "left out by --no-profile" if a.no_profile else "valgrind missing"),
        profile=profile_section(rows, why), base_chain=base_chain,
        copied=copied_sections())
    with open(a.out, "w") as f:
        f.write(page)
    print("wrote %s and %s" % (a.out, a.svg), file=sys.stderr)


COPIED_FIRST = "## Sweeps: speed-up over one core"


def copied_sections():
    """The page's last sections, measured by other scripts and kept in their
    own pages: copied here, the same text whether the page is made whole or
    only these are refreshed (--copied-only)."""
    return """{first}

Measured by `studies/speedup.sh` and kept in `docs/sweeps.md` (section
"Speed-up"), copied here by this script:

{sweeps}

## Batches: speed-up over one thread, and what a run costs

Measured by `bench/batch_scaling.sh` and kept in `docs/batches.md` (section
"Measured"), copied here by this script:

{batches}
""".format(first=COPIED_FIRST, sweeps=section("sweeps.md", "Speed-up"),
           batches=section("batches.md", "Measured"))


def refresh_copied(out):
    """Replaces the copied sections at the end of an existing page (or adds
    them) without measuring anything else."""
    with open(out) as f:
        text = f.read()
    at = text.find(COPIED_FIRST)
    text = (text[:at] if at >= 0 else text.rstrip("\n") + "\n\n") + copied_sections()
    with open(out, "w") as f:
        f.write(text)
    print("refreshed the copied sections of %s" % out, file=sys.stderr)


def section(page, title):
    """The body of docs/PAGE's "## TITLE" section (one source for both pages)."""
    path = os.path.join(ROOT, "docs", page)
    try:
        text = open(path).read()
    except OSError:
        return "(docs/%s not found)" % page
    m = re.search(r"^## %s\n(.*?)(?=^## |\Z)" % re.escape(title), text, re.S | re.M)
    if not m:
        return "(docs/%s has no %s section)" % (page, title)
    return m.group(1).strip()


if __name__ == "__main__":
    main()
