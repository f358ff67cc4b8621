#!/usr/bin/env bash
# Speed against accuracy (issue 8.1): test PSNR and surface RMSE against training wall time,
# for each NeRFrac-like preset, for Refrax's defaults, the paper's reference configuration
# and the paper's ablations (face normals throughout, no recursive subdivision with a full-
# resolution mesh instead, no density/opacity loss). Each run evaluates the test view 6 to 10
# times; metrics.json "evaluations" gives its (training seconds, PSNR, RMSE) points.
#
# Usage: bench/speed-accuracy.sh [--full | --smoke] [--out DIR] [--keep-work]
#   default  tiny presets (64 x 64 px, 8 training views), 32 x 32 patches, SH degree 0, 2,000
#            initial Gaussians; every run gets 40 s of training: the steps that fill it at its
#            configuration's step time, measured first (3..3000 steps); 6 evaluations per run.
#            The reference configuration: 3 steps on the first preset (see below). Measured:
#            23 minutes on 2 shared lavapipe cores (load 8-10), 13 of them the reference's 3 steps.
#   --full   full-size presets (392 x 392 px), 15,000 steps, whole images, SH degree 3,
#            20,000 initial Gaussians (the reference schedule); 10 evaluations per run.
#   --smoke  one preset, two configurations, 3 s budgets (checks the pipeline, not the method).
# Writes DIR/<preset>.csv (one row per evaluation), DIR/psnr-<preset>.svg,
# DIR/rmse-<preset>.svg and DIR/summary.md (device, sizes, final values, time ratios).
set -euo pipefail
. "$(dirname "$0")/suite-lib.sh"
suite_parse_args speed-accuracy "$@"

presets=(nerfrac-primary-sine nerfrac-second-sine nerfrac-hybrid)
# budget: training seconds per run; each configuration gets the steps that fill it, from its
# step time measured here first (so a slow configuration gets fewer steps, not more time, and
# the suite's length does not depend on the machine's load). Full size: fixed reference steps.
# fixed_steps / first_preset_only: configurations too slow for the budget on this machine. The
# reference's 6 x 256 MLP over a 201 x 201 grid takes minutes per step on lavapipe (522x the
# defaults' step in bench/results/speed-accuracy/): it gets 3 steps, on the first preset only,
# and no timing run.
declare -A fixed_steps=() first_preset_only=()
case $mode in
  default) budget=40 evals=6 common="--patch 32 --sh-degree 0 --gaussians 2000"; fixed_steps=([reference]=3); first_preset_only=([reference]=1) ;;
  full) budget="" steps=15000 evals=10 common="" ;;
  smoke) budget=3 evals=2 common="--patch 16 --sh-degree 0 --gaussians 300"; presets=(nerfrac-primary-sine) ;;
esac
min_steps=3 max_steps=3000

# name|options (STEPS: the run's step count). Refrax defaults: MLP 3 x 64, init range 1e-3,
# 64 cells, 2 subdivision levels. Reference (docs/method.md §1.1, 1.2, 1.6): MLP 6 x 256 with the last
# layer in +-0.1 and a 200-cell grid (201 x 201 vertices), K = 2; its loss and schedule are
# Refrax's defaults already. Ablations, from the defaults: face normals for the whole run;
# no subdivision (K = 0) on a 256-cell mesh (the defaults' finest level, 64 x 2^2); no
# density (opacity) loss.
configs=(
  "defaults|"
  "reference|--mlp-width 256 --mlp-layers 6 --mlp-init-range 0.1 --grid-cells 200"
  "face-normals|--face-normals-until STEPS"
  "no-subdivision|--subdivision 0 --grid-cells 256"
  "no-density-loss|--density-loss 0"
)
[ $mode = smoke ] && configs=("${configs[0]}" "${configs[3]}")

declare -A steps_of per_step
if [ $charts_only = 1 ]; then
  for entry in "${configs[@]}"; do steps_of[${entry%%|*}]=STEPS; done
