#!/usr/bin/env python3
"""Writes table.obj: a closed, manifold table (top 1.2 m x 0.8 m x 4 cm at 0.72-0.76 m,
four 5 cm square legs) as the boundary of a union of boxes on a grid, each boundary face
split into two triangles facing outward. Run: python3 make_table.py > table.obj"""

xs = [-0.6, -0.55, -0.5, 0.5, 0.55, 0.6]
ys = [-0.4, -0.35, -0.3, 0.3, 0.35, 0.4]
zs = [0.0, 0.72, 0.76]
legs_x = {0, 4}  # cell indices in x and y that hold legs
legs_y = {0, 4}


def filled(i, j, k):
    if not (0 <= i < len(xs) - 1 and 0 <= j < len(ys) - 1 and 0 <= k < len(zs) - 1):
        return False
    if k == 1:
        return True  # the top
    return i in legs_x and j in legs_y  # the legs


vertices, index, faces = [], {}, []


def vertex(i, j, k):
    key = (i, j, k)
    if key not in index:
        index[key] = len(vertices) + 1
        vertices.append((xs[i], ys[j], zs[k]))
    return index[key]


for i in range(len(xs) - 1):
    for j in range(len(ys) - 1):
        for k in range(len(zs) - 1):
            if not filled(i, j, k):
                continue
            # For each of the six sides facing an empty cell: a quad counter-clockwise
            # seen from outside.
            sides = [
                ((1, 0, 0), [(i + 1, j, k), (i + 1, j + 1, k), (i + 1, j + 1, k + 1), (i + 1, j, k + 1)]),
                ((-1, 0, 0), [(i, j, k), (i, j, k + 1), (i, j + 1, k + 1), (i, j + 1, k)]),
                ((0, 1, 0), [(i, j + 1, k), (i, j + 1, k + 1), (i + 1, j + 1, k + 1), (i + 1, j + 1, k)]),
                ((0, -1, 0), [(i, j, k), (i + 1, j, k), (i + 1, j, k + 1), (i, j, k + 1)]),
                ((0, 0, 1), [(i, j, k + 1), (i + 1, j, k + 1), (i + 1, j + 1, k + 1), (i, j + 1, k + 1)]),
                ((0, 0, -1), [(i, j, k), (i, j + 1, k), (i + 1, j + 1, k), (i + 1, j, k)]),
            ]
            for (di, dj, dk), quad in sides:
                if filled(i + di, j + dj, k + dk):
                    continue
                a, b, c, d = (vertex(*q) for q in quad)
                faces.append((a, b, c))
                faces.append((a, c, d))

print("# A table: top 1.2 m x 0.8 m x 0.04 m at 0.72-0.76 m, four 5 cm legs (metres).")
print("# Written by scenes/meshes/make_table.py; a closed, manifold surface.")
for v in vertices:
    print("v %g %g %g" % v)
for f in faces:
    print("f %d %d %d" % f)
