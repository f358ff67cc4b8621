#!/usr/bin/env bash
# Issue 45, 2026-12-07: the long test's water settings as the CPU's defaults
# (docs/experiments/2026-12-07-cpu-water.md). Lavapipe on a 2-core machine, two trainings at a
# time for the accuracy runs (their seconds are no speed figures), one at a time for the cost.
# Training code b169f10 (git ls-tree of engine/ shaders/ trainer/ CMakeLists.txt | git hash-object),
# the defaults before this change; the candidate is given as flags.
set -u
cd "$(dirname "$0")/../../.."
R=build/refrax
CAND="--level-prior 1000 --surface-lr 3e-3 --surface-batch 1 --restart-gaussians 1000,1600,2200 --surface-freeze 400"
# where the water matters: the method and straight rays, both at 4,000 steps of 64 px patches
bash bench/generalise.sh --set dev --scene-list "9 14 15" --seed-list "1 2 3" --steps 4000 --jobs 2 \
  --models "method no-refraction" --train-flags "--patch 64" --method-flags "$CAND" --out /tmp/cpu-water-dev-water --keep-work
# where it runs away (dev 5, 11: seed 1 in bench/results/strong-wave-levers/test-config-dev) and
# where 3e-3 with 32 px patches ran away on 2026-12-04 (dev 3, 4, 6)
bash bench/generalise.sh --set dev --scene-list "5 11" --seed-list "2 3" --steps 4000 --jobs 2 \
  --models method --train-flags "--patch 64" --method-flags "$CAND" --out /tmp/cpu-water-dev-diverge
bash bench/generalise.sh --set dev --scene-list "6 3 4" --seed-list "1" --steps 4000 --jobs 2 \
  --models method --train-flags "--patch 64" --method-flags "$CAND" --out /tmp/cpu-water-dev-diverge-b
# the strong wave (the long test's data), seeds 1-3: the candidate and straight rays alike
data=/tmp/strong-wave; [ -f $data/water.json ] || $R synth nerfrac-primary-sine --size tiny --width 96 --ior 1.33 --wave-amplitude 2 -o $data >/dev/null
for seed in 1 2 3; do
  $R train $data -o /tmp/sw-cand-$seed --seed $seed --steps 4000 --patch 64 $CAND --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/cand-$seed: /" &
  $R train $data -o /tmp/sw-straight64-$seed --seed $seed --no-refraction --steps 4000 --patch 64 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/straight64-$seed: /" &
  wait
done
# a run's cost, one training at a time: half-length runs on dev 14 and dev 9 (the drawn scenes
# of the first invocation), the earlier defaults 2,000 steps of 32 px (their recipe, as flags),
# the candidate 1,000 of 64 px
for scene in 14 9; do
  d=/tmp/cpu-water-dev-water/work/data/scene_${scene}_wet
  for rep in 1 2; do
    $R train $d -o /tmp/cost-def-$scene-$rep --steps 2000 --patch 32 --surface-lr 1e-3 --surface-batch views --level-prior 10000 \
      --restart-gaussians 666,1066 --surface-freeze 266 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/def-$scene-$rep: /"
    $R train $d -o /tmp/cost-cand-$scene-$rep --steps 1000 --patch 64 --level-prior 1000 --surface-lr 3e-3 --surface-batch 1 \
      --restart-gaussians 250,400,550 --surface-freeze 100 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/cand-$scene-$rep: /"
  done
done
# equal time (the candidate costs 1.52x a run): the candidate at 2,650 steps, and the earlier
# defaults (given as flags: this binary's recipe is the candidate) at 12,000 steps
EQ="--level-prior 1000 --surface-lr 3e-3 --surface-batch 1 --restart-gaussians 662,1060,1457 --surface-freeze 265"
OLD="--surface-lr 1e-3 --surface-batch views --level-prior 10000 --restart-gaussians 4000,6400 --surface-freeze 1600"
bash bench/generalise.sh --set dev --scene-list "14" --seed-list "1 2 3" --steps 2650 --jobs 2 \
  --models method --train-flags "--patch 64" --method-flags "$EQ" --out /tmp/cpu-water-eq-dev14
bash bench/generalise.sh --set dev --scene-list "14" --seed-list "1 2" --steps 12000 --jobs 2 \
  --models method --train-flags "--patch 32" --method-flags "$OLD" --out /tmp/cpu-water-def12k-dev14
for seed in 1 2 3; do
  $R train $data -o /tmp/sw-eq-$seed --seed $seed --steps 2650 --patch 64 $EQ --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/sw-$seed: /"
  $R train $data -o /tmp/sw-def12k-$seed --seed $seed --steps 12000 --patch 32 $OLD --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/sw-$seed: /"
done
# After the change (training code 7c96c57, the defaults of 4c4bf8f): the evaluation set at the
# defaults, seed 1, the method and straight rays, two trainings at a time (eval-defaults/), and
# the comparison with the earlier defaults (eval-defaults/before-after.txt)
PATH=/usr/bin:$PATH bash bench/generalise.sh --set eval --scenes 12 --seed-list "1" --models "method no-refraction" --jobs 2 \
  --out /tmp/cpu-water-eval-defaults