elif [ -n "$budget" ]; then
  rm -f "$out"/*.csv "$out"/*.svg "$out/failures.txt"
  echo "measuring each configuration's step time (after a warm-up run that compiles its pipelines)"
  timing_data=$(suite_dataset "${presets[0]}")  # every preset has the same image size and rig
  for entry in "${configs[@]}"; do
    name=${entry%%|*}
    options=${entry#*|}
    if [ -n "${fixed_steps[$name]:-}" ]; then
      steps_of[$name]=${fixed_steps[$name]}
      per_step[$name]=""
      echo "  $name: ${steps_of[$name]} steps (fixed)"
      continue
    fi
    # shellcheck disable=SC2086
    per_step[$name]=$(suite_step_seconds "$timing_data" $common ${options//STEPS/8})
    steps_of[$name]=$(awk -v b="$budget" -v t="${per_step[$name]}" -v lo=$min_steps -v hi=$max_steps \
      'BEGIN { n = t > 0 ? int(b / t + 0.5) : lo; print (n < lo ? lo : (n > hi ? hi : n)) }')
    echo "  $name: ${per_step[$name]} s/step -> ${steps_of[$name]} steps"
  done
else
  rm -f "$out"/*.csv "$out"/*.svg "$out/failures.txt"
  echo "warming up the shader cache (one 4-step run per configuration)"
  warm_data=$(suite_dataset "${presets[0]}")
  for entry in "${configs[@]}"; do
    name=${entry%%|*}
    steps_of[$name]=$steps
    per_step[$name]=""
    # shellcheck disable=SC2086
    options=${entry#*|}
    # shellcheck disable=SC2086
    suite_warmup "$warm_data" $common ${options//STEPS/4}
  done
fi

for preset in "${presets[@]}"; do
  csv=$out/$preset.csv
  [ $charts_only = 1 ] && configs_to_run=() || configs_to_run=("${configs[@]}")
  [ $charts_only = 1 ] || { echo "$preset:"; data=$(suite_dataset "$preset"); }
  for entry in "${configs_to_run[@]}"; do
    name=${entry%%|*}
    [ -n "${first_preset_only[$name]:-}" ] && [ "$preset" != "${presets[0]}" ] && continue
    n=${steps_of[$name]}
    every=$(( n / evals > 0 ? n / evals : 1 ))
    options=${entry#*|}
    # shellcheck disable=SC2086
    suite_train "$csv" "preset=$preset,config=$name" "$data" "$preset-$name" --steps $n --eval-every $every $common ${options//STEPS/$n}
  done
  [ -f "$csv" ] || continue
  suite_chart "$csv" -o "$out/psnr-$preset.svg" --x eval_seconds --y eval_psnr --series config \
    --title "$preset ($size): test PSNR against training time" --x-label "training wall time (s)" --y-label "test PSNR (dB)"
  suite_chart "$csv" -o "$out/rmse-$preset.svg" --x eval_seconds --y eval_surface_rmse --series config \
    --title "$preset ($size): surface RMSE against training time" --x-label "training wall time (s)" --y-label "surface RMSE (scene units)"
done

{
  echo "# Speed against accuracy ($mode)"
  echo
  echo "Device: $device. Generated by \`bench/speed-accuracy.sh${1:+ $*}\` on $(date -u +%Y-%m-%d) in $(suite_elapsed) s."
  suite_load_line
  echo
  if [ -n "$budget" ]; then
    echo "Sizes: \`refrax synth <preset> --size $size\`; every run \`$common\` plus its configuration's options"
    echo "below, for the steps that fill a budget of $budget s of training time at the configuration's step time (measured"
    echo "first, after a warm-up run that compiles its pipelines), with $evals evaluations of the test view per run."
  else
    echo "Sizes: \`refrax synth <preset> --size $size\`; every run \`--steps $steps $common\` plus its configuration's"
    echo "options below, with $evals evaluations of the test view per run."
  fi
  echo "Times are training wall time (evaluations excluded), every run in this one suite run on one device, one after"
  echo "the other; *time ratio* is the final training time against the defaults' on the same preset, *step ratio* the"
  echo "time per step against the defaults'."
  echo
  echo "| configuration | options | steps | s/step (timing run) |"
  echo "| --- | --- | --- | --- |"
  for entry in "${configs[@]}"; do
    name=${entry%%|*}
    options=${entry#*|}
    echo "| $name | \`${options//STEPS/${steps_of[$name]}}\` | ${steps_of[$name]} | ${per_step[$name]:--} |"
  done
  for name in "${!fixed_steps[@]}"; do
    echo
    echo "*$name* runs a fixed ${fixed_steps[$name]} steps${first_preset_only[$name]:+ on ${presets[0]} only}: its steps take far longer"
    echo "than the budget allows on this device (see its step ratio below), so it cannot fill the same budget."
  done
  echo
  for preset in "${presets[@]}"; do
    csv=$out/$preset.csv
    [ -f "$csv" ] || continue
    echo "## $preset"
    echo
    echo "![PSNR against time](psnr-$preset.svg) ![surface RMSE against time](rmse-$preset.svg)"
    echo
    # Final rows, with the training time as a ratio to the defaults' (measured in this run).
    awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) idx[$i] = i; next }
      $idx["eval_step"] == $idx["config_steps"] { n++; name[n] = $idx["config"]; row[n] = $0; t[n] = $idx["training_seconds"]
        ps[n] = $idx["training_seconds"] / $idx["step"]
        if ($idx["config"] == "defaults") { base = $idx["training_seconds"]; pbase = ps[n] } }
      END { print "| configuration | steps | test PSNR (dB) | SSIM | surface RMSE | flat-surface RMSE | training s | time ratio | step ratio | Gaussians | model bytes |"
            print "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
            for (k = 1; k <= n; k++) { split(row[k], f, ",")
              printf "| %s | %s | %.2f | %.3f | %s | %s | %.1f | %s | %s | %s | %s |\n", name[k], f[idx["step"]], f[idx["psnr"]], f[idx["ssim"]],
                (f[idx["surface_rmse"]] == "" ? "-" : sprintf("%.4f", f[idx["surface_rmse"]])),
                (f[idx["initial_flat_surface_rmse"]] == "" ? "-" : sprintf("%.4f", f[idx["initial_flat_surface_rmse"]])),
                t[k], (base > 0 ? sprintf("%.2fx", t[k] / base) : "-"), (pbase > 0 ? sprintf("%.1fx", ps[k] / pbase) : "-"),
                f[idx["gaussians"]], f[idx["model_bytes"]] } }' "$csv"
    echo
  done
  suite_failed_runs
} > "$out/summary.md.tmp"
suite_publish_summary
