#!/usr/bin/env bash
# How flat is the valley between the flat start and the true water? (issue 45, Build 2)
# The known-water oracle with the true relief scaled about its level (`--known-water-scale S`:
# 0 is flat water at the true level, 1 the truth), on the same data, two ways:
#   sweep  the views' plane-sweep agreement through the scaled water against flat water (the
#          run's surface_sweep_ratio; below 1: the views agree better than through flat water).
#          It does not pass through the Gaussians, so a 2-step run measures it.
#   train  the Gaussians trained through the scaled water at refrax train's defaults (or
#          --steps N), seeds as given: the test PSNR and the water-removal PSNR. If the Gaussians
#          absorb the warp of a wrong water, the half-height water's PSNR comes near the truth's.
# Scenes: `--scene NAME=SYNTH-ARGS`, repeated; each is made by `refrax synth SYNTH-ARGS`
# (for example `--scene nps=nerfrac-primary-sine --size full`, `--scene dev7=random --seed 7`).
#
# Usage: bench/water-valley.sh --scene NAME=ARGS [--scene ...] [--sweep-scales "0 0.5 1 ..."]
#                              [--train-scales "0 0.5 1"] [--seeds "1 2 3"] [--steps N]
#                              [--train-flags "FLAGS"] [--out DIR] [--summary-only]
# Writes DIR (default bench/results/water-valley/): rows.csv (scene, kind, scale, seed, steps,
# psnr, water-removal PSNR, surface RMSE, sweep ratio, seconds), summary.md (medians over the
# seeds, spread max - min), run_info.txt; the datasets and runs in DIR/work/ (removed after).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
REFRAX=${REFRAX:-$root/build/refrax}
out=$root/bench/results/water-valley
scenes=()
sweep_scales="0 0.25 0.5 0.75 1 1.25 1.5 2"
train_scales="0 0.5 1"
seeds="1 2 3"
steps=""
train_flags=""
summary_only=0
while [ $# -gt 0 ]; do
  case $1 in
    --scene) [ $# -ge 2 ] || { echo "water-valley: --scene needs NAME=SYNTH-ARGS" >&2; exit 2; }; scenes+=("$2"); shift ;;
    --sweep-scales) sweep_scales=$2; shift ;;
    --train-scales) train_scales=$2; shift ;;
    --seeds) seeds=$2; shift ;;
    --steps) steps=$2; shift ;;
    --train-flags) train_flags=$2; shift ;;
    --out) out=$2; shift ;;
    --summary-only) summary_only=1 ;;
    -h|--help) sed -n '2,/^set -/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "water-valley: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
mkdir -p "$out"
rows=$out/rows.csv

summarise() {
  python3 - "$rows" >"$out/summary.md" <<'PY'
import csv, statistics, sys
from collections import defaultdict
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["exit"] == "0"]
print("# The valley between flat water and the truth (bench/water-valley.sh)\n")
print("The known-water oracle with the true relief scaled by S about its level (0: flat at the true level).\n")
print("## The views' agreement through the scaled water (plane sweep; below 1: better than flat; no Gaussians)\n")
sweep = defaultdict(dict)
for r in rows:
    if r["kind"] == "sweep": sweep[r["scene"]][float(r["scale"])] = float(r["sweep_ratio"])
scales = sorted({s for d in sweep.values() for s in d})
if scales:
    print("| scene | " + " | ".join("S = %g" % s for s in scales) + " |")
    print("| --- |" + " --- |" * len(scales))
    for sc, d in sweep.items():
        print("| %s | " % sc + " | ".join("%.3f" % d[s] if s in d else "" for s in scales) + " |")
print("\n## The Gaussians trained through the scaled water (median over the seeds, spread max - min)\n")
train = defaultdict(list)
for r in rows:
    if r["kind"] == "train": train[(r["scene"], float(r["scale"]))].append(r)
def cell(rs, k):
    v = [float(r[k]) for r in rs if r[k] not in ("", "nan")]
    return "%.2f (%.2f)" % (statistics.median(v), max(v) - min(v)) if v else ""
