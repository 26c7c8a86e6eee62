#!/usr/bin/python3
"""Writes scenes/meshes/urban-district.obj: the city blocks around the street of
scenes/urban-canyon.toml, as a Wavefront OBJ (z up, metres, x East, y North).

A grid of blocks 60 m (East-West) by 120 m (North-South) between streets 16 m wide; the
observer stands in the middle of the North-South street at x = 0, half-way along a block.
Each block holds two rows of six buildings (20 m along the street, 15 m deep) on its East and
West edges; every third building has a small rooftop structure. Heights are drawn from a seeded
generator, so the file is the same on every run. The twelve buildings that line the observer's
own street are left out: the scene gives them as [[occluders.box]] entries.

Each building is a box without its floor: 8 vertices and 5 quads (10 triangles); faces use
relative (negative) indices to keep the file small.

Run: /usr/bin/python3 scripts/make_urban_district.py > scenes/meshes/urban-district.obj
"""
import random

STREET = 16.0
BLOCK_X, BLOCK_Y = 60.0, 120.0
PITCH_X, PITCH_Y = BLOCK_X + STREET, BLOCK_Y + STREET
COLUMNS = range(-6, 6)   # blocks West (k < 0) and East (k >= 0) of the observer's street
ROWS = range(-3, 4)      # blocks South (j < 0) and North (j > 0); j = 0 holds the observer
DEPTH, LENGTH = 15.0, 20.0

rng = random.Random(20220923)
out = []
triangles = 0


def num(v):
    return f"{v:.1f}".rstrip("0").rstrip(".")


def box(x0, x1, y0, y1, z0, z1):
    global triangles
    for z in (z0, z1):
        for y in (y0, y1):
            for x in (x0, x1):
                out.append(f"v {num(x)} {num(y)} {num(z)}")
    # Corners -8..-1: bit 0 = +x, bit 1 = +y, bit 2 = top (as in scene/box_mesh.cpp).
    for face in ((-4, -3, -1, -2),      # top
                 (-8, -7, -3, -4),      # South
                 (-6, -2, -1, -5),      # North
                 (-8, -4, -2, -6),      # West
                 (-7, -5, -1, -3)):     # East
        out.append("f " + " ".join(str(i) for i in face))
    triangles += 10


buildings = 0
for k in COLUMNS:
    for j in ROWS:
        bx0 = STREET / 2 + k * PITCH_X
        by0 = -BLOCK_Y / 2 + j * PITCH_Y
        for side, (x0, x1) in enumerate(((bx0, bx0 + DEPTH), (bx0 + BLOCK_X - DEPTH, bx0 + BLOCK_X))):
            for i in range(6):
                height = round(rng.uniform(12, 42), 1)
                roof = rng.random() < 1 / 3
                lining_observer = j == 0 and ((k == 0 and side == 0) or (k == -1 and side == 1))
                if lining_observer:
                    continue
                y0 = by0 + i * LENGTH
                box(x0, x1, y0, y0 + LENGTH, 0, height)
                buildings += 1
                if roof:
                    box(x0 + 4, x1 - 4, y0 + 6, y0 + 12, height, height + 3)

print("# scenes/meshes/urban-district.obj: written by scripts/make_urban_district.py (do not edit).")
print(f"# {buildings} buildings, {triangles} triangles; z up, metres; x East, y North.")
print("o urban-district")
print("\n".join(out))
