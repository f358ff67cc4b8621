# The development scenes where the water matters (9, 14, 15) and the gentle ones (10, 16), seeds
# 1-3, the method at three level priors: degree 2 (the defaults of 97e2e32: ../level-prior/lp-water/
# and lp-gentle/), degree 4 (dev-16-9/ for 9 and 16, seeds 1-3; dev-10-s1/ and dev-14-15-s1/, seed 1
# only) and degree 4 with the terms past the bowl at a tenth of the weight (dev-warp-0.1/ for 10
# and 16, dev-9-14-15-warp-0.1/). Per scene: the images' PSNR and the surface against the flat
# start, each seed and the median; '-' where an arm has no run.
# Usage: python3 bench/results/cpu-water/level-degree/dev-warp.py [repository root]
import os, statistics as st, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
here = os.path.join(root, 'bench/results/cpu-water')
sys.path.insert(0, here)
from eval_rows import load  # noqa: E402

arms = [('degree 2', load(here, 'level-prior/lp-water', 'level-prior/lp-gentle')),
        ('degree 4', load(here, 'level-degree/dev-16-9', 'level-degree/dev-10-s1', 'level-degree/dev-14-15-s1')),
        ('degree 4, warp 0.1', load(here, 'level-degree/dev-warp-0.1', 'level-degree/dev-9-14-15-warp-0.1'))]
for sc in ('9', '14', '15', '10', '16'):
    for name, arm in arms:
        runs = [arm.get((sc, s, 'method')) for s in ('1', '2', '3')]
        p = [float(r['eval_psnr']) if r else None for r in runs]
        q = [float(r['eval_surface_rmse']) / float(r['eval_flat_rmse']) if r else None for r in runs]
        cell = lambda v, fmt: '/'.join('-' if e is None else fmt % e for e in v)
        have = lambda v: [e for e in v if e is not None]
        med = lambda v: ('%.2f' % st.median(have(v))) if len(have(v)) == 3 else '-'
        print('dev %s, %s: psnr %s (median %s), surface/flat %s (median %s)' % (
            sc, name, cell(p, '%.2f'), med(p), cell(q, '%.2f'), med(q)))