if train:
    print("| scene | S | seeds | test PSNR (dB) | water removed (dB) | surface RMSE (m) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for (sc, s), rs in sorted(train.items()):
        rm = statistics.median(float(r["surface_rmse"]) for r in rs)
        print("| %s | %g | %d | %s | %s | %.4f |" % (sc, s, len(rs), cell(rs, "psnr"), cell(rs, "water_removal_psnr"), rm))
PY
}
if [ $summary_only = 1 ]; then summarise; cat "$out/summary.md"; exit 0; fi
[ ${#scenes[@]} -gt 0 ] || { echo "water-valley: give at least one --scene NAME=SYNTH-ARGS" >&2; exit 2; }
[ -x "$REFRAX" ] || { echo "water-valley: $REFRAX is not built (cmake --build build)" >&2; exit 2; }
work=$out/work
mkdir -p "$work"
[ -f "$rows" ] || echo "scene,kind,scale,seed,steps,exit,psnr,water_removal_psnr,surface_rmse,sweep_ratio,seconds" >"$rows"
{
  "$REFRAX" --version 2>/dev/null | head -1 || true
  echo "code=$(git -C "$root" rev-parse --short HEAD)$(git -C "$root" diff --quiet -- engine shaders trainer || echo +changes)"
  echo "scenes=${scenes[*]}"
  echo "sweep_scales=$sweep_scales train_scales=$train_scales seeds=$seeds steps=${steps:-default} train_flags=$train_flags"
  echo "started=$(date -u '+%Y-%m-%d %H:%M UTC')"
} >>"$out/run_info.txt"

# one run and its row: scene, kind, scale, seed, steps ("" = the defaults), data
run_one() {
  local scene=$1 kind=$2 scale=$3 seed=$4 n=$5 data=$6 dir=$work/$1-$2-$3-$4 rc=0 t0 t1
  local step_flags=()
  [ -n "$n" ] && step_flags=(--steps "$n")
  rm -rf "$dir"
  t0=$(date +%s)
  # shellcheck disable=SC2086
  "$REFRAX" train "$data" -o "$dir" --known-water --known-water-scale "$scale" --seed "$seed" "${step_flags[@]}" $train_flags \
    >"$dir.log" 2>&1 || rc=$?
  t1=$(date +%s)
  if [ $rc = 0 ]; then
    python3 - "$dir/metrics.json" "$scene" "$kind" "$scale" "$seed" "${n:-default}" "$((t1 - t0))" >>"$rows" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
g = lambda k: "" if m.get(k) is None else "%.6g" % m[k]
print(",".join(sys.argv[2:7] + ["0", g("psnr"), g("water_removal_psnr"), g("surface_rmse"), g("surface_sweep_ratio"), sys.argv[7]]))
PY
  else
    echo "$scene,$kind,$scale,$seed,${n:-default},$rc,,,,,$((t1 - t0))" >>"$rows"
    tail -3 "$dir.log" >&2
  fi
  rm -rf "$dir"
}

declare -A data_of
for spec in "${scenes[@]}"; do
  name=${spec%%=*}
  args=${spec#*=}
  data=$work/data-$name
  # shellcheck disable=SC2086
  [ -f "$data/water.json" ] || "$REFRAX" synth $args -o "$data" >"$work/synth-$name.log" 2>&1 ||
    { cat "$work/synth-$name.log" >&2; echo "water-valley: refrax synth $args failed" >&2; exit 1; }
  data_of[$name]=$data
  for s in $sweep_scales; do
    echo "water-valley: $name sweep S=$s" >&2
    run_one "$name" sweep "$s" 1 2 "$data"
  done
done
for seed in $seeds; do
  for spec in "${scenes[@]}"; do
    name=${spec%%=*}
    for s in $train_scales; do
      echo "water-valley: $name train S=$s seed $seed" >&2
      run_one "$name" train "$s" "$seed" "$steps" "${data_of[$name]}"
    done
  done
done
echo "finished=$(date -u '+%Y-%m-%d %H:%M UTC')" >>"$out/run_info.txt"
rm -rf "$work"
summarise
cat "$out/summary.md"
