#!/usr/bin/env bash
# Scenes no one tunes to (issue 45, part 1): the method against straight rays, the flat plane,
# the dry control and the known-water oracle on random scenes (`refrax synth random --seed N`:
# 1-4 sines and ripples over the stability chart's slopes, IOR 1.1-1.5, top-down grids and
# rings, 96-400 px, floor relief and objects, with and without a dry rim), scenes x training
# seeds. Five models per scene and seed, on the same data, seed and steps:
#   method         `refrax train DATA` with no method flags (the defaults are the method)
#   no-refraction  --no-refraction (straight rays)
#   flat-water     --flat-water (a learned flat plane)
#   dry-control    --no-refraction on `refrax synth random --seed N --dry` (the same views
#                  without the water: what the Gaussians reach at this budget)
#   known-water    --known-water (the true surface, fixed: the oracle)
# Each run is trained, then `refrax eval RUN` (eval.json), `bench/surface-error.py` (the
# amplitude ratio over the square the test views see, scene.json's test_view_half) and
# `refrax report` (its row). bench/generalise-summary.py then writes per scene and seed the
# gain over straight rays, the gap to the oracle, the surface RMSE against the flat start, the
# amplitude ratio, the correlation and the failures, and over the set their medians and rates.
#
# Two sets of scenes (bench/results/generalise/README.md): dev (scene seeds 1, 2, ...) is for
# development, look at it as often as you like; eval (scene seeds 1001, 1002, ...) is the
# evaluation set and is never tuned on: run it to report, not to choose settings.
#
# Usage: bench/generalise.sh [--set dev|eval] [--scenes N] [--seeds S] [--steps N] [--jobs N]
#                            [--dataset-size tiny|full] [--out DIR] [--resume | --charts-only]
#                            [--method-flags "FLAGS"] [--train-flags "FLAGS"] [--models "LIST"]
#                            [--baseline DIR] [--keep-work] [--smoke]
#   --set      dev (default) or eval
#   --scenes N the set's first N scenes (default 12); --seeds S training seeds 1..S (default 2)
#   --seed-list "A B ..."  these training seeds instead (more seeds of an earlier screen, in
#              a folder of their own)
#   --scene-list "A B ..."  these scenes of the set instead (dev: 1-1000, eval: 1001 on), e.g.
#              the dev scenes where the oracle leads straight rays, to choose among candidates
#   --steps N  every model trains N steps (default: refrax train's own default, what a user gets)
#   --jobs N   trainings at a time (default 1; a GPU machine takes several)
#   --method-flags "FLAGS"  a candidate default: the method trains with these flags added (the
#              other models do not); recorded in the settings, so compare two --out folders
#              of the same scenes and seeds, one without. Choose on dev, then check on eval.
#   --train-flags "FLAGS"  flags every model trains with (a CPU study's --patch, say); recorded
#              in the settings
#   --models "LIST"  train only these of the five models (default all; the summary leaves the
#              others' columns empty)
#   --baseline DIR   take the rows of the models other than the method from DIR, an earlier
#              invocation with the same set, scenes, seeds, steps, size and train flags: candidate
#              method flags (or code) are then compared against one trained set of straight rays,
#              flat planes, dry controls and oracles; other training code is recorded, not refused
#   --dataset-size  tiny caps the scenes at 64 px (CI); default full: the drawn 96-400 px
#   --resume   keep the rows in DIR/rows from an earlier invocation with the same settings and
#              the same training code (git's hash of engine/ shaders/ trainer/ CMakeLists.txt;
#              refused outside a clean checkout), and train only the missing runs
#   --charts-only  the table, summary.md and charts again from DIR/runs.csv
#   --smoke    1 scene, 1 seed, 20 steps, tiny: checks the pipeline, not the method
# Writes DIR (default bench/results/generalise/<set>/): runs.csv (`refrax report` rows with
# set, scene, seed, variant (the model above), exit code, eval.json's numbers and the amplitude ratio), scenes/
# (each scene's scene.json: what it was), table.csv and summary.md (bench/generalise-summary.py),
# psnr.svg and gain.svg, run_info.txt, failures.txt (runs that exited non-zero).
# Time: five trainings per scene and seed; at refrax train's defaults (15,000 whole-image
# steps) a GPU's work. On this 2-core machine use --dataset-size tiny and a few thousand steps.
set -euo pipefail
. "$(dirname "$0")/suite-lib.sh"
set_name=dev
scenes=12
seeds=2
scene_list_arg=""
seed_list_arg=""
steps=""
jobs=1
method_flags=""
train_flags=""
models_arg=""
baseline=""
resume=0
dataset_size=full
smoke=0
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --set) [ $# -ge 2 ] && { [ "$2" = dev ] || [ "$2" = eval ]; } || { echo "generalise: --set needs dev or eval" >&2; exit 2; }; set_name=$2; shift ;;
    --scenes) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "generalise: --scenes needs a count" >&2; exit 2; }; scenes=$2; shift ;;
    --scene-list) [ $# -ge 2 ] && [[ $2 =~ ^[0-9\ ]*[1-9][0-9\ ]*$ ]] || { echo "generalise: --scene-list needs scene numbers, quoted as one argument" >&2; exit 2; }; scene_list_arg=$2; shift ;;
    --seed-list) [ $# -ge 2 ] && [[ $2 =~ ^[0-9\ ]*[1-9][0-9\ ]*$ ]] || { echo "generalise: --seed-list needs seed numbers, quoted as one argument" >&2; exit 2; }; seed_list_arg=$2; shift ;;
    --seeds) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "generalise: --seeds needs a count" >&2; exit 2; }; seeds=$2; shift ;;
    --steps) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "generalise: --steps needs a step count" >&2; exit 2; }; steps=$2; shift ;;
    --jobs) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "generalise: --jobs needs a count" >&2; exit 2; }; jobs=$2; shift ;;
    --method-flags) [ $# -ge 2 ] || { echo "generalise: --method-flags needs the flags, quoted as one argument" >&2; exit 2; }; method_flags=$2; shift ;;
    --train-flags) [ $# -ge 2 ] || { echo "generalise: --train-flags needs the flags, quoted as one argument" >&2; exit 2; }; train_flags=$2; shift ;;
    --models) [ $# -ge 2 ] || { echo "generalise: --models needs a list of models" >&2; exit 2; }; models_arg=$2; shift ;;
    --baseline) [ $# -ge 2 ] && [ -f "$2/run_info.txt" ] || { echo "generalise: --baseline needs an earlier invocation's folder (with run_info.txt)" >&2; exit 2; }; baseline=$(cd "$2" && pwd); shift ;;
    --dataset-size) [ $# -ge 2 ] && { [ "$2" = tiny ] || [ "$2" = full ]; } || { echo "generalise: --dataset-size needs tiny or full" >&2; exit 2; }; dataset_size=$2; shift ;;
    --resume) resume=1 ;;
    --smoke) smoke=1 ;;
    --full) echo "generalise: no --full mode: the scenes are drawn at their own size (--dataset-size tiny caps them)" >&2; exit 2 ;;
    *) args+=("$1") ;;
  esac
  shift
