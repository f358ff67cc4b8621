#!/usr/bin/env bash
# What lies under the water, on every preset at full size (issue 49): per preset and seed, the
# three models at refrax train's defaults (the method, --flat-water, --no-refraction), each run
# exported with `refrax export RUN --bottom DIR` on the truth's grid, and bottom.json's
# accuracy against refrax synth's truth: the bed's RMSE and bias (m, and as a share of the
# water depth), its coverage, and the water-free orthophoto's PSNR. Writes DIR/rows.csv (one
# row per run) and DIR/summary.md (per preset and model: the median over seeds and the spread).
#
# Usage: bench/bed.sh [--presets "A B ..."] [--seeds "1 2 3"] [--models "LIST"] [--steps N] [--out DIR] [--keep-work] [--append] [--summary-only]
#   --presets  default: all nine
#   --models   default "method flat-water no-refraction"; add known-water (the true water fixed:
#              what the Gaussians alone make of the bed) to tell their error from the water's
#   --seeds    training seeds (default 1)
#   --steps    every run's steps (default: refrax train's, sized for the device)
#   --out      default bench/results/bed/
#   --append   add the rows to DIR/rows.csv (more seeds or presets in a later sitting, the same
#              code: run_info.txt records each sitting) and summarise them all
#   --summary-only  summary.md again from DIR/rows.csv (rows gathered from several folders)
# Time on this 2-core lavapipe machine at the CPU defaults as they were (4,000 steps of 32 x 32
# patches): about 3 minutes a run and a few seconds an export, so 9 presets x 3 models x 1 seed
# ~ 1.5 h; the defaults' 8,000 steps (2026-12-06) double it.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
REFRAX=${REFRAX:-$root/build/refrax}
presets="nerfrac-primary-sine nerfrac-second-sine nerfrac-hybrid desk kitchen toys desk-topdown kitchen-topdown toys-topdown"
seeds="1"
models="method flat-water no-refraction"
steps=""
out=$root/bench/results/bed
keep=0
append=0
summary_only=0
while [ $# -gt 0 ]; do
  case $1 in
    --presets) [ $# -ge 2 ] || { echo "bed.sh: --presets needs a list" >&2; exit 2; }; presets=$2; shift ;;
    --seeds) [ $# -ge 2 ] || { echo "bed.sh: --seeds needs a list" >&2; exit 2; }; seeds=$2; shift ;;
    --models) [ $# -ge 2 ] || { echo "bed.sh: --models needs a list" >&2; exit 2; }; models=$2; shift
      for m in $models; do case $m in method|flat-water|no-refraction|known-water) ;; *) echo "bed.sh: unknown model '$m' (method, flat-water, no-refraction, known-water)" >&2; exit 2 ;; esac; done ;;
    --steps) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "bed.sh: --steps needs a step count" >&2; exit 2; }; steps=$2; shift ;;
    --out) [ $# -ge 2 ] || { echo "bed.sh: --out needs a folder" >&2; exit 2; }; out=$2; shift ;;
    --keep-work) keep=1 ;;
    --append) append=1 ;;
    --summary-only) summary_only=1 ;;
    -h|--help) sed -n '2,/^set -/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bed.sh: unknown option '$1' (--presets, --seeds, --models, --steps, --out, --keep-work, --append, --summary-only)" >&2; exit 2 ;;
  esac
  shift
