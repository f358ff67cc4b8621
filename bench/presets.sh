#!/usr/bin/env bash
# Every preset (issue 6's closing table): test PSNR, SSIM, surface RMSE and training time of the
# refraction model with the long CI test's method (refraction-sweep: the level prior and the
# Gaussians drawn at a plane sweep's depth, afresh at two restarts; and one surface step per
# pass over the training views, --surface-batch views), of the refraction model
# with and without the slope prior (--surface-smoothness), next to
# --flat-water and --no-refraction on the same data, seed and steps, straight rays given the
# method's start (no-refraction-sweep: the plane sweep and the restarts, so a gain is the
# water's and not the start's), and the dry control (dry-control: straight rays with the same
# start on the same views with the water removed, `refrax synth --dry`: what the Gaussians
# reach at this budget; from the box instead they reach 3 dB less at full size),
# for each NeRFrac-like preset (3 x 3 downward rig, IOR 1.1) and each RefracGS-like scene
# (desk, kitchen, toys: 24 ring views at IOR 1.33, and their 9-camera downward variants).
#
# Usage: bench/presets.sh [--full | --smoke | --cpu-full] [--out DIR] [--keep-work] [--charts-only]
#                         [--models refraction-sweep,refraction,refraction-smooth,flat-water,no-refraction,
#                                   flat-water-sweep,no-refraction-sweep,dry-control]
#                         [--presets NAME,...] [--refraction-options "OPTS"] [--smoothness X]
#                         [--dataset-size tiny|full] [--steps N]
#   default  tiny presets (64 px wide), 1,500 steps of 32 x 32 patches, 2,000 initial Gaussians
#            capped at 4,000, no density resets, SH degree 0; the refraction model with the
#            short-run surface settings (3 octaves, --surface-lr 3e-3, the surface learning from
#            step 200, the anchored mean height; docs/training.md), and the same with
#            --surface-smoothness 0.1 (refraction-smooth), and the same with --level-prior 1000
#            --init-depth sweep --restart-gaussians 500,800 --surface-batch views (refraction-sweep). 63 runs, about
#            80 minutes on this 2-core lavapipe machine.
#   --full   full-size presets (392 px NeRFrac-like, 400 x 300 RefracGS-like), the reference
#            schedule: 15,000 whole-image steps, 20,000 initial Gaussians, SH degree 3 (a GPU).
#   --smoke  two presets, 20 steps (checks the pipeline, not the method).
#   --cpu-full  the full-size table on a CPU in one command (issue 29): full-size presets,
#            6,000 steps of 64 x 64 patches, the Gaussian budget and the water's size derived
#            from the data (no --gaussians/--max-gaussians/--grid-cells given), the short-run
#            surface settings (and --water-sign-check at the restarts, as every full-size
#            refraction-sweep run), and four models: refraction-sweep, flat-water-sweep (the flat
#            plane with the same start), no-refraction-sweep and dry-control. Writes
#            bench/results/presets-cpu-full; with --presets a few at a time, its rows add up.
#            Its summary sets each row beside the same preset and model in the 2026-11-27
#            full-size table (bench/results/presets-full; flat-water-sweep beside its flat-water
#            row, which had no sweep).
#   --models, --presets  run only these models / presets, keeping the other rows of
#            DIR/presets.csv (e.g. after changing one model's settings).
#   --refraction-options replaces the refraction model's extra `refrax train` options ("" for
#            the reference surface settings: 6 octaves, --surface-lr 5e-4, frozen 1/15 of the run;
#            refraction-smooth adds --surface-smoothness X to them, refraction-sweep the level
#            prior, the sweep and the restarts).
#   --dataset-size tiny|full  the presets at this size, trained with the mode's settings (default:
#            the mode's size) -- the full-size table on a CPU: --dataset-size full --steps 6000
#            (training time per step does not grow with the images: 32 x 32 patches).
#   --steps N  train N steps instead of the mode's (the refraction-sweep restarts move with it,
#            to a third and eight fifteenths of the run, as 500,800 of 1,500).
#   --smoothness X  the slope prior's weight for refraction-smooth (default 0.1; 0.01 held
#            2 of the 4 presets whose surface ran away and let a stable one drift, see docs/experiments/2026-11-24-surface-smoothness.md).
# Writes DIR/presets.csv (one row per run: preset and variant, then `refrax report`'s columns) and
# DIR/summary.md (device, load, sizes, and per preset the seven variants with
# refraction-sweep's gain over each other one: over dry-control, what refraction still costs).
set -euo pipefail
. "$(dirname "$0")/suite-lib.sh"
invocation="bench/presets.sh${1:+ $*}"
only_models=""
only_presets=""
cpu_full=0
mode_models=""  # a mode's own model list (--cpu-full), used when --models is not given
refraction_options=unset
smoothness=0.1
dataset_size=""
steps_override=""
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --models) [ $# -ge 2 ] || { echo "presets: --models needs a list" >&2; exit 2; }; only_models=$2; shift ;;
    --presets) [ $# -ge 2 ] || { echo "presets: --presets needs a list" >&2; exit 2; }; only_presets=$2; shift ;;
    --dataset-size) [ $# -ge 2 ] && { [ "$2" = tiny ] || [ "$2" = full ]; } || { echo "presets: --dataset-size needs tiny or full" >&2; exit 2; }; dataset_size=$2; shift ;;
    --steps) [ $# -ge 2 ] && [[ $2 =~ ^[0-9]+$ ]] && [ "$2" -ge 15 ] || { echo "presets: --steps needs a step count (15 or more)" >&2; exit 2; }; steps_override=$2; shift ;;
    --cpu-full) cpu_full=1 ;;
    --smoothness) [ $# -ge 2 ] || { echo "presets: --smoothness needs a number" >&2; exit 2; }; smoothness=$2; shift ;;
    --refraction-options) [ $# -ge 2 ] || { echo "presets: --refraction-options needs a string" >&2; exit 2; }; refraction_options=$2; shift ;;
    *) args+=("$1") ;;
  esac
  shift
