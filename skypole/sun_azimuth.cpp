// The sun's azimuths and the clock: a celestial fix (sun_azimuth.h).
#include "skypole/sun_azimuth.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "camera/camera.h"
#include "camera/lens.h"
#include "sky/sun.h"
#include "sky/units.h"
#include "skypole/sky_images.h"
#include "skypole/sun_vector.h"

namespace skypol::skypole {
namespace {

double wrap_pi(double a) { return std::remainder(a, 2 * kPi); }

// What the fit needs of each frame: the measured level-frame azimuth and the cosine of the
// measured elevation (the residual's weight), and the sun's geocentric direction in the Earth-fixed
// equatorial frame (x towards latitude 0, longitude 0; z north).
struct Sight {
  double azimuth = 0, weight = 0, elevation = 0;
  Eigen::Vector3d geocentric = Eigen::Vector3d::UnitX();
};

// The Earth's equatorial radius over the astronomical unit: the sun's horizontal parallax (8.79″).
constexpr double kParallax = 6378.137 / 149597870.7;

// The sun's ENU direction for an observer at (φ, λ) (radians), parallax included: the geocentric
// direction less the observer's offset from the Earth's centre, in solar distances.
Eigen::Vector3d sun_enu(const Sight& s, double lat, double lon) {
  const double sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  const Eigen::Vector3d up(cl * co, cl * so, sl), east(-so, co, 0), north(-sl * co, -sl * so, cl);
  const Eigen::Vector3d w = s.geocentric - kParallax * up;
  return Eigen::Vector3d(w.dot(east), w.dot(north), w.dot(up)).normalized();
}

// The sun's geocentric direction at t (Earth-fixed equatorial frame): ERFA's topocentric places
// seen from two antipodal points of the equator, whose parallaxes (and diurnal aberrations) cancel
// in their mean to second order (10⁻⁹ rad).
Eigen::Vector3d geocentric_sun(sky::Instant t) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const double lon_deg : {0.0, 180.0}) {
    const sky::Sun g = sky::sun_position(sky::Site{0, lon_deg, 0}, t);
    const double gha = g.hour_angle - lon_deg * kRadPerDeg;  // the hour angle at Greenwich
    sum += Eigen::Vector3d(std::cos(g.declination) * std::cos(gha), -std::cos(g.declination) * std::sin(gha),
                           std::sin(g.declination));
  }
  return sum.normalized();
}

// The heading that best aligns predicted and measured azimuths at (φ, λ): the weighted circular
// mean of A_t − a_t.
double best_heading(const std::vector<Sight>& sights, double lat, double lon) {
  double sx = 0, sy = 0;
  for (const Sight& s : sights) {
    const Eigen::Vector3d d = sun_enu(s, lat, lon);
    const double w = s.weight * s.weight, da = std::atan2(d.x(), d.y()) - s.azimuth;
    sx += w * std::cos(da);
    sy += w * std::sin(da);
  }
  return std::atan2(sy, sx);
}

// Residuals at x = (φ, λ, ψ): cos e_t · wrap(a_t − (A_t − ψ)).
Eigen::VectorXd residuals(const std::vector<Sight>& sights, const Eigen::Vector3d& x) {
  Eigen::VectorXd r(static_cast<Eigen::Index>(sights.size()));
  for (std::size_t t = 0; t < sights.size(); ++t) {
    const Eigen::Vector3d d = sun_enu(sights[t], x(0), x(1));
    r(static_cast<Eigen::Index>(t)) = sights[t].weight * wrap_pi(sights[t].azimuth - (std::atan2(d.x(), d.y()) - x(2)));
  }
  return r;
}

// RMS difference of measured and predicted elevations (radians): a gross check only (multiple
// scattering moves the measured suns' elevations by a degree or two, never by ten).
double elevation_rms(const std::vector<Sight>& sights, double lat, double lon) {
  double sq = 0;
  for (const Sight& s : sights) {
    const double e = sky::elevation_of(sun_enu(s, lat, lon));
    sq += (e - s.elevation) * (e - s.elevation);
  }
  return std::sqrt(sq / static_cast<double>(sights.size()));
}

// The north celestial pole in the level frame for x = (φ, λ, ψ): at altitude φ, level azimuth −ψ.
Eigen::Vector3d level_pole(const Eigen::Vector3d& x) {
  return {-std::sin(x(2)) * std::cos(x(0)), std::cos(x(2)) * std::cos(x(0)), std::sin(x(0))};
}

