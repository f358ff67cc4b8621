#!/usr/bin/env bash
# The long test's flags less one at a time (seed 1): which carries its gain over the defaults.
set -u
cd "$(dirname "$0")/../../../.."  # the repository root
R=build/refrax; data=/tmp/strong-wave
[ -f $data/water.json ] || $R synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2 -o $data >/dev/null
out=/tmp/strong-wave-leave-one-out; mkdir -p $out
BASE="--recipe reference --steps 4000 --patch 64 --gaussians 2000 --max-gaussians 4000 --density-reset-every 0 --sh-degree 0 --checkpoint-every 0 --progress-every 100000"
JOINT="--mlp-octaves 4 --grid-cells 16 --subdivision 2 --mlp-coarse-octaves 3 --octaves-open-until 10000000 --surface-lr 3e-3 --surface-freeze 400 --anchor-mean-height --level-prior 1000 --surface-smoothness 0.1 --init-depth sweep --restart-gaussians 1000,1600,2200"
run() { local name=$1; shift; local dir=$out/$name; rm -rf $dir
  $R train $data -o $dir --seed 1 $BASE $JOINT "$@" > $dir.log 2>&1
  echo "$name: $(tail -n 1 $dir.log)" >> $out/summary.txt
  $R report $dir -o $out/runs-$name.csv --set "name=$name,seed=1" >/dev/null; }
run full &
run no-batch1 --surface-batch views &
wait
run no-lr3e-3 --surface-lr 1e-3 &
run no-patch64 --patch 32 &
wait
run no-restarts --restart-gaussians 1333,2133 &
run no-freeze400 --surface-freeze 533 &
wait
run no-level1e3 --level-prior 10000 &
run no-gaussians --gaussians 1200 --max-gaussians 1200 &
wait
run no-small-model --mlp-octaves 5 --grid-cells 32 &
wait
