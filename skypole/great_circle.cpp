// Great circles of equal DoLP → the pole (method and reasoning in great_circle.h).
#include "skypole/great_circle.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "sky/units.h"
#include "skypole/enum_names.h"
#include "skypole/sky_mask.h"
#include "skypole/stack_sky.h"
#include "skypole/uncertainty.h"

namespace skypol::skypole {
namespace {

using Crossing = CircleCrossing;

double tukey(double r, double c) {
  const double u = r / c;
  return std::abs(u) >= 1 ? 0.0 : (1 - u * u) * (1 - u * u);
}

// Sub-pixel zero crossings of f = a − b between 4-neighbouring valid pixels, each with its two
// pixels' sky sectors (`sector`: one per pixel, or empty: all 0).
std::vector<Crossing> zero_crossings(const std::vector<float>& a, const std::vector<float>& b,
                                     const SkyImages& sky, const std::vector<std::uint8_t>& sector) {
  std::vector<Crossing> out;
  const std::size_t W = static_cast<std::size_t>(sky.width);
  const auto f = [&](std::size_t i) { return static_cast<double>(a[i]) - static_cast<double>(b[i]); };
  const auto add = [&](double x, double y, double fi, double fj, bool horizontal, std::size_t i, std::size_t j) {
    if ((fi > 0) == (fj > 0) || fi == fj) return;
    const double t = fi / (fi - fj);
    const Eigen::Vector2d px = horizontal ? Eigen::Vector2d(x + t, y) : Eigen::Vector2d(x, y + t);
    if (const auto r = sky.lens->ray(px))
      out.push_back({r->normalized(), sector.empty() ? std::uint8_t{0} : sector[i],
                     sector.empty() ? std::uint8_t{0} : sector[j]});
  };
  for (int y = 0; y < sky.height; ++y)
    for (int x = 0; x < sky.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * W + static_cast<std::size_t>(x);
      if (!sky.valid[i]) continue;
      const double fi = f(i);
      if (x + 1 < sky.width && sky.valid[i + 1]) add(x, y, fi, f(i + 1), true, i, i + 1);
      if (y + 1 < sky.height && sky.valid[i + W]) add(x, y, fi, f(i + W), false, i, i + W);
    }
  return out;
}

Eigen::Vector3d smallest_eigenvector(const Eigen::Matrix3d& c) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(c);
  return es.eigenvectors().col(0).normalized();
}

struct PlaneFit {
  Eigen::Vector3d n;
  int inliers = 0;
  double rms = 0;  // radians, inliers
};

// The two planes through the origin that hold the crossings (see great_circle.h step 2).
std::optional<std::array<PlaneFit, 2>> fit_plane_pair(const std::vector<Crossing>& pts) {
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  Matrix6d a = Matrix6d::Zero();
  for (const Crossing& c : pts) {
    const Eigen::Vector3d& p = c.p;
    Vector6d q;
    q << p.x() * p.x(), p.y() * p.y(), p.z() * p.z(), 2 * p.x() * p.y(), 2 * p.x() * p.z(),
        2 * p.y() * p.z();
    a += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Matrix6d> es6(a);
  const Vector6d m = es6.eigenvectors().col(0);
  Eigen::Matrix3d mm;
  mm << m(0), m(3), m(4), m(3), m(1), m(5), m(4), m(5), m(2);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es3(mm);
  const Eigen::Vector3d lam = es3.eigenvalues();
  if (!(lam(2) > 0 && lam(0) < 0)) return std::nullopt;
  const double ka = std::sqrt(lam(2)), kb = std::sqrt(-lam(0));
  std::array<PlaneFit, 2> planes;
  planes[0].n = (ka * es3.eigenvectors().col(2) + kb * es3.eigenvectors().col(0)).normalized();
  planes[1].n = (ka * es3.eigenvectors().col(2) - kb * es3.eigenvectors().col(0)).normalized();

  std::vector<double> r[2];
  std::vector<const Crossing*> members[2];
  for (int iter = 0; iter < 6; ++iter) {
    for (int k = 0; k < 2; ++k) {
      r[k].clear();
      members[k].clear();
    }
    for (const Crossing& c : pts) {
      const double r0 = planes[0].n.dot(c.p), r1 = planes[1].n.dot(c.p);
      const int k = std::abs(r0) <= std::abs(r1) ? 0 : 1;
      members[k].push_back(&c);
      r[k].push_back(k == 0 ? r0 : r1);
    }
    for (int k = 0; k < 2; ++k) {
      if (members[k].size() < 3) return std::nullopt;
      std::vector<double> absr(r[k].size());
      for (std::size_t t = 0; t < r[k].size(); ++t) absr[t] = std::abs(r[k][t]);
      const double sigma = std::max(1.4826 * quantile(absr, 0.5, QuantileRank::upper), 1e-7);
      const double cut = 4.685 * sigma;
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      int inl = 0;
      double sq = 0;
      for (std::size_t t = 0; t < members[k].size(); ++t) {
        const double wt = tukey(r[k][t], cut);
        if (wt <= 0) continue;
        const Eigen::Vector3d& p = members[k][t]->p;
        cov += wt * p * p.transpose();
        ++inl;
        sq += r[k][t] * r[k][t];
      }
      if (inl < 3) return std::nullopt;
      const Eigen::Vector3d n = smallest_eigenvector(cov);
      planes[k].n = n.dot(planes[k].n) < 0 ? Eigen::Vector3d(-n) : n;
      planes[k].inliers = inl;
      planes[k].rms = std::sqrt(sq / inl);
    }
  }
  return planes;
}

// The radial plane refitted (robust TLS, as in fit_plane_pair) on the crossings nearer to it than
// to the other plane and farther than `exclusion` (radians) from the suns' bisector `toward_sun`
// and its antipode. Near the sun and the antisun a real sky is not Rayleigh's: neutral points
// (Babinet, Brewster, Arago: 15–25° from them, on the solar vertical) bend the set where two
// frames' DoLP are equal away from the great circle, and the radial circle runs through both, so
// those crossings pull its normal off the pole. nullopt when fewer than `min_points` remain.
std::optional<PlaneFit> refit_away_from_sun(const std::vector<Crossing>& pts, const Eigen::Vector3d& radial,
                                            const Eigen::Vector3d& other, const Eigen::Vector3d& toward_sun,
                                            double exclusion, int min_points) {
  const double cos_ex = std::cos(exclusion);
  const Eigen::Vector3d a = toward_sun.normalized();
  std::vector<const Crossing*> members;
  for (const Crossing& c : pts)
    if (std::abs(c.p.dot(a)) < cos_ex && std::abs(c.p.dot(radial)) <= std::abs(c.p.dot(other))) members.push_back(&c);
  if (static_cast<int>(members.size()) < min_points) return std::nullopt;
  PlaneFit fit;
  fit.n = radial;
  for (int iter = 0; iter < 6; ++iter) {
    std::vector<double> absr(members.size());
    for (std::size_t t = 0; t < members.size(); ++t) absr[t] = std::abs(fit.n.dot(members[t]->p));
    const double cut = 4.685 * std::max(1.4826 * quantile(absr, 0.5, QuantileRank::upper), 1e-7);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    int inl = 0;
    double sq = 0;
    for (std::size_t t = 0; t < members.size(); ++t) {
      const double wt = tukey(absr[t], cut);
      if (wt <= 0) continue;
      cov += wt * members[t]->p * members[t]->p.transpose();
      ++inl;
      sq += absr[t] * absr[t];
    }
    if (inl < min_points) return std::nullopt;
    const Eigen::Vector3d n = smallest_eigenvector(cov);
    fit.n = n.dot(radial) < 0 ? Eigen::Vector3d(-n) : n;
    fit.inliers = inl;
    fit.rms = std::sqrt(sq / inl);
  }
  return fit;
}

struct Hypothesis {
  Eigen::Vector3d plane_normal, radial_normal;  // A, B of great_circle.h step 3
  double half_separation = 0;                   // h, radians
  double ratio = 1;                             // best SSE / second best
};

// Step 3: which normal is radial, and its orientation, from the two frames' DoLP.
Hypothesis classify(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2,
                    const std::vector<Eigen::Vector3d>& dirs, const std::vector<float>& di,
                    const std::vector<float>& dj, const Eigen::Matrix3d& level_from_camera) {
  const std::array<std::pair<Eigen::Vector3d, Eigen::Vector3d>, 4> combos = {
      {{n1, n2}, {n1, -n2}, {n2, n1}, {n2, -n1}}};
  constexpr int kSteps = 90;
  std::array<double, 4> best_sse{};
  std::array<double, 4> best_h{};
  std::vector<double> u(dirs.size()), v(dirs.size());
  for (std::size_t c = 0; c < combos.size(); ++c) {
    for (std::size_t k = 0; k < dirs.size(); ++k) {
      u[k] = combos[c].first.dot(dirs[k]);
      v[k] = combos[c].second.dot(dirs[k]);
    }
    std::array<double, kSteps> sse{};
    for (int s = 0; s < kSteps; ++s) {
      const double h = (s + 0.5) * (0.5 * kPi / kSteps);
      const double ch = std::cos(h), sh = std::sin(h);
      double sdg = 0, sgg = 0, sdd = 0;
      for (std::size_t k = 0; k < dirs.size(); ++k) {
        const double ci = ch * u[k] + sh * v[k], cj = ch * u[k] - sh * v[k];
        const double gi = (1 - ci * ci) / (1 + ci * ci), gj = (1 - cj * cj) / (1 + cj * cj);
        const double a = di[k], b = dj[k];
        sdg += a * gi + b * gj;
        sgg += gi * gi + gj * gj;
        sdd += a * a + b * b;
      }
      sse[static_cast<std::size_t>(s)] = sgg > 0 ? sdd - sdg * sdg / sgg : sdd;
    }
    const auto it = std::min_element(sse.begin(), sse.end());
    const int s = static_cast<int>(it - sse.begin());
    double offset = 0;  // parabolic refinement of h between grid steps
    if (s > 0 && s + 1 < kSteps) {
      const double y0 = sse[static_cast<std::size_t>(s - 1)], y1 = *it,
                   y2 = sse[static_cast<std::size_t>(s + 1)];
      const double den = y0 - 2 * y1 + y2;
      if (den > 0) offset = std::clamp(0.5 * (y0 - y2) / den, -0.5, 0.5);
    }
    best_sse[c] = *it;
    best_h[c] = (s + 0.5 + offset) * (0.5 * kPi / kSteps);
  }
  // (A, B, h) and (B, A, 90° − h) give the suns {s_i, s_j} and {s_i, −s_j}: the same DoLP, since
  // DoLP cannot tell the sun from the antisun. So combos 0/2 and 1/3 tie; the DoLP decides between
  // the two classes (the order of the suns), the horizon within a class: both suns are up.
  const std::array<std::array<std::size_t, 2>, 2> classes = {{{0, 2}, {1, 3}}};
  std::array<double, 2> class_sse{};
  for (std::size_t k = 0; k < 2; ++k)
    class_sse[k] = std::min(best_sse[classes[k][0]], best_sse[classes[k][1]]);
  const std::size_t win = class_sse[0] <= class_sse[1] ? 0 : 1;
  Hypothesis hyp;
  double best_up = -2;
  for (std::size_t c : classes[win]) {
    Eigen::Vector3d a = combos[c].first, b = combos[c].second;
    if ((level_from_camera * a).z() < 0) {  // the suns' bisector above the horizon
      a = -a;
      b = -b;
    }
    const double h = best_h[c];
    const double zi = (level_from_camera * (std::cos(h) * a + std::sin(h) * b)).z();
    const double zj = (level_from_camera * (std::cos(h) * a - std::sin(h) * b)).z();
    if (std::min(zi, zj) > best_up) {
      best_up = std::min(zi, zj);
      hyp.plane_normal = a;
      hyp.radial_normal = b;
      hyp.half_separation = h;
    }
  }
  const double other = class_sse[1 - win];
  hyp.ratio = other > 0 ? class_sse[win] / other : 1.0;
  return hyp;
}

// Steps 2 and 3b into `cp`, whose radial_normal and plane_normal hold step 3's oriented normals
// and sun_separation_deg its separation: the plane pair's counts, then the radial circle refitted
// away from the sun and the antisun, and whether the pair is used.
void set_circles(CirclePair& cp, const std::vector<Crossing>& pts, const PlaneFit& radial, const PlaneFit& plane,
                 const GreatCircleParams& params) {
  cp.radial_points = radial.inliers;
  cp.plane_points = plane.inliers;
  cp.radial_rms_deg = radial.rms / kRadPerDeg;
  // The largest exclusion (the given one, then 2/3 and 1/3 of it) that leaves enough of the
  // circle; a view of little but the sun's side of the sky (the pole outside the field of view)
  // keeps the fit on every crossing.
  for (const double share : {1.0, 2.0 / 3.0, 1.0 / 3.0}) {
    if (!(params.sun_exclusion_deg > 0)) break;
    const auto away = refit_away_from_sun(pts, radial.n, plane.n, cp.plane_normal,
                                          share * params.sun_exclusion_deg * kRadPerDeg, params.min_points);
    if (!away) continue;
    cp.radial_normal = away->n.dot(cp.radial_normal) < 0 ? Eigen::Vector3d(-away->n) : away->n;
    cp.radial_points = away->inliers;
    cp.radial_rms_deg = away->rms / kRadPerDeg;
    break;
  }
  cp.used = radial.inliers >= params.min_points && cp.sun_separation_deg >= params.min_separation_deg;
}

struct PoleFit {
  Eigen::Vector3d p = Eigen::Vector3d::UnitZ();
  double kappa = 0;
  std::vector<double> weight;  // final robust weights
  double rms = 0;              // weighted RMS residual, radians
};

// Step 4: the pole from the oriented radial normals.
PoleFit solve_pole(const std::vector<Eigen::Vector3d>& n, const std::vector<double>& g,
                   const std::vector<double>& base_w, bool drift) {
  PoleFit fit;
  fit.weight = base_w;
  for (int iter = 0; iter < 10; ++iter) {
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    double sg = 0;
    for (std::size_t k = 0; k < n.size(); ++k) {
      c += fit.weight[k] * n[k] * n[k].transpose();
      b += fit.weight[k] * g[k] * n[k];
      sg += fit.weight[k] * g[k] * g[k];
    }
    if (drift && sg > 0) c -= b * b.transpose() / sg;
    fit.p = smallest_eigenvector(c);
    fit.kappa = drift && sg > 0 ? b.dot(fit.p) / sg : 0.0;
    std::vector<double> absr(n.size());
    for (std::size_t k = 0; k < n.size(); ++k) absr[k] = std::abs(n[k].dot(fit.p) - fit.kappa * g[k]);
    const double sigma = std::max(1.4826 * quantile(absr, 0.5, QuantileRank::upper), 2e-5);
    double sw = 0, swr = 0;
    for (std::size_t k = 0; k < n.size(); ++k) {
      fit.weight[k] = base_w[k] * tukey(absr[k], 4.685 * sigma);
      sw += fit.weight[k];
      swr += fit.weight[k] * absr[k] * absr[k];
    }
    fit.rms = sw > 0 ? std::sqrt(swr / sw) : 0.0;
  }
  return fit;
}

// Angular span (degrees) of the directions of the normals about p: 360° minus the largest gap.
double normal_span_deg(const std::vector<Eigen::Vector3d>& n, const std::vector<double>& w,
                       const Eigen::Vector3d& p) {
  const Eigen::Vector3d e1 = p.unitOrthogonal(), e2 = p.cross(e1);
  std::vector<double> ang;
  for (std::size_t k = 0; k < n.size(); ++k)
    if (w[k] > 0) ang.push_back(std::atan2(n[k].dot(e2), n[k].dot(e1)));
  if (ang.size() < 2) return 0;
  std::sort(ang.begin(), ang.end());
  double gap = ang.front() + 2 * kPi - ang.back();
  for (std::size_t k = 1; k < ang.size(); ++k) gap = std::max(gap, ang[k] - ang[k - 1]);
  return (2 * kPi - gap) / kRadPerDeg;
}

}  // namespace

constexpr EnumNames<DriftModel, 3> kDriftModelNames{
    {{DriftModel::none, "none"}, {DriftModel::fit, "fit"}, {DriftModel::automatic, "automatic"}}};

DriftModel parse_drift_model(std::string_view name) {
  return enum_from_name(kDriftModelNames, name, "drift model");
}
std::string_view drift_model_name(DriftModel m) { return enum_name(kDriftModelNames, m); }

GreatCirclePairs great_circle_pairs(const stack::Stack& stack, const GreatCircleParams& params) {
  const StackSky whole(stack, params.input);
  return great_circle_pairs(SkyView(whole), params);
}

GreatCirclePairs great_circle_pairs(const SkyView& view, const GreatCircleParams& params) {
  const auto t_start = std::chrono::steady_clock::now();
  const char* method = "great_circle";
  if (params.pairs == PairMode::interval && params.interval < 1)
    throw std::invalid_argument("great_circle: pair interval must be ≥ 1 frame, got " +
                                std::to_string(params.interval));
  const std::size_t min_frames =
      params.pairs == PairMode::interval ? static_cast<std::size_t>(params.interval) + 2 : 3;
  GreatCirclePairs out;
  out.sky = view.prepared(min_frames, method);
  if (params.input.sky_mask) apply_mask(out.sky, view.sky_mask(out.sky));
  const SkyImages& sky = out.sky;
  const double radius =
      params.filter_radius_px.value_or(default_filter_radius_px(sky.width, sky.height));
  const std::vector<std::vector<float>> filtered = view.filtered(sky, radius);

  // Sample pixels for the radial/plane decision.
  std::vector<std::size_t> samples;
  {
    const int stride = std::max(
        1, static_cast<int>(std::floor(std::sqrt(static_cast<double>(sky.valid_count) /
                                                 std::max(1, params.model_samples)))));
    for (int y = 0; y < sky.height; y += stride)
      for (int x = 0; x < sky.width; x += stride) {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(sky.width) +
                              static_cast<std::size_t>(x);
        if (sky.valid[i]) samples.push_back(i);
      }
  }
  std::vector<Eigen::Vector3d> sample_dirs;
  for (std::size_t i : samples) sample_dirs.push_back(to_double(sky.ray_camera[i]));

  // Each pixel's sky sector, when the crossings are kept for the sector jackknife.
  std::vector<std::uint8_t> sector;
  if (params.sectors > 0) {
    const camera::Intrinsics& k = sky.lens->intrinsics();
    sector = sector_map(sky.width, sky.height, Eigen::Vector2d(k.cx, k.cy), params.sectors);
  }

  std::vector<CirclePair>& circles = out.circles;
  const auto pairs = make_pairs(static_cast<int>(sky.frames()), params.pairs, params.interval);
  circles.resize(pairs.size());
  out.sectors = std::max(params.sectors, 0);
  if (out.sectors > 0) out.crossings.resize(pairs.size());
  tbb::parallel_for(std::size_t{0}, pairs.size(), [&](std::size_t k) {
    const auto [i, j] = pairs[k];
    CirclePair& cp = circles[k];
    const auto& fi = filtered[static_cast<std::size_t>(i)];
    const auto& fj = filtered[static_cast<std::size_t>(j)];
    std::vector<Crossing> pts = zero_crossings(fi, fj, sky, sector);
    cp.i = i;
    cp.j = j;
    if (static_cast<int>(pts.size()) < 2 * params.min_points) {
      return;
    }
    const auto planes = fit_plane_pair(pts);
    if (!planes) {
      return;
    }
    std::vector<float> di, dj;
    for (std::size_t s : samples) {
      di.push_back(fi[s]);
      dj.push_back(fj[s]);
    }
    const Hypothesis hyp =
        classify((*planes)[0].n, (*planes)[1].n, sample_dirs, di, dj, sky.level_from_camera);
    const PlaneFit& radial =
        std::abs((*planes)[0].n.dot(hyp.radial_normal)) > std::abs((*planes)[1].n.dot(hyp.radial_normal))
            ? (*planes)[0]
            : (*planes)[1];
    const PlaneFit& plane = &radial == &(*planes)[0] ? (*planes)[1] : (*planes)[0];
    cp.radial_normal = hyp.radial_normal;
    cp.plane_normal = hyp.plane_normal;
    cp.sun_separation_deg = 2 * hyp.half_separation / kRadPerDeg;
    cp.hypothesis_ratio = hyp.ratio;
    set_circles(cp, pts, radial, plane, params);
    if (out.sectors > 0) out.crossings[k] = std::move(pts);
  });
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return out;
}

GreatCircleResult estimate_great_circle(const stack::Stack& stack, const GreatCircleParams& params) {
  return great_circle_pole(great_circle_pairs(stack, params), params);
}

namespace {

// Steps 4–5 on `circles` (those with `used` set); `seconds_before` is what the circles took.
GreatCircleResult pole_from_circles(const SkyImages& sky, std::vector<CirclePair> circles, double seconds_before,
                                    const GreatCircleParams& params) {
  const auto t_start = std::chrono::steady_clock::now();
  const char* method = "great_circle";
  GreatCircleResult result;

  const auto seconds = [&] {
    return seconds_before + std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  };
  const auto fail = [&](std::string why) {
    result.estimate = invalid_estimate(method, std::move(why));
    result.estimate.seconds = seconds();
    if (params.keep_circles) result.circles = circles;
    return result;
  };

  std::vector<Eigen::Vector3d> normals;
  std::vector<double> g, w;
  std::vector<std::size_t> index;  // into circles
  for (std::size_t k = 0; k < circles.size(); ++k) {
    const CirclePair& c = circles[k];
    if (!c.used) continue;
    double half_step;  // Δω/2
    if (sky.times_known)
      half_step = 0.5 * kHourAngleRate * (sky.times_s[static_cast<std::size_t>(c.j)] -
                                          sky.times_s[static_cast<std::size_t>(c.i)]);
    else
      half_step = 0.5 * c.sun_separation_deg * kRadPerDeg;
    half_step = std::clamp(half_step, 1e-9, 0.5 * kPi - 1e-3);
    normals.push_back(c.radial_normal);
    g.push_back(half_step / std::sin(half_step));
    // Normal precision ∝ rms / √points; floor the rms so noise-free fits weigh alike.
    const double rms = std::max(c.radial_rms_deg * kRadPerDeg, 1e-4);
    w.push_back(static_cast<double>(c.radial_points) / (rms * rms));
    index.push_back(k);
  }
  if (normals.size() < 2)
    return fail("fewer than two pairs of frames gave usable circles of equal DoLP (" +
                std::to_string(normals.size()) + " of " + std::to_string(circles.size()) +
                "); the sun moved too little, or too little sky is visible");
  const double wmax = *std::max_element(w.begin(), w.end());
  for (double& x : w) x /= wmax;

  PoleFit fit = solve_pole(normals, g, w, params.drift == DriftModel::fit);
  if (params.drift == DriftModel::automatic) {
    const double span = normal_span_deg(normals, fit.weight, fit.p);
    const auto kept = std::count_if(fit.weight.begin(), fit.weight.end(), [](double x) { return x > 0; });
    if (kept >= 4 && span >= params.auto_drift_min_arc_deg) {
      fit = solve_pole(normals, g, w, true);
      result.drift_fitted = true;
    }
  } else {
    result.drift_fitted = params.drift == DriftModel::fit;
  }
  result.drift = fit.kappa;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < normals.size(); ++k) {
    circles[index[k]].used = fit.weight[k] > 0;
    kept += fit.weight[k] > 0 ? 1 : 0;
  }
  if (kept < 2) return fail("the circles of equal DoLP do not agree on a common point");

