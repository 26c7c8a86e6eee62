// The calibration importers (calibration_import.h): one small reader per format, all ending in a
// LensSpec that make_lens checks.
#include "camera/calibration_import.h"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "camera/colmap_import.h"
#include "camera/detail/yaml_tree.h"
#include "camera/ocam_lens.h"
#include "sky/units.h"

namespace skypol::camera {
namespace {

using detail::YamlNode;

[[noreturn]] void fail_at(const Calibration& c, int line, const std::string& msg) {
  throw std::invalid_argument(c.name + ":" + std::to_string(line) + ": " + msg);
}

double number_of(const Calibration& c, const YamlNode& n, const std::string& what) {
  if (n.kind != YamlNode::Kind::scalar) fail_at(c, n.line, what + ": expected a number");
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(n.value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != n.value.size() || !std::isfinite(v))
    fail_at(c, n.line, what + ": \"" + n.value + "\" is not a number");
  return v;
}

int size_of(const Calibration& c, const YamlNode& n, const std::string& what) {
  const double v = number_of(c, n, what);
  if (v < 1 || v > 65536 || v != std::floor(v)) fail_at(c, n.line, what + ": expected a whole number of pixels in [1, 65536]");
  return static_cast<int>(v);
}

std::vector<double> numbers_of(const Calibration& c, const YamlNode& n, const std::string& what) {
  if (n.kind != YamlNode::Kind::sequence) fail_at(c, n.line, what + ": expected a list of numbers");
  std::vector<double> v;
  for (const YamlNode& i : n.items) v.push_back(number_of(c, i, what));
  return v;
}

const YamlNode& required(const Calibration& c, const YamlNode& map, const std::string& key, const std::string& where) {
  const YamlNode* n = map.find(key);
  if (!n) fail_at(c, map.line, "missing key '" + key + "'" + where);
  return *n;
}

void no_selector(const Calibration& c) {
  if (!c.camera.empty())
    throw std::invalid_argument(c.name + ": a " + c.format + " file holds one camera; calibration_camera \"" + c.camera +
                                "\" does not apply");
}

// ---- COLMAP cameras.txt ----
LensSpec from_colmap(const Calibration& c) {
  std::istringstream in(c.text);
  std::string line, ids;
  struct Found {
    int number;
    std::string line;
  };
  std::vector<Found> cams;
  for (int n = 1; std::getline(in, line); ++n) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream l(line);
    std::string id;
    l >> id;
    ids += (ids.empty() ? "" : ", ") + id;
    if (c.camera.empty() || id == c.camera) cams.push_back({n, line});
  }
  if (ids.empty()) throw std::invalid_argument(c.name + ": no camera lines (expected \"CAMERA_ID MODEL WIDTH HEIGHT PARAMS...\")");
  if (cams.empty()) throw std::invalid_argument(c.name + ": no camera with CAMERA_ID " + c.camera + " (the file has " + ids + ")");
  if (cams.size() > 1)
    throw std::invalid_argument(c.name + ": " + std::to_string(cams.size()) + " cameras (" + ids +
                                "); choose one with calibration_camera");
  try {
    return lens_spec_from_colmap(cams[0].line);
  } catch (const std::invalid_argument& e) {
    fail_at(c, cams[0].number, e.what());
  }
}

// ---- OpenCV FileStorage (YAML or JSON) ----
// An !!opencv-matrix (YAML tag) or {"type_id": "opencv-matrix", ...} (JSON): rows × cols numbers.
std::vector<double> opencv_matrix(const Calibration& c, const YamlNode& n, const std::string& key, std::size_t rows,
                                  std::size_t cols_or_count, bool vector) {
  if (n.kind == YamlNode::Kind::sequence) {  // a plain list is accepted too
    const auto v = numbers_of(c, n, key);
    if (v.size() != rows * cols_or_count)
      fail_at(c, n.line, key + ": expected " + std::to_string(rows * cols_or_count) + " numbers, got " + std::to_string(v.size()));
    return v;
  }
  if (n.kind != YamlNode::Kind::mapping) fail_at(c, n.line, key + ": expected an opencv-matrix");
  const auto r = size_of(c, required(c, n, "rows", " in " + key), key + ".rows");
  const auto k = size_of(c, required(c, n, "cols", " in " + key), key + ".cols");
  const YamlNode& data = required(c, n, "data", " in " + key);
  auto v = numbers_of(c, data, key + ".data");
  if (v.size() != static_cast<std::size_t>(r) * k)
    fail_at(c, data.line, key + ".data: " + std::to_string(v.size()) + " numbers for a " + std::to_string(r) + "×" +
                              std::to_string(k) + " matrix");
  const bool ok = vector ? (v.size() == cols_or_count && (r == 1 || k == 1))
                         : (static_cast<std::size_t>(r) == rows && static_cast<std::size_t>(k) == cols_or_count);
  if (!ok) {
    if (vector && key == "D" && (v.size() == 5 || v.size() == 8 || v.size() == 12 || v.size() == 14))
      fail_at(c, n.line, "D has " + std::to_string(v.size()) +
                             " coefficients: that is cv::calibrateCamera's pinhole model, which is not a fisheye "
                             "model (supported: cv::fisheye with 4, cv::omnidir with 4 and xi)");
    fail_at(c, n.line, key + ": expected " + (vector ? std::to_string(cols_or_count) + " coefficients" :
                                                       std::to_string(rows) + "×" + std::to_string(cols_or_count)) +
                           ", got " + std::to_string(r) + "×" + std::to_string(k));
  }
  return v;
}

const YamlNode* first_of(const YamlNode& root, std::initializer_list<const char*> keys, std::string& found) {
  for (const char* k : keys)
    if (const YamlNode* n = root.find(k)) {
      found = k;
      return n;
    }
  return nullptr;
}

LensSpec from_opencv(const Calibration& c) {
  no_selector(c);
  const YamlNode root = detail::parse_yaml(c.text, c.name);
  if (root.kind != YamlNode::Kind::mapping) fail_at(c, root.line, "expected a FileStorage mapping (K, D, ...)");
  std::string kname, dname;
  const YamlNode* kn = first_of(root, {"K", "camera_matrix", "cameraMatrix"}, kname);
  const YamlNode* dn = first_of(root, {"D", "distortion_coefficients", "dist_coeffs", "distCoeffs"}, dname);
  if (!kn) fail_at(c, root.line, "missing the camera matrix (key K or camera_matrix)");
  if (!dn) fail_at(c, root.line, "missing the distortion coefficients (key D or distortion_coefficients)");
  const auto k = opencv_matrix(c, *kn, kname, 3, 3, false);
  if (k[3] != 0 || k[6] != 0 || k[7] != 0 || k[8] != 1)
    fail_at(c, kn->line, kname + ": expected [fx s cx; 0 fy cy; 0 0 1]");
  LensSpec s;
  // Image size: image_width/image_height (OpenCV's samples) or image_size/imageSize [w, h].
  std::string sname;
  if (const YamlNode* w = root.find("image_width")) {
    s.width = size_of(c, *w, "image_width");
    s.height = size_of(c, required(c, root, "image_height", " (with image_width)"), "image_height");
  } else if (const YamlNode* z = first_of(root, {"image_size", "imageSize", "resolution"}, sname)) {
    const auto v = opencv_matrix(c, *z, sname, 1, 2, true);
    YamlNode wn, hn;
    wn.value = std::to_string(v[0]), hn.value = std::to_string(v[1]);
    wn.line = hn.line = z->line;
    s.width = size_of(c, wn, sname);
    s.height = size_of(c, hn, sname);
  } else {
    fail_at(c, root.line, "missing the image size (image_width and image_height, or image_size)");
  }
  s.fx = k[0];
  s.fy = k[4];
  s.cx = k[2];
  s.cy = k[5];
  const auto d = opencv_matrix(c, *dn, dname == "D" ? "D" : dname, 1, 4, true);
  if (const YamlNode* xn = root.find("xi")) {  // cv::omnidir
    const double xi = xn->kind == YamlNode::Kind::scalar ? number_of(c, *xn, "xi") : opencv_matrix(c, *xn, "xi", 1, 1, true)[0];
    s.model = "mei";
    s.skew = k[1];
    s.coefficients = {xi, d[0], d[1], d[2], d[3]};
  } else {  // cv::fisheye
    if (k[1] != 0) fail_at(c, kn->line, kname + ": cv::fisheye skew (K(0,1) = " + std::to_string(k[1]) + ") is not supported");
    s.model = "kannala_brandt";
    s.coefficients = d;
  }
  fit_fov_to_sensor(s);
  return s;
}

// ---- Kalibr camchain YAML ----
LensSpec from_kalibr(const Calibration& c) {
  const YamlNode root = detail::parse_yaml(c.text, c.name);
  if (root.kind != YamlNode::Kind::mapping) fail_at(c, root.line, "expected a camchain mapping (cam0: ...)");
  std::string names;
  for (const auto& [k, v] : root.fields) names += (names.empty() ? "" : ", ") + k;
  const YamlNode* cam = nullptr;
  std::string which = c.camera;
  if (which.empty()) {
    if (root.fields.size() != 1)
      fail_at(c, root.line, std::to_string(root.fields.size()) + " cameras (" + names + "); choose one with calibration_camera");
    which = root.fields[0].first;
  }
  cam = root.find(which);
  if (!cam) fail_at(c, root.line, "no camera \"" + which + "\" (the file has " + names + ")");
  if (cam->kind != YamlNode::Kind::mapping) fail_at(c, cam->line, which + ": expected a mapping");
  const std::string where = " in " + which;
  const YamlNode& model_n = required(c, *cam, "camera_model", where);
  const std::string model = model_n.value;
  const YamlNode& in = required(c, *cam, "intrinsics", where);
  const auto p = numbers_of(c, in, which + ".intrinsics");
  const YamlNode& res = required(c, *cam, "resolution", where);
  const auto wh = numbers_of(c, res, which + ".resolution");
  if (wh.size() != 2) fail_at(c, res.line, which + ".resolution: expected [width, height]");
  std::string dist = "none";
  std::vector<double> dc;
  if (const YamlNode* dm = cam->find("distortion_model")) dist = dm->value;
  if (const YamlNode* dv = cam->find("distortion_coeffs")) dc = numbers_of(c, *dv, which + ".distortion_coeffs");
  const int dist_line = cam->find("distortion_model") ? cam->find("distortion_model")->line : cam->line;
  auto need = [&](std::size_t n, const char* order) {
    if (p.size() != n)
      fail_at(c, in.line, which + ".intrinsics: camera_model " + model + " needs " + std::to_string(n) + " (" + order +
                              "), got " + std::to_string(p.size()));
  };
  auto need_dist = [&](const std::string& legal, std::size_t n) {
    if (dist != legal) fail_at(c, dist_line, which + ": camera_model " + model + " with distortion_model " + dist + " is not supported");
    if (dc.size() != n)
      fail_at(c, dist_line, which + ".distortion_coeffs: " + dist + " needs " + std::to_string(n) + ", got " + std::to_string(dc.size()));
  };
  LensSpec s;
  YamlNode wn = res.items[0], hn = res.items[1];
  s.width = size_of(c, wn, which + ".resolution");
  s.height = size_of(c, hn, which + ".resolution");
  auto pinhole = [&](std::size_t at) {
    s.fx = p[at];
    s.fy = p[at + 1];
    s.cx = p[at + 2];
    s.cy = p[at + 3];
  };
  if (model == "ds") {
    need(6, "xi, alpha, fu, fv, pu, pv");
    if (dist != "none") need_dist("none", 0);
    s.model = "double_sphere";
    pinhole(2);
    s.coefficients = {p[0], p[1]};
  } else if (model == "eucm") {
    need(6, "alpha, beta, fu, fv, pu, pv");
    if (dist != "none") need_dist("none", 0);
    s.model = "eucm";
    pinhole(2);
    s.coefficients = {p[0], p[1]};
  } else if (model == "omni") {
    need(5, "xi, fu, fv, pu, pv");
    s.model = "mei";
    pinhole(1);
    if (dist == "none") {
      s.coefficients = {p[0], 0, 0, 0, 0};
    } else {
      need_dist("radtan", 4);
      s.coefficients = {p[0], dc[0], dc[1], dc[2], dc[3]};
    }
  } else if (model == "pinhole") {
    need(4, "fu, fv, pu, pv");
    pinhole(0);
    if (dist == "none") {
      s.model = "perspective";
    } else {
      need_dist("equidistant", 4);
      s.model = "kannala_brandt";
      s.coefficients = dc;
    }
  } else {
    fail_at(c, model_n.line, which + ".camera_model \"" + model + "\" is not supported (supported: ds, eucm, omni, pinhole)");
  }
  fit_fov_to_sensor(s);
  return s;
}

// ---- basalt calibration.json ----
LensSpec from_basalt(const Calibration& c) {
  const YamlNode root = detail::parse_yaml(c.text, c.name);
  const YamlNode* v0 = root.find("value0");
  if (!v0) fail_at(c, root.line, "missing key 'value0' (basalt's calibration.json)");
  const YamlNode& list = required(c, *v0, "intrinsics", " in value0");
  if (list.kind != YamlNode::Kind::sequence || list.items.empty()) fail_at(c, list.line, "intrinsics: expected a list of cameras");
  std::size_t i = 0;
  if (!c.camera.empty()) {
    try {
      std::size_t used = 0;
      i = std::stoul(c.camera, &used);
      if (used != c.camera.size()) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw std::invalid_argument(c.name + ": calibration_camera for basalt is a camera index (0, 1, ...), got \"" + c.camera + "\"");
    }
  } else if (list.items.size() != 1) {
    fail_at(c, list.line, std::to_string(list.items.size()) + " cameras; choose one with calibration_camera (0.." +
                              std::to_string(list.items.size() - 1) + ")");
  }
  if (i >= list.items.size())
    fail_at(c, list.line, "no camera " + std::to_string(i) + " (the file has " + std::to_string(list.items.size()) + ")");
  const YamlNode& cam = list.items[i];
  const YamlNode& type_n = required(c, cam, "camera_type", "");
  const YamlNode& in = required(c, cam, "intrinsics", "");
  auto get = [&](const char* k) { return number_of(c, required(c, in, k, " in intrinsics"), k); };
  const std::string type = type_n.value;
  if (type != "ds" && type != "eucm" && type != "kb4" && type != "pinhole")
    fail_at(c, type_n.line, "camera_type \"" + type + "\" is not supported (supported: ds, eucm, kb4, pinhole)");
  LensSpec s;
  const YamlNode& res = required(c, *v0, "resolution", " in value0");
  if (res.kind != YamlNode::Kind::sequence || res.items.size() <= i) fail_at(c, res.line, "resolution: no entry for camera " + std::to_string(i));
  const auto wh = numbers_of(c, res.items[i], "resolution");
  if (wh.size() != 2) fail_at(c, res.items[i].line, "resolution: expected [width, height]");
  s.width = size_of(c, res.items[i].items[0], "resolution");
  s.height = size_of(c, res.items[i].items[1], "resolution");
  s.fx = get("fx");
  s.fy = get("fy");
  s.cx = get("cx");
  s.cy = get("cy");
  if (type == "ds") {
    s.model = "double_sphere";
    s.coefficients = {get("xi"), get("alpha")};
  } else if (type == "eucm") {
    s.model = "eucm";
    s.coefficients = {get("alpha"), get("beta")};
  } else if (type == "kb4") {
    s.model = "kannala_brandt";
    s.coefficients = {get("k1"), get("k2"), get("k3"), get("k4")};
  } else {
    s.model = "perspective";
  }
  fit_fov_to_sensor(s);
  return s;
}

LensSpec from_ocamcalib(const Calibration& c) {
  no_selector(c);
  LensSpec s;
  s.model = "ocam";
  s.ocamcalib_path = c.name;
  s.ocamcalib_text = c.text;
  (void)parse_ocamcalib(c.text, c.name);  // its errors name the file and line
  return s;
}

}  // namespace