python3 bench/results/cpu-water/eval-before-after.py . /tmp/cpu-water-eval-defaults
# Gentle waves: dev 10 and 16 (slope bounds 0.152 and 0.217), the method at the defaults, seeds 1-3
# (dev-gentle/), and desk (tiny) at 1,500 steps with --sweep-watch 200 (gentle-screens.txt)
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "10 16" --seed-list "1 2 3" --models method --jobs 1 --out /tmp/cpu-water-dev-gentle
$R synth desk --size tiny -o /tmp/desk >/dev/null
for seed in 1 2 3; do
  $R train /tmp/desk -o /tmp/desk-watch-$seed --steps 1500 --seed $seed --sweep-watch 200 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/watch $seed: /"
done
# The strong wave at the defaults with the long test's Gaussian budget, seeds 1-3 (strong-wave-gaussians.txt)
for seed in 1 2 3; do
  $R train $data -o /tmp/sw-g-$seed --seed $seed --gaussians 2000 --max-gaussians 4000 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/gaussians 2000-4000 seed $seed: /"
done
for seed in 1 2 3; do
  $R train /tmp/desk -o /tmp/desk-lp-$seed --steps 1500 --seed $seed --level-prior 10000 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/level-prior 10000 seed $seed: /"
  $R train /tmp/desk -o /tmp/desk-lr-$seed --steps 1500 --seed $seed --surface-lr 1e-3 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/surface-lr 1e-3 seed $seed: /"
done
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "10" --seed-list "1" --models method --method-flags "--level-prior 10000" --jobs 1 --out /tmp/cpu-water-dev10-lp
# The level prior at 10,000 (level-prior/; training code f7c44d3, the defaults at 1,000, given the
# flag): the method on the gentle dev scenes 10 and 16 and on dev 9, 14, 15 where the water is
# learned, seeds 1-3, two trainings at a time; straight rays on 10 and 16 alike; the strong wave
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "10 16" --seed-list "1 2 3" --models method --method-flags "--level-prior 10000" --jobs 2 --out /tmp/lp-gentle
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "9 14 15" --seed-list "1 2 3" --models method --method-flags "--level-prior 10000" --jobs 2 --out /tmp/lp-water
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "10 16" --seed-list "1 2 3" --models no-refraction --jobs 2 --out /tmp/straight-gentle
for seed in 1 2 3; do
  $R train $data -o /tmp/sw-lp-$seed --seed $seed --level-prior 10000 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/level-prior 10000 seed $seed: /"
done
# At 97e2e32 (the level prior at 10,000 the default): the README's table, the method's rows only
# (the other models' rows kept: their training code is unchanged), and the evaluation set at the
# defaults, the method at seed 1 (straight rays: eval-defaults/) and both models at seed 2
awk -F, 'NR == 1 || $3 != "method"' bench/results/readme-table/rows.csv > /tmp/rows.csv && mv /tmp/rows.csv bench/results/readme-table/rows.csv
echo "seeds=1 2 3 steps=1500" > bench/results/readme-table/settings.txt && echo 7aadf3b > bench/results/readme-table/commit.txt
bash bench/readme-table.sh --resume
PATH=/usr/bin:$PATH bash bench/generalise.sh --set eval --scenes 12 --seed-list "1" --models method --jobs 2 --out /tmp/eval-lp-s1
PATH=/usr/bin:$PATH bash bench/generalise.sh --set eval --scenes 12 --seed-list "2" --models "method no-refraction" --jobs 2 --out /tmp/eval-lp-s2
python3 bench/results/cpu-water/level-prior/eval-compare.py .
# The level prior's degree (level-degree/; training code 8b87bbf, the defaults of 97e2e32 with
# --level-prior-degree D given; lavapipe, two trainings at a time): desk (tiny, 1,500 steps) at
# degrees 2, 3, 4, seeds 1-3, and its error taken apart by degree; then degree 4 on dev 16 and 9
# (seeds 1-3), the strong wave (seeds 1-3), dev 10, 14 and 15 (seed 1)
$R synth desk --size tiny -o /tmp/desk >/dev/null
for seed in 1 2 3; do for d in 2 3 4; do
  $R train /tmp/desk -o /tmp/desk-d$d-$seed --steps 1500 --seed $seed --level-prior-degree $d --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/degree $d seed $seed: /"
done; done
for d in 2 4; do for seed in 1 2 3; do PATH=/usr/bin:$PATH python3 bench/results/cpu-water/level-degree/residual-degrees.py /tmp/desk-d$d-$seed /tmp/desk 0.75; done; done
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "16 9" --seed-list "1 2 3" --models method --method-flags "--level-prior-degree 4" --jobs 2 --out /tmp/dev-16-9
for seed in 1 2 3; do
  $R train $data -o /tmp/sw-d4-$seed --seed $seed --level-prior-degree 4 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/degree 4 seed $seed: /"
