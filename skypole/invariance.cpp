// Minimum of DoLP's variance over time on the sphere (method in invariance.h).
#include "skypole/invariance.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace skypol::skypole {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

struct Cost {
  const SkyImages& sky;
  const std::vector<std::vector<float>>& images;
  Eigen::MatrixXd h;  // N×N residual projector

  // V(d), or nullopt where d does not image onto valid pixels.
  std::optional<double> operator()(const Eigen::Vector3d& d) const {
    const auto px = sky.lens->project(d);
    if (!px) return std::nullopt;
    Eigen::VectorXd v(static_cast<Eigen::Index>(images.size()));
    for (std::size_t t = 0; t < images.size(); ++t) {
      const auto s = sample_bilinear(images[t], sky, *px);
      if (!s) return std::nullopt;
      v(static_cast<Eigen::Index>(t)) = *s;
    }
    return (h * v).squaredNorm() / static_cast<double>(images.size());
  }
};

Eigen::MatrixXd residual_projector(const std::vector<double>& tau, bool linear) {
  const auto n = static_cast<Eigen::Index>(tau.size());
  Eigen::MatrixXd x(n, linear ? 2 : 1);
  for (Eigen::Index t = 0; t < n; ++t) {
    x(t, 0) = 1;
    if (linear) x(t, 1) = tau[static_cast<std::size_t>(t)];
  }
  const Eigen::MatrixXd xtx = x.transpose() * x;
  return Eigen::MatrixXd::Identity(n, n) - x * xtx.ldlt().solve(x.transpose());
}

// Tangent basis at c.
void basis(const Eigen::Vector3d& c, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
  e1 = c.unitOrthogonal();
  e2 = c.cross(e1);
}

// Angular size of one pixel at direction d (radians).
double pixel_angle(const SkyImages& sky, const Eigen::Vector3d& d) {
  const auto px = sky.lens->project(d);
  if (!px) return 1e-3;
  const auto a = sky.lens->ray(*px), b = sky.lens->ray(*px + Eigen::Vector2d(1, 0));
  const auto c = sky.lens->ray(*px - Eigen::Vector2d(1, 0));
  if (a && b) return std::atan2(a->cross(*b).norm(), a->dot(*b));
  if (a && c) return std::atan2(a->cross(*c).norm(), a->dot(*c));
  return 1e-3;
}

// The local model of each frame's DoLP in tangent-plane coordinates u: a full cubic. Near the
// equinox DoLP is stationary at the pole in space and time (the pole lies on every frame's
// maximum-DoLP circle), V grows only as |u|⁴, and a quadratic model's neglected cubic terms would
// move the minimum by a few tenths of a degree.
constexpr int kTerms = 10;
using Basis = Eigen::Matrix<double, kTerms, 1>;
using BasisJacobian = Eigen::Matrix<double, kTerms, 2>;

Basis phi_of(const Eigen::Vector2d& u) {
  const double x = u(0), y = u(1);
  Basis p;
  p << 1, x, y, x * x, x * y, y * y, x * x * x, x * x * y, x * y * y, y * y * y;
  return p;
}

BasisJacobian jac_of(const Eigen::Vector2d& u) {
  const double x = u(0), y = u(1);
  BasisJacobian j;
  j << 0, 0, 1, 0, 0, 1, 2 * x, 0, y, x, 0, 2 * y, 3 * x * x, 0, 2 * x * y, x * x, y * y, 2 * x * y,
      0, 3 * y * y;
  return j;
}

struct SubPixel {
  bool ok = false;
  std::string why;
  Eigen::Vector3d d;
  double v = 0;
  double sigma_rad = 0;
};

