#!/usr/bin/env python3
"""Distance (m) the sheet's centroid travelled down the 20 degree incline of
incline_drop.json: final.obj against frame_000000.obj of each run directory given, and
the answer of Coulomb's law with an inelastic impact."""
import math
import sys

ANGLE, MU, G, DROP = math.radians(20.0), 0.2, 9.81, 0.03  # rad, -, m/s^2, m


def centroid(path):
    points = [tuple(map(float, line.split()[1:4])) for line in open(path) if line.startswith("v ")]
    return [sum(p[k] for p in points) / len(points) for k in range(3)]


def expected():
    fall = DROP / math.cos(ANGLE)  # m, straight down to the incline
    speed = math.sqrt(2.0 * G * fall)  # m/s at the impact
    t_land = speed / G
    along = max(0.0, speed * math.sin(ANGLE) - MU * speed * math.cos(ANGLE))  # m/s after it
    accel = G * (math.sin(ANGLE) - MU * math.cos(ANGLE))  # m/s^2
    t = 1.0 - t_land
    return fall * math.sin(ANGLE) + along * t + 0.5 * accel * t * t


down = (math.cos(ANGLE), 0.0, -math.sin(ANGLE))
print(f"Coulomb's law: {expected():.4f} m")
for run in sys.argv[1:]:
    a, b = centroid(f"{run}/obj/frame_000000.obj"), centroid(f"{run}/obj/final.obj")
    print(f"{run}: {sum((b[k] - a[k]) * down[k] for k in range(3)):.4f} m")
