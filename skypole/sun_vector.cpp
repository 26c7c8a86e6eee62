// Sun from AoLP, pole from the sun's path or from the ephemeris (sun_vector.h).
#include "skypole/sun_vector.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "camera/camera.h"
#include "sky/sun.h"
#include "sky/units.h"
#include "skypole/enum_names.h"
#include "skypole/sky_mask.h"
#include "skypole/stack_sky.h"

namespace skypol::skypole {
namespace {

// A fitted polarizer model beyond this (any term) is not a sensor's error but a sky the model
// does not describe: the fit keeps the E-vectors as read.
constexpr double kMaxPolarizerErrorRad = 5 * kRadPerDeg;

}  // namespace

constexpr EnumNames<PoleFromSun, 2> kPoleFromSunNames{
    {{PoleFromSun::circle, "circle"}, {PoleFromSun::ephemeris, "ephemeris"}}};
constexpr EnumNames<SunSource, 2> kSunSourceNames{{{SunSource::aolp, "aolp"}, {SunSource::dolp, "dolp"}}};

PoleFromSun parse_pole_from_sun(std::string_view name) {
  return enum_from_name(kPoleFromSunNames, name, "sun-vector mode");
}
std::string_view pole_from_sun_name(PoleFromSun m) { return enum_name(kPoleFromSunNames, m); }
SunSource parse_sun_source(std::string_view name) { return enum_from_name(kSunSourceNames, name, "sun source"); }
std::string_view sun_source_name(SunSource s) { return enum_name(kSunSourceNames, s); }

namespace {

// dolp minus the Rayleigh law pmax·(1 − c²)/(1 + c²), c the cosine to the sun, at every valid pixel
// (0 elsewhere).
std::vector<double> law_residual(const SkyImages& sky, const std::vector<float>& dolp, const Eigen::Vector3d& sun,
                                 double pmax) {
  std::vector<double> r(sky.pixels(), 0.0);
  for (std::size_t i = 0; i < sky.pixels(); ++i)
    if (sky.valid[i]) {
      const double c = sun.dot(to_double(sky.ray_camera[i]));
      r[i] = static_cast<double>(dolp[i]) - pmax * (1 - c * c) / (1 + c * c);
    }
  return r;
}

// The rms noise of a width × height grid `v` (row-major, `ok` marking the cells that count), from
// its second differences `lag` cells apart along rows and columns: for noise independent at that
// lag each has variance 6σ². Robust: 1.4826 × the median absolute second difference.
double second_difference_noise(const std::vector<double>& v, const std::vector<std::uint8_t>& ok, int width,
                               int height, int lag) {
  const std::size_t w = static_cast<std::size_t>(width), L = static_cast<std::size_t>(lag);
  std::vector<double> dd;
  const auto add = [&](std::size_t a, std::size_t i, std::size_t b) {
    if (ok[a] && ok[i] && ok[b]) dd.push_back(std::abs(v[a] - 2.0 * v[i] + v[b]));
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x);
      if (x >= lag && x + lag < width) add(i - L, i, i + L);
      if (y >= lag && y + lag < height) add(i - L * w, i, i + L * w);
    }
  return 1.4826 * quantile(std::move(dd), 0.5) / std::sqrt(6.0);
}

}  // namespace

double dolp_noise_rms(const SkyImages& sky, const std::vector<float>& dolp, const Eigen::Vector3d& sun,
                      double pmax) {
  // On the residual from the fitted law, so that the law's own curvature (largest near the sun, and
  // growing with the lag) is not counted as noise.
  return second_difference_noise(law_residual(sky, dolp, sun, pmax), sky.valid, sky.width, sky.height, kNoiseLagPx);
}