struct Minimum {
  Eigen::Vector3d x;
  double cost = 0;
};

// Levenberg–Marquardt from x (numerical Jacobian; three unknowns, a few dozen residuals).
Minimum refine(const std::vector<Sight>& sights, Eigen::Vector3d x) {
  Eigen::VectorXd r = residuals(sights, x);
  double cost = r.squaredNorm(), mu = 1e-3;
  for (int it = 0; it < 100; ++it) {
    Eigen::MatrixXd j(r.size(), 3);
    for (int k = 0; k < 3; ++k) {
      constexpr double h = 1e-7;
      Eigen::Vector3d xp = x, xm = x;
      xp(k) += h;
      xm(k) -= h;
      Eigen::VectorXd d = residuals(sights, xp) - residuals(sights, xm);
      for (Eigen::Index i = 0; i < d.size(); ++i) d(i) = wrap_pi(d(i));
      j.col(k) = d / (2 * h);
    }
    const Eigen::Matrix3d jtj = j.transpose() * j;
    const Eigen::Vector3d g = j.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 20 && !improved; ++tries) {
      Eigen::Matrix3d a = jtj;
      a.diagonal() += mu * jtj.diagonal().cwiseMax(1e-12);
      const Eigen::Vector3d step = -a.ldlt().solve(g);
      if (!step.allFinite()) break;
      Eigen::Vector3d xn = x + step;
      xn(0) = std::clamp(xn(0), -kPi / 2, kPi / 2);
      const Eigen::VectorXd rn = residuals(sights, xn);
      const double cn = rn.squaredNorm();
      if (cn < cost) {
        const double gain = cost - cn;
        x = xn;
        r = rn;
        cost = cn;
        mu = std::max(mu / 3, 1e-12);
        improved = true;
        if (gain <= 1e-15 * std::max(cost, 1e-30) || step.norm() < 1e-13) it = 100;
      } else {
        mu *= 4;
      }
    }
    if (!improved) break;
  }
  x(1) = wrap_pi(x(1));
  x(2) = wrap_pi(x(2));
  return {x, cost};
}

// The sun of one frame refitted on the pixels whose mirror image about the sun's vertical plane is
// usable too (sun_azimuth.h: a symmetric sample of a symmetric field keeps the fitted sun in the
// plane; a tilted camera, a cloud or clipping on one side would otherwise pull it off). Twice, each
// time about the last sun's vertical. nullopt when too few pixels have a usable mirror.
std::optional<Eigen::Vector3d> symmetric_sun(const SkyImages& sky, const std::vector<float>& dolp,
                                             const FrameEVectors& ev, double min_dolp, bool robust,
                                             Eigen::Vector3d sun) {
  const std::size_t n = sky.pixels();
  std::vector<std::uint8_t> usable(n, 0);
  constexpr std::uint8_t kRead = FrameEVectors::kDefined | FrameEVectors::kFiniteAolp;
  std::size_t count = 0;
  for (std::size_t k = 0; k < ev.pixel.size(); ++k) {
    const std::size_t i = ev.pixel[k];
    if (sky.valid[i] && (ev.flags[k] & kRead) == kRead && static_cast<double>(dolp[i]) >= min_dolp) {
      usable[i] = 1;
      ++count;
    }
  }
  // At most ~60k pixels are mirrored (a regular stride, as sun_from_dolp thins its pixels): each
  // costs a lens projection, and the fit's noise is already far below the sky's own departures.
  const int stride = std::max(1, static_cast<int>(std::floor(std::sqrt(static_cast<double>(count) / 60000.0))));
  SkyImages half;  // what sun_from_aolp reads of a sky: the pixels it may use and the level frame
  half.width = sky.width;
  half.height = sky.height;
  half.level_from_camera = sky.level_from_camera;
  const Eigen::Matrix3d camera_from_level = sky.level_from_camera.transpose();
  for (int round = 0; round < 2; ++round) {
    const Eigen::Vector3d l = sky.level_from_camera * sun;
    const double h = std::hypot(l.x(), l.y());
    if (h < 1e-6) return sun;  // a sun at the zenith: every vertical is its mirror plane
    const Eigen::Vector3d normal(-l.y() / h, l.x() / h, 0);
    half.valid.assign(n, 0);
    int kept = 0;
    for (int y = 0; y < sky.height; y += stride)
      for (int x = 0; x < sky.width; x += stride) {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(sky.width) + static_cast<std::size_t>(x);
        if (!usable[i]) continue;
        const Eigen::Vector3d d = sky.level_from_camera * to_double(sky.ray_camera[i]);
        const Eigen::Vector3d mirrored = camera_from_level * (d - 2 * d.dot(normal) * normal);
        const auto px = sky.lens->project(mirrored);
        if (!px) continue;
        const long mx = std::lround(px->x()), my = std::lround(px->y());
        if (mx < 0 || my < 0 || mx >= sky.width || my >= sky.height) continue;
        if (!usable[static_cast<std::size_t>(my) * static_cast<std::size_t>(sky.width) + static_cast<std::size_t>(mx)]) continue;
        half.valid[i] = 1;
        ++kept;
      }
    if (kept < 50) return std::nullopt;
    half.valid_count = kept;
    const auto refit = sun_from_aolp(half, dolp, ev, min_dolp, nullptr, robust);
    if (!refit) return std::nullopt;
    sun = *refit;
  }
  return sun;
}

}  // namespace

