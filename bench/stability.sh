#!/usr/bin/env bash
# Stability where methods fail (issue 8, part 3): test PSNR of Refrax (the refraction model),
# --flat-water and --no-refraction over four sweeps on the NeRFrac-like single-sine scene,
# with failure counts (a run exiting non-zero) and NaN counts (non-finite values in
# metrics.json or in the trained point_cloud.ply):
#   slope  refrax synth --wave-amplitude 0.5,1,1.6,2.4 (max slope from water.json's slope_bound:
#          0.16, 0.31, 0.50, 0.75)
#   tilt   refrax synth --tilt 0,20,40,60 (the 3 x 3 rig turned from the vertical)
#   ior    refrax synth --ior 1.1,1.2,1.33,1.5
#   views  refrax train --train-views 8,4,2 (an even spread of the 8 training views)
# Every sweep holds the others at the preset (amplitude x1, tilt 0, IOR 1.1, 8 views); that
# shared setting is trained once and appears in each sweep's table.
#
# Usage: bench/stability.sh [--full] [--out DIR] [--threshold DB] [--steps N] [--charts-only]
#   (build first; --steps N overrides the step count for a quick check of the script;
#   --charts-only redraws the per-sweep CSVs, charts and summary.md from DIR/stability.csv)
# Default size (this 2-core lavapipe machine, about 15 min): nerfrac-primary-sine --size tiny
#   at 48 x 48 px, 300 steps on 32 x 32 patches, 1,500 Gaussians, SH degree 0.
# --full (a GPU): --size full (392 x 392 px), 15,000 steps on whole images, 20,000 Gaussians,
#   SH degree 3 (the reference configuration).
# Writes to DIR (default bench/results/stability/): stability.csv (every run), one CSV and one
# chart (PSNR against the swept value, one series per model; needs `refrax chart`) per sweep,
# and summary.md (device, sizes, per model the first setting below the threshold).
set -uo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-./build/refrax}

full=0
out=bench/results/stability
threshold=20
steps=""
charts_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --full) full=1 ;;
    --out) out=$2; shift ;;
    --threshold) threshold=$2; shift ;;
    --steps) steps=$2; shift ;;
    --charts-only) charts_only=1 ;;
    -h|--help) sed -n '2,24p' "$0"; exit 0 ;;
    *) echo "stability.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done
. bench/ensure-build.sh
ensure_refrax stability.sh "$REFRAX"

preset=nerfrac-primary-sine
if [ $full = 1 ]; then
  synth_size=(--size full)
  train_opts=(--steps 15000 --gaussians 20000 --sh-degree 3 --checkpoint-every 0 --progress-every 500)
  sizes="nerfrac-primary-sine --size full (392 x 392 px, 8 training views, 1 test view); 15,000 steps on whole images, 20,000 initial Gaussians, SH degree 3"
else
  synth_size=(--size tiny --width 48)
  train_opts=(--steps 300 --gaussians 1500 --patch 32 --sh-degree 0 --checkpoint-every 0 --progress-every 50)
  sizes="nerfrac-primary-sine --size tiny --width 48 (48 x 48 px, 8 training views, 1 test view); 300 steps on 32 x 32 patches, 1,500 initial Gaussians, SH degree 0"
fi

[ -z "$steps" ] || { train_opts+=(--steps "$steps"); sizes="$sizes (step count overridden: --steps $steps)"; }
mkdir -p "$out"
work=$(mktemp -d "${TMPDIR:-/tmp}/refrax-stability.XXXXXX")
trap 'rm -rf "$work"' EXIT

if [ $charts_only = 0 ]; then
start_all=$(date +%s)

# sweep|value|synth options|train options, easiest first in each sweep.
settings=(
  "slope|0.5|--wave-amplitude 0.5|"
  "slope|1|--wave-amplitude 1|"
  "slope|1.6|--wave-amplitude 1.6|"
  "slope|2.4|--wave-amplitude 2.4|"
  "tilt|0|--wave-amplitude 1|"
  "tilt|20|--tilt 20|"
  "tilt|40|--tilt 40|"
  "tilt|60|--tilt 60|"
  "ior|1.1|--wave-amplitude 1|"
  "ior|1.2|--ior 1.2|"
  "ior|1.33|--ior 1.33|"
  "ior|1.5|--ior 1.5|"
  "views|8|--wave-amplitude 1|--train-views 8"
  "views|4|--wave-amplitude 1|--train-views 4"
  "views|2|--wave-amplitude 1|--train-views 2"
)
models=("refrax|" "flat-water|--flat-water" "no-refraction|--no-refraction")

rows="$work/rows.csv"
echo "sweep,value,slope_bound,tilt_deg,ior,train_views,model,exit_code,failed,nan_count,psnr,ssim,surface_rmse,train_seconds,gaussians,run_seconds" >"$rows"

