#!/usr/bin/env bash
# refrax-view frame rate (issue 7): FPS and GPU milliseconds per stage at 256² and 392², with
# the water kept (baked mesh, the default), removed, and kept exactly (--exact-water: the
# trainer's subdivided surface, as refrax render), each with the tiled Gaussian trace (the
# default) and the BVH traversal per ray (--gaussian-trace bvh) one after the other, for two
# trained scenes:
#   tiny    refrax synth nerfrac-primary-sine --size tiny; train --steps 300 --patch 32
#           --gaussians 2000 (densifies to a few thousand)
#   medium  the same data; train --steps 30 --gaussians 30000 --no-densify
# Each benchmark renders --frames frames under xvfb-run (the first is a warm-up, not counted)
# from one fixed camera looking down at the water.
#
# Usage: bench/viewer.sh [--frames N] [--sizes 256,392] [--scenes tiny,medium] [--out FILE]
#   --frames N     frames per benchmark, warm-up included (default 8)
#   --sizes S,...  square image sizes (default 256,392)
#   --scenes ...   which scenes (default tiny,medium)
#   --out FILE     log (default bench/results/viewer_<device>.log)
set -euo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-./build/refrax}
VIEW=${REFRAX_VIEW:-$(dirname "$REFRAX")/refrax-view}

frames=8
sizes=256,392
scenes=tiny,medium
out=
while [ $# -gt 0 ]; do
  case "$1" in
    --frames | --sizes | --scenes | --out)
      [ $# -ge 2 ] || { echo "viewer.sh: $1 needs a value" >&2; exit 2; }
      declare "${1#--}=$2"
      shift ;;
    -h | --help) sed -n '2,/^set -/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "viewer.sh: unknown option '$1' (--frames, --sizes, --scenes, --out)" >&2; exit 2 ;;
  esac
  shift
done
case "$frames" in '' | *[!0-9]* | 0 | 1) echo "viewer.sh: --frames must be a number of at least 2" >&2; exit 2 ;; esac
command -v xvfb-run >/dev/null || { echo "viewer.sh: xvfb-run not found (apt install xvfb, or scripts/install-deps.sh)" >&2; exit 2; }
. bench/ensure-build.sh
ensure_refrax viewer.sh "$REFRAX"
[ -x "$VIEW" ] || { echo "viewer.sh: $VIEW not found (build first, or set REFRAX_VIEW=path)" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
device=$("$REFRAX" devices | sed -n 's/^\[0\] \([^(]*\).*/\1/p' | tr -c 'A-Za-z0-9\n' '_' | sed 's/_*$//')
[ -n "$out" ] || out="bench/results/viewer_${device:-device}.log"

"$REFRAX" synth nerfrac-primary-sine --size tiny -o "$work/data" >/dev/null
log="$work/log"
{
  echo "# bench/viewer.sh: refrax-view --benchmark, $(date -u +%Y-%m-%d), $(nproc) cores, load: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "# scenes: tiny = refrax train (synth nerfrac-primary-sine tiny) --steps 300 --patch 32 --gaussians 2000;"
  echo "#         medium = same data --steps 30 --gaussians 30000 --no-densify"
  echo "# command: xvfb-run -a refrax-view RUN --size S --frames $frames --benchmark --water W --gaussian-trace T --camera 0,-1.2,0.8,0,0,-0.6"
  echo "# (first frame = warm-up, not counted); water keep = baked mesh walked as a height grid (default), keep --exact-water = subdivided surface;"
  echo "# T = tiles (default) or bvh, run back to back so their ratio is measured under the same load"
} >"$log"
for scene in ${scenes//,/ }; do
  case "$scene" in
    tiny) train_args=(--steps 300 --patch 32 --gaussians 2000) ;;
    medium) train_args=(--steps 30 --gaussians 30000 --no-densify) ;;
    *) echo "viewer.sh: unknown scene '$scene' (tiny, medium)" >&2; exit 2 ;;
  esac
  echo "viewer.sh: training the $scene scene" >&2
  "$REFRAX" train "$work/data" -o "$work/$scene" "${train_args[@]}" --progress-every 100 >/dev/null
  for size in ${sizes//,/ }; do
    for water in "keep" "remove" "keep --exact-water"; do
      for trace in tiles bvh; do
        echo "viewer.sh: $scene ${size}² water $water, $trace" >&2
        # shellcheck disable=SC2086  # "keep --exact-water" is two arguments on purpose
        xvfb-run -a "$VIEW" "$work/$scene" --size "$size" --frames "$frames" --benchmark \
          --camera 0,-1.2,0.8,0,0,-0.6 --water $water --gaussian-trace $trace 2>&1 | grep '^benchmark' |
          sed "s#$work/##; s#^benchmark#benchmark [--water $water --gaussian-trace $trace]#" >>"$log"
      done
    done
  done
done
mkdir -p "$(dirname "$out")"
mv "$log" "$out.tmp" && mv "$out.tmp" "$out"
echo "viewer.sh: wrote $out" >&2
grep 'FPS' "$out" >&2
