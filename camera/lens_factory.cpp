// LensSpec → Lens: field checks, unit conversions, then the model's constructor.
#include "camera/lens_factory.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "camera/double_sphere.h"
#include "camera/eucm.h"
#include "camera/mei_lens.h"
#include "camera/intrinsics.h"
#include "camera/kannala_brandt.h"
#include "camera/ocam_lens.h"
#include "camera/radial_lens.h"
#include "camera/tabulated_lens.h"
#include "camera/thin_prism_fisheye.h"

namespace skypol::camera {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

[[noreturn]] void fail(const std::string& msg) { throw std::invalid_argument(msg); }

std::string num(double x) {
  std::string s = std::to_string(x);
  s.erase(s.find_last_not_of('0') + 1);
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

void unused(bool given, const char* field, const std::string& model) {
  if (given) fail(std::string(field) + ": not used by model " + model);
}

double positive(const std::optional<double>& v, const char* field) {
  if (!(std::isfinite(*v) && *v > 0)) fail(std::string(field) + " must be > 0");
  return *v;
}

// Scale and principal point for the models that take fx, fy, cx, cy.
Intrinsics pinhole_intrinsics(const LensSpec& s) {
  if (s.width < 1) fail("width must be > 0");
  if (s.height < 1) fail("height must be > 0");
  Intrinsics k;
  k.width = s.width;
  k.height = s.height;
  const bool by_px = s.fx || s.fy, by_mm = s.focal_mm || s.pitch_um;
  if (by_px && by_mm) fail("give either fx/fy or focal_mm/pitch_um, not both");
  if (by_px) {
    if (!s.fx) fail("fx is required when fy is given");
    k.fx = positive(s.fx, "fx");
    k.fy = s.fy ? positive(s.fy, "fy") : k.fx;
  } else if (by_mm) {
    if (!s.focal_mm) fail("focal_mm is required with pitch_um");
    if (!s.pitch_um) fail("pitch_um is required with focal_mm");
    k.fx = k.fy = positive(s.focal_mm, "focal_mm") / (positive(s.pitch_um, "pitch_um") * 1e-3);
  } else {
    fail("model " + s.model + " needs fx (pixels) or focal_mm and pitch_um");
  }
  k.cx = s.cx ? *s.cx : 0.5 * (s.width - 1);
  k.cy = s.cy ? *s.cy : 0.5 * (s.height - 1);
  if (!std::isfinite(k.cx) || k.cx < -0.5 || k.cx > s.width - 0.5)
    fail("principal point off the sensor (cx = " + num(k.cx) + ", width = " + std::to_string(s.width) + ")");
  if (!std::isfinite(k.cy) || k.cy < -0.5 || k.cy > s.height - 0.5)
    fail("principal point off the sensor (cy = " + num(k.cy) + ", height = " + std::to_string(s.height) + ")");
  return k;
}

double half_fov(const LensSpec& s, bool required) {
  if (!s.fov_deg) {
    if (required) fail("fov_deg is required for model " + s.model);
    return 0;
  }
  if (!(std::isfinite(*s.fov_deg) && *s.fov_deg > 0 && *s.fov_deg <= 360))
    fail("fov_deg must be in (0, 360], got " + num(*s.fov_deg));
  return 0.5 * *s.fov_deg * kDeg;
}

std::shared_ptr<const Lens> build(const LensSpec& s) {
  const std::string& m = s.model;
  const bool radial = std::find(lens_model_names().begin(), lens_model_names().begin() + 5, m) !=
                      lens_model_names().begin() + 5;
  const bool with_coefficients = m == "kannala_brandt" || m == "double_sphere" || m == "thin_prism_fisheye" ||
                                 m == "mei" || m == "eucm";
  if (!with_coefficients) unused(!s.coefficients.empty(), "coefficients", m);
  if (m != "mei") unused(s.skew.has_value(), "skew", m);
  if (m != "tabulated") unused(!s.table.empty(), "table", m);
  if (m != "ocam") unused(!s.ocamcalib_path.empty() || !s.ocamcalib_text.empty(), "ocamcalib_path", m);
  if (m != "kannala_brandt") unused(s.clamp_fov_to_monotone, "clamp_fov_to_monotone", m);

  if (radial) {
    return std::make_shared<RadialLens>(parse_mapping(m), pinhole_intrinsics(s), half_fov(s, true));
  }
  if (m == "kannala_brandt") {
    if (s.coefficients.size() != 4)
      fail("coefficients: kannala_brandt needs 4 (k1 k2 k3 k4), got " + std::to_string(s.coefficients.size()));
    return std::make_shared<KannalaBrandtLens>(
        pinhole_intrinsics(s),
        std::array<double, 4>{s.coefficients[0], s.coefficients[1], s.coefficients[2], s.coefficients[3]},
        half_fov(s, true),
        s.clamp_fov_to_monotone ? KannalaBrandtLens::OnTurnover::clamp_fov
                                : KannalaBrandtLens::OnTurnover::reject);
  }
  if (m == "double_sphere") {
    if (s.coefficients.size() != 2)
      fail("coefficients: double_sphere needs 2 (xi alpha), got " + std::to_string(s.coefficients.size()));
    return std::make_shared<DoubleSphereLens>(pinhole_intrinsics(s), s.coefficients[0],
                                              s.coefficients[1], half_fov(s, true));
  }
  auto need_coefficients = [&](std::size_t n, const char* order) {
    if (s.coefficients.size() != n)
      fail("coefficients: " + m + " needs " + std::to_string(n) + " (" + order + "), got " +
           std::to_string(s.coefficients.size()));
  };
  if (m == "thin_prism_fisheye") {
    need_coefficients(8, "k1 k2 p1 p2 k3 k4 sx1 sy1");
    std::array<double, 8> c{};
    std::copy(s.coefficients.begin(), s.coefficients.end(), c.begin());
    return std::make_shared<ThinPrismFisheyeLens>(pinhole_intrinsics(s), c, half_fov(s, true));
  }
  if (m == "mei") {
    need_coefficients(5, "xi k1 k2 p1 p2");
    const auto& c = s.coefficients;
    return std::make_shared<MeiLens>(pinhole_intrinsics(s), s.skew.value_or(0.0), c[0],
                                     std::array<double, 4>{c[1], c[2], c[3], c[4]}, half_fov(s, true));
  }
  if (m == "eucm") {
    need_coefficients(2, "alpha beta");
    return std::make_shared<EucmLens>(pinhole_intrinsics(s), s.coefficients[0], s.coefficients[1], half_fov(s, true));
  }
  if (m == "tabulated") {
    unused(s.fx.has_value() || s.fy.has_value(), "fx/fy", m);
    unused(s.focal_mm.has_value(), "focal_mm", m);
    if (s.table.empty()) fail("table: tabulated needs (field angle deg, image height mm) rows");
    if (!s.pitch_um) fail("pitch_um is required for model tabulated");
    LensSpec px = s;  // reuse the pinhole checks with 1 mm of image height = 1/pitch pixels
    px.focal_mm = 1.0;
    Intrinsics k = pinhole_intrinsics(px);
    HeightTable t = height_table_from_deg_mm(s.table);
    const double tmax = half_fov(s, false);
    if (tmax > 0) {
      if (t.theta.empty() || tmax > t.theta.back() * (1 + 1e-12))
        fail("fov_deg " + num(*s.fov_deg) + " exceeds the table's last field angle");
      const TabulatedLens full(k, t);  // checks the table; then cut it at tmax
      const double h = full.height(tmax);
      HeightTable cut;
      for (std::size_t i = 0; i < t.theta.size() && t.theta[i] < tmax; ++i) {
        cut.theta.push_back(t.theta[i]);
        cut.height.push_back(t.height[i]);
      }
      cut.theta.push_back(tmax);
      cut.height.push_back(h);
      t = cut;
    }
    return std::make_shared<TabulatedLens>(k, t);
  }
  if (m == "ocam") {
    for (auto [given, field] : {std::pair{s.fx.has_value(), "fx"}, {s.fy.has_value(), "fy"},
                                {s.cx.has_value(), "cx"}, {s.cy.has_value(), "cy"},
                                {s.focal_mm.has_value(), "focal_mm"}, {s.pitch_um.has_value(), "pitch_um"}})
      if (given) fail(std::string(field) + ": not used by model ocam (the calibration file sets it)");
    if (s.ocamcalib_path.empty() && s.ocamcalib_text.empty()) fail("ocamcalib_path is required for model ocam");
    const OCamModel om = s.ocamcalib_text.empty() ? load_ocamcalib(s.ocamcalib_path)
                                                  : parse_ocamcalib(s.ocamcalib_text, s.ocamcalib_path.empty() ? "calib_results.txt" : s.ocamcalib_path);
    if (s.width != 0 && s.width != om.width)
      fail("width " + std::to_string(s.width) + " differs from the calibration's " + std::to_string(om.width));
    if (s.height != 0 && s.height != om.height)
      fail("height " + std::to_string(s.height) + " differs from the calibration's " + std::to_string(om.height));
    return std::make_shared<OCamLens>(om, half_fov(s, false));
  }
  std::string legal;
  for (auto n : lens_model_names()) legal += (legal.empty() ? "" : ", ") + std::string(n);
  fail("unknown lens model \"" + m + "\" (expected one of " + legal + ")");
}

}  // namespace

const std::vector<std::string_view>& lens_model_names() {
  static const std::vector<std::string_view> names = {
      "perspective",    "stereographic", "equidistant", "equisolid", "orthographic",
      "kannala_brandt", "double_sphere", "ocam",        "tabulated",  "thin_prism_fisheye",
      "mei",            "eucm"};
  return names;
}

std::shared_ptr<const Lens> make_lens(const LensSpec& spec) {
  if (spec.binning < 1) fail("binning must be >= 1, got " + std::to_string(spec.binning));
  auto lens = build(spec);
  return spec.binning == 1 ? lens : binned(*lens, spec.binning);
}

}  // namespace skypol::camera