done
# --out's default names the set (a later --out wins)
args=(--out "$(dirname "$0")/results/generalise/$set_name" ${args[@]+"${args[@]}"})
suite_parse_args generalise ${args[@]+"${args[@]}"}
if [ $smoke = 1 ]; then scenes=1 seeds=1 steps=20 dataset_size=tiny; fi
[ $resume = 0 ] || [ $charts_only = 0 ] || { echo "generalise: --resume or --charts-only, not both" >&2; exit 2; }

# The two sets never share a scene: the evaluation set's seeds start at 1001.
first=1
[ "$set_name" = eval ] && first=1001
scene_list=$(seq "$first" $((first + scenes - 1)))
if [ -n "$scene_list_arg" ] && [ $smoke = 0 ]; then
  scene_list=$(echo $scene_list_arg)
  for scene in $scene_list; do
    { [ "$set_name" = eval ] && [ "$scene" -ge 1001 ]; } || { [ "$set_name" = dev ] && [ "$scene" -le 1000 ]; } ||
      { echo "generalise: --scene-list: scene $scene is not in the $set_name set (dev: 1-1000, eval: 1001 on)" >&2; exit 2; }
  done
fi
seed_list=$(seq 1 "$seeds")
if [ -n "$seed_list_arg" ] && [ $smoke = 0 ]; then
  seed_list=$(echo $seed_list_arg)
  seeds=$(echo $seed_list | wc -w)
