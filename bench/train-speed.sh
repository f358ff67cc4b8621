#!/usr/bin/env bash
# Training speed: the refraction model against --flat-water and --no-refraction, side by side in
# one run on one device, with each run's per-stage profile (metrics.json "profile", the same as
# `refrax train --profile`). Workloads:
#   demo   scripts/demo.sh's data and settings: tiny nerfrac-primary-sine (64 px, 8 views),
#          1,500 steps of 32 x 32 patches, 2,000 -> 4,000 Gaussians, the demo's refraction flags
#   whole  the same data and settings with whole 64 x 64 images per step (the paper's batch), 500 steps
#   full   full-size nerfrac-primary-sine (392 px), 6,000 steps of 32 x 32 patches, the full-size
#          presets table's settings (bench/presets.sh --dataset-size full --steps 6000)
#
# Usage: bench/train-speed.sh [--smoke] [--out DIR] [--keep-work] [--workloads demo,whole,full]
#   default  every workload (about 25 minutes on this 2-core lavapipe machine)
#   --smoke  the demo and whole workloads at 40 steps (checks the pipeline, not the speed)
# Writes DIR/runs.csv (one row per run: workload, model, steps, training seconds, ms per step,
# GPU and host ms per step, submits and dispatches per step, the Gaussian trace's share of the
# step, test PSNR, surface RMSE), DIR/<workload>-<model>.profile.json (the run's profile) and
# DIR/summary.md (the device, and per workload the ratio of each model's step to
# --no-refraction's, and each model's costliest stages).
set -euo pipefail
. "$(dirname "$0")/suite-lib.sh"
invocation="bench/train-speed.sh${1:+ $*}"
workloads=demo,whole,full
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --workloads) [ $# -ge 2 ] || { echo "train-speed: --workloads needs a list" >&2; exit 2; }; workloads=$2; shift ;;
    --full) echo "train-speed: --full is not a mode of this suite (the full-size workload is in the default run)" >&2; exit 2 ;;
    *) args+=("$1") ;;
  esac
  shift
done
suite_parse_args train-speed ${args[@]+"${args[@]}"}
for w in ${workloads//,/ }; do
  case $w in demo|whole|full) ;; *) echo "train-speed: unknown workload '$w' (demo, whole, full)" >&2; exit 2 ;; esac
done
[ $mode = smoke ] && workloads=$(echo ",$workloads," | sed 's/,full,/,/g; s/^,//; s/,$//')

# The demo's flags (scripts/demo.sh), its restarts and freeze scaled with the steps.
common="--gaussians 2000 --max-gaussians 4000 --density-reset-every 0 --sh-degree 0"
refraction_flags() {  # steps
  echo "--mlp-coarse-octaves 3 --octaves-open-until 100000000 --surface-lr 3e-3 --surface-freeze $(($1 * 2 / 15))" \
       "--anchor-mean-height --level-prior 1000 --init-depth sweep --restart-gaussians $(($1 / 3)),$(($1 * 8 / 15)) --surface-batch views"
}
csv=$out/runs.csv
[ $charts_only = 1 ] || echo "workload,model,steps,training_seconds,ms_per_step,gpu_ms_per_step,host_ms_per_step,submits_per_step,dispatches_per_step,trace_share,psnr,surface_rmse" > "$csv"

run_workload() {  # workload preset size steps [options...]
  local workload=$1 preset=$2 dsize=$3 steps=$4
  shift 4
  local data
  size=$dsize
  data=$(suite_dataset "$preset")
  echo "$workload: $preset ($dsize), $steps steps $*"
  for model in refraction flat-water no-refraction; do
    local flags="--$model"
    # shellcheck disable=SC2046
    [ $model = refraction ] && flags=$(refraction_flags "$steps")
    # shellcheck disable=SC2086
    suite_warmup "$data" $common "$@" $flags
    local run=$work/runs/$workload-$model
    rm -rf "$run"
    mkdir -p "$work/runs"
    # shellcheck disable=SC2086
    if ! "$REFRAX" train "$data" -o "$run" --steps "$steps" $common "$@" $flags --checkpoint-every 0 --progress-every 100000 \
         > "$work/runs/$workload-$model.log" 2>&1; then
      echo "  $model: FAILED ($(tail -n 1 "$work/runs/$workload-$model.log"))" | tee -a "$out/failures.txt"
      continue
    fi
    python3 - "$run/metrics.json" "$csv" "$workload" "$model" "$steps" "$out/$workload-$model.profile.json" <<'EOF'
import json, sys
metrics, csv, workload, model, steps, profile_out = sys.argv[1:]
m = json.load(open(metrics))
p = m["profile"]
json.dump(p, open(profile_out, "w"), indent=1, sort_keys=True)
trace = p["gpu"].get("gaussian forward", 0) + p["gpu"].get("gaussian backward", 0)
row = [workload, model, steps, f'{m["training_seconds"]:.2f}', f'{p["wall_ms_per_step"]:.3f}', f'{p["gpu_ms_per_step"]:.3f}',
       f'{p["host_ms_per_step"]:.3f}', f'{p["submits_per_step"]:.2f}', f'{p["dispatches_per_step"]:.1f}',
       f'{trace / p["wall_ms_per_step"]:.3f}', f'{m["psnr"]:.3f}', f'{m["surface_rmse"]:.5f}' if "surface_rmse" in m else ""]
open(csv, "a").write(",".join(str(x) for x in row) + "\n")
EOF
    echo "  $model: $(tail -n 1 "$work/runs/$workload-$model.log")"
  done
}

