#!/usr/bin/env python3
"""A cotton strip hung over a horizontal cylinder (docs/implicit.md, "Friction on a curved
obstacle"): writes strip_F.obj and capstan_F.json for each load factor F given, the heavy
side's hanging length being F times the largest that Coulomb's capstan law holds against
the light side's (the strip's own weight included, see tests/physics/capstan_test.cpp).
Cells of 1 cm, rest (u, v) in the OBJ's texture coordinates; laid CLEARANCE off the
cylinder (--clearance M, default 5e-4 m). Units: m, s, kg/m^2.
  python3 make_strip.py 0.8 1.25 && tissu run capstan_1.25.json --set integrator=bdf2 \\
      --set dt=0.004166666666666667 --obj-every 1000000 --out DIR && python3 drop.py DIR"""
import json
import math
import sys

RADIUS, FRICTION, LEFT, WIDTH, CELL = 0.05, 0.3, 0.2, 0.1, 0.01  # m, -, m, m, m


def capstan_limit():
    """Largest heavy-side length (m): dT/dth = mu T + R (mu cos th - sin th), T in rho g m."""
    slope = lambda th, t: FRICTION * t + RADIUS * (FRICTION * math.cos(th) - math.sin(th))
    n, th, t = 2000, -math.pi / 2, LEFT
    d = math.pi / n
    for _ in range(n):
        k1 = slope(th, t)
        k2 = slope(th + d / 2, t + d / 2 * k1)
        k3 = slope(th + d / 2, t + d / 2 * k2)
        k4 = slope(th + d, t + d * k3)
        t, th = t + d / 6 * (k1 + 2 * k2 + 2 * k3 + k4), th + d
    return t


def write_strip(path, right, clearance):
    r = RADIUS + clearance
    wrap = math.pi * r
    length = LEFT + wrap + right
    nu, nw = round(length / CELL), round(WIDTH / CELL)

    def position(s, y):
        if s <= LEFT:
            return (-r, y, -(LEFT - s))
        if s <= LEFT + wrap:
            th = -math.pi / 2 + (s - LEFT) / r
            return (r * math.sin(th), y, r * math.cos(th))
        return (r, y, -(s - LEFT - wrap))

    grid = [(length * i / nu, -WIDTH / 2 + WIDTH * j / nw) for i in range(nu + 1) for j in range(nw + 1)]
    with open(path, "w") as f:
        for s, y in grid:
            f.write("v %.9f %.9f %.9f\n" % position(s, y))
        for s, y in grid:
            f.write("vt %.9f %.9f\n" % (s, y))
        at = lambda i, j: i * (nw + 1) + j + 1
        for i in range(nu):
            for j in range(nw):
                a, b, c, d = at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)
                tris = [(a, c, d), (a, d, b)] if (i + j) % 2 else [(a, c, b), (b, c, d)]
                for t in tris:
                    f.write("f %d/%d %d/%d %d/%d\n" % (t[0], t[0], t[1], t[1], t[2], t[2]))


def main():
    args = sys.argv[1:]
    clearance = 5e-4
    if "--clearance" in args:
        k = args.index("--clearance")
        clearance = float(args[k + 1])
        del args[k:k + 2]
    limit = capstan_limit()
    print(f"capstan limit: {limit:.4f} m against {LEFT} m ({limit / LEFT:.3f} times)")
    for factor in args:
        write_strip(f"strip_{factor}.obj", float(factor) * limit, clearance)
        scene = {"name": f"capstan_{factor}", "integrator": "symplectic_euler", "dt": 1.5e-5,
                 "duration": 1.0, "cloth": {"mesh": {"file": f"strip_{factor}.obj"}, "material": "cotton"},
                 "gravity": [0, 0, -9.81],
                 "obstacles": [{"cylinder": {"center": [0, 0, 0], "axis": [0, 1, 0], "radius": RADIUS,
                                             "length": 0.5, "friction": FRICTION}}]}
        with open(f"capstan_{factor}.json", "w") as f:
            json.dump(scene, f, indent=1)


main()
