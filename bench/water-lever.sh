#!/usr/bin/env bash
# One lever on the water (issue 45, "a method that holds"), against bench/water-chain.sh's
# method rows: the method with extra flags on the same scene and budget, per seed, and the
# learned water's amplitude ratio a (bench/surface-error.py; 1: the waves' full height) beside
# the run's own plane-sweep check (surface_sweep_ratio: the views' colour variance through the
# learned water over the flat water's; under 1 reads "better than flat").
#
# Usage: bench/water-lever.sh --name NAME --flags "FLAGS" [--seeds "1 2 3"] [--steps N] [--width PX]
#                             [--preset NAME] [--out DIR]
# Writes DIR/NAME/runs.csv (refrax report rows) and DIR/NAME/amplitude.csv (seed, a, RMS error,
# its parts, the sweep ratio). Defaults as water-chain.sh: nerfrac-primary-sine at 128 px,
# 2,000 whole-image steps, SH 0, no density resets; DIR bench/results/water-lever.
set -euo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-build/refrax}
seeds="1 2 3"
steps=2000
width=128
preset=nerfrac-primary-sine
out=bench/results/water-lever
name=""
flags=""
while [ $# -gt 0 ]; do
  case $1 in
    --name) name=$2; shift ;;
    --flags) flags=$2; shift ;;
    --seeds) seeds=$2; shift ;;
    --steps) steps=$2; shift ;;
    --width) width=$2; shift ;;
    --preset) preset=$2; shift ;;
    --out) out=$2; shift ;;
    *) echo "water-lever.sh: unknown option $1 (see the header)" >&2; exit 2 ;;
  esac
  shift
done
[ -n "$name" ] || { echo "water-lever.sh: --name NAME is required" >&2; exit 2; }
[ -x "$REFRAX" ] || { echo "water-lever.sh: no $REFRAX (build first, or set REFRAX)" >&2; exit 2; }
export MESA_SHADER_CACHE_DIR=${MESA_SHADER_CACHE_DIR:-$PWD/.cache/mesa-shader-cache}
work=$out/work
mkdir -p "$work" "$out/$name"
data=$work/data-$preset-$width
[ -f "$data/water.json" ] || "$REFRAX" synth "$preset" --size full --width "$width" -o "$data" > /dev/null
common=(--recipe reference --steps "$steps" --sh-degree 0 --density-reset-every 0 --checkpoint-every 0 --progress-every 500)
echo "seed,amplitude_ratio,rms_error_m,surface_sweep_ratio,detail" > "$out/$name/amplitude.csv"
runs=()
for seed in $seeds; do
  run=$work/$name-$seed
  # shellcheck disable=SC2086  # the flags are words
  [ -f "$run/metrics.json" ] || { rm -rf "$run"; "$REFRAX" train "$data" -o "$run" --seed "$seed" "${common[@]}" $flags > "$run.log" 2>&1; }
  line=$(python3 bench/surface-error.py "$run" "$data" | tr '\n' ' ')
  a=$(sed -n 's/.*amplitude ratio \([-0-9.]*\).*/\1/p' <<< "$line")
  err=$(sed -n 's/.*RMS error \([-0-9.]*\) m.*/\1/p' <<< "$line")
  sweep=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1])).get("surface_sweep_ratio", ""))' "$run/metrics.json")
  echo "$seed,$a,$err,$sweep,\"${line//\"/}\"" >> "$out/$name/amplitude.csv"
  runs+=("$run")
  echo "water-lever: $name seed $seed: a $a, RMS error $err m, sweep ratio $sweep"
done
"$REFRAX" report "${runs[@]}" -o "$out/$name/runs.csv" > /dev/null
echo "$flags" > "$out/$name/flags.txt"
echo "water-lever: $out/$name/runs.csv, $out/$name/amplitude.csv"
