#!/usr/bin/env python3
# The README's results table, printed from a presets.csv (bench/presets.sh --out DIR): per
# preset, test PSNR / surface RMSE of refraction-sweep, --flat-water and --no-refraction, and
# the flat start's RMSE, the three models' PSNR on the views between a 3 x 3 rig's training
# cameras (refrax synth's between/), with a column for each setting that differs between the rows (the
# rig, the IOR, the image size: each preset's own, read from its dataset) and a line naming
# what every row shares (steps, patch, seed). Writes the table to stdout; bench/readme-table.sh
# runs the presets and this in one command and writes DIR/readme-table.md.
# Usage: bench/readme-table.py DIR/presets.csv DATASETS_DIR   (DATASETS_DIR: presets.sh's
#        work/data with --keep-work, one folder per preset named after it and its size)
import csv
import glob
import json
import os
import sys

MODELS = [('refraction-sweep', True), ('flat-water', True), ('no-refraction', False)]


def rig_of(dataset):
    """The rig in words and the image size, from the dataset refrax synth wrote."""
    water = json.load(open(os.path.join(dataset, 'water.json')))
    train = json.load(open(os.path.join(dataset, 'transforms_train.json')))
    test = json.load(open(os.path.join(dataset, 'transforms_test.json')))
    frame = train['frames'][0]
    w, h = frame.get('w', train.get('w')), frame.get('h', train.get('h'))
    ring = 'ring' in water.get('description', '') or len(train['frames']) > 9
    rig = f"{'rings' if ring else '3x3 down'}, {len(train['frames'])}+{len(test['frames'])}"
    return rig, f'{w}x{h}'


def main():
    if len(sys.argv) != 3:
        sys.exit('usage: bench/readme-table.py DIR/presets.csv DATASETS_DIR')
    rows = [r for r in csv.DictReader(open(sys.argv[1])) if r['eval_step'] == r['config_steps']]
    by = {(r['preset'], r['variant']): r for r in rows}
    presets = list(dict.fromkeys(r['preset'] for r in rows))
    shared = {k: {r[k] for r in rows} for k in ('config_steps', 'config_patch', 'config_seed')}
    for k, v in shared.items():
        if len(v) != 1:
            sys.exit(f'readme-table: the rows differ in {k} ({sorted(v)}): not one table')
    print('| preset | rig, views | px | IOR | refraction-sweep | `--flat-water` | `--no-refraction` | flat start RMSE | between views |')
    print('| --- | --- | --- | --- | --- | --- | --- | --- | --- |')
    for preset in presets:
        found = sorted(glob.glob(os.path.join(sys.argv[2], preset + '_*')))
        if not found:
            sys.exit(f'readme-table: no dataset of {preset} in {sys.argv[2]}')
        rig, px = rig_of(found[0])
        cells = []
        best = max((float(by[(preset, m)]['eval_psnr']) for m, _ in MODELS if (preset, m) in by), default=None)
        for model, has_surface in MODELS:
            r = by.get((preset, model))
            if r is None:
                cells.append('-')
                continue
            psnr = float(r['eval_psnr'])
            text = f'**{psnr:.2f}**' if psnr == best else f'{psnr:.2f}'
            if has_surface and r['eval_surface_rmse'] not in ('', 'nan'):
                text += f" / {float(r['eval_surface_rmse']):.3f}"
            cells.append(text)
        ref = by.get((preset, 'refraction-sweep')) or next(iter(by[(preset, m)] for m, _ in MODELS if (preset, m) in by))
        ior = float(ref['config_ior'])
        flat = ref['initial_flat_surface_rmse']
        flat = f'{float(flat):.3f}' if flat not in ('', 'nan') else '-'
        # the three models' PSNR on the views between the rig's training cameras, where it has them
        between = [by[(preset, m)].get('between_psnr', '') for m, _ in MODELS if (preset, m) in by]
        between = ' / '.join(f'{float(b):.2f}' for b in between) if all(b not in ('', 'nan') for b in between) else '-'
        print(f'| {preset} | {rig} | {px} | {ior:g} | ' + ' | '.join(cells) + f' | {flat} | {between} |')
    print()
    steps, patch, seed = (next(iter(shared[k])) for k in ('config_steps', 'config_patch', 'config_seed'))
    print(f'Every row: {steps} steps of {patch}x{patch} patches, seed {seed}; test PSNR (dB) / surface RMSE (m); between views: '
          'the three models\' PSNR on the four views between a 3x3 rig\'s training cameras.')


if __name__ == '__main__':
    main()
