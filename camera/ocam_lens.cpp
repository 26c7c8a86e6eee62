// OCamCalib (Scaramuzza) model: loader, closed-form ray, exact projection by bracketed Newton.
#include "camera/ocam_lens.h"
#include "camera/detail/lens_checks.h"
#include "camera/lens_registry.h"
#include <utility>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include "camera/detail/radial_util.h"
#include "camera/detail/ray_table.h"
#include "sky/units.h"

namespace skypol::camera {
namespace {

struct DataLine {
  int number;
  std::string text;
};

std::vector<double> read_numbers(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> v;
  double x;
  while (in >> x) v.push_back(x);
  if (!in.eof()) v.push_back(std::nan(""));  // a token that is not a number
  return v;
}

}  // namespace

OCamModel load_ocamcalib(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path.string() + ": cannot open OCamCalib calibration file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_ocamcalib(text.str(), path.string());
}

OCamModel parse_ocamcalib(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  const std::filesystem::path path(name);
  std::vector<DataLine> lines;
  std::string s;
  for (int n = 1; std::getline(in, s); ++n) {
    const auto first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos || s[first] == '#') continue;
    lines.push_back({n, s});
  }
  const char* what[] = {"polynomial \"N a0 .. aN-1\"", "inverse polynomial \"M p0 .. pM-1\"",
                        "centre \"xc yc\" (row, column)", "affine \"c d e\"",
                        "image size \"height width\""};
  if (lines.size() < 5)
    throw std::invalid_argument(path.string() + ": missing the " + what[lines.size()] +
                                " line (expected 5 data lines, found " +
                                std::to_string(lines.size()) + ")");
  auto fail = [&](std::size_t i, const std::string& why) {
    return std::invalid_argument(path.string() + ":" + std::to_string(lines[i].number) + ": " +
                                 what[i] + ": " + why);
  };
  auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  OCamModel m;
  for (std::size_t i = 0; i < 2; ++i) {
    const auto v = read_numbers(lines[i].text);
    if (v.empty() || !finite(v) || v[0] < 1 || v[0] != std::floor(v[0]) ||
        v.size() != static_cast<std::size_t>(v[0]) + 1)
      throw fail(i, "expected a count followed by that many numbers");
    (i == 0 ? m.pol : m.invpol).assign(v.begin() + 1, v.end());
  }
  auto fixed = [&](std::size_t i, std::size_t n) {
    const auto v = read_numbers(lines[i].text);
    if (v.size() != n || !finite(v)) throw fail(i, "expected " + std::to_string(n) + " numbers");
    return v;
  };
  const auto centre = fixed(2, 2);
  m.xc = centre[0];
  m.yc = centre[1];
  const auto affine = fixed(3, 3);
  m.c = affine[0];
  m.d = affine[1];
  m.e = affine[2];
  const auto size = fixed(4, 2);
  if (size[0] < 1 || size[1] < 1 || size[0] != std::floor(size[0]) || size[1] != std::floor(size[1]))
    throw fail(4, "expected two positive integers");
  m.height = static_cast<int>(size[0]);
  m.width = static_cast<int>(size[1]);
  return m;
}

OCamLens::OCamLens(OCamModel model, double max_field_angle) : m_(std::move(model)) {
  if (m_.pol.empty()) throw std::invalid_argument("ocam: pol must not be empty");
  const auto finite = [](double x) { return std::isfinite(x); };
  if (!std::all_of(m_.pol.begin(), m_.pol.end(), finite) ||
      !std::all_of(m_.invpol.begin(), m_.invpol.end(), finite))
    throw std::invalid_argument("ocam: polynomial coefficients must be finite");
  if (!(m_.pol[0] < 0))
    throw std::invalid_argument("ocam: pol a0 must be < 0 (OCamCalib's Z points out of the lens)");
  if (!std::isfinite(m_.xc) || !std::isfinite(m_.yc))
    throw std::invalid_argument("ocam: centre xc, yc must be finite");
  const double det = m_.c - m_.d * m_.e;
  if (!std::isfinite(det) || std::abs(det) < 1e-12)
    throw std::invalid_argument("ocam: affine c, d, e is singular (c - d*e = 0)");
  if (m_.width < 1 || m_.height < 1)
    throw std::invalid_argument("ocam: image width and height must be > 0");

  k_.fx = k_.fy = -m_.pol[0];
  k_.cx = m_.yc;
  k_.cy = m_.xc;
  k_.width = m_.width;
  k_.height = m_.height;

  // The farthest sensor corner in the pre-affine plane bounds the useful radius.
  double rho_corner = 0;
  for (double row : {-0.5, m_.height - 0.5})
    for (double col : {-0.5, m_.width - 0.5}) {
      const double dr = row - m_.xc, dc = col - m_.yc;
      rho_corner = std::max(rho_corner, std::hypot((dr - m_.d * dc) / det, (-m_.e * dr + m_.c * dc) / det));
    }
  const auto dtheta = [this](double r) { return dtheta_drho(r); };
  if (!(max_field_angle > 0)) {
    const auto turn = detail::first_turning_point(dtheta, rho_corner);
    rho_max_ = turn ? *turn : rho_corner;
    theta_max_ = theta_of_rho(rho_max_);
    return;
  }
  if (!(max_field_angle <= std::numbers::pi))
    throw std::invalid_argument("ocam: field of view must be <= 360°");
  const double rho_search = 4 * std::max(rho_corner, 1.0);
  const auto turn = detail::first_turning_point(dtheta, rho_search);
  const double rho_hi = turn ? *turn : rho_search;
  if (theta_of_rho(rho_hi) < max_field_angle)
    throw std::invalid_argument(
        turn ? "distortion curve not monotone over the declared field of view (turns over at " +
                   detail::format_deg(theta_of_rho(*turn)) + ")"
             : "ocam: the model does not reach the declared field of view");
  const auto rho = detail::solve_increasing([this](double r) { return theta_of_rho(r); }, dtheta,
                                            max_field_angle, 0.0, rho_hi, 0.5 * rho_hi);
  if (!rho) throw std::invalid_argument("ocam: cannot find the radius of the declared field of view");
  rho_max_ = *rho;
  theta_max_ = max_field_angle;
}

