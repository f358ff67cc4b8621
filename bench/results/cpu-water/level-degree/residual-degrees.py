# The learned water's error against the truth, taken apart by polynomial degree: over the square
# |x|, |y| <= HALF at water_height.npy's own grid nodes, the RMS of (learned - true) left after
# removing its least-squares fit by every x^a y^b of a + b <= d, for d = 0..4; and the share of
# the true waves' own variance that such a fit holds. Where the error falls at d = 3 and 4 it lies
# in smooth warps past the bowl, which the level prior of degree 2 does not hold.
# Usage: PATH=/usr/bin:$PATH python3 residual-degrees.py RUN DATASET HALF   (needs numpy)
import json, os, sys
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..'))  # bench/
from water_truth import truth_heights  # noqa: E402

run, dataset, half = sys.argv[1], sys.argv[2], float(sys.argv[3])
learned = np.load(run + '/water_height.npy')
x0, y0, x1, y1 = json.load(open(run + '/config.json'))['domain']
_, truth_at = truth_heights(dataset)
ny, nx = learned.shape
X, Y = np.meshgrid(np.linspace(x0, x1, nx), np.linspace(y0, y1, ny))

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
