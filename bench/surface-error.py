#!/usr/bin/env python3
# The learned water's error, taken apart: over a square centred on x = y = 0 (the NeRFrac-like domains' centre), fits
# learned = a * truth + b + c x + d y by least squares and prints the RMS error, the amplitude
# ratio a (1: the waves' full height; 0: flat), the level and tilt part (b, c, d) and what is
# left. Tells a surface that is right but too low (a < 1) from one that is level-shifted,
# tilted or shaped wrong (docs/experiments/2026-11-29-water-cost.md).
#
# Usage: bench/surface-error.py RUN DATASET [HALF]
#   RUN      a `refrax train` run folder (water_height.npy, config.json)
#   DATASET  its synthetic dataset (water.json and its height map)
#   HALF     half-width of the square in metres (default 0.414: what the NeRFrac-like presets'
#            centre test camera sees, 1 m above the water with a 45 degree field of view)
# Needs only Python 3 (reads .npy itself).
import ast
import json
import math
import os
import struct
import sys


def read_npy(path):
    """A 2-D little-endian float32 .npy: (nx, ny, values in row-major [j][i] order)."""
    with open(path, 'rb') as f:
        if f.read(6) != b'\x93NUMPY':
            sys.exit(f'surface-error: {path} is not a .npy file')
        major = f.read(2)[0]
        header_len = struct.unpack('<H' if major == 1 else '<I', f.read(2 if major == 1 else 4))[0]
        header = ast.literal_eval(f.read(header_len).decode())
        if header['descr'] != '<f4' or header['fortran_order'] or len(header['shape']) != 2:
            sys.exit(f'surface-error: {path} is not a 2-D float32 array')
        ny, nx = header['shape']
        return nx, ny, struct.unpack('<%df' % (nx * ny), f.read(4 * nx * ny))


def height_sampler(path, domain):
    """Bilinear heights over domain [xmin, ymin, xmax, ymax] (value [j][i] at grid node i, j)."""
    nx, ny, values = read_npy(path)
    x0, y0, x1, y1 = domain

    def at(x, y):
        u = (x - x0) / (x1 - x0) * (nx - 1)
        v = (y - y0) / (y1 - y0) * (ny - 1)
        i, j = min(int(u), nx - 2), min(int(v), ny - 2)
        fu, fv = u - i, v - j
        h = lambda a, b: values[b * nx + a]
        return ((h(i, j) * (1 - fu) + h(i + 1, j) * fu) * (1 - fv) +
                (h(i, j + 1) * (1 - fu) + h(i + 1, j + 1) * fu) * fv)
    return at


def least_squares(features, targets):
    """Solves the normal equations of targets ~ features . coefficients (Gauss-Jordan)."""
    k = len(features[0])
    a = [[sum(f[p] * f[q] for f in features) for q in range(k)] for p in range(k)]
    r = [sum(f[p] * t for f, t in zip(features, targets)) for p in range(k)]
    for p in range(k):
        pivot = a[p][p]
        a[p] = [v / pivot for v in a[p]]
        r[p] /= pivot
        for row in range(k):
            if row != p:
                m = a[row][p]
                a[row] = [v - m * w for v, w in zip(a[row], a[p])]
                r[row] -= m * r[p]
    return r


def rms(values):
    return math.sqrt(sum(v * v for v in values) / len(values))


if len(sys.argv) not in (3, 4):
    sys.exit('usage: bench/surface-error.py RUN DATASET [HALF]')
run, dataset = sys.argv[1], sys.argv[2]
half = float(sys.argv[3]) if len(sys.argv) == 4 else 0.414
for path in (run + '/water_height.npy', run + '/config.json', dataset + '/water.json'):
    if not os.path.isfile(path):
        sys.exit(f'surface-error: {path} not found (RUN is a refrax train run, DATASET a refrax synth dataset)')
water = json.load(open(dataset + '/water.json'))
truth = height_sampler(dataset + '/' + water['height_map']['file'], water['height_map']['domain'])

# The learned heights are compared where they are known: at water_height.npy's own grid nodes
# inside the square. Interpolating that grid between its nodes (grid cells + 1 a side, about
# 20 cm apart on the tiny presets) flattened short waves, so even the known water read an
# amplitude ratio of 0.42-0.91 (docs/experiments/2026-12-02-random-dev-tiny.md).
config = json.load(open(run + '/config.json'))
nx, ny, learned_values = read_npy(run + '/water_height.npy')
x0, y0, x1, y1 = config['domain']
points, learned_h = [], []
for j in range(ny):
    for i in range(nx):
        x, y = x0 + (x1 - x0) * i / (nx - 1), y0 + (y1 - y0) * j / (ny - 1)
        if abs(x) <= half and abs(y) <= half:
            points.append((x, y))
            learned_h.append(learned_values[j * nx + i])
if len(points) < 9:
    sys.exit(f'surface-error: only {len(points)} of water_height.npy\'s {nx} x {ny} nodes lie in the {2 * half:g} m square: too few to fit')
true_h = [truth(x, y) for x, y in points]
a, b, c, d = least_squares([(t, 1.0, x, y) for t, (x, y) in zip(true_h, points)], learned_h)
level = [b + c * x + d * y for x, y in points]
residual = [l - a * t - lv for l, t, lv in zip(learned_h, true_h, level)]
print(f'{run}: RMS error {rms([l - t for l, t in zip(learned_h, true_h)]):.5f} m (the waves\' RMS {rms(true_h):.5f}); '
      f'amplitude ratio {a:.3f} (its share of the error {abs(1 - a) * rms(true_h):.5f} m); '
      f'level {b * 1000:+.2f} mm, tilt {c * 1000:+.2f} {d * 1000:+.2f} mm/m (RMS {rms(level):.5f} m); '
      f'the rest {rms(residual):.5f} m; {len(points)} grid nodes')