done
[ $summary_only = 0 ] || [ -f "$out/rows.csv" ] || { echo "bed.sh: --summary-only: no $out/rows.csv" >&2; exit 2; }
mkdir -p "$out"
out=$(cd "$out" && pwd)
rows=$out/rows.csv
if [ $summary_only = 0 ]; then
  . "$root/bench/ensure-build.sh"
  ensure_refrax bed "$REFRAX"
  if [ $keep = 1 ]; then work=$out/work; mkdir -p "$work"; else work=$(mktemp -d "${TMPDIR:-/tmp}/refrax-bed.XXXXXX"); trap 'rm -rf "$work"' EXIT; fi
  device=$("$REFRAX" devices | sed -n '1s/^\[[0-9]*\] //p')
  code=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
  [ -z "$(git status --porcelain -- engine shaders trainer 2>/dev/null)" ] || code="$code (with local changes)"
  header="preset,model,seed,psnr,surface_rmse,bottom_rmse_m,bottom_bias_m,bottom_rmse_share,bottom_bias_share,bottom_coverage,ortho_psnr,export_seconds,train_seconds"
  if [ $append = 1 ] && [ -f "$rows" ]; then
    [ "$(head -n 1 "$rows")" = "$header" ] || { echo "bed.sh: --append: $rows is not a bed.sh table" >&2; exit 2; }
    printf '\n' >>"$out/run_info.txt"  # a sitting of its own
  else
    echo "$header" >"$rows"
    : >"$out/run_info.txt"
  fi
  printf 'device=%s\ncode=%s\npresets=%s\nsteps=%s\nseeds=%s\nmodels=%s\nstarted=%s\n' "$device" "$code" "$presets" "${steps:-default}" "$seeds" "$models" "$(date -u '+%Y-%m-%d %H:%M UTC')" >>"$out/run_info.txt"
  train_steps=()
  [ -z "$steps" ] || train_steps=(--steps "$steps")
  for preset in $presets; do
    data=$work/data-$preset
    [ -f "$data/water.json" ] || "$REFRAX" synth "$preset" --size full -o "$data" >/dev/null 2>"$work/synth-$preset.log" ||
      { cat "$work/synth-$preset.log" >&2; echo "bed.sh: synth $preset failed" >&2; exit 1; }
    for seed in $seeds; do
      for model in $models; do
        run=$work/$preset-$model-$seed
        flag=()
        [ $model = method ] || flag=(--$model)
        rm -rf "$run" "$run-bed"
        t0=$(date +%s)
        if ! "$REFRAX" train "$data" -o "$run" --seed "$seed" ${train_steps[@]+"${train_steps[@]}"} ${flag[@]+"${flag[@]}"} \
             --checkpoint-every 0 --progress-every 100000 >"$run.log" 2>&1; then
          echo "bed.sh: $preset $model seed $seed: training failed ($(tail -n 1 "$run.log"))" >&2; continue
        fi
        t1=$(date +%s)
        "$REFRAX" export "$run" --bottom "$run-bed" >"$run-bed.log" 2>&1 || { echo "bed.sh: $preset $model seed $seed: export failed" >&2; continue; }
        t2=$(date +%s)
        python3 - "$run/metrics.json" "$run-bed/bottom.json" "$preset" "$model" "$seed" "$((t2 - t1))" "$((t1 - t0))" >>"$rows" <<'PY'
import json, sys
m, b = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
a = b.get('accuracy', {})
f = lambda v: '' if v is None else '%.6g' % v
print(','.join(sys.argv[3:6] + [f(m.get('psnr')), f(m.get('surface_rmse')), f(a.get('bottom_rmse_m')), f(a.get('bottom_bias_m')),
      f(a.get('bottom_rmse_share')), f(a.get('bottom_bias_share')), f(a.get('bottom_coverage')), f(a.get('ortho_dry_psnr')),
      sys.argv[6], sys.argv[7]]))
PY
        echo "$(date -u +%H:%M:%S) $preset $model seed $seed: $(tail -n 1 "$rows")"
      done
    done
  done
  printf 'finished=%s\n' "$(date -u '+%Y-%m-%d %H:%M UTC')" >>"$out/run_info.txt"
fi
python3 - "$rows" "$out/summary.md" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
num = lambda v: float(v) if v not in ('', None) else None
lines = ['# The bed under the water: three models per preset (bench/bed.sh)', '',
         'Median over the seeds (spread: max - min). RMSE and bias in metres and as a share of the mean true water depth; '
         'coverage of the seen floor; the orthophoto with the water removed against the true one (dB).', '',
         '| preset | model | seeds | bed RMSE (m) | bias (m) | RMSE / depth | bias / depth | coverage | orthophoto (dB) | test PSNR |',
         '| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |']
keys = []
for r in rows:
    if (r['preset'], r['model']) not in keys: keys.append((r['preset'], r['model']))
def cell(vals, fmt):
    vals = [v for v in vals if v is not None]
    if not vals: return '-'
    med = statistics.median(vals)
    return (fmt % med) + (' (%s)' % (fmt % (max(vals) - min(vals))) if len(vals) > 1 else '')
for p, mdl in keys:
    rs = [r for r in rows if r['preset'] == p and r['model'] == mdl]
    col = lambda k: [num(r[k]) for r in rs]
    lines.append('| %s | %s | %d | %s | %s | %s | %s | %s | %s | %s |' % (p, mdl, len(rs), cell(col('bottom_rmse_m'), '%.3f'), cell(col('bottom_bias_m'), '%+.3f'),
                 cell(col('bottom_rmse_share'), '%.3f'), cell(col('bottom_bias_share'), '%+.3f'), cell(col('bottom_coverage'), '%.3f'),
                 cell(col('ortho_psnr'), '%.2f'), cell(col('psnr'), '%.2f')))
open(sys.argv[2], 'w').write('\n'.join(lines) + '\n')
print('\n'.join(lines))
PY