double OCamLens::pol(double rho) const {
  double z = 0;
  for (auto it = m_.pol.rbegin(); it != m_.pol.rend(); ++it) z = z * rho + *it;
  return z;
}

double OCamLens::pol_derivative(double rho) const {
  double z = 0;
  for (std::size_t i = m_.pol.size() - 1; i >= 1; --i) z = z * rho + static_cast<double>(i) * m_.pol[i];
  return z;
}

double OCamLens::theta_of_rho(double rho) const { return std::atan2(rho, -pol(rho)); }

double OCamLens::dtheta_drho(double rho) const {
  const double p = pol(rho);
  return (-p + rho * pol_derivative(rho)) / (rho * rho + p * p);
}

// ray() and ray_row share these three steps, so they give the same bits: the pre-affine point and
// its radius, the polynomial (Horner, the coefficients in the outer loop so that the pixel loop
// vectorises), and the direction (Y, X, −Z) normalised.
namespace {

struct PreAffine {
  double xp, yp, rho;
};

inline PreAffine pre_affine(const OCamModel& m, double u, double v) {
  const double dr = v - m.xc, dc = u - m.yc;  // row, column offsets
  const double det = m.c - m.d * m.e;
  const double xp = (dr - m.d * dc) / det, yp = (-m.e * dr + m.c * dc) / det;
  return {xp, yp, std::sqrt(xp * xp + yp * yp)};
}

inline bool finish(double xp, double yp, double pol, bool inside, double& x, double& y, double& z) {
  const double dz = -pol;
  const double n = std::sqrt(yp * yp + xp * xp + dz * dz);
  x = yp / n, y = xp / n, z = dz / n;
  return inside & (n > 0) & (n < HUGE_VAL);  // no short circuit: no branch
}

}  // namespace

std::optional<Eigen::Vector3d> OCamLens::ray(const Eigen::Vector2d& pixel) const {
  if (!pixel.allFinite()) return std::nullopt;
  const PreAffine p = pre_affine(m_, pixel.x(), pixel.y());
  const bool inside = p.rho <= rho_max_ * (1 + detail::kEdgeTol);
  Eigen::Vector3d d;
  if (!finish(p.xp, p.yp, pol(std::min(p.rho, rho_max_)), inside, d.x(), d.y(), d.z())) return std::nullopt;
  return d;
}

void OCamLens::ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                       unsigned char* valid) const {
  const bool finite = std::isfinite(y) && std::isfinite(x0) && std::isfinite(x0 + static_cast<double>(n));
  const double limit = rho_max_ * (1 + detail::kEdgeTol);
  double xp[detail::kRowBlock], yp[detail::kRowBlock], rho[detail::kRowBlock], z[detail::kRowBlock];
  for (std::size_t b = 0; b < n; b += detail::kRowBlock) {
    const std::size_t m = std::min(detail::kRowBlock, n - b);
    for (std::size_t i = 0; i < m; ++i) {
      const PreAffine p = pre_affine(m_, detail::column(x0, b + i), y);
      xp[i] = p.xp, yp[i] = p.yp, rho[i] = p.rho, z[i] = 0;
    }
    // pol(min(ρ, ρmax)) as pol() computes it: z = z·ρ + a_j from the highest coefficient down.
    for (auto it = m_.pol.rbegin(); it != m_.pol.rend(); ++it) {
      const double a = *it;
      for (std::size_t i = 0; i < m; ++i) z[i] = z[i] * std::min(rho[i], rho_max_) + a;
    }
    for (std::size_t i = 0; i < m; ++i) {
      double u, v, w;
      const bool ok = finite & finish(xp[i], yp[i], z[i], rho[i] <= limit, u, v, w);
      valid[b + i] = ok ? 1 : 0;
      dx[b + i] = ok ? u : 0.0;
      dy[b + i] = ok ? v : 0.0;
      dz[b + i] = ok ? w : 1.0;
    }
  }
}

