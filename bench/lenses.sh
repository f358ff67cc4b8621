#!/usr/bin/env bash
# Distorted cameras against a pinhole (issue 50's goal): one preset synthesised through each
# camera model at the same pixel count (refrax synth --camera-model pinhole|opencv|fisheye:
# OpenCV's k1 = -0.25, a 180-degree diagonal equidistant fisheye), each trained with the same
# flags on each seed, no undistortion anywhere. A lens traced right trains about as well as the
# pinhole; one misread leaves the views inconsistent and costs dBs.
#
# Usage: bench/lenses.sh [--seeds "1 2 3"] [--steps N] [--preset NAME] [--size tiny|full]
#                        [--flags "FLAGS"] [--out DIR]
# Writes DIR/runs.csv (refrax report rows, one per model and seed) and DIR/summary.txt (test
# PSNR per seed, median and spread per model, each model's median minus the pinhole's).
# Defaults: nerfrac-primary-sine, tiny, 1,000 steps of the training defaults, seeds 1 2 3,
# DIR bench/results/lenses.
set -euo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-build/refrax}
seeds="1 2 3"
steps=1000
preset=nerfrac-primary-sine
size=tiny
flags=""
out=bench/results/lenses
while [ $# -gt 0 ]; do
  case $1 in
    --seeds) seeds=$2; shift ;;
    --steps) steps=$2; shift ;;
    --preset) preset=$2; shift ;;
    --size) size=$2; shift ;;
    --flags) flags=$2; shift ;;
    --out) out=$2; shift ;;
    *) echo "lenses.sh: unknown option $1 (see the header)" >&2; exit 2 ;;
  esac
  shift
done
[ -x "$REFRAX" ] || { echo "lenses.sh: no $REFRAX (build first, or set REFRAX)" >&2; exit 2; }
export MESA_SHADER_CACHE_DIR=${MESA_SHADER_CACHE_DIR:-$PWD/.cache/mesa-shader-cache}
work=$out/work
mkdir -p "$work"
models="pinhole opencv fisheye"
runs=()
for model in $models; do
  data=$work/data-$model
  [ -f "$data/transforms_train.json" ] || "$REFRAX" synth "$preset" --size "$size" --camera-model "$model" -o "$data" > /dev/null
  for seed in $seeds; do
    run=$work/$model-seed$seed
    # shellcheck disable=SC2086  # FLAGS is a list of options
    [ -f "$run/metrics.json" ] || "$REFRAX" train "$data" -o "$run" --recipe reference --steps "$steps" --seed "$seed" --progress-every 250 $flags > "$run.line" 2> "$run.log" ||
      { echo "lenses.sh: training $model seed $seed failed ($run.log)" >&2; exit 1; }
    echo "$model seed $seed: $(cat "$run.line")"
    runs+=("$run")
  done
done
"$REFRAX" report "${runs[@]}" -o "$out/runs.csv" > /dev/null
python3 - "$out/runs.csv" "$preset" "$size" "$steps" "$flags" <<'EOF' | tee "$out/summary.txt"
import csv, statistics, sys
path, preset, size, steps, flags = sys.argv[1:]
rows = list(csv.DictReader(open(path)))
by = {}
for r in rows:
    model = r['run'].split('-seed')[0]
    by.setdefault(model, []).append((int(r['config_seed']), float(r['psnr'])))
print(f'lenses: {preset} ({size}), {steps} steps{", " + flags if flags else ""}; test PSNR (dB) per seed')
base = statistics.median(p for _, p in by['pinhole'])
for model, values in by.items():
    values.sort()
    ps = [p for _, p in values]
    med = statistics.median(ps)
    print(f'  {model:8s} ' + '  '.join(f'{s}: {p:.2f}' for s, p in values) +
          f'   median {med:.2f}, spread {min(ps):.2f}-{max(ps):.2f}, median - pinhole {med - base:+.2f}')
EOF
