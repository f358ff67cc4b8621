#!/usr/bin/env python3
# How far apart two OPENCV lenses put the same rays: each of a 17 x 13 grid of pixels over the
# image is turned into its ray through the first transforms.json's lens (the truth: the
# forward model inverted by Newton's method) and projected through the second's (COLMAP's
# estimate, as `refrax align-poses` wrote it from COLMAP's model). Prints both lenses and the
# largest distance in pixels; exits non-zero when it is over MAX_PX. Read from the files'
# first frame (or their top level): fl_x fl_y cx cy k1 k2 p1 p2 w h.
# Usage: scripts/lens-agreement.py TRUTH.json ESTIMATE.json MAX_PX
import json
import math
import sys

LENS_FIELDS = ['fl_x', 'fl_y', 'cx', 'cy', 'k1', 'k2', 'p1', 'p2']


def lens_of(d):
    """The first frame's lens (or the file's), and the image size."""
    f = d['frames'][0] if 'fl_x' in d['frames'][0] else d
    lens = {k: float(f.get(k, d.get(k, 0.0)) or 0.0) for k in LENS_FIELDS}
    return lens, int(f.get('w', d.get('w'))), int(f.get('h', d.get('h')))


def distort(L, x, y):
    """OpenCV's radial-tangential model on normalised coordinates."""
    r2 = x * x + y * y
    radial = 1 + L['k1'] * r2 + L['k2'] * r2 * r2
    return (x * radial + 2 * L['p1'] * x * y + L['p2'] * (r2 + 2 * x * x),
            y * radial + L['p1'] * (r2 + 2 * y * y) + 2 * L['p2'] * x * y)


def to_pixel(L, x, y):
    u, v = distort(L, x, y)
    return L['fl_x'] * u + L['cx'], L['fl_y'] * v + L['cy']


def from_pixel(L, px, py):
    """The normalised ray of a pixel: Newton's method on the forward model (numeric Jacobian)."""
    tu, tv = (px - L['cx']) / L['fl_x'], (py - L['cy']) / L['fl_y']
    x, y, e = tu, tv, 1e-7
    for _ in range(50):
        u, v = distort(L, x, y)
        ux, vx = distort(L, x + e, y)
        uy, vy = distort(L, x, y + e)
        a, b, c, d = (ux - u) / e, (uy - u) / e, (vx - v) / e, (vy - v) / e
        det = a * d - b * c
        ru, rv = tu - u, tv - v
        x += (d * ru - b * rv) / det
        y += (-c * ru + a * rv) / det
    return x, y


def main():
    if len(sys.argv) != 4:
        sys.exit('usage: scripts/lens-agreement.py TRUTH.json ESTIMATE.json MAX_PX')
    T, w, h = lens_of(json.load(open(sys.argv[1])))
    E, _, _ = lens_of(json.load(open(sys.argv[2])))
    worst = 0.0
    for j in range(13):
        for i in range(17):
            px, py = (i / 16) * w, (j / 12) * h
            qx, qy = to_pixel(E, *from_pixel(T, px, py))
            worst = max(worst, math.hypot(qx - px, qy - py))
    print(f"lens: truth k1 {T['k1']:.3f} k2 {T['k2']:.3f} focal {T['fl_x']:.1f}; COLMAP k1 {E['k1']:.3f} k2 {E['k2']:.3f} "
          f"p1 {E['p1']:.4f} p2 {E['p2']:.4f} focal {E['fl_x']:.1f} {E['fl_y']:.1f}; "
          f"a pixel's ray through the truth's lens lands at most {worst:.2f} px off through COLMAP's")
    if not worst <= float(sys.argv[3]):
        sys.exit(f'lens-agreement: {worst:.2f} px is over {sys.argv[3]} px: the lens was not read as the camera model means it')


if __name__ == '__main__':
    main()