// Step 4 of invariance.h around c.
SubPixel quadratic_refine(const SkyImages& sky, const Eigen::MatrixXd& h, Eigen::Vector3d c,
                          double radius_px) {
  SubPixel out;
  const std::size_t nf = sky.frames();
  const auto nfi = static_cast<Eigen::Index>(nf);
  for (int recentre = 0; recentre < 4; ++recentre) {
    const auto cpx = sky.lens->project(c);
    if (!cpx) {
      out.why = "the minimum lies outside what the lens images (pole outside the field of view)";
      return out;
    }
    Eigen::Vector3d e1, e2;
    basis(c, e1, e2);
    const int r = static_cast<int>(std::ceil(radius_px));
    const int x0 = static_cast<int>(std::lround(cpx->x())), y0 = static_cast<int>(std::lround(cpx->y()));
    std::vector<Basis> rows;
    std::vector<std::size_t> idx;
    bool complete = true;
    double umax = 0;
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        if (dx * dx + dy * dy > radius_px * radius_px) continue;
        const int x = x0 + dx, y = y0 + dy;
        if (x < 0 || y < 0 || x >= sky.width || y >= sky.height) {
          complete = false;
          continue;
        }
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(sky.width) +
                              static_cast<std::size_t>(x);
        if (!sky.valid[i]) {
          complete = false;
          continue;
        }
        const Eigen::Vector3d d = to_double(sky.ray_camera[i]);
        const double u1 = d.dot(e1) / d.dot(c), u2 = d.dot(e2) / d.dot(c);
        rows.push_back(phi_of(Eigen::Vector2d(u1, u2)));
        idx.push_back(i);
        umax = std::max(umax, std::hypot(u1, u2));
      }
    if (!complete) {
      out.why = "the minimum of DoLP variance is at the edge of the usable image (image circle, "
                "mask or horizon): the pole is probably outside the field of view";
      return out;
    }
    const auto m = static_cast<Eigen::Index>(rows.size());
    if (m < 2 * kTerms) {
      out.why = "too few pixels around the minimum for the sub-pixel fit";
      return out;
    }
    Eigen::MatrixXd a(m, kTerms), y(m, nfi);
    for (Eigen::Index k = 0; k < m; ++k) {
      a.row(k) = rows[static_cast<std::size_t>(k)].transpose();
      for (std::size_t t = 0; t < nf; ++t)
        y(k, static_cast<Eigen::Index>(t)) = sky.dolp[t][idx[static_cast<std::size_t>(k)]];
    }
    // Θ (terms×N): each frame's cubic; then R(u) = H Θᵀ φ(u).
    const Eigen::MatrixXd theta = a.colPivHouseholderQr().solve(y);
    const Eigen::MatrixXd g = h * theta.transpose();  // N×terms
    const auto cost_at = [&](const Eigen::Vector2d& uu) {
      const Basis p = phi_of(uu);
      const Eigen::VectorXd res = g * p;
      return res.squaredNorm();
    };
    // V of the local model is a polynomial with a very flat bottom near the equinox: start the
    // Levenberg–Marquardt iterations from the best node of a grid over the window.
    Eigen::Vector2d u = Eigen::Vector2d::Zero();
    double f = cost_at(u);
    constexpr int kGrid = 60;
    for (int j = -kGrid; j <= kGrid; ++j)
      for (int i = -kGrid; i <= kGrid; ++i) {
        const Eigen::Vector2d uu(umax * i / kGrid, umax * j / kGrid);
        if (uu.norm() > umax) continue;
        const double fu = cost_at(uu);
        if (fu < f) {
          f = fu;
          u = uu;
        }
      }
    double lambda = 1e-3;
    for (int it = 0; it < 200; ++it) {
      const Basis p = phi_of(u);
      const BasisJacobian dp = jac_of(u);
      const Eigen::VectorXd res = g * p;
      const Eigen::MatrixXd jac = g * dp;
      const Eigen::Matrix2d jtj = jac.transpose() * jac;
      const Eigen::Vector2d grad = jac.transpose() * res;
      Eigen::Matrix2d damped = jtj;
      damped.diagonal() *= 1 + lambda;
      damped.diagonal().array() += 1e-30;
      const Eigen::Vector2d step = -damped.ldlt().solve(grad);
      const Eigen::Vector2d un = u + step;
      const double fn = cost_at(un);
      if (fn < f) {
        u = un;
        f = fn;
        lambda = std::max(lambda * 0.3, 1e-12);
        if (step.norm() < 1e-12) break;
      } else {
        lambda *= 10;
        if (lambda > 1e12) break;
      }
    }
    const Eigen::Vector3d d = (c + u(0) * e1 + u(1) * e2).normalized();
    if (u.norm() > 0.5 * umax) {  // left the well-fitted part of the window: re-centre there
      c = d;
      continue;
    }
    out.ok = true;
    out.d = d;
    out.v = f / static_cast<double>(nf);
    const BasisJacobian dp = jac_of(u);
    const Eigen::MatrixXd jac = g * dp;
    const Eigen::Matrix2d jtj = jac.transpose() * jac;
    const double dof = std::max(1.0, static_cast<double>(nf) - 2.0);
    const double s2 = f / dof;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(jtj);
    const double lmin = es.eigenvalues()(0);
    out.sigma_rad = lmin > 0 ? std::sqrt(s2 / lmin) : kPi;
    return out;
  }
  out.why = "the sub-pixel fit did not settle (no clear minimum of DoLP variance)";
  return out;
}

}  // namespace

Detrend parse_detrend(std::string_view name) {
  if (name == "none") return Detrend::none;
  if (name == "linear") return Detrend::linear;
  if (name == "automatic" || name == "auto") return Detrend::automatic;
  throw std::invalid_argument("unknown detrend \"" + std::string(name) +
                              "\" (expected one of none, linear, automatic)");
}

std::string_view detrend_name(Detrend d) {
  switch (d) {
    case Detrend::none: return "none";
    case Detrend::linear: return "linear";
    case Detrend::automatic: return "automatic";
  }
  return "?";
}

