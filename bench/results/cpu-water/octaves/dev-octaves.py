# The defaults against the defaults with every octave of the height field opening by step 2,000
# (`--octaves-open-until 2000`, before the last Gaussian restart at 2,200 of 4,000 steps), per
# development scene and seed: the defaults' rows from ../level-prior/lp-water/ (9, 14, 15) and
# ../level-prior/lp-gentle/ (10, 16), the screen's from dev-open-s1/, dev-open-s2/ and dev-open-s2-10/. One or
# two seeds a scene: a screen.
# Usage: python3 bench/results/cpu-water/octaves/dev-octaves.py [repository root]
import os, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
here = os.path.join(root, 'bench/results/cpu-water')
sys.path.insert(0, here)
from eval_rows import load  # noqa: E402

defaults = load(here, 'level-prior/lp-water', 'level-prior/lp-gentle')
opened = load(here, 'octaves/dev-open-s1', 'octaves/dev-open-s2', 'octaves/dev-open-s2-10')
f = lambda r, k: float(r[k])
cycles = {'9': '1.6, 3.9', '10': '2.0, 3.3', '15': '8.9', '16': '9.3'}  # the datasets' water.json, across the water's domain
print('dev scene | waves: cycles across the domain | seed | PSNR: defaults / octaves open | surface / flat start | amplitude | correlation')
for (scene, seed, variant), r in sorted(opened.items(), key=lambda kv: (int(kv[0][0]), kv[0][1])):
    d = defaults.get((scene, seed, 'method'))
    if not d: continue
    pair = lambda k, fmt: ' / '.join(fmt % v for v in (k(d), k(r)))
    print('%s | %s | %s | %s | %s | %s | %s' % (scene, cycles.get(scene, '?'), seed, pair(lambda x: f(x, 'eval_psnr'), '%.2f'),
          pair(lambda x: f(x, 'eval_surface_rmse') / f(x, 'eval_flat_rmse'), '%.2f'), pair(lambda x: f(x, 'amplitude_ratio'), '%.2f'),
          pair(lambda x: f(x, 'eval_correlation'), '%.2f')))