double rayleigh_misfit(const SkyImages& sky, const std::vector<float>& dolp, const Eigen::Vector3d& sun,
                       double pmax) {
  if (!(pmax > 0)) return 1.0;
  // The residual from the law at every valid pixel, kept where the fit keeps it (within 3 robust σ,
  // at least kMinCut: cloud is the fit's outlier, not its misfit) and where the law expects a DoLP
  // of at least 3 pixel-noise σ (below, the noisy DoLP is biased up, and no law fitted to it follows).
  const std::vector<double> r = law_residual(sky, dolp, sun, pmax);
  const double pixel_noise = second_difference_noise(r, sky.valid, sky.width, sky.height, kNoiseLagPx);
  std::vector<double> absr;
  std::vector<std::uint8_t> use(sky.pixels(), 0);
  for (std::size_t i = 0; i < sky.pixels(); ++i)
    if (sky.valid[i]) {
      const double law = static_cast<double>(dolp[i]) - r[i];
      use[i] = law >= 3 * pixel_noise ? 1 : 0;
      absr.push_back(std::abs(r[i]));
    }
  const double cut = std::max(0.005, 3 * 1.4826 * quantile(std::move(absr), 0.5));
  // Mean residual per block (sun_vector.h: why blocks); two blocks apart, the demosaic's shared
  // noise is gone.
  constexpr int B = kNoiseLagPx;
  const int bw = sky.width / B, bh = sky.height / B;
  std::vector<double> block(static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh), 0.0);
  std::vector<std::uint8_t> block_ok(block.size(), 0);
  double ms = 0;
  int blocks = 0;
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      double sum = 0;
      int n = 0;
      for (int y = by * B; y < (by + 1) * B; ++y)
        for (int x = bx * B; x < (bx + 1) * B; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(sky.width) +
                                static_cast<std::size_t>(x);
          if (use[i] && std::abs(r[i]) <= cut) {
            sum += r[i];
            ++n;
          }
        }
      if (2 * n < B * B) continue;
      const std::size_t k = static_cast<std::size_t>(by) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(bx);
      block[k] = sum / n;
      block_ok[k] = 1;
      ms += block[k] * block[k];
      ++blocks;
    }
  if (blocks < 10) return 1.0;
  const double block_noise = second_difference_noise(block, block_ok, bw, bh, 2);
  return std::sqrt(std::max(0.0, ms / blocks - block_noise * block_noise)) / pmax;
}