  // Which end is north: (n_r × n_p)·NCP < 0 for every pair less than half a day of hour angle
  // apart. n_r × n_p ∝ s_i × s_j ∝ −sin Δω·NCP: a pair further apart (the midnight sun of a polar
  // day) sees the sun turned the short way round, the other sense, so its vote counts reversed.
  Eigen::Vector3d axis = fit.p;
  if ((sky.level_from_camera * axis).z() < 0) axis = -axis;  // the end above the horizon
  Eigen::Vector3d ncp;
  std::string source;
  double vote = 0, total = 0;
  for (std::size_t k = 0; k < normals.size(); ++k) {
    if (fit.weight[k] <= 0) continue;
    const CirclePair& c = circles[index[k]];
    const double sense = sky.times_known ? rotation_sense(sky.times_s[static_cast<std::size_t>(c.j)] -
                                                          sky.times_s[static_cast<std::size_t>(c.i)])
                                         : 1.0;
    const double v = c.radial_normal.cross(c.plane_normal).dot(axis) * sense;
    vote += fit.weight[k] * v;
    total += fit.weight[k] * std::abs(v);
  }
  if (params.input.hemisphere != Hemisphere::automatic) {
    // A hint decides unless the pairs contradict it decisively (the rule of decide_hemisphere in
    // sky_images.cpp; skypole/README.md, "North or south"): then the data win, and say so.
    const bool hint_north = params.input.hemisphere == Hemisphere::north;
    bool north = hint_north;
    source = "hint";
    if (total > 0 && std::abs(vote) >= 0.6 * total && (vote < 0) != hint_north) {
      north = vote < 0;
      source = std::string("sun rotation, overriding the hint: hemisphere = ") +
               (hint_north ? "north" : "south") +
               " was given, but the sun's rotation is decisive and says " + (north ? "north" : "south");
    }
    ncp = north ? axis : Eigen::Vector3d(-axis);
  } else {
    if (!(total > 0) || std::abs(vote) < 0.3 * total)
      return fail("cannot tell north from south: the pairs disagree on the sense of the sky's "
                  "rotation; pass hemisphere = north or south");
    ncp = vote < 0 ? axis : Eigen::Vector3d(-axis);
    source = "sun rotation";
  }
  if (fit.kappa != 0 && ncp.dot(fit.p) < 0) result.drift = -fit.kappa;  // κ for the NCP

