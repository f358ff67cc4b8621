#!/usr/bin/env python3
# Refrax's 3DGS PLY carried into the compressed splat formats by PlayCanvas splat-transform, read
# back and compared with the PLY, Gaussian by Gaussian (not with Refrax's code):
#   spz PLY FILE.spz   the .spz (version 3) decoded here from the format's definition (one gzip
#                      stream: a 16-byte header, then positions as 24-bit fixed point, alphas,
#                      colours, scales, rotations as the smallest three, SH), in the PLY's order.
#                      Each value within the rounding of its stored bits (below).
#   sog PLY BACK.ply   a .sog (WebP textures and codebooks, reordered along a Morton curve)
#                      read back into a PLY by splat-transform; each Gaussian found again by
#                      position. Its scales, colours and SH go through 256-entry codebooks, so
#                      no bit depth bounds them: each attribute's RMS error must stay under 5% of
#                      its spread over the file and the worst under 50%, but the SH's RMS under
#                      25% and no worst (one codebook of 256 45-long vectors for all the file's
#                      SH: 18% measured on interop-samples' uncorrelated random SH) -- a misread
#                      axis, channel, activation or order gives errors of 100-140% of the spread.
# splat-transform 3.7.0 writes the PLY's axes unchanged into both (measured: no turn to SPZ's
# RUB), so the values compare directly.
# Usage: scripts/splat-formats-check.py spz|sog PLY OTHER     (exits non-zero on any mismatch)
import gzip
import math
import struct
import sys

SH_REST = 45  # degree 3: 15 coefficients per channel


def read_ply(path):
    """A binary little-endian float PLY as a list of {property: value}."""
    data = open(path, 'rb').read()
    end = data.find(b'end_header\n')
    if end < 0:
        sys.exit(f'splat-formats-check: {path} is not a PLY')
    header = data[:end].decode('ascii').split('\n')
    if 'format binary_little_endian 1.0' not in header:
        sys.exit(f'splat-formats-check: {path} is not a binary little-endian PLY')
    count = int(next(line for line in header if line.startswith('element vertex')).split()[2])
    props = [line.split() for line in header if line.startswith('property')]
    if any(p[1] != 'float' for p in props):
        sys.exit(f'splat-formats-check: {path} has properties that are not float')
    names = [p[2] for p in props]
    values = struct.unpack_from('<%df' % (count * len(names)), data, end + len('end_header\n'))
    return [dict(zip(names, values[i * len(names):(i + 1) * len(names)])) for i in range(count)]


def sigmoid(x):
    return 1.0 / (1.0 + math.exp(-x))


def unit(q):
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


def angle_deg(q, r):
    """The rotation between two quaternions (any order, same for both), in degrees."""
    dot = abs(sum(a * b for a, b in zip(unit(q), unit(r))))
    return math.degrees(2.0 * math.acos(min(1.0, dot)))


def ply_rotation(g):  # the PLY's rot_0..3 are w x y z
    return [g['rot_1'], g['rot_2'], g['rot_3'], g['rot_0']]


