#!/usr/bin/env bash
# Model size (issue 8.2): test PSNR and surface RMSE against the height field's size (MLP
# width, depth, frequency-encoding octaves), the proxy mesh (coarse grid cells x recursive
# subdivision levels) and the Gaussian budget, on one NeRFrac-like preset. One parameter
# varies at a time from Refrax's defaults (MLP 3 x 64, 6 octaves, 64 cells x 2 levels).
#
# Usage: bench/model-size.sh [--full | --smoke] [--out DIR] [--keep-work]
#   default  nerfrac-hybrid tiny (64 x 64 px, 8 training views), 300 steps, 32 x 32 patches,
#            SH degree 0, 2,000 initial Gaussians (the budget sweep sets both the initial count
#            and the cap). Measured: 41 minutes on 2 shared lavapipe cores (load 6-10), 18 of
#            them the width-128 run (layered kernels); the other 15 runs take 15-160 s each.
#   --full   full size (392 x 392 px), 15,000 steps, whole images, SH degree 3, 20,000 initial
#            Gaussians; budgets 2k, 5k, 20k, 100k.
#   --smoke  two configurations, 20 steps (checks the pipeline, not the method).
# Writes DIR/model-size.csv (one row per run, with the swept parameter and its value),
# DIR/<parameter>-psnr.svg, DIR/<parameter>-rmse.svg and DIR/summary.md.
set -euo pipefail
. "$(dirname "$0")/suite-lib.sh"
suite_parse_args model-size "$@"

preset=nerfrac-hybrid
case $mode in
  default) steps=300 common="--patch 32 --sh-degree 0" initial=2000 budgets="500 1000 2000 5000" ;;
  full) steps=15000 common="" initial=20000 budgets="2000 5000 20000 100000" ;;
  smoke) steps=20 common="--patch 16 --sh-degree 0" initial=300 budgets="" ;;
esac

# sweep|value|series|options: each run once; the defaults appear in every sweep as one run.
runs=()
for w in 16 32 64 128; do runs+=("mlp-width|$w|width|--mlp-width $w"); done
for d in 1 3 6; do runs+=("mlp-layers|$d|layers|--mlp-layers $d"); done
for o in 2 4 6; do runs+=("mlp-octaves|$o|octaves|--mlp-octaves $o"); done
for gk in 16x3 32x2 64x2 64x1 128x1; do runs+=("grid|${gk%x*}|K=${gk#*x}|--grid-cells ${gk%x*} --subdivision ${gk#*x}"); done
for b in $budgets; do runs+=("gaussians|$b|budget|--gaussians $b --max-gaussians $b"); done
[ $mode = smoke ] && runs=("mlp-width|16|width|--mlp-width 16" "mlp-width|64|width|--mlp-width 64")
defaults="--mlp-width 64 --mlp-layers 3 --mlp-octaves 6 --grid-cells 64 --subdivision 2"

csv=$out/model-size.csv
if [ $charts_only = 1 ]; then
  runs=()
else
  rm -f "$out"/*.csv "$out"/*.svg "$out/failures.txt"
  data=$(suite_dataset "$preset")
fi
echo "warming up the shader cache (one 4-step run per configuration)"
for entry in "${runs[@]}"; do
  IFS='|' read -r sweep value series options <<< "$entry"
  # shellcheck disable=SC2086
  suite_warmup "$data" $common --gaussians $initial $options
done
echo "$preset:"
declare -A done_run
for entry in "${runs[@]}"; do
  IFS='|' read -r sweep value series options <<< "$entry"
  gaussians="--gaussians $initial"
  [ "$sweep" = gaussians ] && gaussians=""
  # The run's identity: its options on top of the defaults (the defaults' run is shared).
  key="$options"
  case "$defaults" in *"$options"*) [ "$sweep" != gaussians ] && key=defaults ;; esac
  name=$sweep-$value-$series
  if [ "$key" = defaults ] && [ -n "${done_run[defaults]:-}" ]; then
    # Same run as an earlier sweep's default point: its row again, under this sweep.
    "$REFRAX" report "$work/runs/${done_run[defaults]}" -o "$csv" --append --evaluations --set "sweep=$sweep,value=$value,series=$series" > /dev/null
    echo "  $name: the defaults' run (${done_run[defaults]})"
    continue
  fi
  # shellcheck disable=SC2086
  suite_train "$csv" "sweep=$sweep,value=$value,series=$series" "$data" "$name" --steps $steps --eval-every $steps $common $gaussians $options
  [ "$key" = defaults ] && [ -f "$work/runs/$name/metrics.json" ] && done_run[defaults]=$name
done

[ $charts_only = 1 ] && rm -f "$out"/mlp-*.csv "$out"/grid.csv "$out"/gaussians.csv "$out"/*.svg
# One CSV per sweep (the chart tool draws every row of its file), then its two charts.
declare -A label=([mlp-width]="MLP width (hidden units)" [mlp-layers]="MLP hidden layers" [mlp-octaves]="frequency-encoding octaves"
                  [grid]="coarse grid cells per side (series: subdivision levels K)" [gaussians]="Gaussian budget (initial = cap)")
for sweep in mlp-width mlp-layers mlp-octaves grid gaussians; do
  [ -f "$csv" ] || break
  part=$out/$sweep.csv
  awk -F, -v s="$sweep" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "sweep") c = i; print; next } $c == s' "$csv" > "$part"
  [ "$(wc -l < "$part")" -gt 1 ] || { rm -f "$part"; continue; }
  logx=""
  case $sweep in mlp-width|grid|gaussians) logx=--log-x ;; esac
  suite_chart "$part" -o "$out/$sweep-psnr.svg" --x value --y psnr --series series $logx \
    --title "$preset ($size): test PSNR against ${label[$sweep]%% (*}" --x-label "${label[$sweep]}" --y-label "test PSNR (dB)"
  suite_chart "$part" -o "$out/$sweep-rmse.svg" --x value --y surface_rmse --series series $logx \
    --title "$preset ($size): surface RMSE against ${label[$sweep]%% (*}" --x-label "${label[$sweep]}" --y-label "surface RMSE (scene units)"
done

{
  echo "# Model size ($mode)"
  echo
  echo "Device: $device. Generated by \`bench/model-size.sh${1:+ $*}\` on $(date -u +%Y-%m-%d) in $(suite_elapsed) s."
  suite_load_line
  echo
  echo "Sizes: \`refrax synth $preset --size $size\`; every run \`--steps $steps $common --gaussians $initial\` and the"
  echo "defaults (\`$defaults\`) except the one parameter swept (the Gaussian budget sweep sets"
  echo "\`--gaussians B --max-gaussians B\`). Training seconds are wall time on this device, runs one after the other."
  echo
  for sweep in mlp-width mlp-layers mlp-octaves grid gaussians; do
    [ -f "$out/$sweep.csv" ] || continue
    echo "## ${label[$sweep]}"
    echo
    echo "![PSNR]($sweep-psnr.svg) ![surface RMSE]($sweep-rmse.svg)"
    echo
    suite_table "$out/$sweep.csv" "series value psnr ssim surface_rmse training_seconds gaussians model_bytes"
    echo
  done
  suite_failed_runs
} > "$out/summary.md.tmp"
suite_publish_summary