std::optional<Eigen::Vector3d> sun_from_dolp(const SkyImages& sky, const std::vector<float>& dolp,
                                             const Eigen::Vector3d& start, double* pmax,
                                             double* rms, bool robust) {
  // Pixels used: every valid one, thinned to ≤ ~60k on a regular stride.
  const int stride = std::max(
      1, static_cast<int>(std::floor(std::sqrt(static_cast<double>(sky.valid_count) / 60000.0))));
  std::vector<Eigen::Vector3d> d;
  std::vector<double> v;
  for (int y = 0; y < sky.height; y += stride)
    for (int x = 0; x < sky.width; x += stride) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(sky.width) +
                            static_cast<std::size_t>(x);
      if (!sky.valid[i]) continue;
      d.push_back(to_double(sky.ray_camera[i]));
      v.push_back(dolp[i]);
    }
  if (d.size() < 20) return std::nullopt;
  Eigen::Vector3d s = start.normalized();
  double p = 0.7, sse = 0;
  // Fit, then refit twice without the pixels the fit misses by more than 3 robust σ (at least
  // kMinCut of DoLP): cloud lowers DoLP, and a least-squares fit would bend the sun towards it.
  constexpr double kMinCut = 0.005;
  const std::vector<Eigen::Vector3d> d_all = d;
  const std::vector<double> v_all = v;
  for (int round = 0; round < (robust ? 3 : 1); ++round) {
    if (round > 0) {
      std::vector<double> r(d_all.size());
      for (std::size_t k = 0; k < d_all.size(); ++k) {
        const double c = s.dot(d_all[k]);
        r[k] = std::abs(p * (1 - c * c) / (1 + c * c) - v_all[k]);
      }
      const double cut = std::max(kMinCut, 3 * 1.4826 * quantile(r, 0.5, QuantileRank::upper));
      d.clear();
      v.clear();
      for (std::size_t k = 0; k < d_all.size(); ++k)
        if (r[k] <= cut) {
          d.push_back(d_all[k]);
          v.push_back(v_all[k]);
        }
      if (d.size() < 20) return std::nullopt;
    }
    for (int it = 0; it < 30; ++it) {
      const Eigen::Vector3d e1 = s.unitOrthogonal(), e2 = s.cross(e1);
      // Variable projection: Pmax by least squares for this s, then a Gauss–Newton step in s.
      double sgg = 0, sdg = 0;
      for (std::size_t k = 0; k < d.size(); ++k) {
        const double c = s.dot(d[k]), g = (1 - c * c) / (1 + c * c);
        sgg += g * g;
        sdg += g * v[k];
      }
      if (!(sgg > 0)) return std::nullopt;
      p = sdg / sgg;
      Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
      Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
      sse = 0;
      for (std::size_t k = 0; k < d.size(); ++k) {
        const double c = s.dot(d[k]), c2 = c * c, g = (1 - c2) / (1 + c2);
        const double dg = -4 * c / ((1 + c2) * (1 + c2));
        const double r = p * g - v[k];
        const Eigen::Vector3d j(p * dg * d[k].dot(e1), p * dg * d[k].dot(e2), g);
        jtj += j * j.transpose();
        jtr += j * r;
        sse += r * r;
      }
      const Eigen::Vector3d step = -jtj.ldlt().solve(jtr);
      if (!step.allFinite()) return std::nullopt;
      const double len = std::hypot(step(0), step(1));
      const double scale = len > 0.1 ? 0.1 / len : 1.0;  // at most ~6° per step
      s = (s + scale * (step(0) * e1 + step(1) * e2)).normalized();
      if (len < 1e-12) break;
    }
  }
  if ((sky.level_from_camera * s).z() < 0) s = -s;
  if (pmax) *pmax = p;
  if (rms) *rms = std::sqrt(sse / static_cast<double>(d.size()));
  return s;
}

std::optional<Eigen::Vector3d> sun_from_aolp(const SkyImages& sky, const std::vector<float>& dolp,
                                             const std::vector<float>& aolp,
                                             const camera::Camera& camera, double min_dolp, PolarizerFit polarizer,
                                             double* quality, bool robust) {
  return sun_from_aolp(sky, dolp, frame_e_vectors(sky, dolp, aolp, camera.transport(), min_dolp, polarizer),
                       min_dolp, quality, robust);
}

