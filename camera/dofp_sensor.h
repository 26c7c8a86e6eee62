// A division-of-focal-plane polarization sensor (Sony IMX250MZR-like): a 2×2 micro-polarizer
// mosaic in front of the pixels, photon shot noise, dark current, read noise, full-well
// saturation and ADC quantization, and the bilinear demosaic back to Stokes images.
// Pure functions over plain buffers (row-major, width × height, sensor frame: polarizer angles
// from sensor +x towards +y, docs/conventions.md). Each pixel's random numbers come from a
// counter-based hash of (seed, frame index, pixel index), so a frame is the same bit for bit
// whatever the order or the threads that compute it.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace skypol::camera {

// Colour polarization sensors (IMX250MYR) put an RGGB Bayer filter over the 2×2 polarizer
// blocks: block (row/2, col/2) is R when both are even, B when both are odd, G otherwise
// (block order as polanalyser describes the IMX250MYR; nominal, check your camera's pixel format).
enum class ColorFilter { none, rggb_blocks };

struct DofpSensor {
  int width = 0, height = 0;
  ColorFilter color_filter = ColorFilter::none;
  // Colour sensors: relative response of the R, G, B pixels (multiplies electrons_per_radiance_s).
  std::array<double, 3> band_response = {1, 1, 1};
  // Polarizer angle (degrees) of the pixels at (row mod 2, col mod 2), in the order
  // {(0,0), (0,1), (1,0), (1,1)}: the IMX250MZR's 90° 45° over 135° 0°. Angles are in skypol's
  // sensor convention (from +x towards +y, i.e. clockwise as displayed with rows going down).
  // Whether Sony's "45°" pixel transmits along the displayed up-right diagonal (then it is 135°
  // here and the layout is {90, 135, 45, 0}) flips the sign of S2 and of AoLP, never DoLP. It is
  // measured, not assumed: skypol.marseille.diagnose_layout fits the four sign hypotheses to the
  // AoLP predicted from a known sun and camera orientation (docs/conventions.md, "Which polarizer
  // layout"); until a real capture has been run through it, these are the datasheet's labels.
  std::array<double, 4> mosaic_deg = {90, 45, 135, 0};
  // Manufacturing errors per mosaic position: angle offsets (degrees) added to mosaic_deg.
  std::array<double, 4> angle_error_deg = {0, 0, 0, 0};
  double extinction_ratio = 1e9;  // Tmax/Tmin of the micro-polarizers (> 1; large = ideal)

  double exposure_us = 1000;
  // Photo-electrons per second for one unit of radiance reaching the pixel through an ideal
  // polarizer (folds in optics, QE and pixel area: the scene's radiance units → electrons).
  double electrons_per_radiance_s = 1e6;
  double gain_dn_per_e = 0.39;    // conversion gain after the analog gain
  double black_level_dn = 0;      // ADC offset added before quantization
  double read_noise_e = 2.3;      // rms, Gaussian
  double dark_current_e_s = 3;    // mean dark electrons per second
  double full_well_e = 10500;     // the pixel saturates here
  int adc_bits = 12;              // output 0 .. 2^bits − 1 DN
  bool shot_noise = true;         // Poisson photon and dark-current noise
  // Fixed-pattern noise, the same in every frame of a seed (keyed by seed and pixel only):
  double prnu_rms = 0;            // photo-response non-uniformity, relative rms (e.g. 0.01)
  double dsnu_e = 0;              // dark-signal non-uniformity, rms fixed offset in electrons
  std::uint64_t seed = 0;
};

// Throws std::invalid_argument naming the field (width, extinction_ratio, adc_bits, ...).
void validate(const DofpSensor& sensor);

