// The sun-vector baseline: the sun's direction in each frame from the AoLP (single scattering
// polarizes ⟂ the scattering plane, so every E-vector is ⟂ the sun: the sun is the direction most
// nearly ⟂ all of them), then the pole from the sun's path.
// SunSource::dolp finds each sun from the DoLP alone instead, by fitting the Rayleigh law
// DoLP = Pmax·(1 − c²)/(1 + c²), c = s·d, to every valid pixel (Gauss–Newton on s and Pmax, started
// at the lowest filtered DoLP above the horizon): no AoLP needed, every pixel contributes, but it is
// only as good as the Rayleigh law is for the sky (the AoLP route needs only E ⟂ s).
//
// Sun per frame: s = the eigenvector of the smallest eigenvalue of Σ w E Eᵀ over the valid pixels
// with DoLP ≥ min_dolp, w = DoLP² (the angle's noise scales as 1/DoLP), E the unit E-vector in the
// camera frame from the sensor AoLP through the camera's transport (meridional: E = cos a·e0 +
// sin a·d×e0 with e0 = camera::meridional_e0(d); projected: E ⟂ d with the sensor-plane angle a);
// the sign with the sun above the horizon.
// The polarizer model (FrameEVectors::polarizer, on frames whose AoLP assumed the polarizers'
// nominal angles: polarizer_fit, estimate.h). A DoFP sensor whose four micro-polarizers sit ε_k
// off their angles 0°, 45°, 90°, 135°, demosaiced as if they did not, measures
// S1' ∝ cos(2a − A)·cos(ε0 − ε90) and S2' ∝ sin(2a − B)·cos(ε45 − ε135) for a sky AoLP a,
// A = ε0 + ε90, B = ε45 + ε135: it reads a' = a + c0 + c1·cos 4a' + c2·sin 4a' to first order,
// with c0 = −(A + B)/4 (a common turn of every E-vector), c1 = (A − B)/4 and 4·c2 + 1 the ratio of
// the two cosines. The same at every pixel of every frame, and an E-vector turned about its ray is
// no longer ⟂ the sun: a degree of c0 moves the plain fit's sun by about as much. So the fit
// models it exactly (its three parameters as c): s and c minimise Σ w·(s·(E − δ(a', c)·∂E/∂a))²,
// δ the error the model gives at the measured a' (Gauss–Newton from the plain eigenvector, then
// the eigenvector of the corrected E-vectors). A sky mirror-symmetric about the sun's vertical
// plane, sampled symmetrically, has ∂/∂c0 = 0 at c = 0 (s·E is even under the mirror, s·∂E/∂a
// odd), so the model costs such a sky no bias, but on a sky sampled unevenly c0 trades with the
// sun's azimuth near the zenith and the sun's scatter grows (docs/calibration-history.md, "The
// polarizer model"). A fitted term beyond 5° is no sensor's, and the fit then keeps the E-vectors
// as read.
// Pole, PoleFromSun::circle (no ephemeris, no site): the sun turns about the pole at declination
// δ, s_t·p = sin δ_t; p minimises Σ (s_t·p − a − b·τ_t)² (b, the declination drift, only with the
// linear detrend, automatic for windows ≥ 7 h), i.e. the smallest eigenvector of Sᵀ H S with H the
// projector that removes the fitted terms. North from the sun's rotation (estimate.h).
// Pole, PoleFromSun::ephemeris (the classic baseline of the literature): the site and the frame
// times are taken as known, ERFA gives each sun's ENU direction; the heading is the circular mean
// of (true sun azimuth − level-frame sun azimuth), and the pole is the site's true pole placed
// with that heading. Its latitude is the site's, by construction: only its bearing is a result.
// residual_deg: RMS angle between the suns and the fitted cone (circle) or between the measured
// and the ephemeris suns after the heading (ephemeris). Uncertainty: skypole/uncertainty.h.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "stack/frame.h"
#include "skypole/e_vectors.h"
#include "skypole/estimate.h"
#include "skypole/invariance.h"  // Detrend
#include "skypole/sky_images.h"
#include "skypole/stack_sky.h"

