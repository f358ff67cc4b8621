#!/usr/bin/env bash
# The Gaussian restarts at the defaults (2026-12-07): no restarts, --restart-gate 1, and restarts at
# 1/4 and 2/5 of the run (2000,3200) instead of 1/3 and 8/15; 8,000 steps. Lavapipe, two trainings at a time.
set -u
cd "$(dirname "$0")/../../.."
R=build/refrax
# dev scenes, seed 1 (the defaults' and straight rays' rows: bench/results/octaves/defaults,
# bench/results/large-prune/dev-prune-off.csv, bench/results/strong-wave-levers/dev-defaults-5-6)
bash bench/generalise.sh --set dev --scene-list "11 9 12 14 15 5 6" --seeds 1 --steps 8000 --jobs 2 --models method --method-flags "--restart-gaussians 0" --out /tmp/restarts-nr-dev
bash bench/generalise.sh --set dev --scene-list "11 9 12 14 15 5 6" --seeds 1 --steps 8000 --jobs 2 --models method --method-flags "--restart-gate 1" --out /tmp/restarts-rg-dev
bash bench/generalise.sh --set dev --scene-list "14 12 9 6" --seeds 1 --steps 8000 --jobs 1 --models method --method-flags "--restart-gaussians 2000,3200" --out /tmp/restarts-er-dev
bash bench/generalise.sh --set dev --scene-list "11 15 5" --seeds 1 --steps 8000 --jobs 2 --models method --method-flags "--restart-gaussians 2000,3200" --out /tmp/restarts-er-dev-b
bash bench/generalise.sh --set dev --scene-list "14 9" --seed-list "2" --steps 8000 --jobs 2 --models method --method-flags "--restart-gaussians 2000,3200" --out /tmp/restarts-er-dev-s2
# the strong wave (the long test's data), seeds 1-3
data=/tmp/strong-wave; [ -f $data/water.json ] || $R synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2 -o $data >/dev/null
for seed in 1 2 3; do
  for arm in "norestart --restart-gaussians 0" "gate1 --restart-gate 1" "early --restart-gaussians 2000,3200" "defaults-again"; do
    set -- $arm; name=$1; shift
    $R train $data -o /tmp/sw-$name-$seed --seed $seed --checkpoint-every 0 --progress-every 100000 "$@" | tail -n 1 | sed "s/^/$name-$seed: /"
  done
done
