#!/usr/bin/env python3
"""Integrator study (SDK 2.0): accuracy, hydraulic ringing, drift, iterations and
time of every time integrator on the paper's two case studies.

usage: python3 studies/integrator_study.py BUILD/bin/monohydra [--out DIR]
       [--repeats N] [--dts 0.0005,0.001,0.002,0.005] [--ref-dt 0.0001]
       [--check-dt 0.00025]

Runs `monohydra compare MODEL --formulations F --integrators I --dt S --report D`
once per (model, formulation, integrator, dt) (one run per process, so each
process's CPU time is that run's plus loading and the report), reads the CSVs
and prints Markdown tables on stdout. Progress goes to stderr.
Python 3 standard library only.
"""
import argparse
import csv
import math
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MODELS = os.path.join(os.path.dirname(HERE), "models")

# name, model file, independent coordinate (the double-step's choice)
CASES = [("four-bar", "fourbar.yaml", "z3"), ("quick-return", "quickreturn.yaml", "z4")]
FORMULATIONS = ["double-step", "penalty"]
# label, integrator id, rho_inf (None: the integrator's default / no option)
INTEGRATORS = [("trapezoidal", "trapezoidal", None),
               ("generalized-alpha 0.8", "generalized-alpha", None),   # default rho_inf = 0.8
               ("generalized-alpha 0.5", "generalized-alpha", 0.5),
               ("bdf2", "bdf2", None)]
TQ = 2.5e-5        # time quantum: every dt here (0.1, 0.125, 0.25, 0.5 .. 5 ms) and every output time is a multiple of 0.025 ms
OUT_EVERY = 200    # common output times: every 5 ms = 200 quanta
RING_WIN = 0.1     # ringing window after each closing (s)
FIRST, LATER = (0.0, 0.1), (0.3, 0.4)   # windows for the run's own ringing amplitude


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def closings(model_path):
    """Times at which the valve's reference steps from non-zero to zero (the model's
    `reference:` list of [t, U_ref]; a repeated time is a jump)."""
    text = open(model_path).read()
    m = re.search(r"reference:\s*(\[\[.*?\]\])", text)
    pts = [(float(a), float(b)) for a, b in re.findall(r"\[\s*([-\d.eE+]+)\s*,\s*([-\d.eE+]+)\s*\]", m.group(1))]
    return [t1 for (t0, u0), (t1, u1) in zip(pts, pts[1:]) if t0 == t1 and u0 != 0 and u1 == 0]


def model_variant(model_path, rho, tmpdir):
    """The model file with `integrator: {name: generalized-alpha, rho_inf: rho}`: the
    integrator's options are read from the model file only."""
    if rho is None:
        return model_path
    text = open(model_path).read()
    new, n = re.subn(r"(?m)^integrator:.*$", "integrator: {name: generalized-alpha, rho_inf: %g}" % rho, text)
    assert n == 1, "no integrator: line in " + model_path
    path = os.path.join(tmpdir, "%s-rho%g.yaml" % (os.path.splitext(os.path.basename(model_path))[0], rho))
    with open(path, "w") as f:
        f.write(new)
    return path


def run_compare(binary, model, formulation, integrator, dt, report):
    cmd = [binary, "compare", model, "--formulations", formulation, "--integrators", integrator,
           "--dt", repr(dt), "--report", report]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    w0 = time.time()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    w1 = time.time()
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    if p.returncode not in (0, 1):
        raise RuntimeError("%s -> %d\n%s" % (" ".join(cmd), p.returncode, p.stderr))
    status, reason = "ok", ""
    for line in p.stdout.splitlines():
        if line.startswith("status"):
            status = re.split(r"\s{2,}", line.strip())[1]
        m = re.match(r"\S+ FAILED: (.*)", line)
        if m:
            reason = m.group(1)
    if p.returncode == 1 and not reason:
        m = re.search(r"failed on [^:]*: (.*)", p.stderr)
        reason = m.group(1) if m else p.stderr.strip()[-200:]
    csvs = [f for f in os.listdir(report) if f.endswith(".csv")]
    assert len(csvs) == 1, csvs
    return dict(csv=os.path.join(report, csvs[0]), status=status, reason=reason,
                proc_cpu=cpu, proc_wall=w1 - w0, cmd=" ".join(cmd))