  result.estimate = make_estimate(method, sky, ncp, params.input);
  result.estimate.note += (result.estimate.note.empty() ? "" : "; ") +
                          std::string("hemisphere from ") + source;
  result.estimate.residual_deg = std::asin(std::min(1.0, fit.rms)) / kRadPerDeg;
  result.estimate.seconds = seconds();
  if (params.keep_circles) result.circles = circles;
  return result;
}

}  // namespace

GreatCircleResult great_circle_pole(const GreatCirclePairs& pairs, const GreatCircleParams& params,
                                    const std::vector<std::uint8_t>* keep_frame) {
  std::vector<CirclePair> circles = pairs.circles;
  if (keep_frame && !keep_frame->empty())
    for (CirclePair& c : circles)
      if (!(*keep_frame)[static_cast<std::size_t>(c.i)] || !(*keep_frame)[static_cast<std::size_t>(c.j)])
        c.used = false;
  return pole_from_circles(pairs.sky, std::move(circles), pairs.seconds, params);
}

GreatCircleResult great_circle_pole_without_sector(const GreatCirclePairs& pairs, const GreatCircleParams& params,
                                                   int g) {
  if (pairs.sectors <= 0 || pairs.crossings.size() != pairs.circles.size())
    throw std::invalid_argument("great_circle: the pairs' zero crossings were not kept (GreatCircleParams::sectors "
                                "= 0), so no sky sector can be left out");
  if (g < 0 || g >= pairs.sectors)
    throw std::invalid_argument("great_circle: sky sector " + std::to_string(g) + " is not one of 0.." +
                                std::to_string(pairs.sectors - 1));
  const auto t_start = std::chrono::steady_clock::now();
  std::vector<CirclePair> circles = pairs.circles;
  tbb::parallel_for(std::size_t{0}, circles.size(), [&](std::size_t k) {
    const std::vector<Crossing>& all = pairs.crossings[k];
    std::vector<Crossing> pts;
    pts.reserve(all.size());
    for (const Crossing& c : all)
      if (c.sector_a != g && c.sector_b != g) pts.push_back(c);
    // No crossing in the sector: the masked stack gives this pair the same crossings, so the same
    // circles. A pair without circles on the whole sky (too few crossings, no plane pair) has no
    // step-3 decision to keep and stays unused.
    if (pts.size() == all.size() || all.empty()) return;
    CirclePair& cp = circles[k];
    cp.used = false;
    if (static_cast<int>(pts.size()) < 2 * params.min_points) return;
    const auto planes = fit_plane_pair(pts);
    if (!planes) return;
    // Step 3's decision, kept: the radial circle is the plane nearer the whole sky's radial one,
    // both normals turned as step 3 turned them.
    const Eigen::Vector3d old_radial = cp.radial_normal, old_plane = cp.plane_normal;
    const bool first = std::abs((*planes)[0].n.dot(old_radial)) >= std::abs((*planes)[1].n.dot(old_radial));
    const PlaneFit& radial = first ? (*planes)[0] : (*planes)[1];
    const PlaneFit& plane = first ? (*planes)[1] : (*planes)[0];
    cp.radial_normal = radial.n.dot(old_radial) < 0 ? Eigen::Vector3d(-radial.n) : radial.n;
    cp.plane_normal = plane.n.dot(old_plane) < 0 ? Eigen::Vector3d(-plane.n) : plane.n;
    set_circles(cp, pts, radial, plane, params);
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return pole_from_circles(pairs.sky, std::move(circles), seconds, params);
}

}  // namespace skypol::skypole