done
if [ $cpu_full = 1 ]; then
  for a in ${args[@]+"${args[@]}"}; do
    case $a in --full|--smoke) echo "presets: --cpu-full is a mode of its own (not with $a)" >&2; exit 2 ;; esac
  done
  args=(--out "$(dirname "$0")/results/presets-cpu-full" ${args[@]+"${args[@]}"})  # a later --out wins
fi
[ $cpu_full = 0 ] || suite_mode_label=cpu-full
suite_parse_args presets ${args[@]+"${args[@]}"}

presets=(nerfrac-primary-sine nerfrac-second-sine nerfrac-hybrid desk kitchen toys desk-topdown kitchen-topdown toys-topdown)
short_run="--mlp-coarse-octaves 3 --octaves-open-until 100000000 --surface-lr 3e-3 --surface-freeze 200 --anchor-mean-height"
# the long CI test's method, its restarts at a third and a half of the run here
case $mode in
  default) steps=1500 common="--patch 32 --gaussians 2000 --max-gaussians 4000 --density-reset-every 0 --sh-degree 0"
    refraction=$short_run restarts=500,800 ;;
  full) steps=15000 common="" refraction="" restarts=5000,7500 ;;
  smoke) steps=20 common="--patch 16 --gaussians 300 --sh-degree 0" refraction=$short_run restarts=10 presets=(nerfrac-hybrid desk) ;;
esac
earlier_table=""  # a table whose rows the summary sets beside this one's
if [ $cpu_full = 1 ]; then
  earlier_table=$(dirname "$0")/results/presets-full/presets.csv
  # 64 x 64 patches lifted the method by about 2 dB over 32 x 32 at full size (two seeds) and
  # 6,000 of them are the full-size records' budget (docs/experiments/2026-11-27-dry-fit-patches.md)
  mode=cpu-full size=full steps=6000 restarts=2000,3200
  common="--patch 64 --density-reset-every 0 --sh-degree 0"
  refraction=$short_run
  mode_models=refraction-sweep,flat-water-sweep,no-refraction-sweep,dry-control
fi
if [ -n "$steps_override" ]; then
  steps=$steps_override
  restarts=$((steps / 3)),$((steps * 8 / 15))