namespace skypol::skypole {

enum class PoleFromSun { circle, ephemeris };
enum class SunSource { aolp, dolp };
SunSource parse_sun_source(std::string_view name);  // "aolp" | "dolp"
std::string_view sun_source_name(SunSource s);
PoleFromSun parse_pole_from_sun(std::string_view name);  // "circle" | "ephemeris"
std::string_view pole_from_sun_name(PoleFromSun m);

struct SunVectorParams {
  InputOptions input;
  PoleFromSun mode = PoleFromSun::circle;
  SunSource source = SunSource::aolp;
  std::optional<sky::Site> site;  // ephemeris mode; nullopt → frame 0's truth site
  Detrend detrend = Detrend::automatic;
  // The drift unknown b is nearly collinear with the pole over a short arc and amplifies the
  // noise; over a long one it removes the drift's bias (≈ 0.09° of bearing at the equinox).
  // Measured on the paper's protocol through the DoFP sensor (6 headings, frames every 10 min
  // from 09:00 UTC), mean |bearing| without / with b: sun_vector 0.086 / 0.27° at 4 h, 0.090 /
  // 0.076° at 6 h, 0.090 / 0.041° at 7 h; sun_dolp 0.086 / 0.37° at 4 h, 0.088 / 0.13° at 6 h,
  // 0.088 / 0.073° at 7 h. Both gain from 7 h on.
  double auto_detrend_min_hours = 7.0;
  double min_dolp = 0.05;
  // SunSource::dolp: measure the Rayleigh-law misfit (PoleEstimate::model_misfit; a jackknife's
  // sub-runs, which read only the pole, need not).
  bool model_misfit = true;
};

struct SunVectorResult {
  PoleEstimate estimate;
  std::vector<Eigen::Vector3d> suns_camera;  // per frame, unit, above the horizon
  std::vector<double> sun_quality;           // aolp: λ0/λ1; dolp: DoLP RMS residual (small = clear)
};

// The rms of a DoLP image's pixel noise about the Rayleigh law fitted to it (sun, pmax), from second
// differences of the residual at a lag of kNoiseLagPx pixels, along rows and columns of valid
// pixels: for noise of variance σ² that is independent at that lag, (r[x−L] − 2r[x] + r[x+L]) has
// variance 6σ², while a smooth departure from the law adds only its curvature. Robust (1.4826 ×
// the median absolute second difference), so that cloud edges do not count. The lag is the colour
// DoFP sensor's 4-pixel lattice: its demosaic interpolates each band and polarizer bilinearly
// between samples 4 pixels apart, so that neighbours share their noise and second differences of
// neighbours see almost none of it. Even at that lag it reads the colour sensor's noise about
// 15 % low (0.015 against 0.018 from two noise draws of the same sky), which is why the misfit
// below is measured on blocks.
inline constexpr int kNoiseLagPx = 4;
double dolp_noise_rms(const SkyImages& sky, const std::vector<float>& dolp, const Eigen::Vector3d& sun,
                      double pmax);

// How far `dolp` departs from the Rayleigh law fitted to it (sun, pmax) beyond its noise, as a share
// of pmax (PoleEstimate::model_misfit): the rms over kNoiseLagPx² blocks of the mean residual, less
// (in quadrature) the blocks' own noise from their second differences two blocks apart. A block
// holds its pixels within the fit's 3 robust σ (cloud is the fit's outlier, not its misfit) where
// the law expects at least 3 × the pixel noise (below, the noisy DoLP is biased up: no law fitted to
// it follows that); it counts with at least half of them. Blocks, because the blocks' noise is a
// quarter of the pixels' and independent from block to block, so that a sensor's noise that is 2–3
// × a misfit of 1 % does not read as one: a Rayleigh sky through the colour DoFP sensor reads 1.7 %
// when the residual of each pixel is compared with its neighbours' noise (the level of a multiply
// scattering sky), and 0 on blocks; the vrte sky of scenes/skypole-marseille-vrte.toml 2.5 % both
// ways. 1 when fewer than 10 blocks count.
double rayleigh_misfit(const SkyImages& sky, const std::vector<float>& dolp, const Eigen::Vector3d& sun,
                       double pmax);

// robust (the default; InputOptions::sky_mask turns it off for before/after measurements): fit,
// drop the pixels the fit misses by more than 3 robust σ (1.4826·median |residual|), refit twice.
// The sun in one frame from its AoLP (see above); nullopt if too few polarized pixels.
// polarizer: the plain fit, or the sun with the sensor's polarizer error (above; polarizer_fit, estimate.h).
std::optional<Eigen::Vector3d> sun_from_aolp(const SkyImages& sky, const std::vector<float>& dolp,
                                             const std::vector<float>& aolp,
                                             const camera::Camera& camera, double min_dolp, PolarizerFit polarizer,
                                             double* quality = nullptr, bool robust = true);
// The same from the frame's E-vectors computed once (e_vectors.h: `ev` of a sky whose valid pixels
// include `sky`'s, at a min_dolp no higher than this one's; ev.polarizer says whether the
// polarizer error is fitted).
std::optional<Eigen::Vector3d> sun_from_aolp(const SkyImages& sky, const std::vector<float>& dolp,
                                             const FrameEVectors& ev, double min_dolp,
                                             double* quality = nullptr, bool robust = true);

// The sun in one frame from a Rayleigh fit of its DoLP, started at `start`; nullopt if the fit
// fails. pmax receives the fitted Pmax, rms the DoLP residual.
std::optional<Eigen::Vector3d> sun_from_dolp(const SkyImages& sky, const std::vector<float>& dolp,
                                             const Eigen::Vector3d& start, double* pmax = nullptr,
                                             double* rms = nullptr, bool robust = true);

// sun_dolp's per-frame Rayleigh fits of `sky` (masked first when sky_mask, as estimate_sun_vector
// does): where each fit started (nullopt: no sun-like DoLP minimum above the horizon), the sun it
// found (nullopt: it failed), its DoLP rms residual, and its rayleigh_misfit (PoleEstimate::model_misfit).
struct RayleighFits {
  std::vector<std::optional<Eigen::Vector3d>> starts, suns;
  std::vector<double> rms, misfit;
};
RayleighFits fit_rayleigh_law(SkyImages& sky, const stack::Stack& stack, bool sky_mask);
// The same on a view's prepared sky (stack_sky.h); without `misfit`, misfit stays 0.
RayleighFits fit_rayleigh_law(SkyImages& sky, const SkyView& view, bool sky_mask, bool misfit = true);

// How far the stack's sky departs from Rayleigh's law: the median misfit over the frames whose fit
// succeeded (1 when none did: nothing like the law). sun_dolp's own model check, measured for a
// method that assumes what the law implies, that DoLP is a function of the angle to the sun alone
// (great_circle's equal-DoLP great circles), so that its calibration can gate on it.
double rayleigh_law_misfit(const stack::Stack& stack, const InputOptions& input);
double rayleigh_law_misfit(const SkyView& view);  // with the view's input

// Each frame's sun from its AoLP on a view, as sun_vector reads them (the prepared sky, masked when
// input.sky_mask, the cached E-vectors): shared by the methods that read the suns' directions.
// `why` is set (and the suns are incomplete) when a frame has too few polarized pixels; the
// prepared sky's own failures throw, naming `method`.
struct FrameSuns {
  SkyImages sky;                             // the sky the suns were fitted on
  std::vector<Eigen::Vector3d> suns_camera;  // per frame, unit, above the horizon
  std::vector<double> quality;               // λ0/λ1 of each fit
  std::vector<const FrameEVectors*> e_vectors;  // each frame's, on `sky` (the view's cache)
  std::string why;
};
FrameSuns find_aolp_suns(const SkyView& view, const InputOptions& input, double min_dolp, const char* method,
                         std::size_t min_frames);

// SunSource::aolp needs the "AoLP.<band>" channel; circle mode at least 3 frames, ephemeris mode 1.
SunVectorResult estimate_sun_vector(const stack::Stack& stack, const SunVectorParams& params = {});
// The same on a view of a stack (stack_sky.h: a jackknife's sub-run); params.input is the view's.
SunVectorResult estimate_sun_vector(const SkyView& view, const SunVectorParams& params = {});

}  // namespace skypol::skypole
