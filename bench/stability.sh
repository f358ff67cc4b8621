#!/usr/bin/env bash
# Stability where methods fail (issue 8, part 3; issue 29, part 4): test PSNR of Refrax (the
# refraction model), --flat-water and --no-refraction over four sweeps on the NeRFrac-like
# single-sine scene, with failure counts (a run exiting non-zero) and NaN counts (non-finite
# values in metrics.json or in the trained point_cloud.ply):
#   slope  refrax synth --wave-amplitude 0.5,1,1.6,2.4 (max slope from water.json's slope_bound:
#          0.16, 0.31, 0.50, 0.75; --medium starts at 0.25, slope 0.08, nearly flat water)
#   tilt   refrax synth --tilt 0,20,40,60 (the 3 x 3 rig turned from the vertical)
#   ior    refrax synth --ior 1.1,1.2,1.33,1.5
#   views  refrax train --train-views 8,4,2 (an even spread of the 8 training views)
# Every sweep holds the others at the preset (amplitude x1, tilt 0, IOR 1.1, 8 views); that
# shared setting is trained once and appears in each sweep's table.
#
# Usage: bench/stability.sh [--full | --medium] [--jobs N] [--out DIR] [--threshold DB] [--steps N]
#                           [--resume | --charts-only]
#   (build first; --steps N overrides the step count for a quick check of the script;
#   --resume keeps the rows of DIR/stability.csv and trains only the missing ones, with the
#   same mode and steps as the run that wrote them, from a clean git checkout of the same
#   training code; --charts-only redraws the per-sweep CSVs, charts and summary.md from
#   DIR/stability.csv)
# Default size (this 2-core lavapipe machine, about 15 min): nerfrac-primary-sine --size tiny
#   at 48 x 48 px, 300 steps on 32 x 32 patches, 1,500 Gaussians, SH degree 0.
# --medium (a GPU; issue 29): the full-size scene at 128 x 128 px, 4,000 steps on whole images,
#   the full-size table's settings (bench/presets.sh --cpu-full: model size derived from the
#   data; the refraction model with the level prior, the plane-sweep start, Gaussian restarts
#   at a third and 8/15 of the run, one surface step per pass over the views and the
#   water-sign check; flat water and straight rays with the same start and restarts), and a
#   dry control (straight rays on the same views without the water: the Gaussians' ceiling).
# --full (a GPU): --size full (392 x 392 px), 15,000 steps on whole images, 20,000 Gaussians,
#   SH degree 3 (the reference configuration).
# --jobs N trains N runs at once (default 1). Its training times are then not speed figures.
# Writes to DIR (default bench/results/stability/, or stability-medium/ for --medium):
# stability.csv (every finished run, in the order of the sweeps), one CSV and one chart (PSNR
# against the swept value, one series per model; needs `refrax chart`) per sweep, and
# summary.md (device, sizes, per model the first setting below the threshold). Stopped early
# (SIGTERM, e.g. `timeout`), it still writes what finished.
set -uo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-./build/refrax}

mode=default
out=""
threshold=""
steps=""
jobs=1
charts_only=0
resume=0
while [ $# -gt 0 ]; do
  case "$1" in
    --full) mode=full ;;
    --medium) mode=medium ;;
    --out) [ $# -ge 2 ] || { echo "stability.sh: --out needs a folder" >&2; exit 2; }; out=$2; shift ;;
    --threshold) [ $# -ge 2 ] || { echo "stability.sh: --threshold needs a PSNR in dB" >&2; exit 2; }; threshold=$2; shift ;;
    --steps) [ $# -ge 2 ] && [[ $2 =~ ^[0-9]+$ ]] && [ "$2" -ge 15 ] || { echo "stability.sh: --steps needs a step count (15 or more)" >&2; exit 2; }; steps=$2; shift ;;
    --jobs) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "stability.sh: --jobs needs a positive count" >&2; exit 2; }; jobs=$2; shift ;;
    --charts-only) charts_only=1 ;;
    --resume) resume=1 ;;
    -h|--help) sed -n '2,36p' "$0"; exit 0 ;;
    *) echo "stability.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done