done
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "10" --seed-list "1" --models method --method-flags "--level-prior-degree 4" --jobs 1 --out /tmp/dev-10-s1
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "14 15" --seed-list "1" --models method --method-flags "--level-prior-degree 4" --jobs 2 --out /tmp/dev-14-15-s1
# The evaluation set at degree 4, the method at seed 1 (run with the recipe's degree set to 4,
# which is the same; straight rays: eval-defaults/; degree 2: level-prior/eval-lp-s1/)
PATH=/usr/bin:$PATH bash bench/generalise.sh --set eval --scenes 12 --seed-list "1" --models method --method-flags "--level-prior-degree 4" --jobs 2 --out /tmp/eval-d4-s1
python3 bench/results/cpu-water/level-degree/eval-compare.py .
# The terms past the bowl weighted less (--level-prior-warp S, training code 5d243ac): desk at
# degree 4 with S = 0.1, 0.3 and 0.03, seeds 1-3; then dev 10 and 16 at S = 0.1, seeds 1-3
for seed in 1 2 3; do for w in 0.1 0.3 0.03; do
  $R train /tmp/desk -o /tmp/desk-w$w-$seed --steps 1500 --seed $seed --level-prior-degree 4 --level-prior-warp $w --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/degree 4 warp $w seed $seed: /"
done; done
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "10 16" --seed-list "1 2 3" --models method --method-flags "--level-prior-degree 4 --level-prior-warp 0.1" --jobs 2 --out /tmp/dev-warp-0.1
# S = 0.1 on the rest of the development scenes where the water matters and the strong wave
# (training code 5d243ac, unchanged since; seeds 1-3, two trainings at a time), then the
# three arms side by side on the development scenes
for seed in 1 2 3; do
  $R train $data -o /tmp/sw-w0.1-$seed --seed $seed --level-prior-degree 4 --level-prior-warp 0.1 --checkpoint-every 0 --progress-every 100000 | tail -n 1 | sed "s/^/degree 4 warp 0.1 seed $seed: /"
done
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "9 14 15" --seed-list "1 2 3" --models method --method-flags "--level-prior-degree 4 --level-prior-warp 0.1" --jobs 2 --out /tmp/dev-9-14-15-warp-0.1
python3 bench/results/cpu-water/level-degree/dev-warp.py .
# The evaluation set at S = 0.1, the method at seed 1 (training code 5d243ac), and the three
# level priors side by side (straight rays: eval-defaults/)
PATH=/usr/bin:$PATH bash bench/generalise.sh --set eval --scenes 12 --seed-list "1" --models method --method-flags "--level-prior-degree 4 --level-prior-warp 0.1" --jobs 2 --out /tmp/eval-w0.1-s1
python3 bench/results/cpu-water/level-degree/eval-warp.py .
# The evaluation set's second seed at the defaults for the scenes the earlier invocation had not
# reached (1001-1005: level-prior/eval-lp-s2/; training code 90261b9 of the tree, whose defaults
# train as that of 81caa39), one training at a time; the defaults' table over both seeds; and
# where each seed-2 run's water error lies (the run folders and datasets kept by hand from
# generalise's work folder)
PATH=/usr/bin:$PATH bash bench/generalise.sh --set eval --scene-list "1006 1007 1008 1009 1010 1011 1012" --seed-list "2" --models "method no-refraction" --jobs 1 --out /tmp/eval-s2b
python3 bench/results/cpu-water/eval-defaults-s2.py . > bench/results/cpu-water/eval-defaults-s2.txt
for s in 1006 1007 1008 1009 1010 1011 1012; do
  PATH=/usr/bin:$PATH python3 bench/water-error-map.py /tmp/keep/scene_${s}_seed_2_method /tmp/data/scene_${s}_wet
done > bench/results/cpu-water/eval-defaults-s2/error-map.txt
# Every octave of the height field open by step 2,000 at the defaults, on development scenes
# with fine waves (15, 16) and long ones (9, 10), one or two seeds (training code 90261b9;
# --keep-work for bench/water-error-map.py), and dev 10 so without the slope prior; the pairs
# against the defaults' rows of the same seeds
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "16 15 10" --seed-list "1" --models method --method-flags "--octaves-open-until 2000" --keep-work --jobs 1 --out /tmp/dev-open-s1
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "9 16 15" --seed-list "2" --models method --method-flags "--octaves-open-until 2000" --keep-work --jobs 1 --out /tmp/dev-open-s2
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "10" --seed-list "2" --models method --method-flags "--octaves-open-until 2000" --keep-work --jobs 1 --out /tmp/dev-open-s2-10
PATH=/usr/bin:$PATH bash bench/generalise.sh --set dev --scene-list "10" --seed-list "1" --models method --method-flags "--octaves-open-until 2000 --surface-smoothness 0" --keep-work --jobs 1 --out /tmp/dev-open-no-slope-prior
python3 bench/results/cpu-water/octaves/dev-octaves.py . > bench/results/cpu-water/octaves/dev-octaves.txt