AzimuthFix fix_from_sun_azimuths(const std::vector<Eigen::Vector3d>& suns_level,
                                 const std::vector<sky::Instant>& times, double ambiguity_margin) {
  AzimuthFix fix;
  if (suns_level.size() != times.size() || suns_level.size() < 3) {
    fix.why = "fewer than 3 suns";
    return fix;
  }
  std::vector<Sight> sights;
  for (std::size_t t = 0; t < suns_level.size(); ++t) {
    const Eigen::Vector3d& l = suns_level[t];
    Sight s;
    s.azimuth = std::atan2(l.x(), l.y());
    s.elevation = sky::elevation_of(l);
    s.weight = std::hypot(l.x(), l.y());
    s.geocentric = geocentric_sun(times[t]);
    sights.push_back(s);
  }
  // The grid: cost at every (φ, λ) with ψ in closed form; its local minima are the starts.
  constexpr int kLat = 90, kLon = 180;  // 2° cells
  const auto lat_of = [](int i) { return (-89.0 + 2.0 * i) * kRadPerDeg; };
  const auto lon_of = [](int j) { return (-180.0 + 2.0 * j) * kRadPerDeg; };
  std::vector<double> grid(static_cast<std::size_t>(kLat * kLon));
  for (int i = 0; i < kLat; ++i)
    for (int j = 0; j < kLon; ++j) {
      const double lat = lat_of(i), lon = lon_of(j);
      const Eigen::Vector3d x(lat, lon, best_heading(sights, lat, lon));
      grid[static_cast<std::size_t>(i * kLon + j)] = residuals(sights, x).squaredNorm();
    }
  std::vector<std::pair<double, std::array<int, 2>>> starts;
  for (int i = 0; i < kLat; ++i)
    for (int j = 0; j < kLon; ++j) {
      const double c = grid[static_cast<std::size_t>(i * kLon + j)];
      bool lowest = true;
      for (int di = -1; di <= 1 && lowest; ++di)
        for (int dj = -1; dj <= 1 && lowest; ++dj) {
          const int ii = i + di, jj = (j + dj + kLon) % kLon;
          if ((di || dj) && ii >= 0 && ii < kLat && grid[static_cast<std::size_t>(ii * kLon + jj)] < c) lowest = false;
        }
      if (lowest) starts.push_back({c, {i, j}});
    }
  std::sort(starts.begin(), starts.end());
  if (starts.size() > 8) starts.resize(8);
  // Refine each start; keep the distinct minima whose suns are where the images put them within the
  // gross elevation check.
  constexpr double kElevationGrossRad = 10 * kRadPerDeg;
  std::vector<Minimum> minima;
  for (const auto& [c, ij] : starts) {
    const double lat = lat_of(ij[0]), lon = lon_of(ij[1]);
    const Minimum m = refine(sights, Eigen::Vector3d(lat, lon, best_heading(sights, lat, lon)));
    if (!std::isfinite(m.cost) || elevation_rms(sights, m.x(0), m.x(1)) > kElevationGrossRad) continue;
    // Two minima are one answer when they put the pole (what a user asks for) at the same place:
    // at a geographic pole every longitude does, with its own heading.
    const bool seen = std::any_of(minima.begin(), minima.end(), [&](const Minimum& o) {
      return level_pole(o.x).dot(level_pole(m.x)) > std::cos(0.5 * kRadPerDeg);
    });
    if (!seen) minima.push_back(m);
  }
  if (minima.empty()) {
    fix.why = "no site puts the sun where the images see it";
    return fix;
  }
  std::sort(minima.begin(), minima.end(), [](const Minimum& a, const Minimum& b) { return a.cost < b.cost; });
  const Minimum& best = minima.front();
  fix.latitude_deg = std::clamp(best.x(0) / kRadPerDeg, -90.0, 90.0);  // the fit clamps φ to ±π/2; its degrees may round past 90
  fix.longitude_deg = best.x(1) / kRadPerDeg;
  fix.heading_deg = best.x(2) / kRadPerDeg;
  fix.rms_rad = std::sqrt(best.cost / static_cast<double>(sights.size()));
  fix.elevation_rms_deg = elevation_rms(sights, best.x(0), best.x(1)) / kRadPerDeg;
  if (minima.size() > 1 && minima[1].cost <= (1 + ambiguity_margin) * best.cost) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "the suns' azimuths fit two sites about as well (latitude %.1f° or %.1f°): the window "
                  "does not decide",
                  fix.latitude_deg, minima[1].x(0) / kRadPerDeg);
    fix.why = buf;
    return fix;
  }
  fix.ok = true;
  return fix;
}

