#!/usr/bin/env bash
# What refraction buys where it matters (issue 6): test PSNR and surface RMSE of six models
# on the strong-refraction tiny preset, seed by seed, each against --no-refraction on the
# same data, seed, patch size and steps (docs/experiments/2026-11-26-strong-refraction.md and the long training test):
#   no-refraction   plain 3DGRT, straight rays
#   reference       refraction with the reference surface settings (6 octaves, lr 5e-4)
#   short-run       refraction with the short-run surface settings: 3 octaves, --surface-lr
#                   3e-3, --surface-freeze 400, --anchor-mean-height
#   restart         short-run plus --level-prior 1000 and --restart-gaussians at 2/5 of the
#                   steps (1,200 of 3,000)
#   sweep           short-run plus --level-prior 1000, --init-depth sweep and restarts at 1/3,
#                   8/15 and 11/15 of the steps (1,000, 1,600, 2,200 of 3,000): each restart
#                   draws the Gaussians at a plane sweep's depth through the learned water
#   known-water     the true water fixed (oracle): the ceiling a perfect surface gives
# Data: refrax synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2
#   (a 5 cm sine, wavelength 0.5 m, slope 0.63; 8 training views, 1 test view).
# Training: 3,000 steps of 64 x 64 patches, 2,000 initial Gaussians capped at 4,000, no density
#   resets, SH degree 0. About 40 minutes per seed on this 2-core lavapipe machine.
#
# Usage: bench/refraction-gain.sh [--seeds 1,2] [--steps N] [--out DIR]
#   --seeds S,...  seeds to run (default 1)
#   --steps N      override the step count (a quick check of the script)
#   --out DIR      report folder (default bench/results/refraction-gain/)
# Writes DIR/refraction-gain.csv (one row per run, `refrax report` columns plus setting and
# seed) and DIR/summary.md (device, load, sizes, and the table with the gain over no-refraction).
set -euo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-./build/refrax}

seeds=1
steps=3000
out=bench/results/refraction-gain
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) [ $# -ge 2 ] || { echo "refraction-gain.sh: --seeds needs a list" >&2; exit 2; }; seeds=$2; shift ;;
    --steps) [ $# -ge 2 ] || { echo "refraction-gain.sh: --steps needs a number" >&2; exit 2; }; steps=$2; shift ;;
    --out) [ $# -ge 2 ] || { echo "refraction-gain.sh: --out needs a folder" >&2; exit 2; }; out=$2; shift ;;
    -h|--help) sed -n '2,/^set -/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "refraction-gain.sh: unknown option '$1' (--seeds, --steps, --out)" >&2; exit 2 ;;
  esac
  shift
done
case "$steps" in '' | *[!0-9]*) echo "refraction-gain.sh: --steps must be a positive number" >&2; exit 2 ;; esac
. bench/ensure-build.sh
ensure_refrax refraction-gain.sh "$REFRAX"

mkdir -p "$out"
work=$(mktemp -d "${TMPDIR:-/tmp}/refrax-refraction-gain.XXXXXX")
trap 'rm -rf "$work"' EXIT
device=$("$REFRAX" devices | sed -n '1s/^\[[0-9]*\] //p')
load=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)
start=$(date +%s)
echo "refraction-gain on $device -> $out"

data=$work/strong-refraction
"$REFRAX" synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2 -o "$data" > "$work/synth.log" 2>&1 ||
  { cat "$work/synth.log" >&2; exit 1; }

common=(--steps "$steps" --patch 64 --gaussians 2000 --max-gaussians 4000 --density-reset-every 0 --sh-degree 0
  --checkpoint-every 0 --progress-every 100000)
short_run=(--mlp-coarse-octaves 3 --octaves-open-until 10000000 --surface-lr 3e-3 --surface-freeze 400 --anchor-mean-height)
csv=$work/refraction-gain.csv
mkdir -p "$work/runs"
for seed in ${seeds//,/ }; do
  for setting in no-refraction reference short-run restart sweep known-water; do
    case $setting in
      no-refraction) extra=(--no-refraction) ;;
      reference) extra=() ;;
      short-run) extra=("${short_run[@]}") ;;
      restart) extra=("${short_run[@]}" --level-prior 1000 --restart-gaussians $((steps * 2 / 5))) ;;
      sweep) extra=("${short_run[@]}" --level-prior 1000 --init-depth sweep
        --restart-gaussians $((steps / 3)),$((steps * 8 / 15)),$((steps * 11 / 15))) ;;
      known-water) extra=(--known-water) ;;
    esac
    run=$work/runs/$setting-$seed
    t0=$(date +%s)
    "$REFRAX" train "$data" -o "$run" --seed "$seed" "${common[@]}" "${extra[@]}" > "$run.log" 2>&1 ||
      { tail -n 5 "$run.log" >&2; echo "refraction-gain.sh: $setting (seed $seed) failed" >&2; exit 1; }
    "$REFRAX" report "$run" -o "$csv" --append --set "setting=$setting,seed=$seed" > /dev/null
    echo "  $setting, seed $seed: $(tail -n 1 "$run.log") [$(($(date +%s) - t0)) s wall]"
  done
done

# The table: per seed and setting, PSNR, its gain over no-refraction (same seed) and surface RMSE.
python3 - "$csv" "$work/summary.md" "$device" "$load" "$steps" "$(($(date +%s) - start))" <<'EOF'
import csv, sys
path, summary, device, load, steps, seconds = sys.argv[1:]
rows = list(csv.DictReader(open(path)))
plain = {r["seed"]: float(r["psnr"]) for r in rows if r["setting"] == "no-refraction"}
lines = [
    "# Refraction gain on the strong-refraction tiny preset", "",
    f"Device: {device}. Load average at the start: {load}. Wall time: {seconds} s.", "",
    "Data: `refrax synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2`.",
    f"Training: {steps} steps of 64 x 64 patches, 2,000 initial Gaussians capped at 4,000, no density resets, SH degree 0.", "",
    "| setting | seed | test PSNR (dB) | gain over no-refraction (dB) | SSIM | surface RMSE (m) | flat start (m) | training (s) |",
    "|---|---|---|---|---|---|---|---|",
]
for r in rows:
    gain = float(r["psnr"]) - plain[r["seed"]]
    rmse = f'{float(r["surface_rmse"]):.4f}' if r.get("surface_rmse") else "-"
    lines.append(f'| {r["setting"]} | {r["seed"]} | {float(r["psnr"]):.2f} | {gain:+.2f} | {float(r["ssim"]):.3f} | {rmse} | '
                 f'{float(r["initial_flat_surface_rmse"]):.4f} | {float(r["training_seconds"]):.0f} |')
open(summary, "w").write("\n".join(lines) + "\n")
EOF
mv "$csv" "$out/refraction-gain.csv.tmp" && mv "$out/refraction-gain.csv.tmp" "$out/refraction-gain.csv"
mv "$work/summary.md" "$out/summary.md.tmp" && mv "$out/summary.md.tmp" "$out/summary.md"
cat "$out/summary.md"