fi
all_models=(method no-refraction flat-water dry-control known-water)
models=("${all_models[@]}")
if [ -n "$models_arg" ]; then
  read -r -a models <<<"$models_arg"
  for m in "${models[@]}"; do
    [[ " ${all_models[*]} " == *" $m "* ]] || { echo "generalise: --models: no model '$m' (${all_models[*]})" >&2; exit 2; }
  done
fi
[ -z "$baseline" ] || [ $resume = 0 ] || { echo "generalise: --baseline or --resume, not both" >&2; exit 2; }
model_options() {
  case $1 in
    method) echo "$method_flags" ;;
    no-refraction|dry-control) echo "--no-refraction" ;;
    flat-water) echo "--flat-water" ;;
    known-water) echo "--known-water" ;;
  esac
}
train_steps=()
[ -z "$steps" ] || train_steps=(--steps "$steps")
# What the rows of every model depend on (a --baseline must match it), then the method's own flags.
common_settings="set $set_name, scenes $(echo $scene_list | tr ' ' ','), training seeds $(echo $seed_list | tr ' ' ','), ${steps:-default} steps, dataset size $dataset_size${train_flags:+, train flags $train_flags}"
settings="$common_settings${method_flags:+, method flags $method_flags}"
rows=$out/rows

if [ $charts_only = 0 ]; then
  # The training code the rows come from (as bench/stability.sh): --resume keeps rows only
  # from the same code and settings.
  code_paths=(engine shaders trainer CMakeLists.txt)
  code=unknown
  if (cd "$suite_root" && git rev-parse --git-dir >/dev/null 2>&1 && [ -z "$(git status --porcelain -- "${code_paths[@]}")" ]); then
    code=$(cd "$suite_root" && git ls-tree HEAD "${code_paths[@]}" | git hash-object --stdin)
  fi
  if [ $resume = 1 ] && [ -d "$rows" ]; then
    earlier_settings=$(sed -n 's/^settings=//p' "$out/run_info.txt" 2>/dev/null)
    earlier_code=$(sed -n 's/^code=//p' "$out/run_info.txt" 2>/dev/null)
    if [ "$earlier_settings" != "$settings" ]; then
      echo "generalise: --resume: the rows in $out come from other settings (${earlier_settings:-not recorded}), not these ($settings)" >&2; exit 2
    fi
    if [ "$code" = unknown ] || [ "$earlier_code" != "$code" ]; then
      echo "generalise: --resume: the rows in $out come from training code ${earlier_code:-not recorded}, and this checkout's is $code" \
           "(git's hash of ${code_paths[*]}; unknown outside a clean git checkout): train them again without --resume" >&2; exit 2
    fi
  else
    rm -rf "$rows" "$out/scenes" "$out/failures.txt"
  fi
  mkdir -p "$rows" "$out/scenes"
  printf 'settings=%s\ncommon_settings=%s\nmodels=%s\ncode=%s\ndevice=%s\nstarted=%s\n' "$settings" "$common_settings" "${models[*]}" "$code" "$device" \
    "$(date -u '+%Y-%m-%d %H:%M UTC')" >"$out/run_info.txt"
  if [ -n "$baseline" ]; then
    # The other models' rows from an earlier invocation of the same scenes, seeds, steps and
    # training code: only the method trains here.
    base_settings=$(sed -n 's/^common_settings=//p' "$baseline/run_info.txt")
    base_code=$(sed -n 's/^code=//p' "$baseline/run_info.txt")
    [ "$base_settings" = "$common_settings" ] ||
      { echo "generalise: --baseline: $baseline was trained with other settings (${base_settings:-not recorded}), not these ($common_settings)" >&2; exit 2; }
    # Other training code is allowed (a candidate default is often a code change) but recorded:
    # the summary's settings name the baseline's code beside this one's.
    if [ "$base_code" != "$code" ]; then
      echo "generalise: --baseline: $baseline comes from training code ${base_code:-not recorded}, this checkout's is $code: recorded in run_info.txt" >&2
      printf 'baseline_code=%s\n' "${base_code:-not recorded}" >>"$out/run_info.txt"
      settings="$settings, other models' rows from training code ${base_code:-not recorded}"
    fi
    for m in "${all_models[@]}"; do
      [ "$m" != method ] || continue
      for f in "$baseline"/rows/scene_*_"$m".csv; do
        [ -f "$f" ] && cp "$f" "$rows/"
      done
    done
    cp "$baseline"/scenes/scene_*.json "$out/scenes/" 2>/dev/null || true
    baseline_models=$(sed -n 's/^models=//p' "$baseline/run_info.txt")
    for m in $baseline_models; do
      [ "$m" = method ] || [[ " ${models[*]} " == *" $m "* ]] || models+=("$m")
    done
  fi

  # The datasets first (each scene and its dry copy), then the runs, $jobs at a time.
  for scene in $scene_list; do
    for variant in wet dry; do
      data=$work/data/scene_${scene}_$variant
      [ ! -d "$data" ] || continue
      [ $variant = wet ] || [[ " ${models[*]} " == *" dry-control "* ]] || continue
      extra=()
      [ $variant = wet ] || extra=(--dry)
      mkdir -p "$work/data"
      "$REFRAX" synth random --seed "$scene" --size "$dataset_size" ${extra[@]+"${extra[@]}"} -o "$data" >"$work/synth_${scene}_$variant.log" 2>&1 ||
        { cat "$work/synth_${scene}_$variant.log" >&2; echo "generalise: refrax synth random --seed $scene failed" >&2; exit 1; }
    done
    # what was drawn, and the image size trained on (--dataset-size tiny caps the drawn width)
    python3 - "$work/data/scene_${scene}_wet" "$out/scenes/scene_$scene.json" <<'PY'