fi
[ -z "$dataset_size" ] || size=$dataset_size
[[ $smoothness =~ ^[0-9]+([.][0-9]+)?([eE][-+]?[0-9]+)?$ ]] || { echo "presets: --smoothness needs a number >= 0, not '$smoothness'" >&2; exit 2; }
[ "$refraction_options" = unset ] || refraction=$refraction_options
smooth="--surface-smoothness $smoothness"
# --surface-batch views: one surface step per pass over the training views, on their summed
# gradient (without it the surface ran away on 5 of the 9 tiny presets; docs/training.md)
sweep="--level-prior 1000 --init-depth sweep --restart-gaussians $restarts --surface-batch views"
# At full size the restarts also check the water against its mirror image (--water-sign-check):
# 2 of 8 full-size runs learned the waves upside down. Not at 64 px, where the sweep reads the
# waves and their mirror alike (docs/experiments/2026-11-28-upside-down-water.md).
[ "$size" = full ] && sweep="$sweep --water-sign-check"
# name|train options[|synth options]
models=("refraction-sweep|$refraction $sweep" "refraction|$refraction" "refraction-smooth|$refraction $smooth" "flat-water|--flat-water"
        "flat-water-sweep|--flat-water --init-depth sweep --restart-gaussians $restarts"
        "no-refraction|--no-refraction" "no-refraction-sweep|--no-refraction --init-depth sweep --restart-gaussians $restarts"
        "dry-control|--no-refraction --init-depth sweep --restart-gaussians $restarts|--dry")
