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


def goal_line(name, rows, gain, ratio, amplitude):
    """The evaluation goals over rows (each with 'lead', the oracle's lead over straight rays) as
    one line; gain, ratio and amplitude read a row's gain over straight rays, surface error over
    the flat start's and amplitude ratio."""
    import statistics as st
    matters = [x for x in rows if x['lead'] >= 1]
    rest = [x for x in rows if x['lead'] < 1]
    med = lambda v: st.median(v) if v else float('nan')
    return ('%s: %d runs; where the water matters (oracle lead >= 1 dB, %d runs): beats straight rays %d, median gain %+.2f, '
            'median amplitude %.2f; elsewhere (%d runs): within 0.5 dB of straight rays %d, median gain %+.2f; '
            'diverged (> 1.5x the flat start) %d; worse than flat %d; worst %.2fx' % (
                name, len(rows), len(matters), sum(gain(x) > 0 for x in matters), med([gain(x) for x in matters]),
                med([amplitude(x) for x in matters]), len(rest), sum(gain(x) >= -0.5 for x in rest), med([gain(x) for x in rest]),
                sum(ratio(x) > 1.5 for x in rows), sum(ratio(x) > 1 for x in rows), max(ratio(x) for x in rows)))
