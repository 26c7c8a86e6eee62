// The colour maps of the previews, as small tables of sRGB control points designed in Oklab
// (scripts/make_colormaps.py prints them): a perceptual one for DoLP (lightness rises evenly from
// dark violet-blue to yellow, like viridis) and a cyclic one for AoLP (constant lightness around
// the hue circle, so −90° and +90°, the same polarization, share a colour).
#pragma once

#include <array>

namespace skypol::stack {

using Rgb = std::array<float, 3>;  // sRGB-encoded, each in [0, 1]

// t in [0, 1] (clamped; NaN gives the t = 0 colour); linear between the control points.
Rgb perceptual_colour(double t);
// Period 1: t and t + 1 give the same colour.
Rgb cyclic_colour(double t);

}  // namespace skypol::stack