train_options() { local rest=${1#*|}; echo "${rest%%|*}"; }
synth_options() { local rest=${1#*|}; case $rest in *"|"*) echo "${rest#*|}" ;; esac; }
all_presets=$(IFS=,; echo "${presets[*]}")
csv=$out/presets.csv
wanted_models=${only_models:-$mode_models}
if [ -n "$wanted_models" ]; then
  kept=()
  for entry in "${models[@]}"; do
    case ",$wanted_models," in *",${entry%%|*},"*) kept+=("$entry") ;; esac
  done
  [ ${#kept[@]} -gt 0 ] || { echo "presets: --models names none of $(for entry in "${models[@]}"; do printf '%s ' "${entry%%|*}"; done)" >&2; exit 2; }
  models=("${kept[@]}")
fi
if [ -n "$only_presets" ]; then
  kept=()
  for preset in "${presets[@]}"; do
    case ",$only_presets," in *",$preset,"*) kept+=("$preset") ;; esac
  done
  [ ${#kept[@]} -gt 0 ] || { echo "presets: --presets names none of $all_presets" >&2; exit 2; }
  presets=("${kept[@]}")
fi

if [ $charts_only = 0 ]; then
  rm -f "$out/failures.txt"
  if [ -n "$only_models$only_presets" ] && [ -f "$csv" ]; then
    # keep the rows of the other models and presets (the csv's columns 2 and 3)
    run_models=$(for entry in "${models[@]}"; do printf ',%s' "${entry%%|*}"; done)
    run_presets=$(printf ',%s' "${presets[@]}")
    awk -F, -v m="$run_models," -v p="$run_presets," 'NR == 1 || index(m, "," $3 ",") == 0 || index(p, "," $2 ",") == 0' "$csv" > "$csv.tmp"
    mv "$csv.tmp" "$csv"
  else
    rm -f "$csv"
  fi
  # Lavapipe compiles each pipeline at its first dispatch (minutes for the MLP kernels): one
  # discarded 4-step run per model first keeps compile time out of the measured training times.
  echo "warming up the shader cache (one 4-step run per model)"
  for entry in "${models[@]}"; do
    # shellcheck disable=SC2086
    suite_warmup "$(suite_dataset "${presets[0]}")" $common $(train_options "$entry")
  done
  for preset in "${presets[@]}"; do
    echo "$preset:"
    for entry in "${models[@]}"; do
      name=${entry%%|*}
      # shellcheck disable=SC2086
      data=$(suite_dataset "$preset" $(synth_options "$entry"))
      # shellcheck disable=SC2086
      suite_train "$csv" "preset=$preset,variant=$name" "$data" "$preset-$name" --steps $steps --eval-every $steps $common $(train_options "$entry")
    done
  done
fi
[ -f "$csv" ] || { echo "presets.sh: no run finished (see $out/failures.txt)" >&2; exit 1; }

if [ $charts_only = 1 ]; then
  load_line="Table rebuilt from presets.csv; its runs may come from several invocations, each on this device, one run at a time."
else
  load_line=$(suite_load_line)
  # rows of other models or presets kept from an earlier invocation (--models, --presets)
  [ -z "$only_models$only_presets" ] || load_line="$load_line This invocation ran only ${only_models:-every model} on ${only_presets:-every preset}; the other rows come from earlier invocations on this device."
fi
# The table: per preset, each model's final evaluation and the refraction model's gain over it.
summary=$work/summary.md
python3 - "$csv" "$summary" "$earlier_table" <<EOF
import csv, os, sys
path, summary, earlier_path = sys.argv[1:]
rows = [r for r in csv.DictReader(open(path)) if r["eval_step"] == r["config_steps"]]
earlier = {}
if earlier_path and os.path.exists(earlier_path):
    earlier = {(r["preset"], r["variant"]): r for r in csv.DictReader(open(earlier_path)) if r["eval_step"] == r["config_steps"]}
def earlier_row(preset, model):  # the same model, else the one it grew from (flat-water-sweep: flat-water)
    return earlier.get((preset, model)) or earlier.get((preset, model.replace("-sweep", "")))
def num(r, k, fmt):
    v = r.get(k, "")
    return format(float(v), fmt) if v not in ("", "nan") else "-"
lines = [
    "# Every preset: refraction against a flat plane and straight rays ($size presets, $steps steps, $mode settings)", "",
    "Device: $device. Generated by \`$invocation\` on $(date -u +%Y-%m-%d).",
    "$load_line", "",
    "Sizes: \`refrax synth <preset> --size $size\`; every run \`--steps $steps $common\`; the refraction model adds",
    "\`${refraction:-nothing}\`, refraction-smooth also \`$smooth\`, refraction-sweep also \`$sweep\`; no-refraction-sweep is",
    "straight rays with the sweep and the restarts, flat-water-sweep the flat plane with them; dry-control is the same on \`refrax synth <preset> --dry\` (the same views without the water,",
    "the Gaussians' ceiling at this budget). One seed (1); times are training wall time (evaluations excluded), every run on one",
    "device, one after the other. *gain* is the refraction-sweep model's test PSNR minus the other model's on the same preset",
    "(over dry-control: what refraction still costs, negative while the method trails its ceiling);",
    "*flat start* is the surface RMSE of the initial flat plane (the water height the dataset gives).", "",
    "*surface correlation* is the learned heights' correlation with the true ones where the test rays meet the water (negative: waves upside down).",
    "*sweep ratio* is the run's own check of its water (docs/training.md, \"Is the learned water right?\"): above 1.02 it warns.", "",
]
earlier_note = f"*earlier table*: the same preset and model in {earlier_path} (PSNR / SSIM / surface RMSE; the model in brackets when that table ran another)."
if earlier:
    lines += [earlier_note, ""]
lines += [
    "| preset | variant | test PSNR (dB) | gain (dB) | SSIM | surface RMSE | flat start | surface correlation | sweep ratio | training (s) | Gaussians |" + (" earlier table |" if earlier else ""),
    "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |" + (" --- |" if earlier else ""),
]
by = {(r["preset"], r["variant"]): r for r in rows}
def earlier_cell(preset, model):
    e = earlier_row(preset, model)
    if e is None:
        return " - |"
    named = "" if e["variant"] == model else f' ({e["variant"]})'
    return f' {num(e, "eval_psnr", ".2f")} / {num(e, "eval_ssim", ".3f")} / {num(e, "eval_surface_rmse", ".4f")}{named} |'
for preset in dict.fromkeys(r["preset"] for r in rows):
    ref = by.get((preset, "refraction-sweep"))
    # the models run on some preset (the full-size table runs three of the five)
    for model in (m for m in ("refraction-sweep", "refraction-smooth", "refraction", "flat-water", "flat-water-sweep", "no-refraction", "no-refraction-sweep", "dry-control") if any(r["variant"] == m for r in rows)):
        r = by.get((preset, model))
        if r is None:
            lines.append(f"| {preset} | {model} | not run (or failed: failures.txt) | | | | | | | | |" + (" |" if earlier else ""))
            continue
        gain = "" if model == "refraction-sweep" or ref is None else f'{float(ref["eval_psnr"]) - float(r["eval_psnr"]):+.2f}'
        lines.append(f'| {preset} | {model} | {num(r, "eval_psnr", ".2f")} | {gain} | {num(r, "eval_ssim", ".3f")} | '
                     f'{num(r, "eval_surface_rmse", ".4f")} | {num(r, "initial_flat_surface_rmse", ".4f")} | {num(r, "surface_correlation", ".2f")} | '
                     f'{num(r, "surface_sweep_ratio", ".3f")} | '
                     f'{num(r, "training_seconds", ".0f")} | {r.get("gaussians", "-")} |' + (earlier_cell(preset, model) if earlier else ""))
open(summary, "w").write("\n".join(lines) + "\n")
EOF
mv "$summary" "$out/summary.md.tmp" && mv "$out/summary.md.tmp" "$out/summary.md"
echo "presets.sh: $(suite_elapsed) s"
cat "$out/summary.md"
