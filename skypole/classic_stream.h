// classic as run_method runs it (its answer, the Rayleigh-law misfit and sky readings its gates
// and σ terms read, its frame jackknife and calibrated uncertainty), on a stack file read part by
// part, so that its memory is a few frames and per-pixel counts whatever the number of frames:
// a day of full-resolution frames does not fit in memory as floats (23 frames of 2448×2048: 1.8 GB
// of DoLP, AoLP, S0 and mask; docs/benchmarks.md, section 6, "What skypol estimate -m classic costs").
//
// Two or three passes over the file, each decoding the parts one at a time:
//   1. DoLP, mask and clipped: the checks of prepare_sky_images and the whole stack's valid pixels
//      (WholeSkyReader, sky_images.h), which every filter and judgment below reads;
//   2. DoLP, AoLP and S0: per frame, classic's disk filter and its pairs' binary images, fed to the
//      whole stack's run and the frame jackknife's (ClassicRuns, classic.h: a filtered frame is
//      kept until its last pair); the sun of its raw DoLP and its share of the unreadable sky and
//      ring anisotropy (cloud_share.h); its sky-mask judgments, from its E-vectors (computed and
//      let go), folded into per-pixel counts (JudgmentTally, sky_mask.h); the misfit gate's
//      Rayleigh fit on the sky unmasked;
//   3. DoLP, only when the answer stands and the mask leaves out pixels: the Rayleigh fits of the
//      masked sky (a clear sky's mask leaves out none, and pass 2's fits are the misfit's).
// The answer is run_method(read_stack(path, estimator_channels(path, input)), "classic", input),
// bit for bit (tests/skypole/classic_stream_test.cpp).
#pragma once

#include <cstddef>
#include <string>

#include "stack/frame.h"
#include "skypole/estimate.h"

namespace skypol::skypole {

struct StreamedEstimate {
  PoleEstimate estimate;
  // The stack's shared facts and its frames' truths (and sizes, exposures), without channels: what
  // scoring and printing the answer read.
  stack::Stack stack;
  // The most the run kept from one frame to the next (the sky, the runs' counts, the filtered frames
  // still paired, the judgments' counts, per-frame readings), bytes: what grows with the number of
  // frames only by its per-frame readings.
  std::size_t retained_bytes = 0;
  int passes = 0;  // over the file: 2, or 3 when the misfit was measured on a masked sky
};

// Throws what run_method throws (std::invalid_argument naming the method, frame and channel;
// scene::SceneError for a file that is not a stack).
StreamedEstimate run_classic_streamed(const std::string& path, const InputOptions& input = {});

}  // namespace skypol::skypole
