#!/usr/bin/env python3
"""How far (mm) the heavy end of the strip of make_strip.py went down in each run directory
given: the mean of final.obj's lowest right-hand row less frame_000000.obj's."""
import sys


def vertices(path):
    return [tuple(map(float, line.split()[1:4])) for line in open(path) if line.startswith("v ")]


for run in sys.argv[1:]:
    a, b = vertices(f"{run}/obj/frame_000000.obj"), vertices(f"{run}/obj/final.obj")
    right = [i for i, p in enumerate(a) if p[0] > 0]
    low = min(a[i][2] for i in right)
    end = [i for i in right if a[i][2] < low + 1e-6]
    print(f"{run}: {-1000 * sum(b[i][2] - a[i][2] for i in end) / len(end):.1f} mm")
