#!/bin/sh
# Whether two builds give the same results: runs the case studies with both
# monohydra binaries and compares the CSVs byte for byte (all columns,
# 17 significant digits as the CLI writes them).
#   bench/compare_outputs.sh /work/main/build/bin/monohydra build/bin/monohydra [T_END]
set -u
before=$(realpath "$1"); after=$(realpath "$2"); t_end=${3:-10}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$(dirname "$0")/../models"
status=0
for model in fourbar quickreturn; do
  for formulation in penalty double-step; do
    "$before" run "$model.yaml" --formulation "$formulation" --t-end "$t_end" \
      --out "$dir/before.csv" >/dev/null 2>&1
    "$after" run "$model.yaml" --formulation "$formulation" --t-end "$t_end" \
      --out "$dir/after.csv" >/dev/null 2>&1
    if cmp -s "$dir/before.csv" "$dir/after.csv"; then
      echo "$model $formulation: identical"
    else
      echo "$model $formulation: DIFFERENT"
      status=1
    fi
  done
done
exit $status
