#!/usr/bin/env bash
# The example formulation lagrange-baumgarte (examples/lagrange-baumgarte)
# beside double-step and penalty on both case studies: the rows of
# `monohydra compare` that docs/results.md quotes (drift, constraint
# violation, distance from double-step, Newton iterations), at the paper's
# dt = 1 ms and at 5 ms, with its stabilization off (alpha = beta = 0), and
# on the free four-bar at 10 ms.
# Usage: studies/lagrange_baumgarte.sh MONOHYDRA LB_PLUGIN_DIR
#   e.g. studies/lagrange_baumgarte.sh /tmp/mh-prefix/bin/monohydra build/examples/lagrange-baumgarte
set -euo pipefail
cd "$(dirname "$0")/.."
mh=$1
export MONOHYDRA_PLUGIN_PATH=$(realpath "$2")
rows='^(quantity|status|Newton iterations avg|peak \|drift\| \(J\)|max phi_norm|max \|dz\|)'
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for model in fourbar quickreturn; do
  for dt in 0.001 0.005; do
    echo "== $model, dt = $dt s"
    "$mh" compare "models/$model.yaml" --formulations double-step,penalty,lagrange-baumgarte \
      --dt "$dt" | grep -E "$rows"
  done
  # Stabilization off: the model's own formulation, with its options.
  sed -E 's/^formulation: .*/formulation: {name: lagrange-baumgarte, alpha: 0, beta: 0}/' \
    "models/$model.yaml" > "$tmp/$model-index1.yaml"
  echo "== $model, dt = 0.001 s, alpha = beta = 0 (plain index-1 multipliers)"
  "$mh" compare "$tmp/$model-index1.yaml" --formulations lagrange-baumgarte | grep -E "$rows"
done
# The free four-bar (no hydraulics: it falls under gravity) at dt = 10 ms,
# where the constraint drift is large enough to see what Baumgarte buys.
for options in "" ", alpha: 0, beta: 0"; do
  sed -E "s/^formulation: .*/formulation: {name: lagrange-baumgarte$options}/" \
    models/fourbar-free.yaml > "$tmp/fourbar-free.yaml"
  echo "== fourbar-free, dt = 0.01 s, lagrange-baumgarte$options"
  "$mh" compare "$tmp/fourbar-free.yaml" --formulations double-step,penalty,lagrange-baumgarte \
    --dt 0.01 | grep -E "$rows"
done
