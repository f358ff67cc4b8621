#!/usr/bin/env bash
# Around the automatic model size (issue 29 item 3; engine/train/model_sizing.h): test PSNR,
# surface RMSE and training time at the size `refrax train` derives from the data, and one step
# either side of it for each derived size: the octaves (the grid follows, 2^octaves cells), the
# subdivision levels, the Gaussian budget (initial count and cap together, x1/2 and x2), and the
# coarse grid halved with one subdivision level more (the same finest triangles, a quarter of the
# coarse vertices: what the 2^octaves grid costs).
#
# Usage: bench/sizing.sh [--full | --smoke] [--presets "A B ..."] [--steps N] [--out DIR] [--keep-work] [--charts-only]
#   default  tiny presets nerfrac-primary-sine and desk-topdown, 1,500 steps of 32 x 32 patches:
#            8 runs a preset, about 40 s each on 2 lavapipe cores
#   --full   full size (392 px), 6,000 steps of 64 x 64 patches (about 10-30 min a run on lavapipe)
#   --smoke  one preset, 20 steps (checks the pipeline, not the method)
# Every run: the presets table's refraction method (bench/presets.sh refraction-sweep) with an
# octave window that opens (3 coarse octaves, all open at 4/5 of the run), SH degree 0.
# Writes DIR/sizing.csv, DIR/<preset>-<sweep>-{psnr,rmse,seconds}.svg and DIR/summary.md.
set -euo pipefail
. "$(dirname "$0")/suite-lib.sh"
invocation="$*"
presets_arg="" steps_arg=""
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --presets) [ $# -ge 2 ] || { echo "sizing: --presets needs a list" >&2; exit 2; }; presets_arg=$2; shift ;;
    --steps) [ $# -ge 2 ] || { echo "sizing: --steps needs a count" >&2; exit 2; }; steps_arg=$2; shift ;;
    *) args+=("$1") ;;
  esac
  shift
done
suite_parse_args sizing "${args[@]+"${args[@]}"}"

case $mode in
  default) steps=1500 patch=32 presets="nerfrac-primary-sine desk-topdown" ;;
  full) steps=6000 patch=64 presets="nerfrac-primary-sine" ;;
  smoke) steps=20 patch=16 presets="nerfrac-primary-sine" ;;
esac
[ -n "$steps_arg" ] && steps=$steps_arg
[ -n "$presets_arg" ] && presets=$presets_arg
method="--patch $patch --sh-degree 0 --density-reset-every 0 --mlp-coarse-octaves 3 --octaves-open-until $((steps * 4 / 5))
        --surface-lr 3e-3 --surface-freeze $((steps * 2 / 15)) --anchor-mean-height --level-prior 1000 --init-depth sweep
        --restart-gaussians $((steps / 3)),$((steps * 8 / 15)) --surface-batch views"
method=$(echo $method)

csv=$out/sizing.csv
# The derived size of a dataset: a one-step run's config.json (refrax train prints and records it).
chosen() {  # dataset key -> the derived value
  python3 -c 'import json,sys; print(int(json.load(open(sys.argv[1]))["model_sizing"]["derived"][sys.argv[2]]["value"]))' "$work/probe-$3/config.json" "$2"
}

