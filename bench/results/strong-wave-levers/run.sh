#!/usr/bin/env bash
# Strong-wave ablation from the defaults (2026-12-06): one change at a time, seeds 1-3.
set -u
R=/work/main/build/refrax
data=/work/swab/data
[ -f $data/water.json ] || $R synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2 -o $data >/dev/null
run() { local name=$1 seed=$2; shift 2; local dir=/work/swab/runs/$name-$seed; rm -rf $dir; mkdir -p /work/swab/runs
  $R train $data -o $dir --seed $seed --checkpoint-every 0 --progress-every 100000 "$@" > $dir.log 2>&1
  echo "$name-$seed: $(tail -n 1 $dir.log)" >> /work/swab/summary.txt
  $R report $dir -o /work/swab/runs-$name-$seed.csv --set "name=$name,seed=$seed" >/dev/null; }
for seed in 1 2 3; do
  run defaults $seed
  run batch1 $seed --surface-batch 1
  run lr3e-3 $seed --surface-lr 3e-3
  run p64 $seed --patch 64 --steps 4000
  run straight-p64 $seed --patch 64 --steps 4000 --no-refraction
done
