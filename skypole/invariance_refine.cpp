// Sub-pixel refinements of the invariance estimator (invariance_refine.h).
#include "skypole/invariance_refine.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include <Eigen/Geometry>

#include "sky/units.h"

namespace skypol::skypole {
namespace {

// A bivariate polynomial of total degree `degree`, in coordinates normalised to the window
// (|w| ≤ 1) for conditioning. Near the equinox DoLP is stationary at the pole in space and time
// (the pole lies on every frame's maximum-DoLP circle) and the variance grows only as |u|⁴: a
// quadratic would leave cubic terms that move the minimum by tenths of a degree.
constexpr int kMaxDegree = 8;
struct Poly {
  int degree;  // 1 … kMaxDegree
  int terms() const { return (degree + 1) * (degree + 2) / 2; }
  void phi(const Eigen::Vector2d& w, Eigen::Ref<Eigen::VectorXd> p) const {
    std::array<double, kMaxDegree + 1> xp, yp;
    xp[0] = yp[0] = 1;
    for (int i = 1; i <= degree; ++i) {
      xp[static_cast<std::size_t>(i)] = xp[static_cast<std::size_t>(i - 1)] * w(0);
      yp[static_cast<std::size_t>(i)] = yp[static_cast<std::size_t>(i - 1)] * w(1);
    }
    int k = 0;
    for (int n = 0; n <= degree; ++n)
      for (int j = 0; j <= n; ++j) p(k++) = xp[static_cast<std::size_t>(n - j)] * yp[static_cast<std::size_t>(j)];
  }
  Eigen::VectorXd phi(const Eigen::Vector2d& w) const {
    Eigen::VectorXd p(terms());
    phi(w, p);
    return p;
  }
  Eigen::MatrixXd jacobian(const Eigen::Vector2d& w) const {
    Eigen::MatrixXd jm = Eigen::MatrixXd::Zero(terms(), 2);
    int k = 0;
    for (int n = 0; n <= degree; ++n)
      for (int j = 0; j <= n; ++j, ++k) {
        const int i = n - j;
        if (i > 0) jm(k, 0) = i * std::pow(w(0), i - 1) * std::pow(w(1), j);
        if (j > 0) jm(k, 1) = j * std::pow(w(0), i) * std::pow(w(1), j - 1);
      }
    return jm;
  }
};

std::size_t index_of(const SkyImages& sky, int x, int y) {
  return static_cast<std::size_t>(y) * static_cast<std::size_t>(sky.width) + static_cast<std::size_t>(x);
}

// The minimum too near unusable pixels for its window, by what the nearest one is (why_unusable):
// near masked sky the pole may be behind the mask, near the edge of the field of view beyond it;
// either way a minimum that a short or noisy window left shallow wanders to an edge too (in the
// calibration study about half of these declines have the pole well inside the field), so both
// causes are named and neither is claimed.
std::string at_edge(Unusable nearest) {
  return "the minimum of DoLP variance is at " + std::string(unusable_words(nearest)) + ": " +
         std::string(pole_beyond_words(nearest)) + ", or the window is too short or noisy to place it";
}
constexpr const char* kOutside =
    "the minimum lies outside what the lens images (pole outside the field of view)";

// 1-σ of a least-squares minimum: residual variance s2 over the smallest curvature of the
// residual sum (whose Hessian is 2 JᵀJ).
double sigma_from_curvature(const Eigen::Matrix2d& hessian_of_sum, double s2) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(hessian_of_sum);
  const double lmin = es.eigenvalues()(0);
  return lmin > 0 ? std::sqrt(2 * s2 / lmin) : kPi;
}

}  // namespace

void tangent_basis(const Eigen::Vector3d& c, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
  e1 = c.unitOrthogonal();
  e2 = c.cross(e1);
}

