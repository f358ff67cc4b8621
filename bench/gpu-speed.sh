#!/usr/bin/env bash
# Where the device sits idle (issue 48), on any device, lavapipe included: on the full-size
# nerfrac-primary-sine (392 x 392 px, 8 views),
#   1. training: whole-image steps at the reference settings (--recipe reference: the paper's
#      schedule, the issue's figures) with --profile: steps per second, milliseconds per step,
#      the host's milliseconds and share of a step, submits and dispatches per step; on a CPU
#      device (lavapipe maps device memory: its transfers cost no submission) the same run again
#      with REFRAX_FORCE_STAGING=1, for the submissions a discrete GPU would count;
#   2. rendering: `refrax render --benchmark` of the test view at 392 x 392 after that
#      training: the frame (the viewer's: baked water, tiled trace), its stages and its Gaussian
#      stage alone for the same rays; then the same through the trainer's stages
#      (--exact-water --gaussian-trace bvh), side by side;
#   3. the viewer: `refrax-view --frames --benchmark` at 392 x 392, 1280 x 720 and 1920 x 1080
#      under xvfb-run (skipped without it), the baked water, tiled trace (its defaults).
# Writes DIR/<device>.txt (the lines quoted) and DIR/<device>.json. Time: a few minutes on a
# GPU; on this 2-core lavapipe machine about 15 minutes at --steps 40.
# Usage: bench/gpu-speed.sh [--steps N] [--frames N] [--out DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-./build/refrax}
VIEW=${REFRAX_VIEW:-$(dirname "$REFRAX")/refrax-view}
steps=300
frames=8
out=bench/results/gpu-speed
while [ $# -gt 0 ]; do
  case $1 in
    --steps) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "gpu-speed.sh: --steps needs a count" >&2; exit 2; }; steps=$2; shift ;;
    --frames) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] && [ "$2" -ge 2 ] || { echo "gpu-speed.sh: --frames needs a count of at least 2" >&2; exit 2; }; frames=$2; shift ;;
    --out) [ $# -ge 2 ] || { echo "gpu-speed.sh: --out needs a folder" >&2; exit 2; }; out=$2; shift ;;
    -h|--help) sed -n '2,/^set -/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "gpu-speed.sh: unknown option '$1' (--steps, --frames, --out)" >&2; exit 2 ;;
  esac
  shift
done
. bench/ensure-build.sh
ensure_refrax gpu-speed "$REFRAX"
mkdir -p "$out"
work=$(mktemp -d "${TMPDIR:-/tmp}/refrax-gpu-speed.XXXXXX")
trap 'rm -rf "$work"' EXIT
device=$("$REFRAX" devices | sed -n '1s/^\[[0-9]*\] //p')
name=$(echo "$device" | sed 's/ (.*//; s/[^A-Za-z0-9]/_/g')
log=$out/$name.txt
note() { echo "$*" | tee -a "$log"; }
: >"$log"
note "gpu-speed: $device, $(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"

"$REFRAX" synth nerfrac-primary-sine --size full -o "$work/data" >/dev/null
"$REFRAX" train "$work/data" -o "$work/run" --recipe reference --steps "$steps" --patch 0 --checkpoint-every 0 --progress-every 100000 \
  --profile >"$work/train.log" 2>&1 || { tail -n 5 "$work/train.log" >&2; echo "gpu-speed: training failed" >&2; exit 1; }
note "training: $(grep -m 1 '^profile:' "$work/train.log")"
python3 - "$work/run/metrics.json" "$out/$name.json" "$device" <<'PY' | tee -a "$log"
import json, sys
p = json.load(open(sys.argv[1]))['profile']
wall, host = p['wall_ms_per_step'], p['host_ms_per_step']
row = {'device': sys.argv[3], 'steps': p['steps'], 'steps_per_second': 1000.0 / wall, 'ms_per_step': wall, 'median_step_ms': p['median_step_ms'],
       'host_ms_per_step': host, 'host_share': host / wall, 'submits_per_step': p['submits_per_step'],
       'dispatches_per_step': p['dispatches_per_step'], 'steps_not_waited_for': p.get('steps_not_waited_for', 0), 'host_stages': p['host']}
json.dump(row, open(sys.argv[2], 'w'), indent=2)
print('training: %.2f steps/s, %.2f ms per step, host %.2f ms (%.0f%%), %.2f submits and %.1f dispatches per step, %d of %d steps not waited for' %
      (row['steps_per_second'], wall, host, 100 * row['host_share'], row['submits_per_step'], row['dispatches_per_step'], row['steps_not_waited_for'], row['steps']))
PY

# Lavapipe (and an integrated GPU) maps device memory, so its transfers cost no submission; a
# discrete GPU's each cost one. The same run with REFRAX_FORCE_STAGING=1 counts them as it would.
if echo "$device" | grep -q "(CPU)"; then
  REFRAX_FORCE_STAGING=1 "$REFRAX" train "$work/data" -o "$work/run-staged" --recipe reference --steps "$steps" --patch 0 --checkpoint-every 0 \
    --progress-every 100000 --profile >"$work/train-staged.log" 2>&1 || { tail -n 5 "$work/train-staged.log" >&2; echo "gpu-speed: staged training failed" >&2; exit 1; }
  note "training, transfers staged as on a discrete GPU (REFRAX_FORCE_STAGING=1): $(grep -m 1 '^profile:' "$work/train-staged.log" | sed 's/.*), //')"
fi

"$REFRAX" render "$work/run" -o "$work/render" --split test --benchmark 5 >"$work/render.log" 2>&1 ||
  { tail -n 5 "$work/render.log" >&2; echo "gpu-speed: render failed" >&2; exit 1; }
grep '^benchmark' "$work/render.log" | sed 's/^/render: /' | tee -a "$log"
# The same view through the trainer's stages (the subdivided water, a BVH per ray), side by side.
"$REFRAX" render "$work/run" -o "$work/render-exact" --split test --exact-water --gaussian-trace bvh --benchmark 5 >"$work/render-exact.log" 2>&1 ||
  { tail -n 5 "$work/render-exact.log" >&2; echo "gpu-speed: render --exact-water failed" >&2; exit 1; }
grep '^benchmark' "$work/render-exact.log" | sed 's/^/render --exact-water --gaussian-trace bvh: /' | tee -a "$log"

if command -v xvfb-run >/dev/null && [ -x "$VIEW" ]; then
  for size in 392x392 1280x720 1920x1080; do
    w=${size%x*} h=${size#*x}
    if xvfb-run -a -s "-screen 0 ${w}x${h}x24" "$VIEW" "$work/run" --width "$w" --height "$h" --frames "$frames" --benchmark \
         >"$work/view-$size.log" 2>&1; then
      note "viewer $size: $(grep -m 1 '^benchmark: ' "$work/view-$size.log" | sed 's/.*frames: //')"
    else
      note "viewer $size: failed ($(tail -n 1 "$work/view-$size.log"))"
    fi
  done
else
  note "viewer: skipped (no xvfb-run or refrax-view)"
fi
echo "gpu-speed: $log"