# --medium: 25 dB, what issue 29 asks straight rays to reach on flat water at that size
[ -n "$threshold" ] || { [ $mode = medium ] && threshold=25 || threshold=20; }
[[ $threshold =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "stability.sh: --threshold needs a PSNR in dB, not '$threshold'" >&2; exit 2; }
[ -n "$out" ] || { [ $mode = medium ] && out=bench/results/stability-medium || out=bench/results/stability; }
. bench/ensure-build.sh
ensure_refrax stability.sh "$REFRAX"

preset=nerfrac-primary-sine
amplitudes="0.5 1 1.6 2.4"
dry_control=0
case $mode in
  full)
    synth_size=(--size full)
    train_opts=(--recipe reference --steps "${steps:-15000}" --gaussians 20000 --sh-degree 3 --checkpoint-every 0 --progress-every 500)
    sizes="nerfrac-primary-sine --size full (392 x 392 px, 8 training views, 1 test view); ${steps:-15000} steps on whole images, 20,000 initial Gaussians, SH degree 3"
    model_opts=("" "--flat-water" "--no-refraction") ;;
  medium)
    n=${steps:-4000}
    restarts=$((n / 3)),$((n * 8 / 15))
    synth_size=(--size full --width 128)
    amplitudes="0.25 0.5 1 1.6 2.4"
    dry_control=1
    train_opts=(--recipe reference --steps "$n" --eval-every "$n" --density-reset-every 0 --sh-degree 0 --checkpoint-every 0 --progress-every 500)
    # the model options of bench/presets.sh --cpu-full (refraction-sweep, flat-water-sweep,
    # no-refraction-sweep), restarts moved with the step count
    start="--init-depth sweep --restart-gaussians $restarts"
    model_opts=("--mlp-coarse-octaves 3 --octaves-open-until 100000000 --surface-lr 3e-3 --surface-freeze 200 --anchor-mean-height --level-prior 1000 $start --surface-batch views --water-sign-check"
                "--flat-water $start" "--no-refraction $start")
    sizes="nerfrac-primary-sine --size full --width 128 (128 x 128 px, 8 training views, 1 test view); $n steps on whole images, model size derived from the data, SH degree 0, the settings of the full-size table (bench/presets.sh --cpu-full), restarts at steps $restarts" ;;
  *)
    synth_size=(--size tiny --width 48)
    train_opts=(--recipe reference --steps "${steps:-300}" --gaussians 1500 --patch 32 --sh-degree 0 --checkpoint-every 0 --progress-every 50)
    sizes="nerfrac-primary-sine --size tiny --width 48 (48 x 48 px, 8 training views, 1 test view); ${steps:-300} steps on 32 x 32 patches, 1,500 initial Gaussians, SH degree 0"
    model_opts=("" "--flat-water" "--no-refraction") ;;
esac
[ -z "$steps" ] || sizes="$sizes (step count set with --steps $steps)"
[ "$jobs" = 1 ] || sizes="$sizes; $jobs runs at a time, so training times are not speed figures"
mkdir -p "$out"
work=$(mktemp -d "${TMPDIR:-/tmp}/refrax-stability.XXXXXX")
trap 'rm -rf "$work"' EXIT

if [ $charts_only = 0 ]; then
start_all=$(date +%s)

# sweep|value|synth options|train options, easiest first in each sweep.
settings=()
for a in $amplitudes; do settings+=("slope|$a|--wave-amplitude $a|"); done
settings+=(
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
# The dry control: straight rays on the preset's views rendered without the water.
[ $dry_control = 0 ] || settings+=("dry|0|--wave-amplitude 1 --dry|")
models=(refrax flat-water no-refraction)

# Counts non-finite numbers in metrics.json (NaN is written as null or NaN) and in the
# float properties of a binary little-endian PLY.
count_nans() {
  python3 - "$1" "$2" <<'PY'
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
PY
}

# One training run -> $work/row_<runkey> (exit code, failed, NaN count, metrics, seconds).
train_row() {  # runkey data model_opt train_extra
  local runkey=$1 data=$2 model_opt=$3 train_extra=$4 run="$work/run_$1" t0 t1 code
  t0=$(date +%s)
  # shellcheck disable=SC2086
  "$REFRAX" train "$data" -o "$run" "${train_opts[@]}" $model_opt $train_extra >"$work/train_$runkey.log" 2>&1
  code=$?
  t1=$(date +%s)
  python3 - "$run/metrics.json" "$code" "$(count_nans "$run/metrics.json" "$run/point_cloud.ply")" "$((t1 - t0))" >"$work/row_$runkey.tmp" <<'PY'
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
PY
  mv "$work/row_$runkey.tmp" "$work/row_$runkey"
  echo "$(date -u +%H:%M:%S) $runkey: exit $code, $(cut -d, -f4 "$work/row_$runkey") dB, $((t1 - t0)) s" >&2
  [ $code = 0 ] || tail -n 3 "$work/train_$runkey.log" >&2
}

# The device of this invocation, and with --resume those of the rows kept (run_info.txt).
device=$("$REFRAX" devices 2>/dev/null | grep -m1 '^\[' | sed 's/^\[[0-9]*\] //; s/, Vulkan.*//')
# The training code the rows come from: git's hash of the engine/, shaders/, trainer/ and
# CMakeLists.txt trees ("unknown" outside a git checkout or with local changes there). --resume
# keeps rows only from the same code: a changed model-size rule once slipped through under the
# same settings text. (It names the checkout's code; build the binary from it.)
code_paths=(engine shaders trainer CMakeLists.txt)
code=unknown
if git rev-parse --git-dir >/dev/null 2>&1 && [ -z "$(git status --porcelain -- "${code_paths[@]}")" ]; then
  code=$(git ls-tree HEAD "${code_paths[@]}" | git hash-object --stdin)
fi
earlier_seconds=0
if [ $resume = 1 ] && [ -f "$out/stability.csv" ]; then
  earlier_seconds=$(sed -n 's/^seconds=//p' "$out/run_info.txt" 2>/dev/null)
  earlier_sizes=$(sed -n 's/^sizes=//p' "$out/run_info.txt" 2>/dev/null)
  # the training settings without the "N runs at a time" remark, which may differ
  if [ -n "$earlier_sizes" ] && [ "${earlier_sizes%; [0-9]* runs at a time*}" != "${sizes%; [0-9]* runs at a time*}" ]; then
    echo "stability.sh: --resume: the rows in $out were trained with other settings ($earlier_sizes), not these ($sizes)" >&2; exit 2
  fi
  case $earlier_sizes in *"runs at a time"*) sizes=$earlier_sizes ;; esac  # its times are no speed figures either
  earlier_code=$(sed -n 's/^code=//p' "$out/run_info.txt" 2>/dev/null)
  if [ "$code" = unknown ] || [ "$earlier_code" != "$code" ]; then
    echo "stability.sh: --resume: the rows in $out come from training code ${earlier_code:-not recorded}, and this checkout's is $code" \
         "(git's hash of ${code_paths[*]}; unknown outside a git checkout or with local changes there): train them again without --resume" >&2
    exit 2
  fi
  earlier_device=$(sed -n 's/^device=//p' "$out/run_info.txt" 2>/dev/null)
  [ -z "$earlier_device" ] || [ "$earlier_device" = "$device" ] || device="$earlier_device; then $device"
  cp "$out/stability.csv" "$work/earlier.csv"
