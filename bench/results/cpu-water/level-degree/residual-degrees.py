# The learned water's error against the truth, taken apart by polynomial degree: over the square
# |x|, |y| <= HALF at water_height.npy's own grid nodes, the RMS of (learned - true) left after
# removing its least-squares fit by every x^a y^b of a + b <= d, for d = 0..4; and the share of
# the true waves' own variance that such a fit holds. Where the error falls at d = 3 and 4 it lies
# in smooth warps past the bowl, which the level prior of degree 2 does not hold.
# Usage: PATH=/usr/bin:$PATH python3 residual-degrees.py RUN DATASET HALF   (needs numpy)
import json, sys
import numpy as np

run, dataset, half = sys.argv[1], sys.argv[2], float(sys.argv[3])
learned = np.load(run + '/water_height.npy')
x0, y0, x1, y1 = json.load(open(run + '/config.json'))['domain']
water = json.load(open(dataset + '/water.json'))
truth_map = np.load(dataset + '/' + water['height_map']['file'])
tx0, ty0, tx1, ty1 = water['height_map']['domain']
ny, nx = learned.shape
X, Y = np.meshgrid(np.linspace(x0, x1, nx), np.linspace(y0, y1, ny))


def truth_at(x, y):  # bilinear in the truth's height map
    tny, tnx = truth_map.shape
    u, v = (x - tx0) / (tx1 - tx0) * (tnx - 1), (y - ty0) / (ty1 - ty0) * (tny - 1)
    i, j = np.clip(u.astype(int), 0, tnx - 2), np.clip(v.astype(int), 0, tny - 2)
    fu, fv = u - i, v - j
    return ((truth_map[j, i] * (1 - fu) + truth_map[j, i + 1] * fu) * (1 - fv) +
            (truth_map[j + 1, i] * (1 - fu) + truth_map[j + 1, i + 1] * fu) * fv)


inside = (np.abs(X) <= half) & (np.abs(Y) <= half)
l, t = learned[inside], truth_at(X, Y)[inside]
x, y = X[inside] / half, Y[inside] / half
rms = lambda v: 1e3 * np.sqrt(np.mean(v ** 2))


def left_after(values, degree):
    basis = np.stack([x ** a * y ** (d - a) for d in range(degree + 1) for a in range(d + 1)], 1)
    coef = np.linalg.lstsq(basis, values, rcond=None)[0]
    return values - basis @ coef


print('%s: %d nodes; error %.2f mm RMS (flat start %.2f: the waves about their mean)' % (run, inside.sum(), rms(l - t), rms(t - t.mean())))
print('  error left after a fit of degree 0-4 (mm): ' + ' '.join('%.2f' % rms(left_after(l - t, d)) for d in range(5)))
print('  the waves\' variance a fit of degree 1-4 holds: ' + ' '.join('%.2f' % (1 - np.mean(left_after(t - t.mean(), d) ** 2) / np.mean((t - t.mean()) ** 2)) for d in range(1, 5)))