double pixel_angle(const SkyImages& sky, const Eigen::Vector3d& d) {
  const auto px = sky.lens->project(d);
  if (!px) return 1e-3;
  const auto a = sky.lens->ray(*px), b = sky.lens->ray(*px + Eigen::Vector2d(1, 0));
  const auto c = sky.lens->ray(*px - Eigen::Vector2d(1, 0));
  if (a && b) return std::atan2(a->cross(*b).norm(), a->dot(*b));
  if (a && c) return std::atan2(a->cross(*c).norm(), a->dot(*c));
  return 1e-3;
}

SubPixel per_frame_refine(const SkyImages& sky, const Eigen::MatrixXd& h, Eigen::Vector3d c,
                          double radius_px, int degree) {
  SubPixel out;
  const Poly poly{degree};
  const std::size_t nf = sky.frames();
  const auto nfi = static_cast<Eigen::Index>(nf);
  for (int recentre = 0; recentre < 4; ++recentre) {
    const auto cpx = sky.lens->project(c);
    if (!cpx) {
      out.why = kOutside;
      return out;
    }
    Eigen::Vector3d e1, e2;
    tangent_basis(c, e1, e2);
    const int r = static_cast<int>(std::ceil(radius_px));
    const int x0 = static_cast<int>(std::lround(cpx->x())), y0 = static_cast<int>(std::lround(cpx->y()));
    std::vector<Eigen::Vector2d> us;
    std::vector<std::size_t> idx;
    double umax = 0;
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        if (dx * dx + dy * dy > radius_px * radius_px) continue;
        const int x = x0 + dx, y = y0 + dy;
        if (x < 0 || y < 0 || x >= sky.width || y >= sky.height || !sky.valid[index_of(sky, x, y)]) {
          out.why = at_edge(why_unusable(sky, x, y));
          return out;
        }
        const Eigen::Vector3d d = to_double(sky.ray_camera[index_of(sky, x, y)]);
        const Eigen::Vector2d u(d.dot(e1) / d.dot(c), d.dot(e2) / d.dot(c));
        us.push_back(u);
        idx.push_back(index_of(sky, x, y));
        umax = std::max(umax, u.norm());
      }
    const auto m = static_cast<Eigen::Index>(us.size());
    if (m < 2 * poly.terms() || umax <= 0) {
      out.why = "too few pixels around the minimum for the sub-pixel fit";
      return out;
    }
    Eigen::MatrixXd a(m, poly.terms()), y(m, nfi);
    for (Eigen::Index k = 0; k < m; ++k) {
      a.row(k) = poly.phi(us[static_cast<std::size_t>(k)] / umax).transpose();
      for (std::size_t t = 0; t < nf; ++t)
        y(k, static_cast<Eigen::Index>(t)) = sky.dolp[t][idx[static_cast<std::size_t>(k)]];
    }
    // Θ (terms×N): each frame's polynomial; then R(w) = H Θᵀ φ(w).
    const Eigen::MatrixXd theta = a.colPivHouseholderQr().solve(y);
    const Eigen::MatrixXd g = h * theta.transpose();  // N×terms
    const auto cost_at = [&](const Eigen::Vector2d& w) { return (g * poly.phi(w)).squaredNorm(); };
    // V has a very flat bottom near the equinox: start Levenberg–Marquardt from the best node of
    // a grid over the window.
    Eigen::Vector2d w = Eigen::Vector2d::Zero();
    double f = cost_at(w);
    constexpr int kGrid = 60;
    for (int j = -kGrid; j <= kGrid; ++j)
      for (int i = -kGrid; i <= kGrid; ++i) {
        const Eigen::Vector2d ww(static_cast<double>(i) / kGrid, static_cast<double>(j) / kGrid);
        if (ww.norm() > 1) continue;
        if (const double fw = cost_at(ww); fw < f) {
          f = fw;
          w = ww;
        }
      }
    double lambda = 1e-3;
    for (int it = 0; it < 200; ++it) {
      const Eigen::MatrixXd jac = g * poly.jacobian(w);
      Eigen::Matrix2d damped = jac.transpose() * jac;
      damped.diagonal() *= 1 + lambda;
      damped.diagonal().array() += 1e-30;
      const Eigen::Vector2d step = -damped.ldlt().solve(jac.transpose() * (g * poly.phi(w)));
      if (const double fn = cost_at(w + step); fn < f) {
        w += step;
        f = fn;
        lambda = std::max(lambda * 0.3, 1e-12);
        if (step.norm() < 1e-12) break;
      } else {
        lambda *= 10;
        if (lambda > 1e12) break;
      }
    }
    const Eigen::Vector2d u = w * umax;
    const Eigen::Vector3d d = (c + u(0) * e1 + u(1) * e2).normalized();
    if (w.norm() > 0.5) {  // left the well-fitted part of the window: re-centre there
      c = d;
      continue;
    }
    out.ok = true;
    out.d = d;
    out.window_rad = std::atan(umax);
    out.v = f / static_cast<double>(nf);
    const Eigen::MatrixXd jac = g * poly.jacobian(w) / umax;  // per radian of u
    out.sigma_rad = sigma_from_curvature(2 * jac.transpose() * jac,
                                         f / std::max(1.0, static_cast<double>(nf) - 2.0));
    return out;
  }
  out.why = "the sub-pixel fit did not settle (no clear minimum of DoLP variance)";
  return out;
}

