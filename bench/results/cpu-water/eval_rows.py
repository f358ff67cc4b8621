# The rows of bench/generalise.sh result folders, for the comparison scripts beside it.
import csv, glob, os


def load(here, *dirs):
    """{(scene, seed, variant): row} over each folder's rows/*.csv and runs.csv (paths under here),
    the runs that finished (exit code 0) only."""
    d = {}
    for p in dirs:
        p = os.path.join(here, p)
        files = glob.glob(os.path.join(p, 'rows', '*.csv')) + [f for f in [os.path.join(p, 'runs.csv')] if os.path.isfile(f)]
        for f in files:
            for r in csv.DictReader(open(f)):
                if r.get('exit_code', '0') == '0': d[(r['scene'], r['seed'], r['variant'])] = r
    return d
