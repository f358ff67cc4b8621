# The evaluation set, seed 1: the method at three level priors side by side, degree 2 (the
# defaults of 97e2e32: ../level-prior/eval-lp-s1/), degree 4 (eval-d4-s1/, training code 8b87bbf)
# and degree 4 with the terms past the bowl at a tenth of the weight (eval-w0.1-s1/, training
# code 5d243ac, --level-prior-degree 4 --level-prior-warp 0.1); straight rays from
# ../eval-defaults/ (seed 1; their training code is unchanged since), the oracle's lead over
# straight rays from bench/results/generalise/eval-cpu (4,000 steps).
# Usage: python3 bench/results/cpu-water/level-degree/eval-warp.py [repository root]
import os, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
here = os.path.join(root, 'bench/results/cpu-water')
sys.path.insert(0, here)
from eval_rows import goal_line, load  # noqa: E402

arms = [('degree 2', load(here, 'level-prior/eval-lp-s1')), ('degree 4', load(here, 'level-degree/eval-d4-s1')),
        ('degree 4, warp 0.1', load(here, 'level-degree/eval-w0.1-s1'))]
straight = load(here, 'eval-defaults')
oracle = load(here, '../generalise/eval-cpu')
f = lambda r, k: float(r[k])
rows = []
print('scene | oracle lead | straight | method psnr | gain | surface/flat | amplitude | correlation (each: ' + ' / '.join(a for a, _ in arms) + ')')
for sc in map(str, range(1001, 1013)):
    ms, n = [arm.get((sc, '1', 'method')) for _, arm in arms], straight.get((sc, '1', 'no-refraction'))
    if not (all(ms) and n): continue
    o, on = oracle.get((sc, '1', 'known-water')), oracle.get((sc, '1', 'no-refraction'))
    x = dict(lead=f(o, 'eval_psnr') - f(on, 'eval_psnr') if o and on else float('nan'))
    x['p'] = [f(m, 'eval_psnr') for m in ms]
    x['g'] = [p - f(n, 'eval_psnr') for p in x['p']]
    x['r'] = [f(m, 'eval_surface_rmse') / f(m, 'eval_flat_rmse') for m in ms]
    x['a'] = [f(m, 'amplitude_ratio') for m in ms]
    x['c'] = [f(m, 'eval_correlation') for m in ms]
    rows.append(x)
    j = lambda fmt, v: ' / '.join(fmt % e for e in v)
    print('%s | %+.2f | %.2f | %s | %s | %s | %s | %s' % (sc, x['lead'], f(n, 'eval_psnr'), j('%.2f', x['p']), j('%+.2f', x['g']),
                                                       j('%.2f', x['r']), j('%.2f', x['a']), j('%.2f', x['c'])))

for i, (name, _) in enumerate(arms):
    print(goal_line(name, rows, lambda x: x['g'][i], lambda x: x['r'][i], lambda x: x['a'][i]))