def read_csv(path):
    with open(path) as f:
        r = csv.reader(f)
        head = next(r)
        cols = {h: [] for h in head}
        for row in r:
            for h, v in zip(head, row):
                cols[h].append(float(v))
    cols["_key"] = [round(t / TQ) for t in cols["t"]]
    for t, k in zip(cols["t"], cols["_key"]):
        assert abs(t - k * TQ) < 1e-9, "t = %r is not a multiple of 0.025 ms" % t
    return cols


def index(cols):
    return {k: i for i, k in enumerate(cols["_key"])}


def zcols(cols):
    return sorted((h for h in cols if re.fullmatch(r"z\d+", h)), key=lambda h: int(h[1:]))


def errors(run, ref, zind):
    """max over the common output times (every 5 ms) of |z - z_ref| and |p - p_ref|."""
    ri = index(ref)
    e = dict(zind=0.0, zall=0.0, p1=0.0, p2=0.0, n=0)
    zs = zcols(run)
    for i, k in enumerate(run["_key"]):
        if k % OUT_EVERY or k not in ri:
            continue
        j = ri[k]
        e["n"] += 1
        e["zind"] = max(e["zind"], abs(run[zind][i] - ref[zind][j]))
        e["zall"] = max(e["zall"], max(abs(run[z][i] - ref[z][j]) for z in zs))
        e["p1"] = max(e["p1"], abs(run["p1"][i] - ref["p1"][j]))
        e["p2"] = max(e["p2"], abs(run["p2"][i] - ref["p2"][j]))
    return e


def p2p(vals):
    return max(vals) - min(vals) if vals else float("nan")


def detrended(ts, vs):
    """vs minus its least-squares line over the window: the oscillation about the local mean."""
    n = len(ts)
    if n < 3:
        return []
    mt, mv = sum(ts) / n, sum(vs) / n
    stt = sum((t - mt) ** 2 for t in ts)
    b = sum((t - mt) * (v - mv) for t, v in zip(ts, vs)) / stt
    return [v - mv - b * (t - mt) for t, v in zip(ts, vs)]


def ringing(run, ref, tcs, col="p1"):
    """For each closing t_c: the peak-to-peak of p1 - p1_ref over (t_c, t_c + 0.1] (the run's
    own rows, the reference at the same times); and the run's own ringing: the peak-to-peak of
    p1 about its linear trend over a first window (t_c, t_c + 0.1] and a later one
    (t_c + 0.3, t_c + 0.4] (each at least one period of the 10-20 Hz ringing), and their ratio."""
    ri = index(ref)
    out = []
    for tc in tcs:
        kc = round(tc / TQ)
        def sel(a, b):
            return [(i, ri.get(k)) for i, k in enumerate(run["_key"])
                    if kc + round(a / TQ) < k <= kc + round(b / TQ)]
        d = lambda s: [run[col][i] - ref[col][j] for i, j in s if j is not None]
        own = lambda s: p2p(detrended([run["t"][i] for i, _ in s], [run[col][i] for i, _ in s]))
        first, later = own(sel(*FIRST)), own(sel(*LATER))
        out.append(dict(tc=tc, d_full=p2p(d(sel(0, RING_WIN))), first=first, later=later,
                        ratio=later / first if first else float("nan")))
    return out


def summary(run):
    n = len(run["t"])
    it = run["iters"][1:]
    return dict(drift=max(abs(x) for x in run["drift"]), it_avg=sum(it) / len(it) if it else float("nan"),
                it_max=max(it) if it else float("nan"), wall=sum(run["wall_s"]), t_last=run["t"][-1], rows=n)


def freq_estimate(ref, tc, col="p1", span=0.5):
    """Dominant ringing frequency after t_c from the zero crossings of the detrended signal."""
    ts = [t for t in ref["t"] if tc < t <= tc + span]
    if len(ts) < 10:
        return float("nan")
    i0 = ref["t"].index(ts[0])
    vs = ref[col][i0:i0 + len(ts)]
    # remove a slow trend with a 2nd-order polynomial fit (normal equations)
    n = len(ts)
    mt = sum(ts) / n
    x = [t - mt for t in ts]
    S = [sum(xi ** k for xi in x) for k in range(5)]
    T = [sum(v * xi ** k for xi, v in zip(x, vs)) for k in range(3)]
    A = [[S[0], S[1], S[2]], [S[1], S[2], S[3]], [S[2], S[3], S[4]]]
    c = solve3(A, T)
    r = [v - (c[0] + c[1] * xi + c[2] * xi * xi) for xi, v in zip(x, vs)]
    zc = [ts[i] for i in range(1, n) if (r[i - 1] < 0) != (r[i] < 0)]
    if len(zc) < 3:
        return float("nan")
    return (len(zc) - 1) / 2.0 / (zc[-1] - zc[0])