std::optional<Eigen::Vector3d> sun_from_aolp(const SkyImages& sky, const std::vector<float>& dolp,
                                             const FrameEVectors& ev, double min_dolp, double* quality,
                                             bool robust) {
  // The E-vectors read: those of the sky's valid pixels, in pixel order, weighted by DoLP².
  std::vector<std::uint32_t> at;  // indices into ev
  for (std::size_t k = 0; k < ev.pixel.size(); ++k) {
    const std::size_t i = ev.pixel[k];
    if (!sky.valid[i]) continue;
    const double p = dolp[i];
    constexpr std::uint8_t kRead = FrameEVectors::kDefined | FrameEVectors::kFiniteAolp;
    if (!(p >= min_dolp) || (ev.flags[k] & kRead) != kRead) continue;
    at.push_back(static_cast<std::uint32_t>(k));
  }
  if (at.size() < 10) return std::nullopt;
  const auto w_at = [&](std::size_t m) {
    const double p = dolp[ev.pixel[at[m]]];
    return p * p;
  };
  // With the polarizer model, per E-vector read: its turn ∂e/∂a and (cos 2a, sin 2a) of its sensor
  // AoLP a, made with the E-vectors (e_vectors.h).
  const bool model = ev.polarizer == PolarizerFit::modelled;
  if (model && ev.turns.size() != ev.pixel.size())
    throw std::logic_error("sun_from_aolp: E-vectors for the polarizer model without their turns");
  const auto turn_at = [&](std::size_t m) -> const FrameEVectors::Turn& { return ev.turns[at[m]]; };
  // The sensor's AoLP error (radians) at each E-vector read, from the mosaic's model c (sun_vector.h):
  // the measured (cos 2a', sin 2a') ∝ (cos(2a − A), ρ·sin(2a − B)) of the sky's a, so the sky's 2a
  // is the angle of (cos B·cos 2a' − sin A·sin 2a'/ρ, sin B·cos 2a' + cos A·sin 2a'/ρ), with
  // A = 2(c1 − c0), B = −2(c0 + c1), ρ = 1 + 4·c2 (to first order, a' = a + c0 + c1·cos 4a' + c2·sin 4a').
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  std::vector<float> error(model ? at.size() : 0, 0.0f);
  const auto update_error = [&]() {
    const double ca = std::cos(2 * (c(1) - c(0))), sa = std::sin(2 * (c(1) - c(0)));
    const double cb = std::cos(-2 * (c(0) + c(1))), sb = std::sin(-2 * (c(0) + c(1)));
    const double inv_rho = 1 / (1 + 4 * c(2));
    for (std::size_t m = 0; m < error.size(); ++m) {
      const double c2 = turn_at(m).cos2, s2 = turn_at(m).sin2;
      const double x = cb * c2 - sa * s2 * inv_rho, y = sb * c2 + ca * s2 * inv_rho;
      error[m] = static_cast<float>(-0.5 * std::atan2(c2 * y - s2 * x, c2 * x + s2 * y));
    }
  };
  // The E-vector as the sky has it: the sensor's error taken out (to first order in the error).
  const auto e_at = [&](std::size_t m) -> Eigen::Vector3d {
    const Eigen::Vector3d& e = ev.e[at[m]];
    return model ? Eigen::Vector3d(e - static_cast<double>(error[m]) * turn_at(m).turn.cast<double>()) : e;
  };
  std::vector<std::uint8_t> use(at.size(), 1);
  Eigen::Vector3d s;
  Eigen::Vector3d lambda;
  // s = the smallest eigenvector of Σ w·e·eᵀ over the corrected E-vectors, entry by entry as
  // Eigen's `cov += w * e * e.transpose()` adds ((w·e_i)·e_j to cov(i, j), in order), in locals:
  // Eigen kept the sum in memory, where each sum waited on the last.
  const auto smallest_direction = [&]() {
    double c00 = 0, c10 = 0, c20 = 0, c01 = 0, c11 = 0, c21 = 0, c02 = 0, c12 = 0, c22 = 0;
    int used = 0;
    for (std::size_t k = 0; k < at.size(); ++k)
      if (use[k]) {
        const Eigen::Vector3d e = e_at(k);
        const double w = w_at(k), we0 = w * e(0), we1 = w * e(1), we2 = w * e(2);
        c00 += we0 * e(0), c10 += we1 * e(0), c20 += we2 * e(0);
        c01 += we0 * e(1), c11 += we1 * e(1), c21 += we2 * e(1);
        c02 += we0 * e(2), c12 += we1 * e(2), c22 += we2 * e(2);
        ++used;
      }
    if (used < 10) return false;
    Eigen::Matrix3d cov;
    cov << c00, c01, c02, c10, c11, c12, c20, c21, c22;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    s = eig.eigenvectors().col(0).normalized();
    lambda = eig.eigenvalues();
    return true;
  };
  // One Gauss–Newton step on the sun's two tangent angles and c, minimising Σ w·(s·e(c))², with the
  // error's derivative in c taken to first order, (1, cos 4a', sin 4a'): at c = 0 it is exact, and
  // the steps converge on the exact model's c.
  const auto polarizer_step = [&]() {
    const Eigen::Vector3d u1 = s.unitOrthogonal(), u2 = s.cross(u1);
    double a[15] = {}, b[5] = {};  // JᵀWJ's lower triangle and JᵀWr, in locals (as above)
    for (std::size_t k = 0; k < at.size(); ++k)
      if (use[k]) {
        const FrameEVectors::Turn& rd = turn_at(k);
        const Eigen::Vector3d e = e_at(k);
        const double st = -s.dot(rd.turn.cast<double>());
        const double c2 = rd.cos2, s2 = rd.sin2;
        const double j[5] = {e.dot(u1), e.dot(u2), st, st * (c2 * c2 - s2 * s2), st * (2 * c2 * s2)};
        const double w = w_at(k), wr = w * s.dot(e);
        int n = 0;
        for (int p = 0; p < 5; ++p) {
          const double wj = w * j[p];
          for (int q = 0; q <= p; ++q) a[n++] += wj * j[q];
          b[p] += wr * j[p];
        }
      }
    Eigen::Matrix<double, 5, 5> jtj;
    Eigen::Matrix<double, 5, 1> jtr;
    int n = 0;
    for (int p = 0; p < 5; ++p) {
      for (int q = 0; q <= p; ++q) jtj(p, q) = jtj(q, p) = a[n++];
      jtr(p) = b[p];
    }
    const Eigen::Matrix<double, 5, 1> step = -jtj.ldlt().solve(jtr);
    if (!step.allFinite()) return;
    s = (s + step(0) * u1 + step(1) * u2).normalized();
    c += step.tail<3>();
    // A model beyond kMaxPolarizerErrorRad is a sky it does not describe, not a sensor's error.
    if (!c.allFinite() || c.cwiseAbs().maxCoeff() > kMaxPolarizerErrorRad) c.setZero();
    update_error();
  };
  // Fit, then refit without the E-vectors farther out of the plane ⟂ s than 3 robust σ (at least
  // kMinCutDeg): pixels whose AoLP no sun explains (cloud, glare, a neutral point) stop pulling.
  // Without the polarizer model each round's sun is the eigenvector. With it, the model starts at
  // c = 0 from the eigenvector and takes 3 steps, then one more per refit from where the last
  // ended; the sun is the eigenvector of the corrected E-vectors.
  constexpr double kMinCutDeg = 0.5;
  const int rounds = robust ? 3 : 1;
  if (!smallest_direction()) return std::nullopt;
  for (int round = 0; round < rounds; ++round) {
    if (model) {
      for (int it = 0; it < (round == 0 ? 3 : 1); ++it) polarizer_step();
      if (round == rounds - 1 && !smallest_direction()) return std::nullopt;
    } else if (round > 0 && !smallest_direction()) {
      return std::nullopt;
    }
    if (round == rounds - 1) break;
    std::vector<double> r(at.size());
    for (std::size_t k = 0; k < at.size(); ++k) r[k] = std::abs(e_at(k).dot(s));
    const double cut = std::max(std::sin(kMinCutDeg * kRadPerDeg), 3 * 1.4826 * nth_smallest(r, r.size() / 2));
    for (std::size_t k = 0; k < at.size(); ++k) use[k] = r[k] <= cut ? 1 : 0;
  }
  if ((sky.level_from_camera * s).z() < 0) s = -s;
  if (quality) *quality = lambda(1) > 0 ? lambda(0) / lambda(1) : 1.0;
  return s;
}

