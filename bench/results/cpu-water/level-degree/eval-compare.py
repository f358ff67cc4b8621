# The evaluation set, seed 1: the method at the level prior of degree 4 (eval-d4-s1/: training code
# 8b87bbf with the recipe's degree set to 4, the same as --level-prior-degree 4; its run_info says
# "no method flags" for that reason; the change was not kept) against degree 2 (the defaults of
# 97e2e32: ../level-prior/eval-lp-s1/),
# straight rays from ../eval-defaults/ (seed 1; their training code is unchanged since), the
# oracle's lead over straight rays from bench/results/generalise/eval-cpu (4,000 steps).
# Usage: python3 bench/results/cpu-water/level-degree/eval-compare.py [repository root]
import os, statistics as st, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
here = os.path.join(root, 'bench/results/cpu-water')
sys.path.insert(0, here)
from eval_rows import load  # noqa: E402


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


def goals(tag):
    matters = [x for x in rows if x['lead'] >= 1]
    rest = [x for x in rows if x['lead'] < 1]
    med = lambda v: st.median(v) if v else float('nan')
    g, r, a = 'g' + tag, 'r' + tag, 'a' + tag
    print('degree %s: %d runs; where the water matters (oracle lead >= 1 dB, %d runs): beats straight rays %d, median gain %+.2f, '
          'median amplitude %.2f; elsewhere (%d runs): within 0.5 dB of straight rays %d, median gain %+.2f; '
          'diverged (> 1.5x the flat start) %d; worse than flat %d; worst %.2fx' % (
              tag, len(rows), len(matters), sum(x[g] > 0 for x in matters), med([x[g] for x in matters]), med([x[a] for x in matters]),
              len(rest), sum(x[g] >= -0.5 for x in rest), med([x[g] for x in rest]), sum(x[r] > 1.5 for x in rows),
              sum(x[r] > 1 for x in rows), max(x[r] for x in rows)))


goals('2')
goals('4')
