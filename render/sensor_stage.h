// What a scene's [sensor] does to a rendered frame: the ideal Stokes images go through the
// division-of-focal-plane sensor (camera/dofp_sensor.h: polarizer mosaic, shot, dark and read noise,
// full well, ADC) and back through the demosaic, as a real polarization camera's pipeline gives
// them. DoLP and AoLP are then recomputed from the measured Stokes with the usual rules
// (stack/polarization_math.h). Pixels outside the image circle or occluded keep mask 0 and hold
// zeros, as without a sensor; so do the pixels whose demosaic mixed in those dark pixels (the mask
// is eroded by camera::demosaic_reach: 1 pixel on a mono sensor, 3 on a colour one). A pixel
// whose demosaic read a clipped raw value is masked too, its S0 kept; channel "clipped" is 1 on the sky pixels masked so (camera::clipped_pixels). Run
// only when the scene has a [sensor] section.
// Exposure: the sensor's fixed exposure_us, or with exposure = "auto" (SensorSpec::auto_exposure)
// the meter's for this frame, read from the ideal S0 of the sky pixels before any noise
// (camera::metered_exposure_us); either way the frame's exposure_us says which.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "camera/camera.h"

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
// sky: what the meter reads (auto exposure only), 1 per pixel that sees the sky rather than the
// ground (sky_pixels); empty: every pixel does. Either way only pixels with mask > 0 count.
void apply_sensor(const scene::SensorSpec& sensor, const std::vector<std::string>& bands, std::uint64_t frame_index,
                  stack::Frame& frame, bool keep_raw = false, std::span<const std::uint8_t> sky = {});

// What the sensor's AoLP assumes of its polarizers (the frame's polarizer_angles, which
// apply_sensor sets): calibrated when the demosaic inverts the sensor's own analyzer or the
// polarizers sit at their nominal angles (every angle_error_deg 0), nominal otherwise.
stack::PolarizerAngles polarizer_angles(const scene::SensorSpec& sensor);

// 1 for each pixel whose centre's ray looks above the horizon, 0 for the ground and outside the
// image circle: the meter's region for this camera (the same for every frame of a stack).
std::vector<std::uint8_t> sky_pixels(const camera::Camera& camera);

// The exposure the meter sets for this frame (µs): the sensor's auto_exposure percentile of the
// ideal S0 (band_response applied, each pixel in its own band on a colour sensor) over the pixels
// with mask > 0 and, when given, sky = 1. Needs sensor.auto_exposure.
double meter_exposure_us(const scene::SensorSpec& sensor, const std::vector<std::string>& bands,
                         const stack::Frame& frame, std::span<const std::uint8_t> sky = {});

// How many frames the meter has read in this process: a sensor without auto exposure reads none
// (a scene pays only for what it asks for).
std::size_t frames_metered();

}  // namespace skypol::render