RayleighFits fit_rayleigh_law(SkyImages& sky, const stack::Stack& stack, bool sky_mask) {
  const StackSky whole(stack, {});
  return fit_rayleigh_law(sky, SkyView(whole), sky_mask);
}

RayleighFits fit_rayleigh_law(SkyImages& sky, const SkyView& view, bool sky_mask, bool misfit) {
  RayleighFits f;
  f.starts.resize(sky.frames());
  // The fits start at the suns the mask judged by, or else at the lowest DoLP of the unmasked sky:
  // a cloud over the sun would leave the masked sky without a sun-like minimum. (The minimum is
  // looked for only where the mask has no sun: it costs a disk filter of the frame.)
  SkyMask mask;
  if (sky_mask) mask = view.sky_mask(sky);
  std::vector<std::size_t> unjudged;
  for (std::size_t t = 0; t < sky.frames(); ++t)
    if (!sky_mask || !mask.suns[t]) unjudged.push_back(t);
  std::vector<std::vector<float>> filtered(unjudged.size());
  const double radius = default_filter_radius_px(sky.width, sky.height);
  tbb::parallel_for(std::size_t{0}, unjudged.size(),
                    [&](std::size_t k) { filtered[k] = disk_filter(sky.dolp[unjudged[k]], sky, radius); });
  const auto minima = find_suns(sky, filtered);
  for (std::size_t k = 0; k < unjudged.size(); ++k) f.starts[unjudged[k]] = minima[k];
  if (sky_mask) {
    apply_mask(sky, mask);
    for (std::size_t t = 0; t < f.starts.size(); ++t)
      if (mask.suns[t]) f.starts[t] = mask.suns[t];
  }
  f.suns.resize(sky.frames());
  f.rms.assign(sky.frames(), 1.0);
  f.misfit.assign(sky.frames(), 0.0);
  tbb::parallel_for(std::size_t{0}, sky.frames(), [&](std::size_t t) {
    if (!f.starts[t]) return;
    double pmax = 0;
    f.suns[t] = sun_from_dolp(sky, sky.dolp[t], *f.starts[t], &pmax, &f.rms[t], sky_mask);
    if (f.suns[t] && misfit) f.misfit[t] = rayleigh_misfit(sky, sky.dolp[t], *f.suns[t], pmax);
  });
  return f;
}

