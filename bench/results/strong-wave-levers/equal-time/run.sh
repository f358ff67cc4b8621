#!/usr/bin/env bash
# Strong wave: --surface-batch 1 at the defaults' wall time (5,200 steps; the step costs 1.53x), seeds 1-3.
set -u
cd "$(dirname "$0")/../../../.."  # the repository root
R=build/refrax; data=/tmp/strong-wave
[ -f $data/water.json ] || $R synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2 -o $data >/dev/null
out=/tmp/strong-wave-equal-time; mkdir -p $out
run() { local name=$1 seed=$2; shift 2; local dir=$out/$name-$seed; rm -rf $dir
  $R train $data -o $dir --seed $seed --checkpoint-every 0 --progress-every 100000 "$@" > $dir.log 2>&1
  echo "$name-$seed: $(tail -n 1 $dir.log)" >> $out/summary.txt
  $R report $dir -o $out/runs-$name-$seed.csv --set "name=$name,seed=$seed" >/dev/null; }
run batch1-5200 1 --surface-batch 1 --steps 5200 &
run batch1-5200 2 --surface-batch 1 --steps 5200 &
wait
run batch1-5200 3 --surface-batch 1 --steps 5200 &
run defaults-5200 1 --steps 5200 &
wait
