#!/usr/bin/env python3
# bench/generalise.sh's summary step: from DIR/runs.csv (one `refrax report` row per run, with
# eval.json's numbers and the amplitude ratio as columns), DIR/scenes/scene_N.json (what each
# scene was) and DIR/rows/*.failed (runs that exited non-zero), writes
#   DIR/table.csv    one row per scene and training seed: the scene (rig, views, width, slope,
#                    IOR, rim), each model's test PSNR, the method's gain over straight rays,
#                    its gap to the oracle, the oracle's lead over straight rays, the surface
#                    RMSE against the flat start, the amplitude ratio, the correlation, and the
#                    failures (method under straight rays; surface worse than the flat start;
#                    diverged: above 1.5x the flat start; a run that failed)
#   DIR/summary.md   the table and the set's medians and rates, against issue 45's goals
#   DIR/chart_psnr.csv, DIR/chart_gain.csv  what bench/generalise.sh charts
# Usage: bench/generalise-summary.py DIR [--expected-runs N] [--device TEXT] [--settings TEXT]
# Needs only Python 3.
import argparse
import csv
import glob
import json
import os
import re
import statistics

MODELS = ['method', 'no-refraction', 'flat-water', 'dry-control', 'known-water']
# Issue 45's thresholds: the water matters where the oracle leads straight rays by 1 dB or
# more; where it does not, the method should stay within 0.5 dB of them; a surface above
# 1.5x the flat start's error has diverged.
MATTERS_DB, NEUTRAL_DB, DIVERGED = 1.0, 0.5, 1.5

ap = argparse.ArgumentParser()
ap.add_argument('dir')
ap.add_argument('--expected-runs', type=int, default=0)
ap.add_argument('--device', default='')
ap.add_argument('--settings', default='')
ap.add_argument('--models', default=' '.join(MODELS), help='the models this invocation trained (the others count as not run, not as failed)')
a = ap.parse_args()
TRAINED = [m for m in MODELS if m in a.models.split()]
out = a.dir


def num(v):
    try:
        x = float(v)
        return x if x == x else None  # nan -> None
    except (TypeError, ValueError):
        return None


runs = list(csv.DictReader(open(os.path.join(out, 'runs.csv'))))
scenes = {}
for path in glob.glob(os.path.join(out, 'scenes', 'scene_*.json')):
    s = json.load(open(path))
    scenes[str(s['seed'])] = s
failed = set()
for path in glob.glob(os.path.join(out, 'rows', '*.failed')):
    m = re.match(r'scene_(\d+)_seed_(\d+)_(.+)\.failed$', os.path.basename(path))
    if m:
        failed.add((m.group(1), m.group(2), m.group(3)))

by = {(r['scene'], r['seed'], r['variant']): r for r in runs}  # 'model' is report's own column (refraction, ...)
pairs = sorted({(k[0], k[1]) for k in list(by) + list(failed)}, key=lambda p: (int(p[0]), int(p[1])))
set_name = runs[0]['set'] if runs else ''


def psnr(scene, seed, model):
    r = by.get((scene, seed, model))
    return num(r['eval_psnr']) if r else None


def fmt(v, f='%.2f'):
    return '' if v is None else f % v


