#!/usr/bin/env bash
# The long test's strong wave at refrax train's defaults, where the water matters (issue 45):
# `refrax synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2`,
# straight rays and the oracle, then each candidate's flags added to the defaults, per seed.
# One line per run in DIR/summary.txt (refrax train's summary) and DIR/runs.csv (refrax report).
# Usage: bench/strong-wave.sh [--seeds "1 2"] [--out DIR] [NAME="FLAGS" ...]
#   e.g. bench/strong-wave.sh defaults="" level1e3="--level-prior 1000 --surface-lr 3e-3 --surface-smoothness 0"
# About 40 s a run at 32 px patches on this 2-core lavapipe machine.
set -euo pipefail
cd "$(dirname "$0")/.."
REFRAX=${REFRAX:-build/refrax}
seeds="1 2"
out=bench/results/strong-wave
candidates=()
while [ $# -gt 0 ]; do
  case $1 in
    --seeds) seeds=$2; shift ;;
    --out) out=$2; shift ;;
    *=*) candidates+=("$1") ;;
    *) echo "strong-wave.sh: unknown argument '$1' (--seeds, --out, NAME=\"FLAGS\")" >&2; exit 2 ;;
  esac
  shift
done
[ ${#candidates[@]} -gt 0 ] || candidates=("defaults=")
. bench/ensure-build.sh
ensure_refrax strong-wave "$REFRAX"
mkdir -p "$out/work"
data=$out/work/data
[ -f "$data/water.json" ] || "$REFRAX" synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2 -o "$data" >/dev/null
run() {  # name seed flags...
  local name=$1 seed=$2
  shift 2
  local dir=$out/work/$name-$seed
  rm -rf "$dir"
  # shellcheck disable=SC2068
  "$REFRAX" train "$data" -o "$dir" --seed "$seed" --checkpoint-every 0 --progress-every 100000 $@ >"$dir.log" 2>&1
  echo "$name-$seed: $(tail -n 1 "$dir.log")" | tee -a "$out/summary.txt"
  local append=()
  [ -f "$out/runs.csv" ] && append=(--append)
  "$REFRAX" report "$dir" -o "$out/runs.csv" ${append[@]+"${append[@]}"} --set "name=$name,seed=$seed" >/dev/null
}
: >"$out/summary.txt"
rm -f "$out/runs.csv"
for seed in $seeds; do
  run straight "$seed" --no-refraction
  run oracle "$seed" --known-water
  for c in "${candidates[@]}"; do run "${c%%=*}" "$seed" ${c#*=}; done
done
rm -rf "$out/work"