# Counts non-finite numbers in metrics.json (NaN is written as null or NaN) and in the
# float properties of a binary little-endian PLY.
count_nans() {
  python3 - "$1" "$2" <<'EOF'
import json, math, struct, sys
metrics, ply = sys.argv[1], sys.argv[2]
bad = 0
try:
    text = open(metrics).read()
    def walk(v):
        global bad
        if v is None or (isinstance(v, float) and not math.isfinite(v)): bad += 1
        elif isinstance(v, dict): [walk(x) for x in v.values()]
        elif isinstance(v, list): [walk(x) for x in v]
    walk(json.loads(text, parse_constant=lambda c: float('nan')))
except FileNotFoundError:
    pass
try:
    data = open(ply, 'rb').read()
    end = data.index(b'end_header\n') + len(b'end_header\n')
    header = data[:end].decode().splitlines()
    count, props = 0, []
    for line in header:
        w = line.split()
        if w[:2] == ['element', 'vertex']: count = int(w[2])
        if w[:1] == ['property']: props.append(w[1])
    if all(p == 'float' for p in props) and props:
        floats = struct.unpack_from('<%df' % (count * len(props)), data, end)
        bad += sum(1 for f in floats if not math.isfinite(f))
except (FileNotFoundError, ValueError):
    pass
print(bad)
EOF
}

declare -A made
for s in "${settings[@]}"; do
  IFS='|' read -r sweep value synth_opts train_extra <<<"$s"
  key=$(echo "$synth_opts" | tr -c 'A-Za-z0-9.\n' '_')
  data="$work/data_$key"
  if [ -z "${made[$key]:-}" ]; then
    # shellcheck disable=SC2086
    if ! "$REFRAX" synth $preset "${synth_size[@]}" $synth_opts -o "$data" >"$work/synth_$key.log" 2>&1; then
      echo "stability.sh: refrax synth $synth_opts failed:" >&2; cat "$work/synth_$key.log" >&2; exit 1
    fi
    made[$key]=1
  fi
  read -r slope tilt ior <<<"$(python3 -c '
import json, sys, re
w = json.load(open(sys.argv[1] + "/water.json"))
m = re.search(r"rig tilted ([0-9.]+) deg", w["description"])
print("%.3f" % w["surface"]["slope_bound"], m.group(1) if m else 0, w["ior"])' "$data")"
  views=${train_extra#--train-views }
  [ -n "$train_extra" ] || views=8
  for m in "${models[@]}"; do
    IFS='|' read -r model model_opt <<<"$m"
    # The shared preset setting is trained once per model; the other sweeps reuse its row.
    runkey="${key}_${views}_${model}"
    run="$work/run_$runkey"
    if [ ! -f "$work/row_$runkey" ]; then
      t0=$(date +%s)
      # shellcheck disable=SC2086
      "$REFRAX" train "$data" -o "$run" "${train_opts[@]}" $model_opt $train_extra >"$work/train_$runkey.log" 2>&1
      code=$?
      t1=$(date +%s)
      nans=$(count_nans "$run/metrics.json" "$run/point_cloud.ply")
      python3 - "$run/metrics.json" "$code" "$nans" "$((t1 - t0))" >"$work/row_$runkey" <<'EOF'
import json, sys
path, code, nans, secs = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
try:
    m = json.load(open(path), parse_constant=lambda c: float('nan'))
except (FileNotFoundError, ValueError):
    m = {}
def f(k):
    v = m.get(k)
    return '' if v is None else ('%.4f' % v if isinstance(v, float) else str(v))
failed = 1 if code != 0 or not m else 0
print(','.join([str(code), str(failed), str(nans), f('psnr'), f('ssim'), f('surface_rmse'), f('training_seconds'), f('gaussians'), secs]))
EOF
      echo "$(date -u +%H:%M:%S) $sweep=$value $model: exit $code, $(cut -d, -f4 "$work/row_$runkey") dB, $((t1 - t0)) s" >&2
      [ $code = 0 ] || tail -n 3 "$work/train_$runkey.log" >&2
    fi
    echo "$sweep,$value,$slope,$tilt,$ior,$views,$model,$(cat "$work/row_$runkey")" >>"$rows"
  done
done
cp "$rows" "$out/stability.csv"
end_all=$(date +%s)
printf 'seconds=%d\nfinished=%s\n' "$((end_all - start_all))" "$(date -u '+%Y-%m-%d %H:%M UTC')" >"$out/run_info.txt"
fi
[ -f "$out/stability.csv" ] || { echo "stability.sh: no $out/stability.csv to draw from" >&2; exit 1; }
seconds=$(sed -n 's/^seconds=//p' "$out/run_info.txt" 2>/dev/null)

# Per-sweep CSVs (x column named for the chart) and the summary.
device=$("$REFRAX" devices 2>/dev/null | grep -m1 '^\[' | sed 's/^\[[0-9]*\] //; s/, Vulkan.*//')
python3 - "$out" "$threshold" "$device" "$sizes" "${seconds:-0}" <<'EOF'
import csv, sys
out, threshold, device, sizes, seconds = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4], int(sys.argv[5])
rows = list(csv.DictReader(open(out + '/stability.csv')))
sweeps = [('slope', 'slope_bound', 'max wave slope (water.json slope_bound)'), ('tilt', 'tilt_deg', 'camera tilt from the vertical (deg)'),
          ('ior', 'ior', 'index of refraction'), ('views', 'train_views', 'training views')]