def decode_spz(path):
    """SPZ version 3 as its definition reads: each Gaussian as PLY-named raw values."""
    data = gzip.decompress(open(path, 'rb').read())
    magic, version, count, degree, fractional_bits, _, _ = struct.unpack_from('<IIIBBBB', data, 0)
    if magic != 0x5053474e or version != 3:
        sys.exit(f'splat-formats-check: {path} is not SPZ version 3 (magic {magic:#x}, version {version})')
    if degree != 3:
        sys.exit(f'splat-formats-check: {path} holds SH degree {degree}, the PLY degree 3')
    at = 16
    positions, at = data[at:at + 9 * count], at + 9 * count
    alphas, at = data[at:at + count], at + count
    colours, at = data[at:at + 3 * count], at + 3 * count
    scales, at = data[at:at + 3 * count], at + 3 * count
    rotations, at = data[at:at + 4 * count], at + 4 * count
    sh, at = data[at:at + SH_REST * count], at + SH_REST * count
    if at != len(data):
        sys.exit(f'splat-formats-check: {path} holds {len(data)} bytes, {at} expected for {count} Gaussians')

    def fixed24(b, o):
        v = b[o] | b[o + 1] << 8 | b[o + 2] << 16
        return (v - (1 << 24) if v & 0x800000 else v) / (1 << fractional_bits)

    out = []
    for i in range(count):
        g = {'xyz'[c]: fixed24(positions, 9 * i + 3 * c) for c in range(3)}
        a = alphas[i] / 255.0
        g['opacity'] = math.log(a / (1.0 - a)) if 0.0 < a < 1.0 else (-math.inf if a == 0 else math.inf)
        for c in range(3):
            g['f_dc_%d' % c] = (colours[3 * i + c] / 255.0 - 0.5) / 0.15
            g['scale_%d' % c] = scales[3 * i + c] / 16.0 - 10.0
        # the smallest three: 2 bits name the largest component (x y z w), then from the low
        # bits up each other component in reverse order as 9 bits of magnitude (of sqrt(1/2))
        # and a sign bit; the largest is what makes the quaternion unit
        word = struct.unpack_from('<I', rotations, 4 * i)[0]
        largest = word >> 30
        q = [0.0] * 4
        for k in (3, 2, 1, 0):
            if k == largest:
                continue
            magnitude, negative = word & 511, (word >> 9) & 1
            word >>= 10
            q[k] = math.sqrt(0.5) * magnitude / 511.0 * (-1.0 if negative else 1.0)
        q[largest] = math.sqrt(max(0.0, 1.0 - sum(c * c for c in q)))
        g['rotation'] = q
        for k in range(15):  # coefficient-major, channel inner; the PLY is channel-major
            for c in range(3):
                g['f_rest_%d' % (c * 15 + k)] = (sh[SH_REST * i + 3 * k + c] - 128) / 128.0
        out.append(g)
    return out, fractional_bits


def check_spz(ply, spz_path):
    spz, fractional_bits = decode_spz(spz_path)
    if len(spz) != len(ply):
        return [f'{len(spz)} Gaussians in the .spz, {len(ply)} in the PLY']
    # each bound is half the step of the stored value (plus float rounding), where it is rounded
    # to the nearest code; the SH codes are 8-bit values rounded to 5 (degree 1) or 4 bits
    # (degrees 2-3), half a bucket of 8 or 16 codes on top of the code's own half
    bounds = {'position': 0.5 / (1 << fractional_bits) + 1e-6, 'log scale': 0.5 / 16 + 1e-6,
              'opacity (activated)': 0.5 / 255 + 1e-6, 'f_dc': 0.5 / (255 * 0.15) + 1e-6,
              'SH degree 1': 4.5 / 128 + 1e-6, 'SH degrees 2-3': 8.5 / 128 + 1e-6,
              # three components within sqrt(1/2)/1022 each; the rebuilt largest is >= 1/2
              'rotation (degrees)': math.degrees(2.0 * math.sqrt(3.0) * (math.sqrt(0.5) / 1022) / 0.5)}
    worst = {k: 0.0 for k in bounds}
    for g, s in zip(ply, spz):
        worst['position'] = max(worst['position'], *(abs(g[a] - s[a]) for a in 'xyz'))
        worst['log scale'] = max(worst['log scale'], *(abs(g['scale_%d' % c] - s['scale_%d' % c]) for c in range(3)))
        worst['opacity (activated)'] = max(worst['opacity (activated)'], abs(sigmoid(g['opacity']) - sigmoid(s['opacity'])))
        worst['f_dc'] = max(worst['f_dc'], *(abs(g['f_dc_%d' % c] - s['f_dc_%d' % c]) for c in range(3)))
        for c in range(3):
            for k in range(15):
                name = 'SH degree 1' if k < 3 else 'SH degrees 2-3'
                key = 'f_rest_%d' % (c * 15 + k)
                worst[name] = max(worst[name], abs(g[key] - s[key]))
        worst['rotation (degrees)'] = max(worst['rotation (degrees)'], angle_deg(ply_rotation(g), s['rotation']))
    report(worst, bounds, 'worst')
    return [f'{k}: worst {worst[k]:.3g} over the bound {bounds[k]:.3g}' for k in bounds if not worst[k] <= bounds[k]]


