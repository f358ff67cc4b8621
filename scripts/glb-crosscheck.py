#!/usr/bin/env python3
# Refrax's KHR_gaussian_splatting .glb (`refrax export SCENE.ply --glb`) against PlayCanvas
# splat-transform's .glb of the same PLY, read with the extension's own definitions (not
# Refrax's code). Each writer turns the PLY's axes its own way: Refrax into glTF's
# (A: (x, y, z) -> (x, z, -y), -90 degrees about x), splat-transform 3.7.0 by 180 degrees about
# z (Z: (x, y, z) -> (-x, -y, z), measured: its reading of a PLY's axes). So per splat, with the
# PLY's value p:
#   position  ours = A p, theirs = Z p              scale, opacity  equal
#   rotation  ours = +-(a * q), theirs = +-(z * q)   (unit quaternions x y z w; splat-transform
#             writes them unnormalised, so theirs is normalised first)
#   colour    sum_k ours_k Y_k(A d) = sum_k theirs_k Y_k(Z d) for any direction d (the colour the
#             PLY's Gaussian shows along d), with Y_k the real SH basis the extension's text
#             writes out (degrees 0-3, m = -l..l), per channel.
# Usage: scripts/glb-crosscheck.py OURS.glb THEIRS.glb    (exits non-zero on any mismatch)
import json
import math
import random
import struct
import sys


def read_glb(path):
    data = open(path, 'rb').read()
    magic, version, _ = struct.unpack_from('<4sII', data, 0)
    if magic != b'glTF' or version != 2:
        sys.exit(f'glb-crosscheck: {path} is not a glTF 2 binary')
    n, kind = struct.unpack_from('<I4s', data, 12)
    gltf = json.loads(data[20:20 + n])
    at = 20 + n
    m, kind = struct.unpack_from('<I4s', data, at)
    return gltf, data[at + 8:at + 8 + m]


def attribute(gltf, binary, name):
    """A float accessor of the first splat primitive as a list of tuples."""
    prim = gltf['meshes'][0]['primitives'][0]
    acc = gltf['accessors'][prim['attributes'][name]]
    if acc['componentType'] != 5126:
        sys.exit(f'glb-crosscheck: {name} is not float')
    width = {'SCALAR': 1, 'VEC3': 3, 'VEC4': 4}[acc['type']]
    view = gltf['bufferViews'][acc['bufferView']]
    start = view.get('byteOffset', 0) + acc.get('byteOffset', 0)
    stride = view.get('byteStride', 4 * width)
    return [struct.unpack_from('<%df' % width, binary, start + i * stride) for i in range(acc['count'])]


def sh_basis(x, y, z):
    """The extension's real SH basis, degrees 0-3, m = -l..l (its Lighting section)."""
    return [0.2820947917738781,
            -0.4886025119029199 * y, 0.4886025119029199 * z, -0.4886025119029199 * x,
            1.092548430592079 * x * y, -1.092548430592079 * y * z, 0.3153915652525200 * (2 * z * z - x * x - y * y),
            -1.092548430592079 * x * z, 0.5462742152960395 * (x * x - y * y),
            -0.5900435899266435 * y * (3 * x * x - y * y), 2.890611442640554 * x * y * z,
            -0.4570457994644657 * y * (4 * z * z - x * x - y * y), 0.3731763325901154 * z * (2 * z * z - 3 * x * x - 3 * y * y),
            -0.4570457994644657 * x * (4 * z * z - x * x - y * y), 1.445305721320277 * z * (x * x - y * y),
            -0.5900435899266435 * x * (x * x - 3 * y * y)]


def quat_mul(a, b):  # x y z w
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def turn(v):  # A: PLY (Refrax) axes -> Refrax's glTF axes
    return (v[0], v[2], -v[1])


def turn_theirs(v):  # Z: PLY axes -> splat-transform's
    return (-v[0], -v[1], v[2])


def main():
    if len(sys.argv) != 3:
        sys.exit('usage: scripts/glb-crosscheck.py OURS.glb THEIRS.glb')
    (ours, ob), (theirs, tb) = read_glb(sys.argv[1]), read_glb(sys.argv[2])
    names = ['POSITION', 'KHR_gaussian_splatting:ROTATION', 'KHR_gaussian_splatting:SCALE', 'KHR_gaussian_splatting:OPACITY']
    sh_names = ['KHR_gaussian_splatting:SH_DEGREE_%d_COEF_%d' % (l, n) for l in range(4) for n in range(2 * l + 1)]
    o = {k: attribute(ours, ob, k) for k in names + sh_names}
    t = {k: attribute(theirs, tb, k) for k in names + sh_names}
    count = len(o['POSITION'])
    problems = []
    if count != len(t['POSITION']):
        problems.append(f'count: ours {count}, splat-transform {len(t["POSITION"])}')
        count = 0
    a_turn = (-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5))  # A as a quaternion
    z_back = (0.0, 0.0, -1.0, 0.0)                        # Z's inverse
    rng = random.Random(5)
    dirs = []
    for _ in range(4):
        v = [rng.gauss(0, 1) for _ in range(3)]
        s = math.sqrt(sum(c * c for c in v))
        dirs.append(tuple(c / s for c in v))
    worst = {'position': 0.0, 'scale': 0.0, 'opacity': 0.0, 'rotation': 0.0, 'colour': 0.0}
    for i in range(count):
        worst['position'] = max(worst['position'], max(abs(a - b) for a, b in zip(o['POSITION'][i], turn(turn_theirs(t['POSITION'][i])))))
        worst['scale'] = max(worst['scale'], max(abs(a - b) / max(1e-6, abs(b)) for a, b in
                                                 zip(o['KHR_gaussian_splatting:SCALE'][i], t['KHR_gaussian_splatting:SCALE'][i])))
        worst['opacity'] = max(worst['opacity'], abs(o['KHR_gaussian_splatting:OPACITY'][i][0] - t['KHR_gaussian_splatting:OPACITY'][i][0]))
        q = t['KHR_gaussian_splatting:ROTATION'][i]
        qn = math.sqrt(sum(c * c for c in q))
        want = quat_mul(a_turn, quat_mul(z_back, tuple(c / qn for c in q)))
        got = o['KHR_gaussian_splatting:ROTATION'][i]
        worst['rotation'] = max(worst['rotation'], min(max(abs(a - b) for a, b in zip(got, want)), max(abs(a + b) for a, b in zip(got, want))))
        for d in dirs:
            yt, yo = sh_basis(*turn_theirs(d)), sh_basis(*turn(d))
            for c in range(3):
                seen_t = sum(t[n][i][c] * yt[k] for k, n in enumerate(sh_names))
                seen_o = sum(o[n][i][c] * yo[k] for k, n in enumerate(sh_names))
                worst['colour'] = max(worst['colour'], abs(seen_t - seen_o))
    bars = {'position': 1e-5, 'scale': 1e-5, 'opacity': 1e-6, 'rotation': 1e-5, 'colour': 1e-4}
    for k, bar in bars.items():
        if worst[k] > bar:
            problems.append(f'{k}: largest difference {worst[k]:.3g} (bar {bar:g})')
    print(f'glb-crosscheck: {count} Gaussians against {theirs["asset"].get("generator", "?")}: largest differences ' +
          ', '.join(f'{k} {v:.2g}' for k, v in worst.items()) + f'; {len(problems)} mismatches')
    for p in problems:
        print('  ' + p)
    sys.exit(1 if problems else 0)


main()
