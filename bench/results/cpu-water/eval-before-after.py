# The evaluation set at the CPU defaults of 2026-12-07 (eval-defaults/, seed 1; the runs of seed 2
# to come) against the earlier defaults (bench/results/large-prune: eval-prune-off.csv seed 1,
# eval-seed2/runs.csv seed 2) and the oracle's lead over straight rays from
# bench/results/generalise/eval-cpu (4,000 steps).
# Usage: python3 bench/results/cpu-water/eval-before-after.py . bench/results/cpu-water/eval-defaults
import csv, glob, os, statistics as st, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
new_dirs = sys.argv[2:]
def load(paths):
    d = {}
    for p in paths:
        files = [p] if os.path.isfile(p) else glob.glob(os.path.join(p, 'rows', '*.csv')) + ([os.path.join(p, 'runs.csv')] if os.path.isfile(os.path.join(p, 'runs.csv')) else [])
        for f in files:
            for r in csv.DictReader(open(f)):
                d[(r['scene'], r['seed'], r['variant'])] = r
    return d
old = load([root + '/bench/results/large-prune/eval-prune-off.csv', root + '/bench/results/large-prune/eval-seed2/runs.csv'])
orc = load([root + '/bench/results/generalise/eval-cpu/runs.csv'])
new = load(new_dirs)
def f(r, k): return float(r[k])
rows = []
print('scene seed | oracle lead | method before -> after | straight before -> after | gain before -> after | surface/flat before -> after | amplitude before -> after')
for sc in range(1001, 1013):
    for seed in ('1', '2'):
        m, n = new.get((str(sc), seed, 'method')), new.get((str(sc), seed, 'no-refraction'))
        if not m or not n or m['exit_code'] != '0' or n['exit_code'] != '0':
            if m or n: print(sc, seed, 'missing or failed')
            continue
        mo, no = old[(str(sc), seed, 'method')], old[(str(sc), seed, 'no-refraction')]
        o, on = orc.get((str(sc), seed, 'known-water')), orc.get((str(sc), seed, 'no-refraction'))
        lead = f(o, 'eval_psnr') - f(on, 'eval_psnr')
        g0, g1 = f(mo, 'eval_psnr') - f(no, 'eval_psnr'), f(m, 'eval_psnr') - f(n, 'eval_psnr')
        r0, r1 = f(mo, 'eval_surface_rmse') / f(mo, 'eval_flat_rmse'), f(m, 'eval_surface_rmse') / f(m, 'eval_flat_rmse')
        a0, a1 = f(mo, 'amplitude_ratio'), f(m, 'amplitude_ratio')
        rows.append(dict(sc=sc, seed=seed, lead=lead, g0=g0, g1=g1, r0=r0, r1=r1, a0=a0, a1=a1))
        print('%d %s | %+.2f | %.2f -> %.2f | %.2f -> %.2f | %+.2f -> %+.2f | %.2f -> %.2f | %.2f -> %.2f' % (
            sc, seed, lead, f(mo, 'eval_psnr'), f(m, 'eval_psnr'), f(no, 'eval_psnr'), f(n, 'eval_psnr'), g0, g1, r0, r1, a0, a1))
def goals(tag, g, r, a):
    mat = [x for x in rows if x['lead'] >= 1]
    rest = [x for x in rows if x['lead'] < 1]
    print('%s: runs %d; where the water matters (oracle lead >= 1 dB, %d runs): beats straight rays %d/%d, median gain %+.2f, median amplitude %.2f; elsewhere (%d runs) within 0.5 dB of straight rays %d/%d, median gain %+.2f; diverged (>1.5x flat) %d; worse than flat %d' % (
        tag, len(rows), len(mat), sum(x[g] > 0 for x in mat), len(mat), st.median([x[g] for x in mat]) if mat else float('nan'),
        st.median([x[a] for x in mat]) if mat else float('nan'), len(rest), sum(x[g] >= -0.5 for x in rest), len(rest),
        st.median([x[g] for x in rest]) if rest else float('nan'), sum(x[r] > 1.5 for x in rows), sum(x[r] > 1 for x in rows)))
goals('before (the earlier defaults)', 'g0', 'r0', 'a0')
goals('after (the defaults of 2026-12-07)', 'g1', 'r1', 'a1')
