#!/usr/bin/env bash
# Is the water's gradient chain sound? (issue 45, "why the water is under-recovered", its
# cheapest decisive test.) On one scene, per seed:
#   oracle  --known-water: the true surface fixed, the Gaussians learn (a fit that is right);
#   fixed   the water learned from the flat start against the oracle's Gaussians held fixed
#           (--gaussians-from ORACLE/point_cloud.ply --gaussians-fixed);
#   method  the method as a user runs it (the same steps, the defaults).
# bench/surface-error.py gives each learned water's amplitude ratio a (1: the waves' full
# height). fixed reaching a >= 0.9 clears the surface's chain (the images pull the water to
# its height when the Gaussians do not absorb the warp); fixed near the method's a ~ 0.5
# points inside the chain (the gradient, the mesh, the schedule).
#
# Usage: bench/water-chain.sh [--seeds "1 2 3"] [--steps N] [--width PX] [--preset NAME] [--out DIR]
# Writes DIR/runs.csv (refrax report rows), DIR/amplitude.csv (run, seed, a, rms and parts)
# and DIR/summary.md. Default: nerfrac-primary-sine at 128 px, 2,000 whole-image steps, SH 0.
set -euo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-build/refrax}
seeds="1 2 3"
steps=2000
width=128
preset=nerfrac-primary-sine
out=bench/results/water-chain
while [ $# -gt 0 ]; do
  case $1 in
    --seeds) seeds=$2; shift ;;
    --steps) steps=$2; shift ;;
    --width) width=$2; shift ;;
    --preset) preset=$2; shift ;;
    --out) out=$2; shift ;;
    *) echo "water-chain.sh: unknown option $1 (see the header)" >&2; exit 2 ;;
  esac
  shift
done
[ -x "$REFRAX" ] || { echo "water-chain.sh: no $REFRAX (build first)" >&2; exit 2; }
export MESA_SHADER_CACHE_DIR=${MESA_SHADER_CACHE_DIR:-$PWD/.cache/mesa-shader-cache}
work=$out/work
mkdir -p "$work"
data=$work/data
[ -f "$data/water.json" ] || "$REFRAX" synth "$preset" --size full --width "$width" -o "$data" > /dev/null
common=(--recipe reference --steps "$steps" --sh-degree 0 --density-reset-every 0 --checkpoint-every 0 --progress-every 500)
echo "run,seed,amplitude_ratio,rms_error_m,detail" > "$out/amplitude.csv"
runs=()
for seed in $seeds; do
  oracle=$work/oracle-$seed fixed=$work/fixed-$seed method=$work/method-$seed
  [ -f "$oracle/metrics.json" ] || { rm -rf "$oracle"; "$REFRAX" train "$data" -o "$oracle" --known-water --seed "$seed" "${common[@]}" > "$oracle.log" 2>&1; }
  [ -f "$fixed/metrics.json" ] || { rm -rf "$fixed"; "$REFRAX" train "$data" -o "$fixed" --seed "$seed" "${common[@]}" \
      --gaussians-from "$oracle/point_cloud.ply" --gaussians-fixed > "$fixed.log" 2>&1; }
  [ -f "$method/metrics.json" ] || { rm -rf "$method"; "$REFRAX" train "$data" -o "$method" --seed "$seed" "${common[@]}" > "$method.log" 2>&1; }
  for kind in fixed method; do
    run=$work/$kind-$seed
    line=$(python3 bench/surface-error.py "$run" "$data" | tr '\n' ' ')
    a=$(sed -n 's/.*amplitude ratio \([-0-9.]*\).*/\1/p' <<< "$line")
    err=$(sed -n 's/.*RMS error \([-0-9.]*\) m.*/\1/p' <<< "$line")
    echo "$kind,$seed,$a,$err,\"${line//\"/}\"" >> "$out/amplitude.csv"
  done
  runs+=("$oracle" "$fixed" "$method")
  echo "water-chain: seed $seed done"
done
"$REFRAX" report "${runs[@]}" -o "$out/runs.csv" > /dev/null
echo "water-chain: $out/runs.csv, $out/amplitude.csv"