models = ['refrax', 'flat-water', 'no-refraction']
lines = ['# Stability sweeps', '', 'Device: %s. Sizes: %s. Wall time of the suite: %d min %d s.' % (device, sizes, seconds // 60, seconds % 60), '',
         'Scene: the NeRFrac-like single sine (`refrax synth nerfrac-primary-sine`), each sweep varying one thing from the preset '
         '(amplitude x1: max slope 0.31, rig vertical, IOR 1.1, all 8 training views; the slope sweep starts below it, at x0.5). PSNR is the test-view PSNR of `metrics.json`; '
         'failed: the run exited non-zero; NaN: non-finite values in metrics.json or the trained PLY.', '']
for sweep, col, label in sweeps:
    part = [r for r in rows if r['sweep'] == sweep]
    with open('%s/stability_%s.csv' % (out, sweep), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow([col, 'model', 'psnr', 'ssim', 'surface_rmse', 'failed', 'nan_count', 'train_seconds'])
        for r in part:
            w.writerow([r[col], r['model'], r['psnr'], r['ssim'], r['surface_rmse'], r['failed'], r['nan_count'], r['train_seconds']])
    lines += ['## %s' % label, '', '| %s | model | test PSNR (dB) | surface RMSE | failed | NaN |' % col, '|---|---|---|---|---|---|']
    for r in part:
        lines.append('| %s | %s | %s | %s | %s | %s |' % (r[col], r['model'], r['psnr'] or '-', r['surface_rmse'] or '-', r['failed'], r['nan_count']))
    lines.append('')
    for m in models:
        mine = [r for r in part if r['model'] == m]
        def psnr(r):
            return float(r['psnr']) if r['psnr'] and r['failed'] == '0' else float('-inf')
        below = next((r for r in mine if psnr(r) < threshold), None)
        fails = sum(int(r['failed']) for r in mine)
        nans = sum(int(r['nan_count']) for r in mine)
        base = psnr(mine[0]) if mine else float('-inf')
        drop = next((r for r in mine if psnr(r) < base - 1.0), None)
        text = '- %s: ' % m
        if below is None:
            text += 'never below %g dB' % threshold
        elif below is mine[0]:
            text += 'below %g dB already at the easiest setting (%s = %s: %s dB)' % (threshold, col, below[col], below['psnr'] or 'failed')
        else:
            text += 'first below %g dB at %s = %s (%s dB)' % (threshold, col, below[col], below['psnr'] or 'failed')
        text += '; first more than 1 dB under its own easiest setting: %s' % (
            'none' if drop is None else '%s = %s (%s dB against %.2f)' % (col, drop[col], drop['psnr'] or 'failed', base))
        text += '; %d failed, %d NaN values' % (fails, nans)
        lines.append(text)
    lines.append('')
    lines.append('![PSNR against %s](stability_%s.svg)' % (label, sweep))
    lines.append('')
open(out + '/summary.md', 'w').write('\n'.join(lines))
EOF

# Charts (refrax chart: CSV -> SVG line chart).
if "$REFRAX" chart --help >/dev/null 2>&1; then
  for spec in "slope|slope_bound|max wave slope (slope_bound)|Test PSNR against wave slope" \
              "tilt|tilt_deg|camera tilt from the vertical (deg)|Test PSNR against camera tilt" \
              "ior|ior|index of refraction|Test PSNR against IOR" \
              "views|train_views|training views|Test PSNR against the number of training views"; do
    IFS='|' read -r sweep col xlabel title <<<"$spec"
    "$REFRAX" chart "$out/stability_$sweep.csv" -o "$out/stability_$sweep.svg" --x "$col" --y psnr --series model \
      --title "$title" --x-label "$xlabel" --y-label "test PSNR (dB)" --hline "$threshold:$threshold dB" ||
      echo "stability.sh: refrax chart failed for $sweep" >&2
  done
else
  echo "stability.sh: this refrax has no 'chart' command: CSVs written, charts not drawn" >&2
  printf '\n(Charts not drawn: this build of refrax has no `chart` command.)\n' >>"$out/summary.md"
fi
echo "stability.sh: done (runs took ${seconds:-?} s) -> $out" >&2