double rayleigh_law_misfit(const stack::Stack& stack, const InputOptions& input) {
  const StackSky whole(stack, input);
  return rayleigh_law_misfit(SkyView(whole));
}

double rayleigh_law_misfit(const SkyView& view) {
  SkyImages sky = view.prepared(1, "rayleigh_law_misfit");
  const RayleighFits f = fit_rayleigh_law(sky, view, view.input().sky_mask);
  std::vector<double> fitted;
  for (std::size_t t = 0; t < f.suns.size(); ++t)
    if (f.suns[t]) fitted.push_back(f.misfit[t]);
  return fitted.empty() ? 1.0 : quantile(fitted, 0.5);
}

FrameSuns find_aolp_suns(const SkyView& view, const InputOptions& input, double min_dolp, const char* method,
                         std::size_t min_frames) {
  FrameSuns found;
  found.sky = view.prepared(min_frames, method);
  SkyImages& sky = found.sky;
  // The frames' E-vectors, computed once for the whole stack (usable on this sky and its mask).
  found.e_vectors = view.e_vectors(sky);
  const std::vector<const FrameEVectors*>& e_vectors = found.e_vectors;
  if (input.sky_mask) apply_mask(sky, view.sky_mask(sky));
  // The AoLP channels are read where the fits are (StackSky, SkyView::aolp_suns); here a frame
  // without one is named.
  (void)aolp_channels(view.frames(), sky, method);
  std::vector<double> quality;
  const auto suns = view.aolp_suns(sky, e_vectors, min_dolp, input.sky_mask, &quality);
  for (std::size_t t = 0; t < sky.frames(); ++t) {
    if (!suns[t]) {
      found.why = "frame " + std::to_string(t) + " has too few polarized pixels (DoLP ≥ " +
                  std::to_string(min_dolp) + ") to find the sun from the AoLP";
      return found;
    }
    found.suns_camera.push_back(*suns[t]);
    found.quality.push_back(quality[t]);
  }
  return found;
}

