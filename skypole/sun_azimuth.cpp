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

#include "sky/sun.h"
#include "skypole/sky_images.h"
#include "skypole/sun_vector.h"

namespace skypol::skypole {
namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

double wrap_pi(double a) { return std::remainder(a, 2 * kPi); }

// What the fit needs of each frame: the measured level-frame azimuth and the cosine of the
// measured elevation (the residual's weight), and the sun's site-free equatorial place.
struct Sight {
  double azimuth = 0, weight = 0, elevation = 0;
  double sin_dec = 0, cos_dec = 0, gha = 0;
};

// The sun's ENU direction for an observer at (φ, λ) (radians).
Eigen::Vector3d sun_enu(const Sight& s, double lat, double lon) {
  const double h = s.gha + lon, sl = std::sin(lat), cl = std::cos(lat);
  return {-s.cos_dec * std::sin(h), s.sin_dec * cl - s.cos_dec * std::cos(h) * sl,
          s.sin_dec * sl + s.cos_dec * std::cos(h) * cl};
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
    const double e = std::asin(std::clamp(sun_enu(s, lat, lon).z(), -1.0, 1.0));
    sq += (e - s.elevation) * (e - s.elevation);
  }
  return std::sqrt(sq / static_cast<double>(sights.size()));
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
    s.elevation = std::asin(std::clamp(l.z(), -1.0, 1.0));
    s.weight = std::hypot(l.x(), l.y());
    const sky::Sun g = sky::sun_position(sky::Site{}, times[t]);
    s.sin_dec = std::sin(g.declination);
    s.cos_dec = std::cos(g.declination);
    s.gha = g.hour_angle;
    sights.push_back(s);
  }
  // The grid: cost at every (φ, λ) with ψ in closed form; its local minima are the starts.
  constexpr int kLat = 90, kLon = 180;  // 2° cells
  const auto lat_of = [](int i) { return (-89.0 + 2.0 * i) * kDeg; };
  const auto lon_of = [](int j) { return (-180.0 + 2.0 * j) * kDeg; };
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
  constexpr double kElevationGrossRad = 10 * kDeg;
  std::vector<Minimum> minima;
  for (const auto& [c, ij] : starts) {
    const double lat = lat_of(ij[0]), lon = lon_of(ij[1]);
    const Minimum m = refine(sights, Eigen::Vector3d(lat, lon, best_heading(sights, lat, lon)));
    if (!std::isfinite(m.cost) || elevation_rms(sights, m.x(0), m.x(1)) > kElevationGrossRad) continue;
    const bool seen = std::any_of(minima.begin(), minima.end(), [&](const Minimum& o) {
      return std::abs(o.x(0) - m.x(0)) < 0.5 * kDeg && std::abs(wrap_pi(o.x(1) - m.x(1))) < 0.5 * kDeg;
    });
    if (!seen) minima.push_back(m);
  }
  if (minima.empty()) {
    fix.why = "no site puts the sun where the images see it";
    return fix;
  }
  std::sort(minima.begin(), minima.end(), [](const Minimum& a, const Minimum& b) { return a.cost < b.cost; });
  const Minimum& best = minima.front();
  fix.latitude_deg = best.x(0) / kDeg;
  fix.longitude_deg = best.x(1) / kDeg;
  fix.heading_deg = best.x(2) / kDeg;
  fix.rms_rad = std::sqrt(best.cost / static_cast<double>(sights.size()));
  if (minima.size() > 1) fix.second_cost_ratio = minima[1].cost / std::max(best.cost, 1e-300);
  if (minima.size() > 1 && minima[1].cost <= (1 + ambiguity_margin) * best.cost) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "the suns' azimuths fit two sites about as well (latitude %.1f° or %.1f°): the window "
                  "does not decide",
                  fix.latitude_deg, minima[1].x(0) / kDeg);
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
  std::vector<Eigen::Vector3d> level;
  std::vector<sky::Instant> times;
  for (std::size_t t = 0; t < found.suns_camera.size(); ++t) {
    level.push_back(sky.level_from_camera * found.suns_camera[t]);
    times.push_back(view.frames()[t]->truth.time);
  }
  const AzimuthFix fix = fix_from_sun_azimuths(level, times, params.ambiguity_margin);
  if (!fix.ok) return fail(fix.why);
  const double psi = fix.heading_deg * kDeg, lat = fix.latitude_deg * kDeg;
  const Eigen::Matrix3d world_from_level = Eigen::AngleAxisd(-psi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d ncp_world(0, std::cos(lat), std::sin(lat));
  const Eigen::Vector3d ncp = sky.level_from_camera.transpose() * world_from_level.transpose() * ncp_world;
  PoleEstimate e = make_estimate(kMethod, sky, ncp, params.input);
  char buf[120];
  std::snprintf(buf, sizeof buf, "fitted longitude %.3f°", fix.longitude_deg);
  e.note += (e.note.empty() ? "" : "; ") + std::string(buf);
  e.residual_deg = fix.rms_rad / kDeg;
  e.seconds = seconds();
  return e;
}

}  // namespace skypol::skypole
