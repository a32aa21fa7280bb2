#!/bin/sh
# Instructions per time step of a run stepped through the embedding API
# against the command line's own loop, both from callgrind, each the
# difference of a 1 s and a 2 s run divided by the 1000 steps between them
# (every forked process counted), rows every ROW_EVERY steps written as text:
#   bench/embedded_instructions_per_step.sh BUILD_DIR MODEL FORMULATION [ROW_EVERY]
# e.g. bench/embedded_instructions_per_step.sh build fourbar.yaml double-step 10
set -eu
build=$(realpath "$1"); model=$(realpath "$(dirname "$0")/../models/$2"); formulation=$3
every=${4:-10}
interval=$(echo "$every / 1000" | bc -l)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
count() {  # count NAME COMMAND...: instructions of every process
  name=$1
  shift
  valgrind --tool=callgrind --trace-children=yes --callgrind-out-file="$dir/$name.%p" "$@" \
    >/dev/null 2>&1
  cat "$dir/$name".* | sed -n 's/^summary: *//p' | awk '{s += $1} END {print s}'
}
cli() { count "cli$1" "$build/bin/monohydra" run "$model" --formulation "$formulation" \
  --t-end "$1" --output-interval "$interval" --out /dev/null; }
api() { count "api$1" "$build/bin/mh_embedded_run" "$model" "$formulation" "$1" "$every"; }
c1=$(cli 1); c2=$(cli 2); a1=$(api 1); a2=$(api 2)
c=$(( (c2 - c1) / 1000 )); a=$(( (a2 - a1) / 1000 ))
echo "$2 $formulation: command line $c, embedding API $a instructions per step ($(echo "scale=2; 100 * ($a - $c) / $c" | bc) %)"