namespace {

// The co-rotating window: pixels (binned into blocks when there are many, which keeps the cost
// of one evaluation bounded at full resolution while averaging the same noise) and their DoLP.
struct CorotatingWindow {
  std::vector<Eigen::Vector3d> dirs;  // sample directions (camera frame)
  Eigen::MatrixXd dolp;               // samples × frames
  double radius_rad = 0;
};

constexpr std::size_t kMaxSamples = 6000;

// Pixels within radius of c, the radius shrunk to stay clear of unusable pixels; nullopt with
// `why` when less than min_radius is clear.
std::optional<CorotatingWindow> corotating_window(const SkyImages& sky, const Eigen::Vector3d& c,
                                                  double radius, double min_radius, std::string& why) {
  const auto cpx = sky.lens->project(c);
  if (!cpx) {
    why = kOutside;
    return std::nullopt;
  }
  const double pa = pixel_angle(sky, c);
  const int r = static_cast<int>(std::ceil(1.5 * radius / pa)) + 2;
  const int x0 = static_cast<int>(std::lround(cpx->x())), y0 = static_cast<int>(std::lround(cpx->y()));
  // The clear radius: the angle to the nearest unusable pixel (outside the image: by its lens ray,
  // or its pixel distance where the lens has none).
  double clear = radius;
  Unusable nearest = Unusable::field_edge;
  std::vector<std::pair<double, std::size_t>> inside;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      const int x = x0 + dx, y = y0 + dy;
      const bool in_image = x >= 0 && y >= 0 && x < sky.width && y < sky.height;
      if (in_image && sky.valid[index_of(sky, x, y)]) {
        const Eigen::Vector3d d = to_double(sky.ray_camera[index_of(sky, x, y)]);
        const double ang = std::atan2(d.cross(c).norm(), d.dot(c));
        if (ang <= radius) inside.emplace_back(ang, index_of(sky, x, y));
        continue;
      }
      const auto ray = sky.lens->ray(Eigen::Vector2d(x, y));
      const double ang = ray ? std::atan2(ray->cross(c).norm(), ray->dot(c)) : std::hypot(dx, dy) * pa;
      if (ang - pa < clear) {
        clear = ang - pa;
        nearest = why_unusable(sky, x, y);
      }
    }
  if (clear < min_radius) {
    why = at_edge(nearest);
    return std::nullopt;
  }
  std::erase_if(inside, [&](const auto& p) { return p.first > clear; });
  // Blocks of b×b pixels when the window holds more than kMaxSamples.
  const int b = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(inside.size()) /
                                                                 static_cast<double>(kMaxSamples)))));
  const std::size_t nf = sky.frames();
  std::vector<std::pair<int, int>> keys;
  std::vector<std::size_t> order(inside.size());
  for (std::size_t k = 0; k < inside.size(); ++k) {
    const int x = static_cast<int>(inside[k].second % static_cast<std::size_t>(sky.width));
    const int y = static_cast<int>(inside[k].second / static_cast<std::size_t>(sky.width));
    keys.emplace_back(static_cast<int>(std::floor(static_cast<double>(y - y0) / b)),
                      static_cast<int>(std::floor(static_cast<double>(x - x0) / b)));
    order[k] = k;
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t bb) { return keys[a] < keys[bb]; });
  CorotatingWindow win;
  win.radius_rad = clear;
  std::vector<Eigen::VectorXd> rows;
  for (std::size_t s = 0; s < order.size();) {
    std::size_t e = s;
    Eigen::Vector3d dsum = Eigen::Vector3d::Zero();
    Eigen::VectorXd vsum = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nf));
    for (; e < order.size() && keys[order[e]] == keys[order[s]]; ++e) {
      const std::size_t i = inside[order[e]].second;
      dsum += to_double(sky.ray_camera[i]);
      for (std::size_t t = 0; t < nf; ++t) vsum(static_cast<Eigen::Index>(t)) += static_cast<double>(sky.dolp[t][i]);
    }
    win.dirs.push_back(dsum.normalized());
    rows.push_back(vsum / static_cast<double>(e - s));
    s = e;
  }
  win.dolp.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(nf));
  for (std::size_t k = 0; k < rows.size(); ++k) win.dolp.row(static_cast<Eigen::Index>(k)) = rows[k].transpose();
  return win;
}

