# The evaluation set at the level prior of 10,000 (the defaults of 97e2e32: eval-lp-s1/ seed 1,
# eval-lp-s2/ seed 2) against 1,000 (the defaults of 4c4bf8f: ../eval-defaults/, seed 1 only),
# straight rays from the same folders, the oracle's lead over straight rays from
# bench/results/generalise/eval-cpu (4,000 steps), as ../eval-before-after.py.
# Usage: python3 bench/results/cpu-water/level-prior/eval-compare.py [repository root]
import os, statistics as st, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
here = os.path.join(root, 'bench/results/cpu-water')
sys.path.insert(0, here)
from eval_rows import load  # noqa: E402
lp1k = load(here, 'eval-defaults')
lp10k = load(here, 'level-prior/eval-lp-s1', 'level-prior/eval-lp-s2')
orc = load(here, '../generalise/eval-cpu')
def f(r, k): return float(r[k])
rows = []
print('scene seed | oracle lead | straight | method 1,000 -> 10,000 | gain 1,000 -> 10,000 | surface/flat 1,000 -> 10,000 | amplitude 1,000 -> 10,000')
for sc in map(str, range(1001, 1013)):
    for seed in ('1', '2'):
        m1 = lp10k.get((sc, seed, 'method'))
        n = lp10k.get((sc, seed, 'no-refraction')) or lp1k.get((sc, seed, 'no-refraction'))
        if not m1 or not n: continue
        m0 = lp1k.get((sc, seed, 'method'))
        o, on = orc.get((sc, seed, 'known-water')), orc.get((sc, seed, 'no-refraction'))
        lead = f(o, 'eval_psnr') - f(on, 'eval_psnr') if o and on else float('nan')
        x = dict(lead=lead, g1=f(m1, 'eval_psnr') - f(n, 'eval_psnr'), r1=f(m1, 'eval_surface_rmse') / f(m1, 'eval_flat_rmse'),
                 a1=f(m1, 'amplitude_ratio'), old=m0 is not None)
        if m0: x.update(g0=f(m0, 'eval_psnr') - f(n, 'eval_psnr'), r0=f(m0, 'eval_surface_rmse') / f(m0, 'eval_flat_rmse'), a0=f(m0, 'amplitude_ratio'))
        rows.append(x)
        old = lambda k, fmt: (fmt % x[k]) if m0 else '-'
        print('%s %s | %+.2f | %.2f | %s -> %.2f | %s -> %+.2f | %s -> %.2f | %s -> %.2f' % (
            sc, seed, lead, f(n, 'eval_psnr'), ('%.2f' % f(m0, 'eval_psnr')) if m0 else '-', f(m1, 'eval_psnr'),
            old('g0', '%+.2f'), x['g1'], old('r0', '%.2f'), x['r1'], old('a0', '%.2f'), x['a1']))
def goals(tag, rs, g, r, a):
    mat = [x for x in rs if x['lead'] >= 1]
    rest = [x for x in rs if x['lead'] < 1]
    med = lambda v: st.median(v) if v else float('nan')
    print('%s: %d runs; where the water matters (oracle lead >= 1 dB, %d runs): beats straight rays %d, median gain %+.2f, median amplitude %.2f; '
          'elsewhere (%d runs): within 0.5 dB of straight rays %d, median gain %+.2f; diverged (> 1.5x the flat start) %d; worse than flat %d' % (
          tag, len(rs), len(mat), sum(x[g] > 0 for x in mat), med([x[g] for x in mat]), med([x[a] for x in mat]), len(rest),
          sum(x[g] >= -0.5 for x in rest), med([x[g] for x in rest]), sum(x[r] > 1.5 for x in rs), sum(x[r] > 1 for x in rs)))
both = [x for x in rows if x['old']]
goals('level prior 1,000, the runs both have', both, 'g0', 'r0', 'a0')
goals('level prior 10,000, the same runs', both, 'g1', 'r1', 'a1')
goals('level prior 10,000, every run', rows, 'g1', 'r1', 'a1')