fi

# The datasets first (seconds each), then every run, $jobs at a time. table lists
# sweep|value|slope|tilt|ior|views|model|runkey in the order of the sweeps.
declare -A made started
table=()
# A SIGTERM (timeout) stops the launching and the waiting; the rows that finished are written.
stopped=0
trap 'stopped=1' TERM
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
  for i in "${!models[@]}"; do
    model=${models[$i]}
    # the dry control is trained with straight rays only
    [ "$sweep" != dry ] || [ "$model" = no-refraction ] || continue
    # The shared preset setting is trained once per model; the other sweeps reuse its row.
    table+=("$sweep|$value|$slope|$tilt|$ior|$views|$model|${key}_${views}_${model}|$data|$i|$train_extra")
  done
done
for line in "${table[@]}"; do
  IFS='|' read -r _ _ _ _ _ _ _ runkey data i train_extra <<<"$line"
  [ -z "${started[$runkey]:-}" ] || continue
  started[$runkey]=1
  if [ -f "$work/earlier.csv" ]; then  # --resume: a row kept from the earlier run
    IFS='|' read -r sweep value _ _ _ _ model _ <<<"$line"
    kept=$(grep -m1 "^$sweep,$value,[^,]*,[^,]*,[^,]*,[^,]*,$model," "$work/earlier.csv" | cut -d, -f8-)
    if [ -n "$kept" ]; then echo "$kept" >"$work/row_$runkey"; continue; fi
  fi
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ] && [ $stopped = 0 ]; do wait -n; done
  [ $stopped = 0 ] || break
  train_row "$runkey" "$data" "${model_opts[$i]}" "$train_extra" &
done

# Writes stability.csv from the rows that finished (all of them, or what a SIGTERM left).
write_rows() {
  local rows="$work/rows.csv" line sweep value slope tilt ior views model runkey done_count=0 total=0
  echo "sweep,value,slope_bound,tilt_deg,ior,train_views,model,exit_code,failed,nan_count,psnr,ssim,surface_rmse,train_seconds,gaussians,run_seconds" >"$rows"
  for line in "${table[@]}"; do
    IFS='|' read -r sweep value slope tilt ior views model runkey _ <<<"$line"
    total=$((total + 1))
    [ -f "$work/row_$runkey" ] || continue
    echo "$sweep,$value,$slope,$tilt,$ior,$views,$model,$(cat "$work/row_$runkey")" >>"$rows"
    done_count=$((done_count + 1))
  done
  cp "$rows" "$out/stability.csv"
  end_all=$(date +%s)
  printf 'seconds=%d\nfinished=%s\nrows=%d of %d\ndevice=%s\nsizes=%s\ncode=%s\n' "$((${earlier_seconds:-0} + end_all - start_all))" \
    "$(date -u '+%Y-%m-%d %H:%M UTC')" "$done_count" "$total" "$device" "$sizes" "$code" >"$out/run_info.txt"
}
while [ "$(jobs -rp | wc -l)" -gt 0 ] && [ $stopped = 0 ]; do wait -n; done
if [ $stopped = 1 ]; then
  echo "stability.sh: stopped: writing the rows that finished" >&2
  for job in $(jobs -rp); do pkill -TERM -P "$job"; kill "$job"; done 2>/dev/null
  wait
