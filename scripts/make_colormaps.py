#!/usr/bin/python3
"""Prints the colour-map tables of stack/colormap.cpp. Both maps are designed in Oklab
(Björn Ottosson's perceptual colour space, 2020) and written as sRGB control points:

  perceptual (DoLP): lightness rising linearly from 0.28 to 0.92 while the hue turns from
                     violet-blue (295°) through teal to yellow (105°), chroma kept inside sRGB;
  cyclic (AoLP):     constant lightness 0.72 and chroma 0.11 around the full hue circle, so
                     −90° and +90° (the same polarization) get the same colour.

Run: /usr/bin/python3 scripts/make_colormaps.py
"""
import numpy as np


def oklab_to_linear_srgb(L, a, b):
    l_ = L + 0.3963377774 * a + 0.2158037573 * b
    m_ = L - 0.1055613458 * a - 0.0638541728 * b
    s_ = L - 0.0894841775 * a - 1.2914855480 * b
    l, m, s = l_ ** 3, m_ ** 3, s_ ** 3
    return np.array([4.0767416621 * l - 3.3077115913 * m + 0.2309699292 * s,
                     -1.2684380046 * l + 2.6097574011 * m - 0.3413193965 * s,
                     -0.0041960863 * l - 0.7034186147 * m + 1.7076147010 * s])


def srgb_encode(x):
    assert x.min() > -1e-4 and x.max() < 1 + 1e-4, "out of the sRGB gamut"
    x = np.clip(x, 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def lch(L, C, h_deg):
    h = np.radians(h_deg)
    return srgb_encode(oklab_to_linear_srgb(L, C * np.cos(h), C * np.sin(h)))


def table(name, rows):
    print(f"constexpr std::array<Rgb, {len(rows)}> {name}{{{{")
    for r in rows:
        print(f"    {{{r[0]:.4f}f, {r[1]:.4f}f, {r[2]:.4f}f}},")
    print("}};")


t = np.linspace(0, 1, 17)
L = 0.28 + 0.64 * t
h = np.interp(t, [0, 0.5, 1], [295, 185, 105])
C = np.interp(t, [0, 0.25, 0.5, 0.7, 1], [0.13, 0.085, 0.085, 0.12, 0.175])
table("kPerceptual", [lch(L[i], C[i], h[i]) for i in range(len(t))])
table("kCyclic", [lch(0.72, 0.11, hue) for hue in np.arange(0, 360, 15)])