std::optional<Eigen::Vector2d> OCamLens::project(const Eigen::Vector3d& dir_cam) const {
  const auto p = detail::polar_of(dir_cam);
  if (!p || p->theta > theta_max_ + detail::kEdgeTol) return std::nullopt;
  const double theta = std::min(p->theta, theta_max_);
  double guess = rho_max_ * theta / theta_max_;
  if (!m_.invpol.empty()) {  // OCamCalib's own approximate inverse, in t = θ − π/2
    const double t = theta - std::numbers::pi / 2;
    double g = 0;
    for (auto it = m_.invpol.rbegin(); it != m_.invpol.rend(); ++it) g = g * t + *it;
    if (std::isfinite(g)) guess = g;
  }
  const auto rho = detail::solve_increasing([this](double r) { return theta_of_rho(r); },
                                            [this](double r) { return dtheta_drho(r); }, theta,
                                            0.0, rho_max_, guess);
  if (!rho) return std::nullopt;
  // Pre-affine point along the direction's azimuth: OCam (X, Y) = (d.y, d.x) → (s, c).
  const double xp = *rho * p->s, yp = *rho * p->c;
  return Eigen::Vector2d(m_.e * xp + yp + m_.yc, m_.c * xp + m_.d * yp + m_.xc);
}

std::shared_ptr<const Lens> OCamLens::rescaled(double s) const {
  if (!(std::isfinite(s) && s > 0)) throw std::invalid_argument("pixel scale must be > 0");
  OCamModel m = m_;
  for (std::size_t i = 0; i < m.pol.size(); ++i)
    m.pol[i] *= std::pow(s, 1.0 - static_cast<double>(i));
  for (double& p : m.invpol) p *= s;
  m.xc = s * (m.xc + 0.5) - 0.5;
  m.yc = s * (m.yc + 0.5) - 0.5;
  m.width = static_cast<int>(std::floor(s * m.width + 1e-9));
  m.height = static_cast<int>(std::floor(s * m.height + 1e-9));
  return std::make_shared<OCamLens>(m, theta_max_);
}

std::vector<std::pair<std::string, double>> OCamLens::parameters() const {
  std::vector<std::pair<std::string, double>> p;
  auto key = [](char prefix, std::size_t i) {
    std::string k(1, prefix);
    k += std::to_string(i);
    return k;
  };
  for (std::size_t i = 0; i < m_.pol.size(); ++i) p.emplace_back(key('a', i), m_.pol[i]);
  for (std::size_t i = 0; i < m_.invpol.size(); ++i) p.emplace_back(key('p', i), m_.invpol[i]);
  for (auto [name, v] : {std::pair<const char*, double>{"xc", m_.xc}, {"yc", m_.yc}, {"c", m_.c},
                         {"d", m_.d}, {"e", m_.e}, {"height", m_.height}, {"width", m_.width},
                         {"fov_deg", deg_from_rad(2 * theta_max_)}})
    p.emplace_back(name, v);
  return p;
}

LensModel ocam_lens_model() {
  LensModel m;
  m.name = "ocam";
  m.description = "Scaramuzza's OCamCalib polynomial, read from its calib_results.txt";
  m.fields = {LensField::ocamcalib_path};
  m.size_from_file = true;
  m.make = [](const LensSpec& s) -> std::shared_ptr<const Lens> {
    for (auto [given, field] : {std::pair{s.fx.has_value(), "fx"}, {s.fy.has_value(), "fy"}, {s.cx.has_value(), "cx"},
                                {s.cy.has_value(), "cy"}, {s.focal_mm.has_value(), "focal_mm"},
                                {s.pitch_um.has_value(), "pitch_um"}})
      if (given) detail::lens_fail(std::string(field) + ": not used by model ocam (the calibration file sets it)");
    if (s.ocamcalib_path.empty() && s.ocamcalib_text.empty()) detail::lens_fail("ocamcalib_path is required for model ocam");
    const OCamModel om = s.ocamcalib_text.empty()
                             ? load_ocamcalib(s.ocamcalib_path)
                             : parse_ocamcalib(s.ocamcalib_text, s.ocamcalib_path.empty() ? "calib_results.txt" : s.ocamcalib_path);
    if (s.width != 0 && s.width != om.width)
      detail::lens_fail("width " + std::to_string(s.width) + " differs from the calibration's " + std::to_string(om.width));
    if (s.height != 0 && s.height != om.height)
      detail::lens_fail("height " + std::to_string(s.height) + " differs from the calibration's " + std::to_string(om.height));
    return std::make_shared<OCamLens>(om, detail::half_fov(s, false));
  };
  return m;
}

}  // namespace skypol::camera