// Auto-exposure as a camera's meter sets it, frame by frame: the exposure time that puts the
// `percentile`-th percentile of the sky's S0, in photo-electrons, at `target` × the pixel's full
// scale (full_scale_e), within the camera's exposure range and steps. The meter reads the ideal
// image before any noise; DofpSensor::exposure_us is then the frame's metered exposure.
struct AutoExposure {
  double percentile = 99.5;  // of the sky pixels' S0, in (0, 100]
  double target = 0.8;       // share of the full scale, in (0, 1]
  double min_us = 1;         // the camera's shortest exposure
  double max_us = 1e7;       // its longest (10 s); also the exposure of a sky with no light
  double step_us = 0;        // exposures are whole multiples of this (0: any time in the range)
};
// Throws std::invalid_argument naming the field (percentile, target, min_us, max_us, step_us).
void validate(const AutoExposure& meter);

// Electrons at which the pixel stops reading more light: its full well, or the ADC's top in
// electrons ((2^adc_bits − 1 − black_level_dn) / gain_dn_per_e) when that comes first.
double full_scale_e(const DofpSensor& sensor);

// The linearly interpolated percentile (NumPy's default rule: rank p/100·(n − 1) between the
// sorted values) of `values`, reordered in place; 0 for none.
double percentile_of(std::span<float> values, double percentile);

// The metered exposure (µs) for a sky whose `percentile`-th S0 percentile is `sky_s0` (radiance
// units, as the pixel's band sees it: band_response applied): target·full_scale_e /
// (electrons_per_radiance_s · sky_s0), rounded down to whole steps (never past the target), and
// clamped to [min_us, max_us]. A sky of no light (sky_s0 ≤ 0) gets max_us.
double metered_exposure_us(const DofpSensor& sensor, const AutoExposure& meter, double sky_s0);

// Mean radiance reaching the pixel at (row, col) behind its polarizer, for Stokes (s0, s1, s2)
// in the sensor frame: ½[(1 + 1/ER)·S0 + (1 − 1/ER)·(S1 cos 2θ + S2 sin 2θ)], θ with its error.
double polarizer_radiance(const DofpSensor& sensor, int row, int col, double s0, double s1, double s2);

// One raw pixel value (DN) of frame `frame` — the function every pixel of simulate_raw calls.
std::uint16_t simulate_pixel(const DofpSensor& sensor, int row, int col, double s0, double s1,
                             double s2, std::uint64_t frame);

// The raw mosaic (DN, row-major) of a frame from per-pixel Stokes images in the sensor frame.
// Buffers must hold width·height values; throws std::invalid_argument otherwise.
std::vector<std::uint16_t> simulate_raw(const DofpSensor& sensor, std::span<const float> s0,
                                        std::span<const float> s1, std::span<const float> s2,
                                        std::uint64_t frame);
// The same into `raw`, which keeps its storage when it already holds width·height values (a
// pipeline reusing its buffers frame after frame pays no allocation and no page faults).
void simulate_raw_into(const DofpSensor& sensor, std::span<const float> s0, std::span<const float> s1,
                       std::span<const float> s2, std::uint64_t frame, std::vector<std::uint16_t>& raw);

// Stokes images recovered from a raw mosaic: DN → radiance (black level, mean dark signal, gain,
// exposure undone), each polarizer channel interpolated bilinearly to every pixel, then
// S0 = ½(I0 + I45 + I90 + I135), S1 = I0 − I90, S2 = I45 − I135 — assuming ideal polarizers at
// the nominal mosaic angles, as an uncalibrated pipeline does (so ER and angle errors show up).
// The mosaic must hold the four angles 0, 45, 90, 135 in some order.
// Demosaic::calibrated instead inverts the sensor's own analyzer (extinction ratio and angle
// errors included) by least squares over the four interpolated channels, as a pipeline with a
// per-sensor calibration does; then any four distinct angles (mod 180°) will do.
struct StokesPlanes {
  std::vector<float> s0, s1, s2;
};
enum class Demosaic { nominal, calibrated };
// Mono sensors only (color_filter none).
StokesPlanes demosaic_bilinear(const DofpSensor& sensor, std::span<const std::uint16_t> raw,
                               Demosaic mode = Demosaic::nominal);