InvarianceResult estimate_invariance(const render::Stack& stack, const InvarianceParams& params) {
  const auto t_start = std::chrono::steady_clock::now();
  const char* method = "invariance";
  if (!(params.coarse_step_deg > 0.05 && params.coarse_step_deg <= 20))
    throw std::invalid_argument("invariance: coarse_step_deg must be in (0.05, 20], got " +
                                std::to_string(params.coarse_step_deg));
  const SkyImages sky = prepare_sky_images(stack, params.input, 3, method);
  const double radius =
      params.filter_radius_px.value_or(default_filter_radius_px(sky.width, sky.height));
  const double fit_radius = params.fit_radius_px.value_or(
      std::max(3.0, 0.01 * std::min(sky.width, sky.height)));
  const std::vector<std::vector<float>> filtered = filter_all(sky, radius);

  InvarianceResult result;
  const double span_h = (sky.times_s.back() - sky.times_s.front()) / 3600.0;
  result.detrended = params.detrend == Detrend::linear ||
                     (params.detrend == Detrend::automatic && sky.times_known &&
                      span_h >= params.auto_detrend_min_hours && sky.frames() >= 5);
  std::vector<double> tau;
  for (std::size_t t = 0; t < sky.frames(); ++t)
    tau.push_back(sky.times_known ? sky.times_s[t] / std::max(1.0, sky.times_s.back())
                                  : static_cast<double>(t));
  const Cost cost{sky, filtered, residual_projector(tau, result.detrended)};

  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  };
  const auto fail = [&](std::string why) {
    result.estimate = invalid_estimate(method, std::move(why));
    result.estimate.seconds = seconds();
    return result;
  };

  // Coarse: Fibonacci lattice of the sky (level frame) above min_elevation.
  const double step = params.coarse_step_deg * kDeg;
  const int m = static_cast<int>(std::ceil(4 * kPi / (step * step)));
  const double golden = kPi * (3 - std::sqrt(5.0));
  const double min_z = std::sin(params.input.min_elevation_deg * kDeg);
  const Eigen::Matrix3d camera_from_level = sky.level_from_camera.transpose();
  std::vector<std::pair<double, Eigen::Vector3d>> coarse;
  for (int k = 0; k < m; ++k) {
    const double z = 1 - 2 * (k + 0.5) / m;
    if (z < min_z) continue;
    const double rr = std::sqrt(std::max(0.0, 1 - z * z)), ph = k * golden;
    const Eigen::Vector3d d = camera_from_level * Eigen::Vector3d(rr * std::cos(ph), rr * std::sin(ph), z);
    if (const auto v = cost(d)) coarse.emplace_back(*v, d);
  }
  if (coarse.size() < 3) return fail("too little of the sky is visible for the coarse search");
  std::sort(coarse.begin(), coarse.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const double v_median = coarse[coarse.size() / 2].first;
  std::vector<Eigen::Vector3d> starts;
  for (const auto& [v, d] : coarse) {
    bool far = true;
    for (const auto& s : starts) far = far && std::acos(std::clamp(s.dot(d), -1.0, 1.0)) > 4 * step;
    if (far) starts.push_back(d);
    if (static_cast<int>(starts.size()) >= std::max(1, params.candidates)) break;
  }

  // Fine: pattern search in the tangent plane.
  double best_v = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_d = starts.front();
  for (Eigen::Vector3d c : starts) {
    double s = step;
    double vc = cost(c).value_or(std::numeric_limits<double>::infinity());
    const double stop = 0.25 * pixel_angle(sky, c);
    for (int it = 0; it < 200 && s > stop; ++it) {
      Eigen::Vector3d e1, e2;
      basis(c, e1, e2);
      Eigen::Vector3d nb = c;
      double vb = vc;
      for (int j = -2; j <= 2; ++j)
        for (int i = -2; i <= 2; ++i) {
          if (i == 0 && j == 0) continue;
          const Eigen::Vector3d d = (c + s * (i * e1 + j * e2)).normalized();
          if ((sky.level_from_camera * d).z() < min_z) continue;
          const auto v = cost(d);
          if (v && *v < vb) {
            vb = *v;
            nb = d;
          }
        }
      if (vb < vc) {
        c = nb;
        vc = vb;
      } else {
        s *= 0.5;
      }
    }
    if (vc < best_v) {
      best_v = vc;
      best_d = c;
    }
  }

  const SubPixel sp = quadratic_refine(sky, cost.h, best_d, fit_radius);
  if (!sp.ok) return fail(sp.why);

  // Which end: the minimum is above the horizon; the sun's rotation says if it is the NCP.
  const HemisphereDecision hemi =
      decide_hemisphere(find_suns(sky, filtered), sp.d, params.input.hemisphere);
  if (!hemi.ok) return fail(hemi.why);
  result.estimate = make_estimate(method, sky, hemi.is_north ? sp.d : Eigen::Vector3d(-sp.d), params.input);
  result.estimate.note += (result.estimate.note.empty() ? "" : "; ") +
                          std::string("hemisphere from ") + hemi.source;
  result.dolp_rms_at_pole = std::sqrt(sp.v);
  result.estimate.residual_deg = sp.sigma_rad / kDeg;
  result.estimate.confidence =
      v_median > 0 ? std::clamp(1 - std::sqrt(std::max(0.0, sp.v) / v_median), 0.0, 1.0) : 0.0;
  result.estimate.seconds = seconds();
  return result;
}

}  // namespace skypol::skypole
