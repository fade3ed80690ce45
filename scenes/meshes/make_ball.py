#!/usr/bin/env python3
"""Writes ball.obj: a sphere of radius 0.15 m centred at the origin, as an icosahedron
subdivided three times with every new point pushed onto the sphere (642 vertices, 1280
triangles facing outward, edges of 1.6-1.9 cm). Run: python3 make_ball.py > ball.obj"""
import math

RADIUS = 0.15  # m
SUBDIVISIONS = 3


def unit(p):
    n = math.sqrt(sum(c * c for c in p))
    return tuple(c / n for c in p)


def icosahedron():
    t = (1 + 5 ** 0.5) / 2
    points = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
              (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return [unit(p) for p in points], faces


def subdivide(points, faces):
    middle = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in middle:
            points.append(unit(tuple((points[a][i] + points[b][i]) / 2 for i in range(3))))
            middle[key] = len(points) - 1
        return middle[key]

    result = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        result += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return points, result


def main():
    points, faces = icosahedron()
    for _ in range(SUBDIVISIONS):
        points, faces = subdivide(points, faces)
    print("# ball.obj, written by make_ball.py: an icosphere of radius %g m" % RADIUS)
    for p in points:
        print("v %.6f %.6f %.6f" % tuple(RADIUS * c for c in p))
    for a, b, c in faces:
        print("f %d %d %d" % (a + 1, b + 1, c + 1))


if __name__ == "__main__":
    main()