const std::vector<std::string_view>& calibration_formats() {
  static const std::vector<std::string_view> f = {"colmap", "opencv", "kalibr", "basalt", "ocamcalib"};
  return f;
}

LensSpec lens_spec_from_calibration(const Calibration& c) {
  if (c.format == "colmap") return from_colmap(c);
  if (c.format == "opencv") return from_opencv(c);
  if (c.format == "kalibr") return from_kalibr(c);
  if (c.format == "basalt") return from_basalt(c);
  if (c.format == "ocamcalib") return from_ocamcalib(c);
  throw std::invalid_argument("unknown calibration format \"" + c.format + "\" (expected colmap, opencv, kalibr, basalt or ocamcalib)");
}

namespace {

// The lens of `s` at the largest field of view the model accepts, that field of view in *widest;
// null if it accepts none.
std::shared_ptr<const Lens> widest_lens(const LensSpec& s, double* widest) {
  // The largest field of view the model accepts: bisection on make_lens (the models check their
  // own limits: a fold, a turning point, the unified models' valid angle).
  auto accepts = [&](double fov) {
    LensSpec t = s;
    t.fov_deg = fov;
    try {
      return make_lens(t);
    } catch (const std::invalid_argument&) {
      return std::shared_ptr<const Lens>();
    }
  };
  const double top = s.model == "perspective" ? 179.999 : 360;
  double lo = 0, hi = top;
  std::shared_ptr<const Lens> lens = accepts(top);
  if (lens) {
    lo = top;
  } else {
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      (accepts(mid) ? lo : hi) = mid;
    }
    lens = lo > 0 ? accepts(lo) : nullptr;
  }
  *widest = lo;
  return lens;
}

}  // namespace