struct CorotatingFit {
  const SkyImages& sky;
  const SunMotion& motion;
  const CorotatingWindow& win;
  Poly poly;
  bool trend;
  double sign = 1;  // sense of the sky's turn about P: −1 when P is the NCP, +1 the SCP
  // The window's samples this fit uses (keep[k] = 0 leaves sample k out: the sector jackknife);
  // nullptr: all.
  const std::vector<std::uint8_t>* keep = nullptr;

  // The rotation that takes frame t's sky back to the middle instant's, about pole p:
  // tilt(a, −sign·Δδ_t) · spin(p, −sign·ΔH_t), undoing the turn about the pole and then the
  // sun's step along its hour circle. The tilt axis a = p × s_mid (s_mid: the sun at the middle
  // instant) moves the sun along that circle; a northward drift (Δδ > 0) brings it towards the
  // NCP and away from the SCP, which `sign` also says.
  // The tilt axis for pole p, or nullopt when the drift is not modelled.
  std::optional<Eigen::Vector3d> tilt_axis(const Eigen::Vector3d& p) const {
    if (motion.suns_in_frames.empty() || motion.declination_change.empty()) return std::nullopt;
    Eigen::Vector3d s_mid = Eigen::Vector3d::Zero();
    for (const auto& [k, s_k] : motion.suns_in_frames)
      s_mid += Eigen::AngleAxisd(-sign * motion.hour_angle_change[k], p) * s_k;
    const Eigen::Vector3d a = p.cross(s_mid);
    if (a.norm() < 1e-9) return std::nullopt;
    return a.normalized();
  }

  Eigen::Matrix3d turn_back(const Eigen::Vector3d& p, const std::optional<Eigen::Vector3d>& axis,
                            std::size_t t) const {
    const Eigen::Matrix3d spin(Eigen::AngleAxisd(-sign * motion.hour_angle_change[t], p));
    if (!axis) return spin;
    return Eigen::Matrix3d(Eigen::AngleAxisd(-sign * motion.declination_change[t], *axis)) * spin;
  }

