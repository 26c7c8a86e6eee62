// The picture of an estimate: what a user looks at to trust or doubt an answer (`skypol estimate
// --plot`, skypol.plot_estimate). One frame of the stack (the middle one unless asked) in three
// panels — its DoLP, its AoLP, and the pixels the estimators read, coloured by what became of them
// (read; unpolarized or otherwise left out by the sky mask, sky_mask.h; clipped by the sensor;
// occluded; not read) — with, over every panel:
//   - the sun's track: the sun each frame was judged by (sky_mask.h judge_sky: fitted to the AoLP,
//     E ⟂ sun, or to the DoLP where the stack has no AoLP) as dots, the shown frame's ringed; and
//     the ephemeris' suns of the header, joined, where the stack knows its site — placed with the
//     true orientation where that is known (a render), else with the first answer's heading;
//   - each answer's pole (a ×, in the method's colour) and its 95 % cone projected through the lens
//     (a darker line of the same hue); the truth's pole (a white +) where the stack knows it;
//   - under the panels, one line per answer: its bearing, latitude and cone, or for a decline its
//     reason, and the legend.
// The drawing itself is the stack room's (stack/preview.h write_plot_png); nothing here renders.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "stack/frame.h"
#include "stack/preview.h"
#include "skypole/estimate.h"

namespace skypol::skypole {

struct PlotOptions {
  std::optional<std::size_t> frame;  // the frame shown; nullopt: the middle one (frames / 2)
  int max_panel_px = 512;            // panels sample every k-th pixel so that no side exceeds this
  // The shown frame's "clipped" channel when `stack` was read without it (skypol estimate reads the
  // estimator channels only); empty: the frame's own, if it has one.
  std::vector<float> clipped;
};

// The colour of a method's marks (stable per name: the order of method_names()); its cone's is
// this times kPlotConeShade. Every colour here is fully saturated, so that no category of the
// third panel, no colour map and no text has it.
stack::Rgb plot_colour(std::string_view method);
inline constexpr float kPlotConeShade = 0.6f;
inline constexpr stack::Rgb kPlotTruthColour{1.0f, 1.0f, 1.0f};

// The picture's content. Throws std::invalid_argument for a stack the estimators cannot read (as
// prepare_sky_images does) or a frame index past the stack's end.
stack::PlotFrame estimate_plot(const stack::Stack& stack, const std::vector<PoleEstimate>& estimates,
                               const InputOptions& input, const PlotOptions& options = {});

// estimate_plot written as a PNG at `path` (stack/preview.h write_plot_png).
void write_estimate_plot(const stack::Stack& stack, const std::vector<PoleEstimate>& estimates,
                         const InputOptions& input, const std::string& path, const PlotOptions& options = {});

// What `skypol estimate --plot TARGET` writes: TARGET ending in '/' or naming an existing folder,
// one PNG per answer, TARGET/METHOD.png (the folder is made if needed); otherwise one PNG at TARGET
// with every answer. Returns the paths written. Throws std::runtime_error naming a path it cannot
// write.
std::vector<std::string> write_estimate_plots(const stack::Stack& stack, const std::vector<PoleEstimate>& estimates,
                                              const InputOptions& input, const std::string& target,
                                              const PlotOptions& options = {});

// Text as the picture's font draws it: ASCII, with the degree sign, σ, ×, −, ⟂ and the like
// spelled out (OpenImageIO's text draws "°" as a zero).
std::string plot_ascii(std::string_view text);

}  // namespace skypol::skypole