void fit_fov_to_sensor(LensSpec& s) {
  double lo = 0;
  const std::shared_ptr<const Lens> lens = widest_lens(s, &lo);
  if (!lens) return;
  // The farthest corner: every pixel-edge corner that has a ray; one without sees past the limit.
  double theta = 0;
  for (double u : {-0.5, s.width - 0.5})
    for (double v : {-0.5, s.height - 0.5}) {
      const auto d = lens->ray({u, v});
      if (!d) return void(s.fov_deg = lo);
      theta = std::max(theta, std::atan2(std::hypot(d->x(), d->y()), d->z()));
    }
  s.fov_deg = std::min(lo, deg_from_rad(2 * theta));
}

void fit_fov_to_image_circle(LensSpec& s, double radius_px) {
  if (!(radius_px > 0)) throw std::invalid_argument("the image circle's radius must be > 0 pixels");
  double lo = 0;
  const std::shared_ptr<const Lens> lens = widest_lens(s, &lo);
  if (!lens) throw std::invalid_argument("the lens model accepts no field of view");
  const Intrinsics& k = lens->intrinsics();
  // The smallest angle off the axis at the circle, every 0.5° around it (a pixel without a ray
  // lies past the model's own limit, which then bounds the field).
  double theta = std::min(rad_from_deg(lo / 2), lens->max_field_angle());
  for (int a = 0; a < 720; ++a) {
    const double phi = a * std::numbers::pi / 360;
    const auto d = lens->ray({k.cx + radius_px * std::cos(phi), k.cy + radius_px * std::sin(phi)});
    if (d) theta = std::min(theta, std::atan2(std::hypot(d->x(), d->y()), d->z()));
  }
  s.fov_deg = deg_from_rad(2 * theta);
}

}  // namespace skypol::camera
