#!/bin/sh
# The case studies' CPU times of two builds, one after the other on the same
# machine state: BENCH_BEFORE and BENCH_AFTER are mh_bench binaries.
#   bench/case_studies_before_after.sh /work/main/build/bin/mh_bench build/bin/mh_bench
set -eu
filter='case/(fourbar|quickreturn)/(double-step|penalty)/trapezoidal/klu'
for bin in "$1" "$2"; do
  echo "== $bin"
  "$bin" --benchmark_filter="$filter" --benchmark_repetitions=3 \
    --benchmark_report_aggregates_only=true 2>/dev/null | grep -E "_median"
done