fi
write_rows
fi
[ -f "$out/stability.csv" ] || { echo "stability.sh: no $out/stability.csv to draw from" >&2; exit 1; }
seconds=$(sed -n 's/^seconds=//p' "$out/run_info.txt" 2>/dev/null)
finished_rows=$(sed -n 's/^rows=//p' "$out/run_info.txt" 2>/dev/null)
# The device and sizes of the runs themselves (a --charts-only redraw may run elsewhere).
device=$(sed -n 's/^device=//p' "$out/run_info.txt" 2>/dev/null)
[ -n "$device" ] || device=$("$REFRAX" devices 2>/dev/null | grep -m1 '^\[' | sed 's/^\[[0-9]*\] //; s/, Vulkan.*//')
stored_sizes=$(sed -n 's/^sizes=//p' "$out/run_info.txt" 2>/dev/null)
[ -z "$stored_sizes" ] || sizes=$stored_sizes

# Per-sweep CSVs (x column named for the chart) and the summary.
python3 - "$out" "$threshold" "$device" "$sizes" "${seconds:-0}" "${finished_rows:-}" <<'EOF'
import csv, sys
out, threshold, device, sizes, seconds, finished = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4], int(sys.argv[5]), sys.argv[6]
rows = list(csv.DictReader(open(out + '/stability.csv')))
sweeps = [('slope', 'slope_bound', 'max wave slope (water.json slope_bound)'), ('tilt', 'tilt_deg', 'camera tilt from the vertical (deg)'),
          ('ior', 'ior', 'index of refraction'), ('views', 'train_views', 'training views')]
models = ['refrax', 'flat-water', 'no-refraction']
lines = ['# Stability sweeps', '', 'Device: %s. Sizes: %s. Wall time of the suite: %d min %d s.' % (device, sizes, seconds // 60, seconds % 60), '',
         'Scene: the NeRFrac-like single sine (`refrax synth nerfrac-primary-sine`), each sweep varying one thing from the preset '
         '(amplitude x1: max slope 0.31, rig vertical, IOR 1.1, all 8 training views; the slope sweep starts below it). PSNR is the test-view PSNR of `metrics.json`; '
         'failed: the run exited non-zero; NaN: non-finite values in metrics.json or the trained PLY.', '']
done, total = (finished.split(' of ') + [''])[:2] if finished else ('', '')
if done and done != total:
    lines += ['**Stopped early: %s of %s rows finished**; the tables below hold those only.' % (done, total), '']
dry = [r for r in rows if r['sweep'] == 'dry']
if dry:
    r = dry[0]
    lines += ['Dry control (straight rays on the same views rendered without the water, the Gaussians\' ceiling at this budget): '
              'test PSNR %s dB, SSIM %s.' % (r['psnr'] or 'failed', r['ssim'] or '-'), '']
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
            text += 'never below %g dB' % threshold + (' in the rows that finished' if done and done != total else '')
        elif below is mine[0]:
            text += 'below %g dB already at the easiest setting (%s = %s: %s)' % (threshold, col, below[col], below['psnr'] + ' dB' if below['psnr'] else 'failed')
        else:
            text += 'first below %g dB at %s = %s (%s)' % (threshold, col, below[col], below['psnr'] + ' dB' if below['psnr'] else 'failed')
        text += '; first more than 1 dB under its own easiest setting: %s' % (
            'none' if drop is None else '%s = %s (%s against %.2f dB)' % (col, drop[col], drop['psnr'] + ' dB' if drop['psnr'] else 'failed', base))
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
    [ "$(wc -l <"$out/stability_$sweep.csv")" -gt 1 ] || continue  # no finished run in this sweep
    "$REFRAX" chart "$out/stability_$sweep.csv" -o "$out/stability_$sweep.svg" --x "$col" --y psnr --series model \
      --title "$title" --x-label "$xlabel" --y-label "test PSNR (dB)" --hline "$threshold:$threshold dB" ||
      echo "stability.sh: refrax chart failed for $sweep" >&2
  done
else
  echo "stability.sh: this refrax has no 'chart' command: CSVs written, charts not drawn" >&2
  printf '\n(Charts not drawn: this build of refrax has no `chart` command.)\n' >>"$out/summary.md"
fi
echo "stability.sh: done (runs took ${seconds:-?} s) -> $out" >&2