PoleEstimate estimate_sun_azimuth(const stack::Stack& stack, const SunAzimuthParams& params) {
  const StackSky whole(stack, params.input);
  return estimate_sun_azimuth(SkyView(whole), params);
}

PoleEstimate estimate_sun_azimuth(const SkyView& view, const SunAzimuthParams& params) {
  const auto t_start = std::chrono::steady_clock::now();
  constexpr const char* kMethod = "sun_azimuth";
  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  };
  const auto fail = [&](std::string why) {
    PoleEstimate e = invalid_estimate(kMethod, std::move(why));
    e.seconds = seconds();
    return e;
  };
  FrameSuns found = find_aolp_suns(view, params.input, params.min_dolp, kMethod, 3);
  if (!found.why.empty()) return fail(found.why);
  const SkyImages& sky = found.sky;
  if (!sky.times_known) return fail("the frames carry no distinct times: the fix needs the clock");
  // Each frame's sun again on its symmetric sample (in parallel).
  const std::size_t frames = found.suns_camera.size();
  std::vector<std::optional<Eigen::Vector3d>> suns(frames);
  const std::vector<const std::vector<float>*> aolp = aolp_channels(view.frames(), sky, kMethod);
  tbb::parallel_for(std::size_t{0}, frames, [&](std::size_t t) {
    // A view whose sky has pixels the whole stack's lacks has no cached E-vectors: made here.
    std::optional<FrameEVectors> own;
    if (!found.e_vectors[t])
      own = frame_e_vectors(sky, sky.dolp[t], *aolp[t], view.stack().camera->transport(), params.min_dolp,
                            polarizer_fit(*view.frames()[t], params.input.polarizer_model));
    const FrameEVectors& ev = own ? *own : *found.e_vectors[t];
    suns[t] = symmetric_sun(sky, sky.dolp[t], ev, params.min_dolp, params.input.sky_mask, found.suns_camera[t]);
  });
  std::vector<Eigen::Vector3d> level;
  std::vector<sky::Instant> times;
  for (std::size_t t = 0; t < frames; ++t) {
    if (!suns[t])
      return fail("frame " + std::to_string(t) + " has too few polarized pixels whose mirror image about the "
                  "sun's vertical is sky too");
    level.push_back(sky.level_from_camera * *suns[t]);
    times.push_back(view.frames()[t]->truth.time);
  }
  const AzimuthFix fix = fix_from_sun_azimuths(level, times, params.ambiguity_margin);
  if (!fix.ok) return fail(fix.why);
  PoleEstimate e = make_estimate(kMethod, sky, ncp_camera_at(sky, fix.heading_deg * kRadPerDeg, fix.latitude_deg), params.input);
  char buf[120];
  std::snprintf(buf, sizeof buf, "fitted longitude %.3f°; suns' elevations %.3f° rms from the fit's", fix.longitude_deg,
                fix.elevation_rms_deg);
  e.note += (e.note.empty() ? "" : "; ") + std::string(buf);
  e.residual_deg = fix.rms_rad / kRadPerDeg;
  e.seconds = seconds();
  return e;
}

}  // namespace skypol::skypole
