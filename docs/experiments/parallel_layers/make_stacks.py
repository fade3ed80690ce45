#!/usr/bin/env python3
"""Writes the two stacks of docs/implicit.md ("Nearly parallel edges: the mollifier"):
two 0.5 m cotton sheets of 20 x 20 cells, the upper 6 mm above the lower.

  regular_stack.obj    both sheets the same regular grid: every upper edge lies parallel
                       over a lower one
  irregular_stack.obj  each sheet's inner vertices moved by up to 30% of a cell and its
                       cells split along a random diagonal (seeds 7 and 8)

Texture coordinates are the rest shape in metres; the upper sheet's are moved 1 m along u,
so that the two are separate pieces of fabric. Run: python3 make_stacks.py
"""
import random

CELLS = 20
SIDE = 0.5   # m
GAP = 0.006  # m, between the layers


def write(path, irregular):
    h = SIDE / CELLS
    positions, uvs, faces = [], [], []
    for layer in range(2):
        rng = random.Random(7 + layer)
        base = layer * (CELLS + 1) ** 2
        for j in range(CELLS + 1):
            for i in range(CELLS + 1):
                x, y = i * h - SIDE / 2, j * h - SIDE / 2
                if irregular and 0 < i < CELLS and 0 < j < CELLS:
                    x += rng.uniform(-0.3, 0.3) * h
                    y += rng.uniform(-0.3, 0.3) * h
                positions.append((x, y, layer * GAP))
                uvs.append((x + layer * 1.0, y))
        for j in range(CELLS):
            for i in range(CELLS):
                a = base + j * (CELLS + 1) + i + 1  # OBJ ids start at 1
                b, c = a + 1, a + CELLS + 1
                d = c + 1
                if not irregular or rng.random() < 0.5:
                    faces += [(a, b, d), (a, d, c)]
                else:
                    faces += [(a, b, c), (b, d, c)]
    with open(path, "w") as out:
        for p in positions:
            out.write("v %.6f %.6f %.6f\n" % p)
        for t in uvs:
            out.write("vt %.6f %.6f\n" % t)
        for f in faces:
            out.write("f %d/%d %d/%d %d/%d\n" % (f[0], f[0], f[1], f[1], f[2], f[2]))


write("regular_stack.obj", irregular=False)
write("irregular_stack.obj", irregular=True)