if [ $charts_only = 0 ]; then
  rm -f "$csv" "$out"/*.svg "$out/failures.txt"
  for preset in $presets; do
    data=$(suite_dataset "$preset")
    "$REFRAX" train "$data" -o "$work/probe-$preset" --steps 1 --checkpoint-every 0 > "$work/probe-$preset.log" 2>&1 ||
      { cat "$work/probe-$preset.log" >&2; exit 1; }
    grep '^model size' "$work/probe-$preset.log" | sed 's/^/  /'
    L=$(chosen "$data" mlp_octaves "$preset") K=$(chosen "$data" subdivision_levels "$preset") G=$(chosen "$data" initial_gaussians "$preset")
    M=$(chosen "$data" max_gaussians "$preset")
    # sweep|value|chosen|size flags (every run names all five, so none is left to the data)
    runs=("octaves|$L|1|--mlp-octaves $L --grid-cells $((1 << L)) --subdivision $K --gaussians $G --max-gaussians $M")
    for l in $((L - 1)) $((L + 1)); do
      [ $l -ge 2 ] && runs+=("octaves|$l|0|--mlp-octaves $l --grid-cells $((1 << l)) --subdivision $K --gaussians $G --max-gaussians $M")
    done
    for k in $((K - 1)) $((K + 1)); do
      [ $k -ge 0 ] && runs+=("subdivision|$k|0|--mlp-octaves $L --grid-cells $((1 << L)) --subdivision $k --gaussians $G --max-gaussians $M")
    done
    [ $L -ge 3 ] && [ $K -lt 6 ] &&
      runs+=("grid|$((1 << (L - 1)))|0|--mlp-octaves $L --grid-cells $((1 << (L - 1))) --subdivision $((K + 1)) --gaussians $G --max-gaussians $M")
    for f in half double; do
      [ $f = half ] && g=$((G / 2)) m=$((M / 2))
      [ $f = double ] && g=$((G * 2)) m=$((M * 2))
      runs+=("gaussians|$m|0|--mlp-octaves $L --grid-cells $((1 << L)) --subdivision $K --gaussians $g --max-gaussians $m")
    done
    echo "$preset ($size): chosen $L octaves, $((1 << L)) x $K, $G Gaussians (cap $M)"
    for entry in "${runs[@]}"; do
      IFS='|' read -r sweep value is_chosen flags <<< "$entry"
      # shellcheck disable=SC2086
      suite_warmup "$data" $method $flags
      # shellcheck disable=SC2086
      suite_train "$csv" "preset=$preset,sweep=$sweep,value=$value,chosen=$is_chosen" "$data" "$preset-$sweep-$value" --steps $steps \
        --eval-every $steps $method $flags
    done
    # The chosen run is a point of every sweep: its row again under the others.
    for sweep in subdivision gaussians grid; do
      v=$K; [ $sweep = gaussians ] && v=$M; [ $sweep = grid ] && v=$((1 << L))
      [ -d "$work/runs/$preset-octaves-$L" ] && "$REFRAX" report "$work/runs/$preset-octaves-$L" -o "$csv" --append --evaluations \
        --set "preset=$preset,sweep=$sweep,value=$v,chosen=1" > /dev/null
    done
  done
fi

[ -f "$csv" ] || { echo "sizing: no rows in $csv" >&2; exit 1; }
declare -A label=([octaves]="frequency-encoding octaves (grid 2^octaves)" [subdivision]="subdivision levels"
                  [gaussians]="Gaussian cap (initial count 1/8 of it)"
                  [grid]="coarse grid cells (halved: one subdivision level more)")
{
  echo "# Around the automatic model size ($mode)"
  echo
  echo "Device: $device. Generated by \`bench/sizing.sh${invocation:+ $invocation}\` on $(date -u +%Y-%m-%d) in $(suite_elapsed) s."
  suite_load_line
  echo
  echo "Every run: \`refrax synth PRESET --size $size\`, \`--steps $steps $method\`, and the sizes below"
  echo "(chosen = 1: the size \`refrax train\` derives from the data). One seed, one run each; training seconds are"
  echo "wall time on this device, runs one after the other."
  echo
  for preset in $presets; do
    for sweep in octaves subdivision gaussians grid; do
      part=$work/$preset-$sweep.csv
      # this preset's sweep, by value (the chart joins its points in row order)
      python3 - "$csv" "$preset" "$sweep" > "$part" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
keep = sorted((r for r in rows if r["preset"] == sys.argv[2] and r["sweep"] == sys.argv[3]), key=lambda r: float(r["value"]))
w = csv.DictWriter(sys.stdout, fieldnames=list(rows[0].keys()), lineterminator="\n")
w.writeheader()
w.writerows(keep)
EOF
      [ "$(wc -l < "$part")" -gt 1 ] || continue
      logx=""; [ $sweep = gaussians ] && logx=--log-x
      for y in psnr surface_rmse training_seconds; do
        suite_chart "$part" -o "$out/$preset-$sweep-$y.svg" --x value --y $y $logx --title "$preset ($size): $y against ${label[$sweep]}" \
          --x-label "${label[$sweep]}" --y-label "$y"
      done
      echo "## $preset: ${label[$sweep]}"
      echo
      echo "![PSNR]($preset-$sweep-psnr.svg) ![surface RMSE]($preset-$sweep-surface_rmse.svg) ![time]($preset-$sweep-training_seconds.svg)"
      echo
      suite_table "$part" "value chosen psnr ssim surface_rmse initial_flat_surface_rmse training_seconds gaussians"
      echo
    done
  done
  suite_failed_runs
} > "$out/summary.md.tmp"
suite_publish_summary