// The same from DN that need not be whole (a capture's raw after its dark and flat corrections,
// stack/capture_import.h, which kept in floating point add no rounding).
StokesPlanes demosaic_bilinear(const DofpSensor& sensor, std::span<const float> raw, Demosaic mode = Demosaic::nominal);
// The same into `out` (storage kept as for simulate_raw_into).
void demosaic_bilinear_into(const DofpSensor& sensor, std::span<const std::uint16_t> raw,
                            Demosaic mode, StokesPlanes& out);

// Colour sensors (color_filter rggb_blocks). band_of_pixel: 0 = R, 1 = G, 2 = B (−1 for mono).
int band_of_pixel(const DofpSensor& sensor, int row, int col);
struct BandStokes {
  std::span<const float> s0, s1, s2;
};
// Raw mosaic from R, G, B Stokes images (each pixel reads its own band, scaled by band_response).
std::vector<std::uint16_t> simulate_raw_color(const DofpSensor& sensor,
                                              const std::array<BandStokes, 3>& rgb,
                                              std::uint64_t frame);
void simulate_raw_color_into(const DofpSensor& sensor, const std::array<BandStokes, 3>& rgb,
                             std::uint64_t frame, std::vector<std::uint16_t>& raw);
// R, G, B Stokes images: per band and polarizer, bilinear on the band's 4-pixel lattice (G: the
// mean of its two lattices), then as demosaic_bilinear.
std::array<StokesPlanes, 3> demosaic_color_bilinear(const DofpSensor& sensor,
                                                    std::span<const std::uint16_t> raw,
                                                    Demosaic mode = Demosaic::nominal);
void demosaic_color_bilinear_into(const DofpSensor& sensor, std::span<const std::uint16_t> raw,
                                  Demosaic mode, std::array<StokesPlanes, 3>& out);
// The same from DN that need not be whole (see demosaic_bilinear).
std::array<StokesPlanes, 3> demosaic_color_bilinear(const DofpSensor& sensor, std::span<const float> raw,
                                                    Demosaic mode = Demosaic::nominal);

// How far (pixels, along a row or a column) the bilinear demosaic reaches for the raw values of one
// output pixel: 1 on a mono sensor's 2-pixel lattices, 3 on a colour one's 4-pixel lattices (the
// lattice's period − 1). An output pixel within this distance of a raw pixel mixes that pixel in.
int demosaic_reach(const DofpSensor& sensor);
// Sets to 0 every pixel of `mask` (width × height, row-major) within `reach` pixels along a row
// and a column (a square) of one whose value is ≤ 0: the pixels whose demosaic, with that reach,
// mixed in a pixel that sees no sky.
void erode_mask(std::vector<float>& mask, int width, int height, int reach);

// The raw value (DN) at and above which a pixel reads as clipped: its full well (the read noise,
// added after the well clips, scatters clipped readings about it, so 4 of its σ below) or the
// ADC's top, whichever is lower.
double clip_level_dn(const DofpSensor& sensor);
// Per pixel of the demosaic's output, 1 where it read a clipped raw value: a raw pixel at or above
// clip_level_dn within its footprint (±demosaic_reach). There the Stokes vector is wrong, and not
// by noise: a clipped polarizer reads less than it saw, so DoLP falls and AoLP turns away from that
// polarizer's angle, alike in every frame, which no jackknife sees (docs/benchmarks-calibration.md
// measures how far it moves a heading).
std::vector<std::uint8_t> clipped_pixels(const DofpSensor& sensor, std::span<const std::uint16_t> raw);
// Masks the pixels `clipped` marks (mask = 0) and writes `clipped_sky`: 1 where such a pixel was sky
// (mask > 0 before), else 0 — the stack's "clipped" channel (docs/exr-format.md). Renders and
// imported captures alike.
void mask_clipped(std::span<const std::uint8_t> clipped, std::vector<float>& mask, std::vector<float>& clipped_sky);

}  // namespace skypol::camera
