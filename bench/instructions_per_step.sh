#!/bin/sh
# Instructions per time step of a case study, from callgrind: the difference
# of two runs (T1 and T2 simulated seconds at dt = 1 ms) divided by the steps
# between them, so that loading, parsing and start-up cancel out.
# NEWTON is mh_profile's: per-step (what the default, auto, runs on the case
# studies), full (the paper's) or modified, or auto, articulated. EXTRA is
# mh_profile's last argument, when given: sens:K (forward sensitivities) or
# filter:ekf, filter:ukf (the model as a Kalman filter on its sensors).
#   bench/instructions_per_step.sh PROFILE_BINARY MODEL FORMULATION NEWTON [T1 T2 [EXTRA]]
# e.g. bench/instructions_per_step.sh build/bin/mh_profile fourbar.yaml penalty per-step
#      bench/instructions_per_step.sh build/bin/mh_profile excavator.yaml double-step per-step 0.5 1.5 filter:ekf
set -eu
bin=$(realpath "$1"); model=$2; formulation=$3; newton=$4
t1=${5:-0.5}; t2=${6:-1.5}; extra=${7:-}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$(dirname "$0")/../models"
total() {
  valgrind --tool=callgrind --callgrind-out-file="$dir/out.$1" "$bin" "$model" "$formulation" \
    "$1" none "$newton" $extra >/dev/null 2>&1
  sed -n 's/^summary: *//p' "$dir/out.$1"
}
i1=$(total "$t1"); i2=$(total "$t2")
echo "$model $formulation $newton${extra:+ $extra}: $(( (i2 - i1) / $(echo "($t2 - $t1) * 1000 / 1" | bc) )) instructions per step"