  // Residual sum of squares of the shared fit for pole p; `rows` gets the number of data.
  double rss(const Eigen::Vector3d& p, std::size_t* rows = nullptr) const {
    Eigen::Vector3d e1, e2;
    tangent_basis(p, e1, e2);
    const std::size_t nf = sky.frames();
    const double t_mid = 0.5 * (sky.times_s.front() + sky.times_s.back());
    const double span = std::max(1.0, sky.times_s.back() - sky.times_s.front());
    const double scale = 1 / std::tan(win.radius_rad);
    const int np = poly.terms(), terms = np + (trend ? 1 : 0);
    Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(terms, terms);
    Eigen::VectorXd aty = Eigen::VectorXd::Zero(terms), row(terms);
    double yty = 0;
    std::size_t n = 0;
    const std::optional<Eigen::Vector3d> axis = tilt_axis(p);
    for (std::size_t t = 0; t < nf; ++t) {
      const Eigen::Matrix3d back = turn_back(p, axis, t);
      if (trend) row(np) = (sky.times_s[t] - t_mid) / span;
      for (std::size_t k = 0; k < win.dirs.size(); ++k) {
        if (keep && !(*keep)[k]) continue;
        const Eigen::Vector3d d = back * win.dirs[k];
        const double dp = d.dot(p);
        if (dp <= 0) continue;
        poly.phi(Eigen::Vector2d(d.dot(e1), d.dot(e2)) * (scale / dp), row.head(np));
        const double y = win.dolp(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(t));
        ata.selfadjointView<Eigen::Lower>().rankUpdate(row);
        aty += y * row;
        yty += y * y;
        ++n;
      }
    }
    if (rows) *rows = n;
    const Eigen::MatrixXd full = ata.selfadjointView<Eigen::Lower>();
    return std::max(0.0, yty - aty.dot(full.ldlt().solve(aty)));
  }
};

// Newton steps on fit.rss from c (where it is f0) over a 3×3 stencil whose spacing shrinks from
// two pixel angles `px` to a hundredth of one. Returns the tangent-plane offset from c of the
// minimum (f0 and hess: the residual sum there and its Hessian), or stops early once the offset
// passes half of `reach` (tan of the window's radius: the caller re-centres there).
Eigen::Vector2d descend(const CorotatingFit& fit, const Eigen::Vector3d& c, double px, double reach, double& f0,
                        Eigen::Matrix2d& hess) {
  Eigen::Vector3d e1, e2;
  tangent_basis(c, e1, e2);
  const auto at = [&](const Eigen::Vector2d& x) { return (c + x(0) * e1 + x(1) * e2).normalized(); };
  Eigen::Vector2d x = Eigen::Vector2d::Zero();
  double h = 2 * px;
  hess = Eigen::Matrix2d::Identity();
  for (int it = 0; it < 60 && h > 0.01 * px; ++it) {
    double f[3][3];
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i)
        f[j + 1][i + 1] = (i == 0 && j == 0) ? f0 : fit.rss(at(x + h * Eigen::Vector2d(i, j)));
    const Eigen::Vector2d g((f[1][2] - f[1][0]) / (2 * h), (f[2][1] - f[0][1]) / (2 * h));
    hess(0, 0) = (f[1][2] - 2 * f0 + f[1][0]) / (h * h);
    hess(1, 1) = (f[2][1] - 2 * f0 + f[0][1]) / (h * h);
    hess(0, 1) = hess(1, 0) = (f[2][2] - f[2][0] - f[0][2] + f[0][0]) / (4 * h * h);
    Eigen::Vector2d step = Eigen::Vector2d::Zero();
    if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(hess).eigenvalues()(0) > 0) {
      step = -hess.ldlt().solve(g);
      if (step.norm() > 3 * h) step *= 3 * h / step.norm();
    } else {  // not convex at this scale: go to the best node of the stencil
      double fb = f0;
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i)
          if (f[j + 1][i + 1] < fb) {
            fb = f[j + 1][i + 1];
            step = h * Eigen::Vector2d(i, j);
          }
    }
    if (const double fn = fit.rss(at(x + step)); fn < f0) {
      x += step;
      f0 = fn;
      if (step.norm() < 0.5 * h) h *= 0.5;
    } else {
      h *= 0.5;
    }
    if (x.norm() > 0.5 * reach) break;
  }
  return x;
}

}  // namespace

