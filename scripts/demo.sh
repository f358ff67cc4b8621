#!/usr/bin/env bash
# The main job on a tiny synthetic example: install what is missing, build, then
# synthesise -> train (and the two comparison models) -> render -> evaluate -> print metrics.
# A few minutes on lavapipe (2 cores).
#   scripts/demo.sh            the demo, into demo-out/ (REFRAX_DEMO_DIR)
#   scripts/demo.sh --record   the same, and its summary with what made it (date, device,
#                              settings, training code) written to bench/results/demo/: the
#                              README quotes the demo's figures from there
set -euo pipefail
cd "$(dirname "$0")/.."
record=0
case "${1:-}" in
  "") ;;
  --record) record=1 ;;
  *) echo "demo.sh: unknown option $1 (--record, or none)" >&2; exit 2 ;;
esac
[ "${REFRAX_SKIP_INSTALL:-0}" = 1 ] || bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j"$(nproc)"
./build/refrax devices
./build/refrax selftest --validation

OUT="${REFRAX_DEMO_DIR:-demo-out}"
STEPS="${REFRAX_DEMO_STEPS:-1500}"
SEED="${REFRAX_DEMO_SEED:-1}"
rm -rf "$OUT"
mkdir -p "$OUT"
./build/refrax synth nerfrac-primary-sine --size tiny -o "$OUT/data"
# refrax train's defaults: no method flags (the method, sized for this device and the data;
# docs/training.md "The defaults"), a step count that suits 64 px images, and the two
# comparison models on the same defaults.
COMMON=(--steps "$STEPS" --seed "$SEED" --progress-every 100 --checkpoint-every 500)
for model in refraction flat-water no-refraction; do
  flag=(); [ "$model" = refraction ] || flag=(--"$model")
  # stdout of train is its one-line summary (progress goes to stderr)
  echo "$model: $(./build/refrax train "$OUT/data" -o "$OUT/$model" ${flag[@]+"${flag[@]}"} "${COMMON[@]}" 2> >(tee "$OUT/$model.log" >&2))" >>"$OUT/summary.txt"
done
./build/refrax render "$OUT/refraction" --split test --water keep -o "$OUT/renders/keep"
./build/refrax render "$OUT/refraction" --split test --water remove -o "$OUT/renders/removed"
./build/refrax eval "$OUT/refraction" -o "$OUT/refraction/eval.json"
echo
echo "== tiny nerfrac-primary-sine, refrax train's defaults at $STEPS steps, seed $SEED (metrics.json and config.json in each run folder)"
cat "$OUT/summary.txt"
if [ $record = 1 ]; then
  rec=bench/results/demo
  mkdir -p "$rec"
  cp "$OUT/summary.txt" "$rec/summary.txt"
  # The training code the figures come from, as bench/stability.sh names it ("unknown" with
  # local changes there: such figures are no record of a commit).
  code=unknown
  if git rev-parse --git-dir >/dev/null 2>&1 && [ -z "$(git status --porcelain -- engine shaders trainer CMakeLists.txt)" ]; then
    code="$(git rev-parse --short HEAD) (trees $(git ls-tree HEAD engine shaders trainer CMakeLists.txt | git hash-object --stdin))"
  fi
  {
    echo "date=$(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "device=$(./build/refrax devices 2>/dev/null | grep -m1 '^\[' | sed 's/^\[[0-9]*\] //; s/, Vulkan.*//')"
    echo "cores=$(nproc)"
    echo "settings=tiny nerfrac-primary-sine, refrax train's defaults at $STEPS steps, seed $SEED: $(grep -m 1 "^the method's settings" "$OUT/refraction.log" 2>/dev/null || echo 'see refraction/config.json')"
    echo "code=$code"
  } > "$rec/run_info.txt"
  ./build/refrax report "$OUT/refraction" "$OUT/flat-water" "$OUT/no-refraction" -o "$rec/runs.csv" >/dev/null
  echo "demo: recorded in $rec/ (summary.txt, run_info.txt, runs.csv)"
fi
