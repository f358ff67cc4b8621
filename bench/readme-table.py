#!/usr/bin/env python3
# The README's results table, printed from bench/readme-table.sh's rows.csv (one `refrax
# report` row per run with preset, variant and seed): per preset, the median over the seeds
# (and its spread, max - min) of the test PSNR / surface RMSE of the method, --flat-water and
# --no-refraction at refrax train's defaults, the flat start's RMSE and the three models' median
# PSNR on the views between a 3 x 3 rig's training cameras (refrax synth's between/), with the
# rig, IOR and image size read from each preset's dataset, and a line naming what every row
# shares (steps, patch, seeds).
# Usage: bench/readme-table.py rows.csv DATASETS_DIR   (DATASETS_DIR: one folder per preset)
import csv
import json
import os
import statistics
import sys

MODELS = [('method', True, 'the method'), ('flat-water', True, '`--flat-water`'), ('no-refraction', False, '`--no-refraction`')]


def rig_of(dataset):
    """The rig in words and the image size, from the dataset refrax synth wrote."""
    water = json.load(open(os.path.join(dataset, 'water.json')))
    train = json.load(open(os.path.join(dataset, 'transforms_train.json')))
    test = json.load(open(os.path.join(dataset, 'transforms_test.json')))
    frame = train['frames'][0]
    w, h = frame.get('w', train.get('w')), frame.get('h', train.get('h'))
    ring = 'ring' in water.get('description', '') or len(train['frames']) > 9
    return f"{'rings' if ring else '3x3 down'}, {len(train['frames'])}+{len(test['frames'])}", f'{w}x{h}'


def num(v):
    try:
        x = float(v)
        return x if x == x else None
    except (TypeError, ValueError):
        return None


def median_spread(values):
    values = [v for v in values if v is not None]
    if not values:
        return None, None
    return statistics.median(values), max(values) - min(values)


def main():
    if len(sys.argv) != 3:
        sys.exit('usage: bench/readme-table.py rows.csv DATASETS_DIR')
    rows = [r for r in csv.DictReader(open(sys.argv[1])) if r['step'] == r['config_steps']]
    presets = list(dict.fromkeys(r['preset'] for r in rows))
    shared = {k: {r[k] for r in rows} for k in ('config_steps',)}
    for k, v in shared.items():
        if len(v) != 1:
            sys.exit(f'readme-table: the rows differ in {k} ({sorted(v)}): not one table')
    seeds = sorted({int(r['seed']) for r in rows})
    batches = {}  # image size -> the batch the defaults chose for it (patches on a CPU, whole images on a GPU or small images)
    print('| preset | rig, views | px | IOR | ' + ' | '.join(label for _, _, label in MODELS) + ' | flat start RMSE | between views |')
    print('| --- | --- | --- | --- | --- | --- | --- | --- | --- |')
    for preset in presets:
        rig, px = rig_of(os.path.join(sys.argv[2], preset))
        for r in rows:
            if r['preset'] == preset:
                batches.setdefault(px, set()).add(r['config_patch'])
        of = {m: [r for r in rows if r['preset'] == preset and r['variant'] == m] for m, _, _ in MODELS}
        medians = {m: median_spread([num(r['psnr']) for r in of[m]]) for m, _, _ in MODELS}
        best = max((v[0] for v in medians.values() if v[0] is not None), default=None)
        cells = []
        for model, has_surface, _ in MODELS:
            psnr, spread = medians[model]
            if psnr is None:
                cells.append('-')
                continue
            text = f'{psnr:.2f}' + (f' ({spread:.2f})' if len(of[model]) > 1 else '')
            if psnr == best:
                text = f'**{text}**'
            rmse, _ = median_spread([num(r['surface_rmse']) for r in of[model]])
            if has_surface and rmse is not None:
                text += f' / {rmse:.3f}'
            cells.append(text)
        ref = of['method'][0] if of['method'] else next(r for m, _, _ in MODELS for r in of[m])
        flat, _ = median_spread([num(r['initial_flat_surface_rmse']) for r in of['method']])
        between = [median_spread([num(r.get('between_psnr')) for r in of[m]])[0] for m, _, _ in MODELS]
        between = ' / '.join(f'{b:.2f}' for b in between) if all(b is not None for b in between) else '-'
        print(f"| {preset} | {rig} | {px} | {float(ref['config_ior']):g} | " + ' | '.join(cells) +
              f" | {'-' if flat is None else f'{flat:.3f}'} | {between} |")
    print()
    steps = next(iter(shared['config_steps']))
    name = lambda p: f'{p}x{p} patches' if p not in ('0', '') else 'whole images'
    by_batch = {}  # the batch's words -> the image sizes that trained with it, in the table's order
    for px, ps in batches.items():
        by_batch.setdefault(' or '.join(name(p) for p in sorted(ps)), []).append(px)
    batch = '; '.join(f"{words} at {' and '.join(sizes)}" for words, sizes in by_batch.items())
    print(f"Every row: refrax train's defaults at {steps} steps ({batch}), seeds {', '.join(map(str, seeds))}; the median over the seeds "
          "(its spread, max - min) of the test PSNR (dB) / surface RMSE (m); between views: the three models' median PSNR on the four "
          "views between a 3x3 rig's training cameras.")


if __name__ == '__main__':
    main()