def solve3(A, b):
    import copy
    A = copy.deepcopy(A)
    b = list(b)
    for c in range(3):
        p = max(range(c, 3), key=lambda r: abs(A[r][c]))
        A[c], A[p] = A[p], A[c]
        b[c], b[p] = b[p], b[c]
        for r in range(c + 1, 3):
            f = A[r][c] / A[c][c]
            for k in range(c, 3):
                A[r][k] -= f * A[c][k]
            b[r] -= f * b[c]
    x = [0.0] * 3
    for r in (2, 1, 0):
        x[r] = (b[r] - sum(A[r][k] * x[k] for k in range(r + 1, 3))) / A[r][r]
    return x


def g(x, fmt="%.2g"):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return fmt % x


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("monohydra")
    ap.add_argument("--out", default=None, help="folder for the reports and CSVs (default: a temp folder)")
    ap.add_argument("--repeats", type=int, default=3, help="runs per case for the median time")
    ap.add_argument("--dts", default="0.0005,0.001,0.002,0.005")
    ap.add_argument("--ref-dt", type=float, default=1.25e-4,
                    help="0.125 ms: at 0.1 ms the double-step fails on the quick-return at the 6.5 s event")
    ap.add_argument("--check-dt", type=float, default=2.5e-4)
    ap.add_argument("--cases", default="four-bar,quick-return")
    ap.add_argument("--integrators", default=",".join(i[0] for i in INTEGRATORS))
    a = ap.parse_args()
    binary = os.path.abspath(a.monohydra)
    out = a.out or tempfile.mkdtemp(prefix="mh-integrator-study-")
    os.makedirs(out, exist_ok=True)
    dts = [float(x) for x in a.dts.split(",")]
    want_cases = a.cases.split(",")
    want_int = a.integrators.split(",")
    t_start = time.time()
    c_start = resource.getrusage(resource.RUSAGE_CHILDREN)

    print("# Integrator study (generated by studies/integrator_study.py)\n")
    print("Command per run: `monohydra compare MODEL --formulations F --integrators I --dt S --report DIR`"
          " (one run per process). Load average at start: %s.\n" % " ".join("%.2f" % x for x in os.getloadavg()))

    for cname, mfile, zind in CASES:
        if cname not in want_cases:
            continue
        mpath = os.path.join(MODELS, mfile)
        tcs = closings(mpath)
        refs = {}
        print("## %s (%s; independent coordinate %s; valve closes at %s s)\n" %
              (cname, mfile, zind, ", ".join("%g" % t for t in tcs)))
        # reference and its convergence check
        print("### Reference: trapezoidal at dt = %g ms, checked against dt = %g ms\n" % (a.ref_dt * 1e3, a.check_dt * 1e3))
        print("| formulation | ref status | ref wall (s) | max dz %s (rad) | max dz all (rad) | max dp1 (Pa) | max dp2 (Pa) | Richardson error estimate of the reference z / p1 / p2 |" % zind)
        print("|---|---|---|---|---|---|---|---|")
        for f in FORMULATIONS:
            res = {}
            for dt in (a.ref_dt, a.check_dt):
                d = os.path.join(out, cname, "ref", f, "%g" % dt)
                os.makedirs(d, exist_ok=True)
                log("%s ref %s dt=%g" % (cname, f, dt))
                r = run_compare(binary, mpath, f, "trapezoidal", dt, d)
                res[dt] = (r, read_csv(r["csv"]))
            ref = res[a.ref_dt][1]
            refs[f] = ref
            e = errors(res[a.check_dt][1], ref, zind)
            # second order: err(ref) ~ diff * h_ref^2 / (h_chk^2 - h_ref^2)
            q = a.ref_dt ** 2 / (a.check_dt ** 2 - a.ref_dt ** 2)
            print("| %s | %s | %.2f | %s | %s | %s | %s | %s / %s / %s |" % (
                f, res[a.ref_dt][0]["status"], summary(ref)["wall"], g(e["zind"]), g(e["zall"]),
                g(e["p1"]), g(e["p2"]), g(q * e["zall"]), g(q * e["p1"]), g(q * e["p2"])))
        ed = errors(refs["penalty"], refs["double-step"], zind)
        print("\nThe two references (double-step against penalty): %s rad (all z), %s Pa (p1), %s Pa (p2).\n" %
              (g(ed["zall"]), g(ed["p1"]), g(ed["p2"])))
        fr = ["%.1f Hz after %g s" % (freq_estimate(refs["double-step"], tc), tc) for tc in tcs]
        print("Ringing frequency of p1 in the reference (zero crossings of p1 minus a quadratic trend, 0.5 s after the closing): %s.\n" % "; ".join(fr))
        rr = ringing(refs["double-step"], refs["double-step"], tcs)
        print("Reference's own p1 ringing (peak-to-peak about the local linear trend) in (tc, tc+0.1] and (tc+0.3, tc+0.4], ratio: %s.\n" %
              "; ".join("%g s: %s, %s Pa, %.3f" % (x["tc"], g(x["first"]), g(x["later"]), x["ratio"]) for x in rr))

        # the runs
        print("### Runs (errors against the same formulation's reference)\n")
        print("Errors: max over t = 0, 5, 10, ... ms. Ringing error: peak-to-peak of p1 - p1_ref over (tc, tc+0.1 s] at each closing tc. "
              "Ringing decay: the run's own p1 ringing (peak-to-peak about its linear trend) in (tc+0.3, tc+0.4] over that in (tc, tc+0.1] (reference above). "
              "Time: median of the runs' total wall time as compare reports it (sum of wall_s), n = runs; proc CPU: median CPU time of the whole process.\n")
        print("| formulation | integrator | dt (ms) | err %s (rad) | err z all (rad) | err p1 (Pa) | err p2 (Pa) | ringing error p1-p1ref p2p (Pa) | ringing decay ratio | peak abs drift (J) | iters avg / max | wall (s) | proc CPU (s) | status |" % zind)
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for f in FORMULATIONS:
            for ilabel, iid, rho in INTEGRATORS:
                if ilabel not in want_int:
                    continue
                model = model_variant(mpath, rho, out)
                for dt in dts:
                    walls, cpus, statuses, last = [], [], [], None
                    for k in range(a.repeats):
                        d = os.path.join(out, cname, f, ilabel.replace(" ", "-"), "%g" % dt, str(k))
                        os.makedirs(d, exist_ok=True)
                        log("%s %s %s dt=%g #%d (load %.2f)" % (cname, f, ilabel, dt, k, os.getloadavg()[0]))
                        r = run_compare(binary, model, f, iid, dt, d)
                        cols = read_csv(r["csv"])
                        walls.append(summary(cols)["wall"])
                        cpus.append(r["proc_cpu"])
                        statuses.append(r["status"])
                        last = (r, cols)
                    r, cols = last
                    s = summary(cols)
                    e = errors(cols, refs[f], zind)
                    rg = ringing(cols, refs[f], tcs)
                    status = r["status"] if r["status"] == "ok" else "**%s**: %s" % (r["status"], r["reason"])
                    if len(set(statuses)) > 1:
                        status += " (repeats: %s)" % ", ".join(statuses)
                    elif r["status"] != "ok":
                        status += " (all %d repeats); errors, drift, iterations and time up to t = %g s" % (len(statuses), s["t_last"])
                    print("| %s | %s | %g | %s | %s | %s | %s | %s | %s | %s | %.2f / %d | %.3f (n=%d) | %.3f | %s |" % (
                        f, ilabel, dt * 1e3, g(e["zind"]), g(e["zall"]), g(e["p1"]), g(e["p2"]),
                        " / ".join(g(x["d_full"]) for x in rg),
                        " / ".join(g(x["ratio"], "%.3f") for x in rg),
                        g(s["drift"]), s["it_avg"], s["it_max"], statistics.median(walls), len(walls),
                        statistics.median(cpus), status))
                    sys.stdout.flush()
        print()
    c_end = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (c_end.ru_utime - c_start.ru_utime) + (c_end.ru_stime - c_start.ru_stime)
    me = resource.getrusage(resource.RUSAGE_SELF)
    print("Study: %.0f s wall, %.0f s CPU of the monohydra processes, %.0f s CPU of this script; load average at the end: %s. Outputs in %s.\n" % (
        time.time() - t_start, cpu, me.ru_utime + me.ru_stime, " ".join("%.2f" % x for x in os.getloadavg()), out))


if __name__ == "__main__":
    main()
