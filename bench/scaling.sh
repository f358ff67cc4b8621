#!/usr/bin/env bash
# Scaling (issue 8, part 4): time per training step and per rendered frame (medians), and the
# peak memory, against the image size, the Gaussian count and the surface grid size, from
# `refrax bench scaling` (trainer/bench/bench_scaling.cpp: the refraction model, whole-image steps,
# no densification, the surface learning from the first step).
#
# Usage: bench/scaling.sh [--full] [--out DIR]   (build first)
# Default size (this 2-core lavapipe machine, about 15 min): nerfrac-primary-sine --size tiny
#   at 64, 128, 256 and 392 px; Gaussians 10k, 20k, 50k, 100k, 200k (at 64 px, grid 64);
#   grid 32, 64, 128, 256 cells (at 64 px, 20k Gaussians); SH degree 0; median of 3 steps or
#   renders after 1 warm-up.
# --full (a GPU): --size full geometry at 128, 256, 392, 800 px, the Gaussian and grid sweeps
#   at 392 px, SH degree 3, median of 10 after 3 warm-ups.
# Writes to DIR (default bench/results/scaling/): scaling.csv (every setting), per sweep a
# time CSV and chart (step and frame ms) and a memory CSV and chart, and summary.md.
set -uo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-./build/refrax}

full=0
out=bench/results/scaling
while [ $# -gt 0 ]; do
  case "$1" in
    --full) full=1 ;;
    --out) out=$2; shift ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) echo "scaling.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done
. bench/ensure-build.sh
ensure_refrax scaling.sh "$REFRAX"

if [ $full = 1 ]; then
  size=full; widths=(392 128 256 800); bench_opts=(--sh-degree 3 --runs 10 --warmup 3)
  sizes="nerfrac-primary-sine --size full geometry; images 128-800 px (Gaussian and grid sweeps at 392 px); SH degree 3; median of 10 after 3 warm-ups"
else
  size=tiny; widths=(64 128 256 392); bench_opts=(--sh-degree 0 --runs 3 --warmup 1)
  sizes="nerfrac-primary-sine --size tiny geometry; images 64-392 px (Gaussian and grid sweeps at 64 px); SH degree 0; median of 3 after 1 warm-up"
fi

mkdir -p "$out"
work=$(mktemp -d "${TMPDIR:-/tmp}/refrax-scaling.XXXXXX")
trap 'rm -rf "$work"' EXIT
start_all=$(date +%s)

datasets=""
for w in "${widths[@]}"; do
  "$REFRAX" synth nerfrac-primary-sine --size $size --width "$w" -o "$work/data_$w" >"$work/synth_$w.log" 2>&1 ||
    { echo "scaling.sh: refrax synth --width $w failed:" >&2; cat "$work/synth_$w.log" >&2; exit 1; }
  datasets="${datasets:+$datasets,}$work/data_$w"
done

"$REFRAX" bench scaling --datasets "$datasets" --csv "$out/scaling.csv" "${bench_opts[@]}" || exit 1
end_all=$(date +%s)

device=$("$REFRAX" devices 2>/dev/null | grep -m1 '^\[' | sed 's/^\[[0-9]*\] //; s/, Vulkan.*//')
python3 - "$out" "$device" "$sizes" "$((end_all - start_all))" <<'EOF'
import csv, sys
out, device, sizes, seconds = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
rows = list(csv.DictReader(open(out + '/scaling.csv')))
sweeps = [('image_size', 'pixels', 'image size (pixels per image)'), ('gaussians', 'gaussians', 'Gaussian count'),
          ('grid_cells', 'grid_cells', 'surface grid (cells per side)')]
lines = ['# Scaling', '', 'Device: %s. Sizes: %s. Wall time of the suite: %d min %d s.' % (device, sizes, seconds // 60, seconds % 60), '',
         'Refraction model (`refrax bench scaling`): one training step on a whole training image (camera rays, surface forward, '
         'Gaussian forward, loss, Gaussian and surface backward, Adam), one rendered frame of the test view through the water; '
         'medians of wall times. Peak memory: the process\'s peak resident set (VmHWM) during the setting; on lavapipe the device '
         'buffers are host memory and are included. The base setting appears once in each sweep, measured each time: the spread '
         'between those rows is the run-to-run noise of the machine (other work ran beside it).', '']
for sweep, col, label in sweeps:
    part = sorted((r for r in rows if r['sweep'] == sweep), key=lambda r: float(r[col]))
    with open('%s/scaling_%s.csv' % (out, sweep), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow([col, 'what', 'ms'])
        for r in part:
            w.writerow([r[col], 'training step', r['step_ms']])
            w.writerow([r[col], 'rendered frame', r['render_ms']])
    with open('%s/scaling_%s_memory.csv' % (out, sweep), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow([col, 'what', 'peak_rss_mib'])
        for r in part:
            w.writerow([r[col], 'peak RSS', r['peak_rss_mib']])
    lines += ['## %s' % label, '', '| image | Gaussians | grid | step (ms) | frame (ms) | peak RSS (MiB) |', '|---|---|---|---|---|---|']
    for r in part:
        lines.append('| %sx%s | %s | %s | %.1f | %.1f | %.0f |' % (r['width'], r['height'], r['gaussians'], r['grid_cells'], float(r['step_ms']),
                                                             float(r['render_ms']), float(r['peak_rss_mib'])))
    if len(part) >= 2:
        a, b = part[0], part[-1]
        for key, what in (('step_ms', 'step'), ('render_ms', 'frame')):
            lines.append('')
            lines.append('- %s time: x%.2f from %s = %s to %s (x%.2f)' % (what, float(b[key]) / float(a[key]), col, a[col], b[col],
                                                                            float(b[col]) / float(a[col])))
    lines += ['', '![time against %s](scaling_%s.svg) ![peak memory against %s](scaling_%s_memory.svg)' % (label, sweep, label, sweep), '']
open(out + '/summary.md', 'w').write('\n'.join(lines))
EOF

if "$REFRAX" chart --help >/dev/null 2>&1; then
  for spec in "image_size|pixels|pixels per image" "gaussians|gaussians|Gaussians" "grid_cells|grid_cells|grid cells per side"; do
    IFS='|' read -r sweep col xlabel <<<"$spec"
    "$REFRAX" chart "$out/scaling_$sweep.csv" -o "$out/scaling_$sweep.svg" --x "$col" --y ms --series what --log-x \
      --title "Time per training step and per frame against $xlabel" --x-label "$xlabel" --y-label "ms (median)" ||
      echo "scaling.sh: refrax chart failed for $sweep" >&2
    "$REFRAX" chart "$out/scaling_${sweep}_memory.csv" -o "$out/scaling_${sweep}_memory.svg" --x "$col" --y peak_rss_mib --series what \
      --log-x --title "Peak memory against $xlabel" --x-label "$xlabel" --y-label "peak RSS (MiB)" ||
      echo "scaling.sh: refrax chart failed for $sweep memory" >&2
  done
else
  echo "scaling.sh: this refrax has no 'chart' command: CSVs written, charts not drawn" >&2
  printf '\n(Charts not drawn: this build of refrax has no `chart` command.)\n' >>"$out/summary.md"
fi
echo "scaling.sh: done in $((end_all - start_all)) s -> $out" >&2
