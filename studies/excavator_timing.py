#!/usr/bin/env python3
"""How long the excavator's 22 s digging cycle (models/excavator.yaml) takes per
formulation and integrator: CPU time of the process, real-time factor on CPU
time, Newton iterations per step (mean and max), and the run's status.

usage: python3 studies/excavator_timing.py BUILD/bin/monohydra [--repeats N]
       [--formulations double-step,penalty]
       [--integrators trapezoidal,generalized-alpha,bdf2]

Runs `monohydra run models/excavator.yaml --formulation F --integrator I --out
CSV` once per process and repeat (so the child's CPU time, user + system from
getrusage, is that run's plus loading the plugins and writing the CSV), keeps
the smallest CPU time of the repeats (the machine is shared: CPU time, not
wall time, and the minimum, which other processes inflate least) and prints a
Markdown table on stdout. Python 3 standard library only.
"""
import argparse
import csv
import os
import resource
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
MODEL = os.path.join(os.path.dirname(HERE), "models", "excavator.yaml")


def run_once(exe, formulation, integrator, out):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([exe, "run", MODEL, "--formulation", formulation, "--integrator",
                           integrator, "--out", out], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return proc.returncode, cpu, proc.stdout + proc.stderr


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--formulations", default="double-step,penalty")
    ap.add_argument("--integrators", default="trapezoidal,generalized-alpha,bdf2")
    args = ap.parse_args()
    print("| formulation | integrator | status | steps | simulated (s) | CPU time (s) | "
          "real-time factor (CPU) | Newton iterations avg / max | max phi_norm | "
          "max abs(drift) / max abs(W) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for f in args.formulations.split(","):
            for i in args.integrators.split(","):
                out = os.path.join(tmp, f"{f}+{i}.csv")
                cpus, code, log = [], 0, ""
                for _ in range(args.repeats):
                    code, cpu, log = run_once(args.exe, f, i, out)
                    cpus.append(cpu)
                    print(f"{f} + {i}: {cpu:.2f} s CPU, exit {code}", file=sys.stderr)
                rows = list(csv.DictReader(open(out))) if os.path.exists(out) else []
                steps = len(rows) - 1
                t = float(rows[-1]["t"]) if rows else 0.0
                iters = [int(r["iters"]) for r in rows[1:]]
                phi = max((float(r["phi_norm"]) for r in rows), default=0.0)
                work = max((abs(float(r["W"])) for r in rows), default=0.0)
                drift = max((abs(float(r["drift"])) for r in rows), default=0.0)
                status = "ok" if code == 0 else "FAILED at t = %.3f s" % t
                cpu = min(cpus)
                print(f"| {f} | {i} | {status} | {steps} | {t:g} | {cpu:.2f} | {t / cpu:.2f} | "
                      f"{sum(iters) / max(len(iters), 1):.3f} / {max(iters, default=0)} | "
                      f"{phi:.1e} | {drift / work if work else 0.0:.1e} |")
                sys.stdout.flush()


if __name__ == "__main__":
    main()
