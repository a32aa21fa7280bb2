#!/usr/bin/env bash
# The sweep's speed-up over one worker (docs/sweeps.md "Speed-up"): runs
# studies/speedup.yaml with --jobs 1, with every core (--jobs $(nproc)), and
# under mpirun with 1, 2 and 3 worker ranks (-np 2, 3, 4: rank 0 only hands
# out the cases), REPEATS times each, interleaved, and prints a Markdown table
# of the median wall time and the speed-up. Checks that every table equals
# --jobs 1's apart from the timing columns.
#   usage: studies/speedup.sh BUILD/bin/monohydra [REPEATS]
set -euo pipefail
bin=$(realpath "$1")
repeats=${2:-3}
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
study=$here/speedup.yaml
mpi="mpirun --allow-run-as-root --oversubscribe"
modes=("jobs-1" "jobs-$(nproc)" "mpi-1" "mpi-2" "mpi-3")

run_mode() {  # run_mode MODE DIR
  case $1 in
    jobs-*) "$bin" sweep "$study" --out "$2" --jobs "${1#jobs-}" ;;
    mpi-*) $mpi -np $(( ${1#mpi-} + 1 )) "$bin" sweep "$study" --out "$2" ;;
  esac
}

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for r in $(seq "$repeats"); do
  for m in "${modes[@]}"; do
    dir=$out/$m-$r
    t0=$(date +%s%N)
    run_mode "$m" "$dir" >/dev/null 2>&1
    ms=$(( ($(date +%s%N) - t0) / 1000000 ))
    echo "$m $ms" >>"$out/times"
    echo "$m repeat $r: $ms ms" >&2
  done
done

load_after=$(cut -d' ' -f1-3 /proc/loadavg)

python3 - "$out" "$repeats" "$load_before" "$load_after" "${modes[@]}" <<'PY'
import csv, statistics, sys
out, repeats, load_before, load_after = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
modes = sys.argv[5:]
def table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    keep = [i for i, n in enumerate(rows[0]) if n not in ("cpu_s", "wall_s")]
    return [[r[i] for i in keep] for r in rows], [float(r[rows[0].index("cpu_s")]) for r in rows[1:]]
base, _ = table(f"{out}/jobs-1-1/results.csv")
times = {}
for line in open(f"{out}/times"):
    m, t = line.split()
    times.setdefault(m, []).append(float(t) / 1000.0)
cpu = {}
for m in modes:
    for r in range(1, repeats + 1):
        t, c = table(f"{out}/{m}-{r}/results.csv")
        if t != base:
            sys.exit(f"{m} repeat {r}: the table differs from --jobs 1's")
        cpu.setdefault(m, []).append(sum(c))
one = statistics.median(times["jobs-1"])
print("| run | workers | wall time, median of %d (s) | speed-up over --jobs 1 | CPU time of the cases, median (s) |" % repeats)
print("|---|---|---|---|---|")
for m in modes:
    w = statistics.median(times[m])
    kind, n = m.split("-")
    label = f"--jobs {n}" if kind == "jobs" else f"mpirun -np {int(n) + 1}"
    print(f"| `{label}` | {n} | {w:.2f} | {one / w:.2f} | {statistics.median(cpu[m]):.2f} |")
print(f"\n{len(base) - 1} cases; every table equal to --jobs 1's apart from cpu_s and wall_s. "
      f"Load average (1, 5, 15 min) before: {load_before}, after: {load_after}.")
PY
