#!/usr/bin/env python3
# Where a learned water's error lies: by how many training views see each point of the water, and
# by polynomial order. At water_height.npy's own grid nodes, over the nodes at least one training
# view sees (weighted by how many do, as the level prior and the divergence check weigh them), the
# error (learned - true) and the true waves, their weighted means removed, as RMS:
#   - per band of the views that see a node (1, 2-3, 4-7, 8-15, 16+);
#   - by order: the part a weighted least-squares fit by every x^a y^b of a + b <= 2 holds (the
#     tilt and the bowl, which the level prior of degree 2 holds), what degree 4 adds past that
#     (the smooth warps), what degree 6 adds, and what is left (the waves themselves, mostly).
# Where a run's excess error lies in the warps, a prior past the bowl would hold it; where it lies
# at the nodes few views see, a weight by the views would; where it lies in "the rest" with the
# true waves, it is the waves learned wrong (docs/experiments/2026-12-07-eval-seed-2.md). For
# `refrax synth random` scenes it also prints each wave's cycles across the domain: the height
# field's coarse octaves, all the defaults open, repeat at most 4 times across it.
# Usage: PATH=/usr/bin:$PATH python3 bench/water-error-map.py RUN DATASET   (needs numpy)
#   RUN      a `refrax train` run folder (water_height.npy, config.json)
#   DATASET  its synthetic dataset (water.json and its height map, transforms_train.json)
import json
import sys

import numpy as np

from water_truth import truth_heights

if len(sys.argv) != 3:
    sys.exit('usage: bench/water-error-map.py RUN DATASET')
run, dataset = sys.argv[1:]
config = json.load(open(run + '/config.json'))
learned = np.load(run + '/water_height.npy').astype(np.float64)  # value [j][i]
ny, nx = learned.shape
x0, y0, x1, y1 = config['domain']
X, Y = np.meshgrid(np.linspace(x0, x1, nx), np.linspace(y0, y1, ny))

water, truth_at = truth_heights(dataset)

# How many training views see each node (pinhole, NeRF's camera axes: x right, y up, looking
# down -z), at the water's height.
frames = json.load(open(dataset + '/transforms_train.json'))
points = np.stack([X.ravel(), Y.ravel(), np.full(X.size, config.get('water_height', 0.0))], 1)
views = np.zeros(X.size)
for frame in frames['frames']:
    get = lambda k: frame.get(k, frames.get(k))
    m = np.array(frame['transform_matrix'])
    local = (points - m[:3, 3]) @ m[:3, :3]
    depth = -local[:, 2]
    safe = np.maximum(depth, 1e-9)
    u = get('cx') + get('fl_x') * local[:, 0] / safe
    v = get('cy') - get('fl_y') * local[:, 1] / safe
    views += (depth > 0) & (u >= 0) & (u < get('w')) & (v >= 0) & (v < get('h'))
views = views.reshape(X.shape)

seen = views > 0
w = views[seen]
error = (learned - truth_at(X, Y))[seen]
true = truth_at(X, Y)[seen]
error, true = error - np.average(error, weights=w), true - np.average(true, weights=w)
rms = lambda a, m=slice(None): np.sqrt(np.average(a[m] ** 2, weights=w[m]))
print(f'{run}: {seen.sum()} of {seen.size} nodes seen (by up to {int(views.max())} views); error {rms(error) * 1000:.2f} mm RMS, '
      f'the waves {rms(true) * 1000:.2f} mm ({rms(error) / rms(true):.2f}x)')
terms = water.get('scene_parameters', {}).get('water', {}).get('terms', [])
if terms:  # refrax synth random's waves: how finely each repeats across the domain
    print('  the waves, cycles across the domain (amplitude): ' + ', '.join('%s %.1f (%.1f mm)' % (
        'sine' if 'sine' in t['type'] else 'ripple', (x1 - x0) / t['wavelength'], t['amplitude'] * 1000) for t in terms))
for lo, hi in ((1, 1), (2, 3), (4, 7), (8, 15), (16, 10 ** 6)):
    band = (w >= lo) & (w <= hi)
    if band.any():
        label = '1 view' if hi == 1 else f'{lo}+ views' if hi > 10 ** 5 else f'{lo}-{hi} views'
        print(f'  seen by {label}: {band.sum()} nodes, '
              f'{w[band].sum() / w.sum() * 100:.1f}% of the weight: error {rms(error, band) * 1000:.2f} mm, the waves {rms(true, band) * 1000:.2f} mm')

half = max(x1 - x0, y1 - y0) / 2
xs, ys = X[seen] / half, Y[seen] / half
sw = np.sqrt(w)


def fit(values, degree):  # the weighted least-squares fit by every x^a y^b of a + b <= degree
    basis = np.stack([xs ** a * ys ** (d - a) for d in range(degree + 1) for a in range(d + 1)], 1)
    coefficients = np.linalg.lstsq(basis * sw[:, None], values * sw, rcond=None)[0]
    return basis @ coefficients


for name, values in (('error', error), ('the waves', true)):
    fits = [fit(values, d) for d in (2, 4, 6)]
    print(f'  {name} by order (mm RMS): tilt and bowl {rms(fits[0]) * 1000:.2f}, degree 3-4 {rms(fits[1] - fits[0]) * 1000:.2f}, '
          f'degree 5-6 {rms(fits[2] - fits[1]) * 1000:.2f}, the rest {rms(values - fits[2]) * 1000:.2f}')
