// A stack as a polarization camera records it, in memory: the renderer's Stokes images of a sky
// at the given times with the truth of each frame, and optionally the same frames through a
// division-of-focal-plane sensor (camera/dofp_sensor.h: mosaic, shot and read noise, ADC, then
// the bilinear demosaic a camera pipeline runs). For protocols that need many stacks and no
// files (skypol reproduce); render_scene is the path to EXR, with the same Renderer.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/dofp_sensor.h"
#include "camera/lens.h"
#include "stack/frame.h"
#include "sky/sky_spec.h"
#include "sky/sun.h"
#include "sky/time.h"

namespace skypol::render {

struct RecordingSetup {
  sky::Site site;
  sky::SunOptions sun_options;
  std::shared_ptr<const camera::Lens> lens;
  double heading_deg = 0, tilt_deg = 0, roll_deg = 0;  // camera/orientation.h
  sky::SkySpec sky;                                    // default: Rayleigh, Pmax 1
  // One band (mono), or R, G, B for a colour sensor; a vrte sky is solved per band (its
  // sky.wavelengths_nm, or each band's default wavelength).
  std::vector<std::string> bands = {"Y"};
};

// One frame per time, in the given order, with channels S0, S1, S2, DoLP, AoLP (sensor frame) of
// each band and mask, and the truth (sun from ERFA with setup.sun_options, orientation, the visible
// celestial pole and its pixel, as scene/truth.h's make_truth). Throws std::invalid_argument
// for a missing lens or an invalid sky spec.
stack::Stack record_stack(const RecordingSetup& setup, const std::vector<sky::Instant>& times);

// The stack a DoFP camera delivers: each frame's S0–S2 through the scene sensor stage
// (render/sensor_stage.h: simulate_raw with frame index i and the sensor's seed, the nominal
// bilinear demosaic, DoLP and AoLP recomputed), with the mask eroded by the demosaic's reach
// (camera::demosaic_reach: 1 pixel, 3 on a colour sensor): a pixel that near the image circle's
// edge mixes in the dark pixels beyond it and its DoLP is wrong. Only DoLP, AoLP and mask are kept. The sensor's width
// and height are set to the stack's. A mono sensor needs a one-band stack, a colour one
// (rggb_blocks) bands R, G, B (apply_sensor); throws std::invalid_argument otherwise, or for
// frames without S0–S2.
// auto_exposure: each frame is taken at the meter's exposure instead of sensor.exposure_us
// (render/sensor_stage.h: the sky pixels of the stack's camera, above its horizon); every frame's
// exposure_us says which.
stack::Stack through_sensor(const stack::Stack& ideal, camera::DofpSensor sensor,
                            const std::optional<camera::AutoExposure>& auto_exposure = std::nullopt);

}  // namespace skypol::render
