#!/usr/bin/env python3
"""Distance (m) each run's cloth centroid travelled, final.obj against frame_000000.obj of
each run directory given, and the answer of Coulomb's law with an inelastic impact: down
the 20 degree incline of incline_drop.json, or with --belt along the belt of
belt_drop.json."""
import math
import sys

G, DROP = 9.81, 0.03  # m/s^2, m


def centroid(path):
    points = [tuple(map(float, line.split()[1:4])) for line in open(path) if line.startswith("v ")]
    return [sum(p[k] for p in points) / len(points) for k in range(3)]


def incline():
    angle, mu = math.radians(20.0), 0.2  # rad, -
    fall = DROP / math.cos(angle)  # m, straight down to the incline
    speed = math.sqrt(2.0 * G * fall)  # m/s at the impact
    t_land = speed / G
    along = max(0.0, speed * math.sin(angle) - mu * speed * math.cos(angle))  # m/s after it
    accel = G * (math.sin(angle) - mu * math.cos(angle))  # m/s^2
    t = 1.0 - t_land
    travel = fall * math.sin(angle) + along * t + 0.5 * accel * t * t
    return travel, (math.cos(angle), 0.0, -math.sin(angle))


def belt():
    mu, belt_speed, duration = 0.3, 1.5, 0.3  # -, m/s, s
    t_land = math.sqrt(2.0 * DROP / G)
    speed = min(belt_speed, mu * G * t_land)  # m/s along the belt after the impact
    t = duration - t_land
    t_slip = min(t, (belt_speed - speed) / (mu * G))  # s until it rides the belt
    travel = speed * t_slip + 0.5 * mu * G * t_slip ** 2 + belt_speed * (t - t_slip)
    return travel, (1.0, 0.0, 0.0)


args = sys.argv[1:]
expected, direction = belt() if args[:1] == ["--belt"] else incline()
print(f"Coulomb's law: {expected:.4f} m")
for run in [a for a in args if a != "--belt"]:
    a, b = centroid(f"{run}/obj/frame_000000.obj"), centroid(f"{run}/obj/final.obj")
    print(f"{run}: {sum((b[k] - a[k]) * direction[k] for k in range(3)):.4f} m")
