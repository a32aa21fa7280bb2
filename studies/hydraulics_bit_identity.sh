#!/bin/sh
# Are today's models bit-for-bit what they were before a change to the
# hydraulics plugin? Builds the plugin of a base commit alone (its own
# plugins/components/hydraulics, plugins/hydraulics before the folders by
# concept, and sdk headers; a base of the same ABI major), runs every case study with both
# formulations once with it (MONOHYDRA_PLUGIN_PATH puts it first, so the
# build's own library is refused) and once with the build's, and compares the
# CSVs byte for byte.
#
# usage: sh studies/hydraulics_bit_identity.sh BUILD_DIR [BASE_COMMIT]
#        (BASE_COMMIT defaults to the merge base with main)
set -eu
build=$(cd "$1" && pwd)
base=${2:-$(git merge-base HEAD main)}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/src" "$work/plugin"
dir=plugins/components/hydraulics
git cat-file -e "$base:$dir" 2>/dev/null || dir=plugins/hydraulics
git archive "$base" "$dir" sdk | tar -x -C "$work/src"
c++ -shared -std=c++17 -O3 -DNDEBUG -fPIC -fvisibility=hidden -fvisibility-inlines-hidden \
  -I"$work/src/sdk/include" "$work/src/$dir"/*.cpp \
  -o "$work/plugin/monohydra-hydraulics.so"
# The base library must be the one loaded, or the comparison proves nothing.
MONOHYDRA_PLUGIN_PATH="$work/plugin" "$build/bin/monohydra" plugins 2>&1 |
  grep -q "^$work/plugin/monohydra-hydraulics.so" ||
  { echo "the base plugin was not loaded first" >&2; exit 2; }
status=0
for model in fourbar quickreturn; do
  for formulation in double-step penalty; do
    MONOHYDRA_PLUGIN_PATH="$work/plugin" "$build/bin/monohydra" run "models/$model.yaml" \
      --formulation "$formulation" --out "$work/base.csv" >/dev/null
    "$build/bin/monohydra" run "models/$model.yaml" --formulation "$formulation" \
      --out "$work/new.csv" >/dev/null
    if cmp -s "$work/base.csv" "$work/new.csv"; then
      echo "$model $formulation: identical ($(wc -l <"$work/new.csv") lines) to $base"
    else
      echo "$model $formulation: DIFFERS from $base"
      status=1
    fi
  done
done
exit $status
