#!/usr/bin/env python3
"""The floor of the side-by-side comparison: the same frames as skypol's paper scene, in NumPy.

2448x2048 equidistant fisheye (f = 521.7 px, 185 deg), zenith camera, Marseille on 2022-09-23,
frames every 30 min from 06:00 UTC; Rayleigh DoLP and AoLP (meridional frame) as float32. It
writes nothing: it is what a careful 40-line script costs, the floor any tool is measured against.
Usage: numpy_floor.py FRAMES
"""
import math
import sys

import numpy as np

W, H, F, CX, CY, THETA_MAX = 2448, 2048, 1.8 / 3.45e-3, 1223.5, 1023.5, math.radians(92.5)
LAT, LON = math.radians(43.28699), 5.40336


def sun_enu(hours_utc):
    """Sun direction (east, north, up) from NOAA's low-precision formulas, 23 Sep 2022."""
    g = 2 * math.pi / 365 * (265 + (hours_utc - 12) / 24)
    decl = (0.006918 - 0.399912 * math.cos(g) + 0.070257 * math.sin(g) - 0.006758 * math.cos(2 * g)
            + 0.000907 * math.sin(2 * g) - 0.002697 * math.cos(3 * g) + 0.00148 * math.sin(3 * g))
    eqt = 229.18 * (0.000075 + 0.001868 * math.cos(g) - 0.032077 * math.sin(g)
                    - 0.014615 * math.cos(2 * g) - 0.040849 * math.sin(2 * g))
    ha = math.radians((hours_utc * 60 + eqt + 4 * LON) / 4 - 180)
    up = math.sin(LAT) * math.sin(decl) + math.cos(LAT) * math.cos(decl) * math.cos(ha)
    east = -math.cos(decl) * math.sin(ha)
    north = math.cos(LAT) * math.sin(decl) - math.sin(LAT) * math.cos(decl) * math.cos(ha)
    return np.array([east, north, up], dtype=np.float32)


def main():
    frames = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    u, v = np.meshgrid(np.arange(W, dtype=np.float32), np.arange(H, dtype=np.float32))
    mx, my = (u - CX) / F, (v - CY) / F
    r = np.hypot(mx, my)
    inside = r <= THETA_MAX
    theta = np.minimum(r, THETA_MAX)
    s = np.where(r > 0, np.sin(theta) / np.maximum(r, 1e-12), 1.0).astype(np.float32)
    # Camera frame: x right, y down, z up the optical axis; image-up is north, so x = west.
    d = np.stack([mx * s, my * s, np.cos(theta)])
    one_plus_dz = 1 + d[2]
    e0 = np.stack([1 - d[0] ** 2 / one_plus_dz, -d[0] * d[1] / one_plus_dz, -d[0]])
    e1 = np.cross(d, e0, axis=0)
    for k in range(frames):
        east, north, up = sun_enu(6 + 0.5 * k)
        sun = np.array([-east, -north, up], dtype=np.float32)  # in the camera frame
        cos_g = np.tensordot(sun, d, axes=1)
        dolp = np.where(inside, (1 - cos_g ** 2) / (1 + cos_g ** 2), 0).astype(np.float32)
        e = np.cross(d, sun[:, None, None], axis=0)  # E is perpendicular to the scattering plane
        aolp = np.arctan2((e * e1).sum(0), (e * e0).sum(0))
        aolp = np.where(aolp > np.pi / 2, aolp - np.pi, np.where(aolp <= -np.pi / 2, aolp + np.pi, aolp))
        aolp = np.where(inside, np.degrees(aolp), 0).astype(np.float32)
        assert np.isfinite(dolp).all() and np.isfinite(aolp).all()


if __name__ == "__main__":
    main()
