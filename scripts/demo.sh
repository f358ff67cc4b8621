#!/usr/bin/env bash
# The main job on a tiny synthetic example: install what is missing, build, then
# synthesise -> train (and the two comparison models) -> render -> evaluate -> print metrics.
# A few minutes on lavapipe (2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
[ "${REFRAX_SKIP_INSTALL:-0}" = 1 ] || bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j"$(nproc)"
./build/refrax devices
./build/refrax selftest --validation

OUT="${REFRAX_DEMO_DIR:-demo-out}"
STEPS="${REFRAX_DEMO_STEPS:-1500}"
GAUSSIANS="${REFRAX_DEMO_GAUSSIANS:-2000}"
PATCH="${REFRAX_DEMO_PATCH:-32}"
rm -rf "$OUT"
mkdir -p "$OUT"
./build/refrax synth nerfrac-primary-sine --size tiny -o "$OUT/data"
COMMON=(--steps "$STEPS" --gaussians "$GAUSSIANS" --max-gaussians $((2 * GAUSSIANS)) --patch "$PATCH" --density-reset-every 0
        --sh-degree 0 --progress-every 100 --checkpoint-every 500)
# The refraction model with the presets table's method (bench/presets.sh refraction-sweep, docs/training.md):
# the fast surface settings, the level prior, Gaussians drawn at a plane sweep's depth (afresh
# at a third and a half of the run) and one surface step per pass over the 8 training views.
REFRACTION=(--mlp-coarse-octaves 3 --octaves-open-until 100000000 --surface-lr 3e-3 --surface-freeze $((STEPS * 2 / 15))
            --anchor-mean-height --level-prior 1000 --init-depth sweep --restart-gaussians $((STEPS / 3)),$((STEPS * 8 / 15))
            --surface-batch views)
for model in refraction flat-water no-refraction; do
  flag=("${REFRACTION[@]}"); [ "$model" = refraction ] || flag=(--"$model")
  # stdout of train is its one-line summary (progress goes to stderr)
  echo "$model: $(./build/refrax train "$OUT/data" -o "$OUT/$model" "${flag[@]}" "${COMMON[@]}")" >>"$OUT/summary.txt"
done
./build/refrax render "$OUT/refraction" --split test --water keep -o "$OUT/renders/keep"
./build/refrax render "$OUT/refraction" --split test --water remove -o "$OUT/renders/removed"
./build/refrax eval "$OUT/refraction" -o "$OUT/refraction/eval.json"
echo
echo "== tiny nerfrac-primary-sine, $STEPS steps, $GAUSSIANS Gaussians (metrics.json in each run folder)"
cat "$OUT/summary.txt"