import json, sys
data, dest = sys.argv[1:]
s = json.load(open(data + '/scene.json'))
t = json.load(open(data + '/transforms_train.json'))
s['dataset_width'], s['dataset_height'] = t['w'], t['h']
json.dump(s, open(dest, 'w'), indent=2)
PY
    echo "scene $scene: $(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["summary"])' "$out/scenes/scene_$scene.json")"
  done

  # One run: train, eval, the amplitude ratio, its report row -> rows/KEY.csv (or a failure).
  one_run() {  # scene seed model
    local scene=$1 seed=$2 model=$3 key="scene_${1}_seed_${2}_$3" data run t0 code=0 ratio="" half
    data=$work/data/scene_${scene}_wet
    [ "$model" != dry-control ] || data=$work/data/scene_${scene}_dry
    run=$work/runs/$key
    rm -rf "$run"
    mkdir -p "$work/runs"
    t0=$(date +%s)
    # shellcheck disable=SC2046
    "$REFRAX" train "$data" -o "$run" --seed "$seed" ${train_steps[@]+"${train_steps[@]}"} $train_flags $(model_options "$model") \
      --checkpoint-every 0 --progress-every 100000 >"$work/runs/$key.log" 2>&1 || code=$?
    if [ $code = 0 ]; then
      "$REFRAX" eval "$run" -o "$run/eval.json" >"$work/runs/$key.eval.log" 2>&1 || code=$?
    fi
    if [ $code != 0 ]; then
      echo "$key: FAILED (exit $code: $(tail -n 1 "$work/runs/$key.log"))" | tee -a "$out/failures.txt" >&2
      printf 'exit_code=%s\n' "$code" >"$rows/$key.failed"
      return 0
    fi
    if [ -f "$run/water_height.npy" ]; then
      half=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["test_view_half"])' "$data/scene.json")
      ratio=$(python3 "$suite_root/bench/surface-error.py" "$run" "$data" "$half" 2>/dev/null | sed -n 's/.*amplitude ratio \([-0-9.naninf]*\).*/\1/p') || ratio=""
    fi
    local cols
    cols=$(python3 - "$run/eval.json" <<'PY'
import json, math, sys
m = json.load(open(sys.argv[1]), parse_constant=lambda c: float('nan'))
def f(k):
    v = m.get(k)
    return '' if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v) else '%.6g' % v
print(','.join('%s=%s' % (c, f(k)) for c, k in (('eval_psnr', 'psnr'), ('eval_ssim', 'ssim'), ('eval_surface_rmse', 'surface_rmse'),
               ('eval_flat_rmse', 'initial_flat_surface_rmse'), ('eval_correlation', 'surface_correlation'),
               ('eval_water_removal_psnr', 'water_removal_psnr'))))
