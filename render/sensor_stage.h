// What a scene's [sensor] does to a rendered frame: the ideal Stokes images go through the
// division-of-focal-plane sensor (camera/dofp_sensor.h: polarizer mosaic, shot, dark and read noise,
// full well, ADC) and back through the demosaic, as a real polarization camera's pipeline gives
// them. DoLP and AoLP are then recomputed from the measured Stokes with the usual rules
// (stack/polarization_math.h). Pixels outside the image circle or occluded keep mask 0 and hold
// zeros, as without a sensor; so do their 8 neighbours, whose demosaic mixed in those dark pixels
// (the mask is eroded by one pixel). A pixel whose demosaic read a clipped raw value is masked too,
// its S0 kept; channel "clipped" is 1 on the sky pixels masked so (camera::clipped_pixels). Run
// only when the scene has a [sensor] section.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stack/frame.h"
#include "scene/scene.h"

namespace skypol::render {

// The Stokes channels the sensor stage needs from the renderer for these bands.
std::vector<std::string> sensor_inputs(const std::vector<std::string>& bands);

// The channels a render keeps, from the renderer's own (render::channel_names) and the channels
// the scene asked for: "raw" if asked (a sensor's mosaic), and "clipped" beside a sensor's "mask".
std::vector<std::string> kept_channels(std::vector<std::string> rendered, const std::vector<std::string>& asked,
                                       bool has_sensor);

// Replaces S0/S1/S2 (and DoLP/AoLP, if present) of every band by the measured ones. `frame_index`
// keys the noise: the same scene gives the same noisy frames on any machine and thread count.
// keep_raw: also store the raw mosaic (DN, exact in float) as channel "raw".
// Mono sensors need one band; colour (rggb_blocks) sensors need bands R, G, B. Throws
// std::invalid_argument otherwise (the scene loader checks this first).
void apply_sensor(const scene::SensorSpec& sensor, const std::vector<std::string>& bands, std::uint64_t frame_index,
                  stack::Frame& frame, bool keep_raw = false);

}  // namespace skypol::render