if [ $charts_only = 0 ]; then
  rm -f "$out/failures.txt"
  demo_steps=1500 whole_steps=500 full_steps=6000
  [ $mode = smoke ] && demo_steps=40 whole_steps=40
  for w in ${workloads//,/ }; do
    case $w in
      demo) run_workload demo nerfrac-primary-sine tiny $demo_steps --patch 32 ;;
      whole) run_workload whole nerfrac-primary-sine tiny $whole_steps --patch 0 ;;
      full) run_workload full nerfrac-primary-sine full $full_steps --patch 32 ;;
    esac
  done
  load_line=$(suite_load_line)
else
  load_line="Summary rebuilt from runs.csv."
fi

python3 - "$csv" "$out" "$out/summary.md" <<EOF
import csv, json, os, sys
path, out, summary = sys.argv[1:]
rows = list(csv.DictReader(open(path)))
lines = ["# Training speed: refraction against a flat plane and straight rays, side by side", "",
         "Device: $device. Generated by \`$invocation\` on $(date -u +%Y-%m-%d). $load_line", "",
         "Each workload's three models run one after the other on this device, each after a discarded 4-step warm-up (shader",
         "compilation). *ms/step* is training wall time per step (evaluations excluded) from the run's profile; *ratio* is a",
         "model's step over the --no-refraction step of the same workload; *trace share* is the Gaussian forward and backward's",
         "GPU time over the whole step (the rest is loss, optimisers, densification, the water and host work).", "",
         "| workload | model | steps | training (s) | ms/step | ratio | GPU ms | host ms | submits | dispatches | trace share | test PSNR | surface RMSE |",
         "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
for w in dict.fromkeys(r["workload"] for r in rows):
    base = next((float(r["ms_per_step"]) for r in rows if r["workload"] == w and r["model"] == "no-refraction"), None)
    for r in (r for r in rows if r["workload"] == w):
        ratio = f'{float(r["ms_per_step"]) / base:.2f}x' if base else "-"
        lines.append(f'| {w} | {r["model"]} | {r["steps"]} | {float(r["training_seconds"]):.1f} | {float(r["ms_per_step"]):.2f} | {ratio} | '
                     f'{float(r["gpu_ms_per_step"]):.2f} | {float(r["host_ms_per_step"]):.2f} | {float(r["submits_per_step"]):.1f} | '
                     f'{float(r["dispatches_per_step"]):.0f} | {float(r["trace_share"]):.2f} | {float(r["psnr"]):.2f} | {r["surface_rmse"] or "-"} |')
lines += ["", "The costliest stages of each run (mean ms per step; GPU stages from timestamps, host stages timed on the host):", ""]
for r in rows:
    f = os.path.join(out, f'{r["workload"]}-{r["model"]}.profile.json')
    if not os.path.exists(f):
        continue
    p = json.load(open(f))
    stages = [(ms, name, "GPU") for name, ms in p["gpu"].items()] + [(ms, name, "host") for name, ms in p["host"].items()]
    stages.sort(reverse=True)
    top = ", ".join(f"{name} {ms:.2f}" for ms, name, _ in stages[:6])
    lines.append(f'- {r["workload"]} {r["model"]}: {top}; unattributed host {p["host_ms_per_step"] - sum(ms for ms, _, w in stages if w == "host"):.2f}')
open(summary, "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
EOF
echo "train-speed: $(suite_elapsed) s; $out/summary.md"