SubPixel corotating_refine(const SkyImages& sky, const SunMotion& motion, bool trend,
                           Eigen::Vector3d c, double radius_deg, double min_radius_deg, int degree,
                           int sectors) {
  SubPixel out;
  for (int recentre = 0; recentre < 4; ++recentre) {
    const auto win = corotating_window(sky, c, radius_deg * kRadPerDeg, min_radius_deg * kRadPerDeg, out.why);
    if (!win) return out;
    CorotatingFit fit{sky, motion, *win, Poly{degree}, trend};
    if (static_cast<int>(win->dirs.size()) < 2 * fit.poly.terms()) {
      out.why = "too few pixels around the minimum for the sub-pixel fit";
      return out;
    }
    Eigen::Vector3d e1, e2;
    tangent_basis(c, e1, e2);
    const auto at = [&](const Eigen::Vector2d& x) { return (c + x(0) * e1 + x(1) * e2).normalized(); };
    // Which sense the sky turns in: the one that fits.
    double f0 = std::numeric_limits<double>::infinity();
    for (const double sg : {-1.0, 1.0}) {
      CorotatingFit trial = fit;
      trial.sign = sg;
      if (const double v = trial.rss(c); v < f0) {
        f0 = v;
        fit.sign = sg;
      }
    }
    Eigen::Matrix2d hess;
    const Eigen::Vector2d x = descend(fit, c, pixel_angle(sky, c), std::tan(win->radius_rad), f0, hess);
    if (x.norm() > 0.5 * std::tan(win->radius_rad)) {
      c = at(x);
      continue;
    }
    std::size_t rows = 0;
    f0 = fit.rss(at(x), &rows);
    out.ok = true;
    out.why.clear();
    out.d = at(x);
    out.window_rad = win->radius_rad;
    out.sense = fit.sign < 0 ? -1 : 1;
    CorotatingFit other = fit;
    other.sign = -fit.sign;
    out.sense_contrast = f0 > 0 ? other.rss(out.d) / f0 : std::numeric_limits<double>::infinity();
    out.v = f0 / static_cast<double>(std::max<std::size_t>(1, rows));
    out.sigma_rad = sigma_from_curvature(
        hess, f0 / std::max(1.0, static_cast<double>(rows) - fit.poly.terms() - (trend ? 3.0 : 2.0)));
    // The sector jackknife's refits: the window's samples dealt into azimuth sectors about the
    // minimum, each refit without one sector from the minimum found with all of them.
    if (sectors > 0) {
      Eigen::Vector3d u1, u2;
      tangent_basis(out.d, u1, u2);
      std::vector<int> sector(win->dirs.size());
      for (std::size_t k = 0; k < win->dirs.size(); ++k) {
        const double a = std::atan2(win->dirs[k].dot(u2), win->dirs[k].dot(u1));
        sector[k] = std::clamp(static_cast<int>(std::floor((a + kPi) / (2 * kPi) * sectors)), 0, sectors - 1);
      }
      const double reach = std::tan(win->radius_rad), px = pixel_angle(sky, out.d);
      for (int g = 0; g < sectors; ++g) {
        std::vector<std::uint8_t> keep(win->dirs.size());
        for (std::size_t k = 0; k < keep.size(); ++k) keep[k] = sector[k] != g;
        CorotatingFit sub = fit;
        sub.keep = &keep;
        double fg = sub.rss(out.d);
        Eigen::Matrix2d hg;
        const Eigen::Vector2d xg = descend(sub, out.d, px, reach, fg, hg);
        if (xg.norm() > 0.5 * reach)
          out.without_sector.emplace_back(std::nullopt);  // left the window: no minimum without g
        else
          out.without_sector.emplace_back((out.d + xg(0) * u1 + xg(1) * u2).normalized());
      }
    }
    return out;
  }
  out.why = "the sub-pixel fit did not settle (no clear minimum of DoLP variance)";
  return out;
}

}  // namespace skypol::skypole
