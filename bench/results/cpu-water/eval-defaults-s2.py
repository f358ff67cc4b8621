# The evaluation set at the defaults (level prior 10,000 at degree 2), both seeds: the "before"
# table of issue 45's goals. The method: seed 1 from level-prior/eval-lp-s1/, seed 2 from
# level-prior/eval-lp-s2/ (1001-1005) and eval-defaults-s2/ (1006-1012, trained later by a binary
# whose defaults train alike: the options added since, --level-prior-degree and
# --level-prior-warp, default to what ran). Straight rays: seed 1 from eval-defaults/, seed 2 from
# the same folders as the method's. The oracle's lead over straight rays: bench/results/generalise/
# eval-cpu (4,000 steps), per seed.
# Usage: python3 bench/results/cpu-water/eval-defaults-s2.py [repository root]
import os, statistics as st, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
here = os.path.join(root, 'bench/results/cpu-water')
sys.path.insert(0, here)
from eval_rows import goal_line, load  # noqa: E402

method = load(here, 'level-prior/eval-lp-s1', 'level-prior/eval-lp-s2', 'eval-defaults-s2')
straight = load(here, 'eval-defaults', 'level-prior/eval-lp-s2', 'eval-defaults-s2')
oracle = load(here, '../generalise/eval-cpu')
f = lambda r, k: float(r[k])
rows = []
print('scene | seed | oracle lead | straight | method | gain | surface/flat | amplitude | correlation')
for sc in map(str, range(1001, 1013)):
    for seed in ('1', '2'):
        m, n = method.get((sc, seed, 'method')), straight.get((sc, seed, 'no-refraction'))
        o, on = oracle.get((sc, seed, 'known-water')), oracle.get((sc, seed, 'no-refraction'))
        if not (m and n and o and on): continue
        x = dict(scene=sc, seed=seed, lead=f(o, 'eval_psnr') - f(on, 'eval_psnr'), gain=f(m, 'eval_psnr') - f(n, 'eval_psnr'),
                 ratio=f(m, 'eval_surface_rmse') / f(m, 'eval_flat_rmse'), amp=f(m, 'amplitude_ratio'))
        rows.append(x)
        print('%s | %s | %+.2f | %.2f | %.2f | %+.2f | %.2f | %.2f | %.2f' % (sc, seed, x['lead'], f(n, 'eval_psnr'), f(m, 'eval_psnr'), x['gain'],
                                                                           x['ratio'], x['amp'], f(m, 'eval_correlation')))
print(goal_line('the defaults, seeds 1 and 2', rows, lambda x: x['gain'], lambda x: x['ratio'], lambda x: x['amp']))
for seed in ('1', '2'):
    part = [x for x in rows if x['seed'] == seed]
    if part: print(goal_line('seed ' + seed, part, lambda x: x['gain'], lambda x: x['ratio'], lambda x: x['amp']))
# where the water matters, the oracle's lead against the method's gain: the gap to the oracle
gaps = [x['lead'] - x['gain'] for x in rows if x['lead'] >= 1]
if gaps: print('where the water matters: median gap to the oracle %.2f dB (goal <= 1.5; the oracle from eval-cpu, 4,000 steps at the settings of then), %d runs' % (st.median(gaps), len(gaps)))
