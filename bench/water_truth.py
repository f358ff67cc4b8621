# The synthetic truth's water (refrax synth's water.json and its height map), for the bench
# scripts that hold a learned water against it (water-error-map.py, the level-degree study's
# residual-degrees.py).
import json

import numpy as np


def truth_heights(dataset):
    """(water.json as read, a function (x, y) -> the true heights there, bilinear in the height
    map; x and y numpy arrays of one shape)."""
    water = json.load(open(dataset + '/water.json'))
    grid = np.load(dataset + '/' + water['height_map']['file'])
    x0, y0, x1, y1 = water['height_map']['domain']

    def at(x, y):
        ny, nx = grid.shape
        u, v = (x - x0) / (x1 - x0) * (nx - 1), (y - y0) / (y1 - y0) * (ny - 1)
        i, j = np.clip(u.astype(int), 0, nx - 2), np.clip(v.astype(int), 0, ny - 2)
        fu, fv = u - i, v - j
        return ((grid[j, i] * (1 - fu) + grid[j, i + 1] * fu) * (1 - fv) +
                (grid[j + 1, i] * (1 - fu) + grid[j + 1, i + 1] * fu) * fv)
    return water, at