SunVectorResult estimate_sun_vector(const stack::Stack& stack, const SunVectorParams& params) {
  const StackSky whole(stack, params.input);
  return estimate_sun_vector(SkyView(whole), params);
}

SunVectorResult estimate_sun_vector(const SkyView& view, const SunVectorParams& params) {
  const auto t_start = std::chrono::steady_clock::now();
  // The name a decline speaks in: the method the user ran (a stack it cannot use says so in its words).
  const char* method = params.source == SunSource::dolp          ? "sun_dolp"
                       : params.mode == PoleFromSun::ephemeris ? "sun_vector_ephemeris"
                                                               : "sun_vector";
  const std::size_t min_frames = params.mode == PoleFromSun::circle ? 3 : 1;
  const FrameRefs& frames = view.frames();
  SunVectorResult result;
  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  };
  const auto fail = [&](std::string why) {
    result.estimate = invalid_estimate(method, std::move(why));
    result.estimate.seconds = seconds();
    return result;
  };

  // Each frame's sun on its own (in parallel); the first failing frame is reported.
  SkyImages sky;
  RayleighFits fits;  // SunSource::dolp's suns (it masks the sky as it fits)
  std::vector<std::optional<Eigen::Vector3d>> suns;
  if (params.source == SunSource::aolp) {
    FrameSuns found = find_aolp_suns(view, params.input, params.min_dolp, method, min_frames);
    if (!found.why.empty()) return fail(std::move(found.why));
    sky = std::move(found.sky);
    result.suns_camera = std::move(found.suns_camera);
    result.sun_quality = std::move(found.quality);
    for (const auto& s : result.suns_camera) suns.emplace_back(s);
  } else {
    sky = view.prepared(min_frames, method);
    fits = fit_rayleigh_law(sky, view, params.input.sky_mask, params.model_misfit);
    suns = fits.suns;
    for (std::size_t t = 0; t < sky.frames(); ++t) {
      if (!suns[t]) {
        if (!fits.starts[t])
          return fail("frame " + std::to_string(t) + " shows no sun-like DoLP minimum above the "
                      "horizon to start the Rayleigh fit from");
        return fail("the Rayleigh fit of frame " + std::to_string(t) + " failed");
      }
      result.suns_camera.push_back(*suns[t]);
      result.sun_quality.push_back(fits.rms[t]);
    }
  }
  const std::vector<double>& misfit = fits.misfit;

  if (params.mode == PoleFromSun::ephemeris) {
    const sky::Site site = params.site.value_or(frames.front()->truth.site);
    double sx = 0, sy = 0, sq = 0;
    std::vector<Eigen::Vector3d> enu;
    for (std::size_t t = 0; t < sky.frames(); ++t) {
      enu.push_back(sky::sun_position(site, frames[t]->truth.time).direction);
      const Eigen::Vector3d l = sky.level_from_camera * result.suns_camera[t];
      const double d = std::atan2(enu[t].x(), enu[t].y()) - std::atan2(l.x(), l.y());
      sx += std::cos(d);
      sy += std::sin(d);
    }
    if (std::hypot(sx, sy) < 1e-9) return fail("the suns' azimuths give no heading");
    const double psi = std::atan2(sy, sx);  // world = Rz(−ψ)·level
    const Eigen::Matrix3d world_from_level =
        Eigen::AngleAxisd(-psi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // The elevation misfit: the heading takes only the suns' azimuths, so an error every frame's sun
    // shares along the azimuth (the colour sensor's demosaicked AoLP under cloud) moves the answer
    // while the residual about the mean heading stays small; the same kind of error along the
    // elevation, which no heading absorbs, shows its size. Across the sun at elevation e, a step d
    // turns its azimuth by d/cos e (capped at 90°: a sun at the zenith has no azimuth).
    double elevation_sq = 0;
    for (std::size_t t = 0; t < sky.frames(); ++t) {
      const Eigen::Vector3d w = world_from_level * sky.level_from_camera * result.suns_camera[t];
      const double a = std::atan2(w.cross(enu[t]).norm(), w.dot(enu[t]));
      sq += a * a;
      const double de = std::asin(std::clamp(w.z(), -1.0, 1.0)) - std::asin(std::clamp(enu[t].z(), -1.0, 1.0));
      const double turn = std::min(std::abs(de) / std::max(std::hypot(enu[t].x(), enu[t].y()), 1e-9), kPi / 2);
      elevation_sq += turn * turn;
    }
    const double lat = site.latitude_deg * kRadPerDeg;
    result.estimate = make_estimate(method, sky, ncp_camera_at(sky, psi, site.latitude_deg), params.input);
    result.estimate.note += (result.estimate.note.empty() ? "" : "; ") +
                            std::string("ephemeris mode: latitude is the given site's");
    result.estimate.residual_deg = std::sqrt(sq / static_cast<double>(sky.frames())) / kRadPerDeg;
    // A heading error h moves the pole by h·cos(its altitude) in the tangent plane.
    result.estimate.sun_elevation_misfit_deg =
        std::sqrt(elevation_sq / static_cast<double>(sky.frames())) * std::cos(lat) / kRadPerDeg;
    if (params.source == SunSource::dolp) result.estimate.model_misfit = quantile(misfit, 0.5);
    result.estimate.seconds = seconds();
    return result;
  }

  // Circle: s_t·p = a + b·τ_t.
  const double span_h = (sky.times_s.back() - sky.times_s.front()) / 3600.0;
  const bool linear = params.detrend == Detrend::linear ||
                      (params.detrend == Detrend::automatic && sky.times_known &&
                       span_h >= params.auto_detrend_min_hours && sky.frames() >= 5);
  const auto n = static_cast<Eigen::Index>(sky.frames());
  Eigen::MatrixXd x(n, linear ? 2 : 1), s(n, 3);
  for (Eigen::Index t = 0; t < n; ++t) {
    x(t, 0) = 1;
    if (linear) x(t, 1) = sky.times_s[static_cast<std::size_t>(t)] / std::max(1.0, sky.times_s.back());
    s.row(t) = result.suns_camera[static_cast<std::size_t>(t)].transpose();
  }
  const Eigen::MatrixXd xtx = x.transpose() * x;
  const Eigen::MatrixXd h = Eigen::MatrixXd::Identity(n, n) - x * xtx.ldlt().solve(x.transpose());
  const Eigen::Matrix3d c = s.transpose() * h * s;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(c);
  Eigen::Vector3d p = es.eigenvectors().col(0).normalized();
  if (!(es.eigenvalues()(1) > 1e-14))
    return fail("the suns do not span an arc: they are too few or too close together");
  if ((sky.level_from_camera * p).z() < 0) p = -p;
  const HemisphereDecision hemi = decide_hemisphere(suns, p, params.input.hemisphere,
                                                    sky.times_known ? sky.times_s : std::vector<double>{});
  if (!hemi.ok) return fail(hemi.why);
  result.estimate = make_estimate(method, sky, hemi.is_north ? p : Eigen::Vector3d(-p), params.input);
  result.estimate.note += (result.estimate.note.empty() ? "" : "; ") +
                          std::string("hemisphere from ") + hemi.source;
  const Eigen::VectorXd r = h * (s * p);
  result.estimate.residual_deg = std::sqrt(r.squaredNorm() / static_cast<double>(n)) / kRadPerDeg;
  if (params.source == SunSource::dolp) result.estimate.model_misfit = quantile(misfit, 0.5);
  result.estimate.seconds = seconds();
  return result;
}

}  // namespace skypol::skypole
