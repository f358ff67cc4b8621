# The evaluation set, seed 1: the method at the level prior of degree 4 (eval-d4-s1/: training code
# 8b87bbf with the recipe's degree set to 4, the same as --level-prior-degree 4; its run_info says
# "no method flags" for that reason; the change was not kept) against degree 2 (the defaults of
# 97e2e32: ../level-prior/eval-lp-s1/),
# straight rays from ../eval-defaults/ (seed 1; their training code is unchanged since), the
# oracle's lead over straight rays from bench/results/generalise/eval-cpu (4,000 steps).
# Usage: python3 bench/results/cpu-water/level-degree/eval-compare.py [repository root]
import os, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
here = os.path.join(root, 'bench/results/cpu-water')
sys.path.insert(0, here)
from eval_rows import goal_line, load  # noqa: E402


straight = load(here, 'eval-defaults')
degree2 = load(here, 'level-prior/eval-lp-s1')
degree4 = load(here, 'level-degree/eval-d4-s1')
oracle = load(here, '../generalise/eval-cpu')
f = lambda r, k: float(r[k])
rows = []
print('scene | oracle lead | straight | method degree 2 -> 4 | gain 2 -> 4 | surface/flat 2 -> 4 | amplitude 2 -> 4 | correlation 2 -> 4')
for sc in map(str, range(1001, 1013)):
    m2, m4, n = degree2.get((sc, '1', 'method')), degree4.get((sc, '1', 'method')), straight.get((sc, '1', 'no-refraction'))
    if not (m2 and m4 and n): continue
    o, on = oracle.get((sc, '1', 'known-water')), oracle.get((sc, '1', 'no-refraction'))
    x = dict(lead=f(o, 'eval_psnr') - f(on, 'eval_psnr') if o and on else float('nan'))
    for tag, m in (('2', m2), ('4', m4)):
        x['g' + tag] = f(m, 'eval_psnr') - f(n, 'eval_psnr')
        x['r' + tag] = f(m, 'eval_surface_rmse') / f(m, 'eval_flat_rmse')
        x['a' + tag] = f(m, 'amplitude_ratio')
        x['c' + tag] = f(m, 'eval_correlation')
        x['p' + tag] = f(m, 'eval_psnr')
    rows.append(x)
    print('%s | %+.2f | %.2f | %.2f -> %.2f | %+.2f -> %+.2f | %.2f -> %.2f | %.2f -> %.2f | %.2f -> %.2f' % (
        sc, x['lead'], f(n, 'eval_psnr'), x['p2'], x['p4'], x['g2'], x['g4'], x['r2'], x['r4'], x['a2'], x['a4'], x['c2'], x['c4']))


for tag in ('2', '4'):
    print(goal_line('degree ' + tag, rows, lambda x: x['g' + tag], lambda x: x['r' + tag], lambda x: x['a' + tag]))
