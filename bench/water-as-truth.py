#!/usr/bin/env python3
"""A copy of a `refrax synth` dataset whose known water (what `refrax train --known-water` holds
fixed) is another surface on a grid: a run's learned water (its water_height.npy), or the true
water resampled to that run's grid (the control: what the grid alone costs). Fresh Gaussians
trained under a learned water then say how much of a run's gap to the oracle is the water and
how much the Gaussians' history (docs/experiments/2026-12-05-water-valley.md, ninth session).

The copy links every file of DATA but water.json, which drops the closed-form 'surface' (so the
oracle reads the height map) and names the new map. Plain Python: no NumPy.

Usage: bench/water-as-truth.py DATA OUT (--run RUN | --truth-on-grid RUN)
"""
import argparse
import ast
import json
import os
import shutil
import struct
import sys


def read_npy(path):
    raw = open(path, 'rb').read()
    if raw[:6] != b'\x93NUMPY':
        sys.exit(f'water-as-truth: {path} is not a .npy file')
    header_len = struct.unpack('<H', raw[8:10])[0]
    header = ast.literal_eval(raw[10:10 + header_len].decode())
    if header['descr'] != '<f4' or header['fortran_order'] or len(header['shape']) != 2:
        sys.exit(f'water-as-truth: {path} must hold a 2-D little-endian float32 array')
    ny, nx = header['shape']
    values = struct.unpack(f'<{nx * ny}f', raw[10 + header_len:10 + header_len + 4 * nx * ny])
    return [list(values[j * nx:(j + 1) * nx]) for j in range(ny)]


def write_npy(path, rows):
    ny, nx = len(rows), len(rows[0])
    header = "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d), }" % (ny, nx)
    header += ' ' * (64 - (10 + len(header) + 1) % 64) + '\n'
    with open(path, 'wb') as f:
        f.write(b'\x93NUMPY\x01\x00' + struct.pack('<H', len(header)) + header.encode())
        for row in rows:
            f.write(struct.pack(f'<{nx}f', *row))


def resampled(rows, ny, nx):
    """Bilinear samples of a grid over a domain at ny x nx points over the same domain."""
    sy, sx = len(rows), len(rows[0])
    out = []
    for j in range(ny):
        y = j * (sy - 1) / (ny - 1)
        j0 = min(int(y), sy - 2)
        fy = y - j0
        row = []
        for i in range(nx):
            x = i * (sx - 1) / (nx - 1)
            i0 = min(int(x), sx - 2)
            fx = x - i0
            row.append((rows[j0][i0] * (1 - fx) + rows[j0][i0 + 1] * fx) * (1 - fy) + (rows[j0 + 1][i0] * (1 - fx) + rows[j0 + 1][i0 + 1] * fx) * fy)
        out.append(row)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('data')
    ap.add_argument('out')
    which = ap.add_mutually_exclusive_group(required=True)
    which.add_argument('--run', help="the run whose learned water (water_height.npy) becomes the known water")
    which.add_argument('--truth-on-grid', metavar='RUN', help="the true water resampled to this run's water_height.npy grid")
    a = ap.parse_args()
    water = json.load(open(os.path.join(a.data, 'water.json')))
    truth = water.get('height_map')
    if not isinstance(truth, dict) or 'file' not in truth or 'domain' not in truth:
        sys.exit(f"water-as-truth: {a.data}/water.json has no 'height_map' with a 'file' and a 'domain' (refrax synth writes one)")
    run = a.run or a.truth_on_grid
    learned = read_npy(os.path.join(run, 'water_height.npy'))
    config = json.load(open(os.path.join(run, 'config.json')))
    if os.path.realpath(config.get('dataset', '')) != os.path.realpath(a.data):
        print(f"water-as-truth: note: {run} was trained on {config.get('dataset')}, not {a.data}", file=sys.stderr)
    rows = learned if a.run else resampled(read_npy(os.path.join(a.data, truth['file'])), len(learned), len(learned[0]))
    if os.path.exists(a.out):
        shutil.rmtree(a.out)
    os.makedirs(a.out)
    for entry in os.listdir(a.data):
        if entry != 'water.json':
            os.symlink(os.path.abspath(os.path.join(a.data, entry)), os.path.join(a.out, entry))
    water.pop('surface', None)
    truth = dict(truth, file='water_as_truth_height.npy', shape=[len(rows), len(rows[0])])
    truth.pop('mean', None)
    truth['what'] = f"the known water for a study: {'the learned water of ' + run if a.run else 'the true water on the grid of ' + run}"
    water['height_map'] = truth
    json.dump(water, open(os.path.join(a.out, 'water.json'), 'w'), indent=1)
    write_npy(os.path.join(a.out, 'water_as_truth_height.npy'), rows)
    print(f'water-as-truth: {a.out}: known water {len(rows)} x {len(rows[0])} ({"learned" if a.run else "true, resampled"})')


if __name__ == '__main__':
    main()