def match_by_position(ply, back):
    """For each PLY Gaussian, the index of the read-back one nearest it (a grid of cells)."""
    cell = 0.02
    grid = {}
    key = lambda g: (math.floor(g['x'] / cell), math.floor(g['y'] / cell), math.floor(g['z'] / cell))
    for j, g in enumerate(back):
        grid.setdefault(key(g), []).append(j)
    found = []
    for g in ply:
        cx, cy, cz = key(g)
        best = None
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for j in grid.get((cx + dx, cy + dy, cz + dz), []):
                        h = back[j]
                        d = (g['x'] - h['x']) ** 2 + (g['y'] - h['y']) ** 2 + (g['z'] - h['z']) ** 2
                        if best is None or d < best[0]:
                            best = (d, j)
        found.append(None if best is None else best[1])
    return found


def check_sog(ply, back):
    if len(back) != len(ply):
        return [f'{len(back)} Gaussians read back from the .sog, {len(ply)} in the PLY']
    found = match_by_position(ply, back)
    if None in found or len(set(found)) != len(ply):
        return [f'{len(set(j for j in found if j is not None))} of {len(ply)} Gaussians found again by position']
    values = {  # attribute -> (PLY value, read-back value) per Gaussian and component
        'position': lambda g: [g[a] for a in 'xyz'],
        'log scale': lambda g: [g['scale_%d' % c] for c in range(3)],
        'opacity (activated)': lambda g: [sigmoid(g['opacity'])],
        'f_dc': lambda g: [g['f_dc_%d' % c] for c in range(3)],
        'SH': lambda g: [g['f_rest_%d' % k] for k in range(SH_REST)],
    }
    rms, worst, spread = {}, {}, {}
    for name, get in values.items():
        pairs = [(a, b) for g, j in zip(ply, found) for a, b in zip(get(g), get(back[j]))]
        mean = sum(a for a, _ in pairs) / len(pairs)
        spread[name] = math.sqrt(sum((a - mean) ** 2 for a, _ in pairs) / len(pairs))
        rms[name] = math.sqrt(sum((a - b) ** 2 for a, b in pairs) / len(pairs))
        worst[name] = max(abs(a - b) for a, b in pairs)
    # a rotation's spread: the mean angle to the nearest of the others would be data-dependent;
    # random unit quaternions are 90+ degrees apart on average, so hold it to 5 and 45 degrees
    angles = [angle_deg(ply_rotation(g), ply_rotation(back[j])) for g, j in zip(ply, found)]
    rms['rotation (degrees)'] = math.sqrt(sum(a * a for a in angles) / len(angles))
    worst['rotation (degrees)'] = max(angles)
    spread['rotation (degrees)'] = 90.0
    share = {k: 0.25 if k == 'SH' else 0.05 for k in rms}
    report(rms, {k: share[k] * v for k, v in spread.items()}, 'RMS')
    problems = [f'{k}: RMS error {rms[k]:.3g} over {share[k]:.0%} of its spread {spread[k]:.3g}' for k in rms if not rms[k] <= share[k] * spread[k]]
    problems += [f'{k}: worst error {worst[k]:.3g} over 50% of its spread {spread[k]:.3g}' for k in worst if k != 'SH' and not worst[k] <= 0.5 * spread[k]]
    return problems


def report(errors, bounds, what):
    for k in errors:
        print(f'  {k}: {what} {errors[k]:.3g} (bound {bounds[k]:.3g})')


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ('spz', 'sog'):
        sys.exit('usage: scripts/splat-formats-check.py spz|sog PLY OTHER')
    ply = read_ply(sys.argv[2])
    if sys.argv[1] == 'spz':
        problems = check_spz(ply, sys.argv[3])
    else:
        problems = check_sog(ply, read_ply(sys.argv[3]))
    print(f'splat-formats-check {sys.argv[1]}: {len(ply)} Gaussians, {len(problems)} mismatches')
    for p in problems:
        print('  ' + p)
    sys.exit(1 if problems else 0)


if __name__ == '__main__':
    main()