table = []
for scene, seed in pairs:
    s = scenes.get(scene, {})
    rig = s.get('rig', {})
    # width: what was trained on (the drawn width, unless --dataset-size tiny capped it)
    p = {m: psnr(scene, seed, m) for m in MODELS}
    method = by.get((scene, seed, 'method'))
    row = {'set': set_name, 'scene': scene, 'seed': seed, 'rig': rig.get('type', ''), 'train_views': rig.get('train_views', ''),
           'width': s.get('dataset_width', rig.get('width', '')), 'slope_bound': fmt(s.get('water', {}).get('slope_bound'), '%.3f'), 'ior': fmt(s.get('ior'), '%.3f'),
           'rim': int(bool(s.get('rim'))) if s else ''}
    for m in MODELS:
        row['psnr_' + m] = fmt(p[m])
    d = lambda x, y: None if x is None or y is None else x - y
    gain, gap, lead = d(p['method'], p['no-refraction']), d(p['known-water'], p['method']), d(p['known-water'], p['no-refraction'])
    row.update({'gain_over_straight': fmt(gain), 'gap_to_oracle': fmt(gap), 'oracle_lead': fmt(lead),
                'over_flat_plane': fmt(d(p['method'], p['flat-water'])), 'under_dry_control': fmt(d(p['dry-control'], p['method']))})
    rmse = num(method['eval_surface_rmse']) if method else None
    flat = num(method['eval_flat_rmse']) if method else None
    ratio = rmse / flat if rmse is not None and flat else None
    row.update({'surface_rmse': fmt(rmse, '%.5f'), 'flat_start_rmse': fmt(flat, '%.5f'), 'surface_vs_flat': fmt(ratio, '%.3f'),
                'amplitude_ratio': fmt(num(method['amplitude_ratio']) if method else None, '%.3f'),
                'correlation': fmt(num(method['eval_correlation']) if method else None, '%.3f')})
    run_failed = [m for m in TRAINED if (scene, seed, m) in failed or (scene, seed, m) not in by]
    row['failed_runs'] = ' '.join(run_failed)
    row['water_matters'] = '' if lead is None else int(lead >= MATTERS_DB)
    row['under_straight'] = '' if gain is None else int(gain < 0)
    row['worse_than_flat'] = '' if ratio is None else int(ratio > 1)
    row['diverged'] = '' if ratio is None else int(ratio > DIVERGED)
    # A failure: the method did not finish, or fell under straight rays, or left the water
    # further from the truth than the flat start.
    row['failure'] = int('method' in run_failed or row['under_straight'] == 1 or row['worse_than_flat'] == 1)
    row['_gain'], row['_gap'], row['_lead'], row['_ratio'] = gain, gap, lead, ratio
    row['_amp'] = num(row['amplitude_ratio'])
    table.append(row)

columns = [k for k in table[0] if not k.startswith('_')] if table else []
with open(os.path.join(out, 'table.csv'), 'w', newline='') as f:
    w = csv.DictWriter(f, fieldnames=columns, extrasaction='ignore')
    w.writeheader()
    w.writerows(table)

# Charts: each model's PSNR (mean over seeds) against the scene's slope; the gain against
# the oracle's lead, per scene and seed, by rig.
with open(os.path.join(out, 'chart_psnr.csv'), 'w', newline='') as f:
    w = csv.writer(f)
    w.writerow(['slope_bound', 'model', 'psnr'])
    for scene in sorted({r['scene'] for r in table}, key=lambda s: num(scenes.get(s, {}).get('water', {}).get('slope_bound')) or 0):
        for m in MODELS:
            vals = [psnr(scene, r['seed'], m) for r in table if r['scene'] == scene]
            vals = [v for v in vals if v is not None]
            if vals and scene in scenes:
                w.writerow(['%.4f' % scenes[scene]['water']['slope_bound'], m, '%.3f' % statistics.mean(vals)])
with open(os.path.join(out, 'chart_gain.csv'), 'w', newline='') as f:
    w = csv.writer(f)
    w.writerow(['oracle_lead', 'gain', 'rig'])
    for r in sorted((r for r in table if r['_lead'] is not None and r['_gain'] is not None), key=lambda r: r['_lead']):
        w.writerow(['%.3f' % r['_lead'], '%.3f' % r['_gain'], r['rig']])


def median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def db(v):
    return '-' if v is None else '%+.2f dB' % v


def share(flags):
    flags = list(flags)
    return '%d of %d (%.0f%%)' % (sum(flags), len(flags), 100.0 * sum(flags) / len(flags)) if flags else 'none'


matters = [r for r in table if r['_lead'] is not None and r['_lead'] >= MATTERS_DB]
neutral = [r for r in table if r['_lead'] is not None and r['_lead'] < MATTERS_DB]
done = sum(1 for k in by)
lines = ['# Random scenes: the method against straight rays, the flat plane, the dry control and the oracle (%s set)' % set_name, '']
if a.device:
    lines.append('Device: %s.' % a.device)