PY
) || { echo "$key: eval.json unreadable" | tee -a "$out/failures.txt" >&2; printf 'exit_code=eval\n' >"$rows/$key.failed"; return 0; }
    "$REFRAX" report "$run" -o "$rows/$key.csv.tmp" \
      --set "set=$set_name,scene=$scene,seed=$seed,variant=$model,exit_code=0,$cols,amplitude_ratio=$ratio,wall_seconds=$(( $(date +%s) - t0 ))" >/dev/null ||
      { echo "$key: refrax report failed" | tee -a "$out/failures.txt" >&2; printf 'exit_code=report\n' >"$rows/$key.failed"; return 0; }
    mv "$rows/$key.csv.tmp" "$rows/$key.csv"
    echo "$(date -u +%H:%M:%S) $key: $(python3 -c 'import json, sys; m = json.load(open(sys.argv[1])); print("%.2f dB" % m["psnr"])' "$run/eval.json"), $(( $(date +%s) - t0 )) s" >&2
  }

  stopped=0
  trap 'stopped=1' TERM INT
  for scene in $scene_list; do
    for seed in $seed_list; do
      for model in "${models[@]}"; do
        key="scene_${scene}_seed_${seed}_$model"
        [ ! -f "$rows/$key.csv" ] || continue  # kept by --resume
        rm -f "$rows/$key.failed"
        while [ "$(jobs -rp | wc -l)" -ge "$jobs" ] && [ $stopped = 0 ]; do wait -n || true; done
        [ $stopped = 0 ] || break 3
        one_run "$scene" "$seed" "$model" &
      done
    done
  done
  while [ "$(jobs -rp | wc -l)" -gt 0 ] && [ $stopped = 0 ]; do wait -n || true; done
  if [ $stopped = 1 ]; then
    echo "generalise: stopped: the table holds the runs that finished (--resume trains the rest)" >&2
    for job in $(jobs -rp); do pkill -TERM -P "$job"; kill "$job"; done 2>/dev/null || true
    wait || true
  fi

  # runs.csv: every finished run's row (header once), in the order of the loops.
  : >"$out/runs.csv.tmp"
  for scene in $scene_list; do
    for seed in $seed_list; do
      for model in "${models[@]}"; do
        f=$rows/scene_${scene}_seed_${seed}_$model.csv
        [ -f "$f" ] || continue
        if [ -s "$out/runs.csv.tmp" ]; then tail -n +2 "$f" >>"$out/runs.csv.tmp"; else cat "$f" >>"$out/runs.csv.tmp"; fi
      done
    done
  done
  mv "$out/runs.csv.tmp" "$out/runs.csv"
  printf 'finished=%s\nseconds=%d\n' "$(date -u '+%Y-%m-%d %H:%M UTC')" "$(suite_elapsed)" >>"$out/run_info.txt"
fi
[ -s "$out/runs.csv" ] || { echo "generalise: no run finished (see $out/failures.txt)" >&2; exit 1; }

# The table, the summary and the charts' CSVs.
python3 "$suite_root/bench/generalise-summary.py" "$out" --models "${models[*]}" --expected-runs $(( $(echo $scene_list | wc -w) * seeds * ${#models[@]} )) \
  --device "$device" --settings "$settings"
suite_chart "$out/chart_psnr.csv" -o "$out/psnr.svg" --x slope_bound --y psnr --series model \
  --title "Test PSNR against the scene's wave slope ($set_name set)" --x-label "slope bound (water.json)" --y-label "test PSNR (dB, mean over seeds)"
# (the gain chart needs the oracle and straight rays: a --models subset may have neither)
[ "$(wc -l <"$out/chart_gain.csv")" -lt 2 ] || suite_chart "$out/chart_gain.csv" -o "$out/gain.svg" --x oracle_lead --y gain --series rig \
  --title "The method's gain over straight rays against the oracle's ($set_name set)" --x-label "oracle - straight rays (dB)" \
  --y-label "method - straight rays (dB)" --hline "0:straight rays"
echo "generalise: done in $(suite_elapsed) s -> $out/summary.md"
