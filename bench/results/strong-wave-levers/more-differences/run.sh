#!/usr/bin/env bash
# The long test's other differences, one at a time from the defaults, on the strong wave, seeds 1-3: 2,000 -> 4,000 Gaussians; the level prior at 1,000.
set -u
cd "$(dirname "$0")/../../../.."  # the repository root
R=build/refrax; data=/tmp/strong-wave
[ -f $data/water.json ] || $R synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2 -o $data >/dev/null
out=/tmp/strong-wave-runs; mkdir -p $out
run() { local name=$1 seed=$2; shift 2; local dir=$out/$name-$seed; rm -rf $dir
  $R train $data -o $dir --seed $seed --checkpoint-every 0 --progress-every 100000 "$@" > $dir.log 2>&1
  echo "$name-$seed: $(tail -n 1 $dir.log)" >> $out/summary.txt
  $R report $dir -o $out/runs-$name-$seed.csv --set "name=$name,seed=$seed" >/dev/null; }
run g4000 1 --gaussians 2000 --max-gaussians 4000 &
run level1e3 1 --level-prior 1000 &
wait
run g4000 2 --gaussians 2000 --max-gaussians 4000 &
run level1e3 2 --level-prior 1000 &
wait
run g4000 3 --gaussians 2000 --max-gaussians 4000 &
run level1e3 3 --level-prior 1000 &
wait
