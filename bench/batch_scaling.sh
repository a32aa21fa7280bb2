#!/usr/bin/env bash
# A batch's speed-up over one thread and the memory a run adds
# (docs/batches.md "Measured"): 256 four-bars (valve flow coefficient, load
# mass, bulk modulus within +-20 %) and 32 load-sensing excavators (bucket and
# arm mass, the arm cylinder's bulk modulus) stepped over 10 s on 1 and on
# 2 threads, REPEATS times each, interleaved; beside them the machine's own
# ceiling, two independent one-thread processes of half the four-bars each
# at once against one process of them all (each its stepping time, the
# slower of the two). Prints a Markdown table: the medians of the times and
# of each repeat's own speed-up (the machine's speed drifts between
# repeats; a 1-thread run and the 2-thread one right after it share it).
# Memory: resident size after the first step of a batch of 1 and of a batch
# of N runs, (N-run - 1-run) / (N - 1).
#   usage: bench/batch_scaling.sh BUILD/bin/mh_batch_run [REPEATS]
set -euo pipefail
bin=$(realpath "$1")
repeats=${2:-3}
root=$(cd "$(dirname "$0")/.." && pwd)
fourbar=$root/models/fourbar.yaml
excavator=$root/models/excavator-ls.yaml
fourbar_params=(subsystems/valve/flow_coefficient=1.7104e-8:2.5656e-8 bodies/body3/mass=40:60
                subsystems/cylinder/fluid_bulk_modulus=1.2e9:1.8e9)
excavator_params=(bodies/bucket/mass=2040:3060 bodies/arm/mass=760:1140
                  subsystems/arm_cyl/fluid_bulk_modulus=1.2e9:1.8e9)

seconds() {  # seconds LINE: the stepping time mh_batch_run printed
  sed -n 's/.*: \([0-9.]*\) s stepping.*/\1/p' <<<"$1"
}
resident() {  # resident OUTPUT: MB after the first step
  sed -n 's/.*MB opened, \([0-9.]*\) MB after the first step/\1/p' <<<"$1"
}

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for r in $(seq "$repeats"); do
  for threads in 1 2; do
    echo "fourbar-$threads $r $(seconds "$("$bin" "$fourbar" 256 $threads 10 "${fourbar_params[@]}")")" >>"$out/times"
  done
  # Two processes at once, 128 four-bars each on 1 thread: the slower one's
  # stepping time, the same measure as the batch's.
  "$bin" "$fourbar" 128 1 10 "${fourbar_params[@]}" >"$out/p1" &
  "$bin" "$fourbar" 128 1 10 "${fourbar_params[@]}" >"$out/p2"
  wait
  a=$(seconds "$(cat "$out/p1")"); b=$(seconds "$(cat "$out/p2")")
  echo "processes-2 $r $(python3 -c "print(max($a, $b))")" >>"$out/times"
  for threads in 1 2; do
    echo "excavator-$threads $r $(seconds "$("$bin" "$excavator" 32 $threads 10 "${excavator_params[@]}")")" >>"$out/times"
  done
  echo "repeat $r done" >&2
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
f1=$(resident "$("$bin" "$fourbar" 1 1 0.001)")
f256=$(resident "$("$bin" "$fourbar" 256 1 0.001 "${fourbar_params[@]}")")
e1=$(resident "$("$bin" "$excavator" 1 1 0.001)")
e32=$(resident "$("$bin" "$excavator" 32 1 0.001 "${excavator_params[@]}")")

python3 - "$out/times" "$repeats" "$load_before" "$load_after" "$f1" "$f256" "$e1" "$e32" <<'PY'
import statistics, sys
path, repeats, before, after = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
f1, f256, e1, e32 = map(float, sys.argv[5:9])
times = {}
for line in open(path):
    name, r, value = line.split()
    times.setdefault(name, {})[int(r)] = float(value)
med = {k: statistics.median(v.values()) for k, v in times.items()}
# Speed-ups repeat by repeat (each 1-thread time against the 2-thread time
# measured right after it): the machine's speed drifts between repeats.
def ratios(one, two):
    return sorted(times[one][r] / times[two][r] for r in times[one])
def row(label, one, two):
    q = ratios(one, two)
    return (f"| {label} | {med[one]:.2f} | {med[two]:.2f} | {statistics.median(q):.2f} "
            f"({q[0]:.2f}-{q[-1]:.2f}) |")
print(f"{repeats} repeats, interleaved; stepping time (s, median; opening excluded); "
      f"speed-up: the median of the repeats' own ratios (their range). "
      f"Load average before: {before}, after: {after}.\n")
print("| batch | 1 thread (s) | 2 threads (s) | speed-up |")
print("|---|---|---|---|")
print(row("256 four-bars, 10 s", "fourbar-1", "fourbar-2"))
print(row("the machine's ceiling: 2 processes x 128 four-bars, 1 thread each (the slower's stepping)",
          "fourbar-1", "processes-2"))
print(row("32 excavators (load sensing), 10 s", "excavator-1", "excavator-2"))
share = ratios("processes-2", "fourbar-2")
print(f"\nThe four-bar batch on 2 threads against the two processes of the same repeat: "
      f"{statistics.median(share):.2f} of their speed ({share[0]:.2f}-{share[-1]:.2f}).")
print()
print(f"Memory a run adds (resident after the first step): four-bar "
      f"{(f256 - f1) / 255 * 1000:.0f} kB ({f1:.1f} MB for 1 run, {f256:.1f} MB for 256); "
      f"excavator {(e32 - e1) / 31 * 1000:.0f} kB ({e1:.1f} MB for 1 run, {e32:.1f} MB for 32).")
PY