if a.settings:
    lines.append('Settings: %s.' % a.settings)
lines += ['Runs finished: %d%s; failed: %d.' % (done, ' of %d' % a.expected_runs if a.expected_runs else '', len(failed)), '',
          'Scenes: `refrax synth random --seed N` (scenes/scene_N.json says what each was); the method is `refrax train` with no '
          'method flags (but the settings\' method flags, where they name some). *gain*: method minus straight rays (test PSNR, dB); *gap*: the oracle (`--known-water`) minus the method; '
          '*lead*: the oracle minus straight rays (the water matters where it is %g dB or more); *surface / flat*: the method\'s '
          'surface RMSE over the flat start\'s (above 1: worse than the flat start; above %g: diverged); *amplitude*: '
          'bench/surface-error.py\'s amplitude ratio over the square the test views see (1: the waves\' full height). '
          'A *failure* is a method run that failed, fell under straight rays, or ended worse than the flat start.' % (MATTERS_DB, DIVERGED), '',
          '## Over the set', '',
          '| measure | value | issue 45 goal |', '| --- | --- | --- |',
          '| scene x seed pairs | %d | |' % len(table),
          '| failure rate | %s | |' % share(r['failure'] for r in table),
          '| median gain over straight rays | %s | |' % db(median(r['_gain'] for r in table)),
          '| where the water matters (lead >= %g dB): method beats straight rays | %s | >= 90%% |' % (MATTERS_DB, share(r['_gain'] is not None and r['_gain'] > 0 for r in matters)),
          '| where the water matters: median gain | %s | >= +2 dB |' % db(median(r['_gain'] for r in matters)),
          '| where it does not: method within %g dB of straight rays | %s | all |' % (NEUTRAL_DB, share(r['_gain'] is not None and r['_gain'] >= -NEUTRAL_DB for r in neutral)),
          '| median gap to the oracle | %s | <= 1.5 dB |' % db(median(r['_gap'] for r in table)),
          '| surface worse than the flat start | %s | |' % share(r['worse_than_flat'] == 1 for r in table if r['_ratio'] is not None),
          '| diverged (surface above %gx the flat start) | %s | none |' % (DIVERGED, share(r['diverged'] == 1 for r in table if r['_ratio'] is not None)),
          '| median surface RMSE / flat start | %s | |' % (fmt(median(r['_ratio'] for r in table), '%.3f') or '-'),
          '| median amplitude ratio where the water matters | %s | >= 0.85 |' % (fmt(median(r['_amp'] for r in matters), '%.3f') or '-'),
          '', '## Per scene and seed', '',
          '| scene | seed | rig | views | px | slope | IOR | rim | method | straight | flat | dry | oracle | gain | gap | surface / flat | amplitude | correlation | failure |',
          '| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |']
for r in table:
    lines.append('| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |' % (
        r['scene'], r['seed'], r['rig'], r['train_views'], r['width'], r['slope_bound'], r['ior'], 'yes' if r['rim'] == 1 else 'no',
        r['psnr_method'] or '-', r['psnr_no-refraction'] or '-', r['psnr_flat-water'] or '-', r['psnr_dry-control'] or '-',
        r['psnr_known-water'] or '-', r['gain_over_straight'] or '-', r['gap_to_oracle'] or '-', r['surface_vs_flat'] or '-',
        r['amplitude_ratio'] or '-', r['correlation'] or '-',
        ('yes' if r['failure'] else 'no') + (' (not finished: %s)' % r['failed_runs'] if r['failed_runs'] else '')))
lines += ['', '![PSNR against slope](psnr.svg)', '', '![gain against the oracle\'s lead](gain.svg)', '']
with open(os.path.join(out, 'summary.md.tmp'), 'w') as f:
    f.write('\n'.join(lines))
os.replace(os.path.join(out, 'summary.md.tmp'), os.path.join(out, 'summary.md'))
print('\n'.join(lines[:22]))
