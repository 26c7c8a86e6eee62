#include "skypole/estimate_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <stdexcept>

#include <Eigen/Geometry>

#include "sky/units.h"
#include "skypole/evaluate.h"
#include "skypole/sky_images.h"
#include "skypole/sky_mask.h"

namespace skypol::skypole {
namespace {

// The third panel's categories, in this order (the indices of PlotFrame::category).
enum Category : std::uint8_t { kRead, kUnpolarized, kMaskedOther, kClipped, kOccluded, kNotRead };
std::vector<stack::PlotCategory> categories() {
  return {
      {{0.80f, 0.80f, 0.80f}, "sky read by the estimators (grey: brighter where DoLP is higher)"},
      {{0.25f, 0.45f, 0.95f}, "unpolarized: DoLP below half the clear sky's in this frame (sky mask: cloud, neutral points)"},
      {{0.62f, 0.30f, 0.78f}, "left out by the sky mask for its AoLP, saturation or darkness in some frames"},
      {{0.95f, 0.45f, 0.10f}, "clipped by the sensor (the stack's clipped channel)"},
      {{0.52f, 0.40f, 0.34f}, "occluded or masked in the stack (mask 0)"},
      {{0.30f, 0.30f, 0.30f}, "not read: below the elevation limit, or unusable in another frame"},
  };
}

const stack::Rgb kSunFound{1.0f, 0.75f, 0.0f};
const stack::Rgb kSunEphemeris{1.0f, 1.0f, 0.55f};

stack::Rgb scaled(stack::Rgb c, float k) {
  for (float& v : c) v *= k;
  return c;
}

// A number with `decimals` decimals.
std::string num(double v, int decimals = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string pixel_text(const Eigen::Vector2d& p) { return "pixel (" + num(p.x(), 1) + ", " + num(p.y(), 1) + ")"; }

// A unit camera-frame direction's pixel, or nullopt where the lens does not image it.
std::optional<Eigen::Vector2d> pixel_of(const camera::Lens& lens, const Eigen::Vector3d& d_cam) {
  return lens.project(d_cam.normalized());
}

// The circle of angular radius r about unit direction p, projected: polylines broken where the
// lens does not image the circle.
std::vector<std::vector<Eigen::Vector2d>> projected_circle(const camera::Lens& lens, const Eigen::Vector3d& p, double r) {
  const Eigen::Vector3d a = p.unitOrthogonal(), b = p.cross(a);
  std::vector<std::vector<Eigen::Vector2d>> pieces(1);
  constexpr int kSteps = 360;
  for (int k = 0; k <= kSteps; ++k) {
    const double phi = 2 * std::numbers::pi * k / kSteps;
    const Eigen::Vector3d d = std::cos(r) * p + std::sin(r) * (std::cos(phi) * a + std::sin(phi) * b);
    if (const auto px = pixel_of(lens, d)) {
      pieces.back().push_back(*px);
    } else if (!pieces.back().empty()) {
      pieces.emplace_back();
    }
  }
  return pieces;
}

std::string describe(const PoleEstimate& e, const stack::Stack& stack) {
  if (!e.valid) return e.method + ": declined: " + e.why_invalid;
  std::string s = e.method + ": north bearing " +
                  (e.heading_deg ? num(*e.heading_deg) + " deg" : std::string("undefined")) + ", latitude " +
                  num(e.latitude_deg) + " deg, 95% cone " + num(e.cone95_deg) + " deg";
  s += e.pixel ? ", pole at " + pixel_text(*e.pixel) : std::string(", pole outside the image");
  if (stack.truth_known) {
    s += ", " + num(score(e, stack.frames.front().truth).angular_error_deg) + " deg from the truth";
  }
  if (!e.note.empty()) s += "; " + e.note;
  return s;
}

}  // namespace

std::string plot_ascii(std::string_view text) {
  static const std::pair<std::string_view, std::string_view> kWords[] = {
      {"°", " deg"}, {"σ", "sigma"}, {"×", "x"}, {"−", "-"}, {"–", "-"}, {"—", "-"}, {"≈", "~"},
      {"⟂", "perp."}, {"≤", "<="}, {"≥", ">="}, {"…", "..."}, {"²", "^2"}, {"’", "'"}, {"‘", "'"},
      {"“", "\""}, {"”", "\""}, {"α", "alpha"}, {"γ", "gamma"}, {"λ", "lambda"}, {"√", "sqrt"},
  };
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      out += text[i++];
      continue;
    }
    bool known = false;
    for (const auto& [from, to] : kWords) {
      if (text.substr(i, from.size()) == from) {
        out += to;
        i += from.size();
        known = true;
        break;
      }
    }
    if (known) continue;
    // Any other character: one '?' for its whole UTF-8 sequence.
    out += '?';
    ++i;
    while (i < text.size() && (static_cast<unsigned char>(text[i]) & 0xC0) == 0x80) ++i;
  }
  return out;
}

stack::Rgb plot_colour(std::string_view method) {
  static const stack::Rgb kPalette[] = {
      {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 1.0f}, {1.0f, 0.0f, 1.0f},
      {0.0f, 0.5f, 1.0f}, {1.0f, 0.5f, 0.0f}, {0.5f, 0.0f, 1.0f}, {1.0f, 0.0f, 0.5f},
  };
  constexpr std::size_t kColours = sizeof kPalette / sizeof kPalette[0];
  const std::vector<std::string>& names = method_names();
  const auto at = std::find(names.begin(), names.end(), method);
  const std::size_t k = at != names.end() ? static_cast<std::size_t>(at - names.begin())
                                          : std::hash<std::string_view>{}(method);
  return kPalette[k % kColours];
}

namespace {

// The picture without the answers: the panels, the sun's track and the truth.
// `estimates` only lend a heading to place the ephemeris' suns on a capture.
stack::PlotFrame plot_base(const stack::Stack& stack, const std::vector<PoleEstimate>& estimates,
                           const InputOptions& input, const PlotOptions& options) {
  if (stack.frames.empty() || !stack.camera) throw std::invalid_argument("estimate plot: the stack has no frames");
  const std::size_t fi = options.frame.value_or(stack.frames.size() / 2);
  if (fi >= stack.frames.size()) {
    throw std::invalid_argument("estimate plot: frame " + std::to_string(fi) + " asked for, the stack has " +
                                std::to_string(stack.frames.size()));
  }
  const stack::Frame& frame = stack.frames[fi];
  const camera::Lens& lens = stack.camera->lens();
  const SkyImages sky = prepare_sky_images(stack, input, 1, "the estimate plot");
  const std::size_t n = sky.pixels();

  stack::PlotFrame p;
  stack::PreviewFrame& f = p.frame;
  f.width = sky.width;
  f.height = sky.height;
  f.dolp = sky.dolp[fi];
  const std::string aolp_name = "AoLP." + sky.band;
  f.aolp = frame.has(aolp_name) ? frame.channel(aolp_name) : std::vector<float>(n, 0.0f);
  f.mask = frame.has("mask") ? frame.channel("mask") : std::vector<float>(n, 1.0f);
  f.inside = stack::preview_inside(*stack.camera);
  f.title = "frame " + std::to_string(fi) + " of " + std::to_string(stack.frames.size()) + ", " +
            sky::format_iso8601(frame.truth.time) + ", band " + sky.band + (frame.has(aolp_name) ? "" : " (no AoLP)");

  // What became of each pixel.
  const std::vector<float>* clipped = !options.clipped.empty() ? &options.clipped
                                      : frame.has("clipped")   ? &frame.channel("clipped")
                                                               : nullptr;
  if (clipped && clipped->size() != n) throw std::invalid_argument("estimate plot: the clipped channel's size differs from the frame's");
  std::optional<SkyJudgments> judged;
  SkyMask mask;
  std::string mask_failure;
  try {
    judged = judge_sky(sky, all_frames(stack), *stack.camera);
    mask = mask_from_judgments(sky, *judged);
  } catch (const std::exception& e) {
    mask_failure = e.what();
  }
  float dolp_top = valid_quantile(f.dolp, sky, 0.99);
  if (!(dolp_top > 0)) dolp_top = 1;
  p.categories = categories();
  p.category.assign(n, kNotRead);
  p.shade.assign(n, 1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(f.mask[i] > 0)) {
      p.category[i] = clipped && (*clipped)[i] > 0 ? kClipped : kOccluded;
    } else if (!sky.valid[i]) {
      p.category[i] = kNotRead;
    } else if (judged && (judged->marks[fi][i] & SkyJudgments::kLow)) {
      p.category[i] = kUnpolarized;
    } else if (!mask.masked.empty() && mask.masked[i]) {
      p.category[i] = kMaskedOther;
    } else {
      p.category[i] = kRead;
      p.shade[i] = std::isfinite(f.dolp[i]) ? f.dolp[i] / dolp_top : 0.0f;
    }
  }

  // The sun's track: the suns judged by, and the ephemeris' where the site is known.
  const PoleEstimate* placing = nullptr;  // the answer whose heading places the ephemeris on a capture
  for (const PoleEstimate& e : estimates) {
    if (e.valid && e.heading_deg && !placing) placing = &e;
  }
  if (stack.site_known && (stack.truth_known || placing)) {
    // World → camera: the truth's orientation, or the level frame turned by the answer's heading
    // (a direction's world azimuth is its level-frame azimuth + heading; estimate.h).
    const Eigen::Matrix3d camera_from_world =
        stack.truth_known ? frame.truth.world_from_camera.transpose()
                          : Eigen::Matrix3d(sky.level_from_camera.transpose() *
                                            Eigen::AngleAxisd(*placing->heading_deg / kDegPerRad, Eigen::Vector3d::UnitZ()));
    std::vector<Eigen::Vector2d> track;
    for (const stack::Frame& fr : stack.frames) {
      const auto px = pixel_of(lens, camera_from_world * fr.truth.sun.direction);
      if (px) track.push_back(*px);
      if ((!px || &fr == &stack.frames.back()) && !track.empty()) {
        p.lines.push_back({track, kSunEphemeris});
        track.clear();
      }
    }
    if (const auto px = pixel_of(lens, camera_from_world * frame.truth.sun.direction)) {
      p.marks.push_back({*px, kSunEphemeris, stack::PlotMark::Shape::square, 5});
    }
    p.texts.push_back({stack.truth_known ? "ephemeris sun track: the header's suns through the true orientation (square: "
                                           "this frame's)"
                                         : "ephemeris sun track: the header's suns, placed with " + placing->method +
                                               "'s heading (square: this frame's)",
                       kSunEphemeris});
  } else {
    p.texts.push_back({stack.site_known ? "no ephemeris sun track: no answer gives the heading it needs"
                                        : "no ephemeris sun track: the stack does not know its site",
                       std::nullopt});
  }
  if (judged) {
    std::size_t found = 0;
    for (std::size_t k = 0; k < judged->suns.size(); ++k) {
      const auto& s = judged->suns[k];
      if (!s) continue;
      ++found;
      if (const auto px = pixel_of(lens, *s)) {
        p.marks.push_back({*px, kSunFound, stack::PlotMark::Shape::dot, k == fi ? 4 : 2});
      }
    }
    p.texts.push_back({"suns the frames were judged by (" + std::string(judged->have_aolp ? "fitted to the AoLP" : "fitted to the DoLP") +
                           "; the larger dot: this frame's): " + std::to_string(found) + " of " +
                           std::to_string(judged->suns.size()) + " frames",
                       kSunFound});
  } else {
    p.texts.push_back({"no sky mask and no suns: " + mask_failure, std::nullopt});
  }

  const scene::Truth& truth = stack.frames.front().truth;
  if (stack.truth_known) {
    if (truth.pole_pixel) p.marks.push_back({*truth.pole_pixel, kPlotTruthColour, stack::PlotMark::Shape::plus, 8});
    p.texts.push_back({"truth (the stack's header): north bearing " + num(truth.heading_deg) + " deg, latitude " +
                           num(truth.site.latitude_deg) + " deg" +
                           (truth.pole_pixel ? ", pole at " + pixel_text(*truth.pole_pixel)
                                             : std::string(", pole outside the image")),
                       kPlotTruthColour});
  } else {
    p.texts.push_back({"truth unknown: a capture (skypol import) has nothing to score against", std::nullopt});
  }
  return p;
}

// The answers drawn into a picture made by the above: cones, crosses (after every other mark, so
// that they stay on top) and one line of text each, before the truth's.
void add_answers(stack::PlotFrame& p, const stack::Stack& stack, const std::vector<PoleEstimate>& estimates) {
  const camera::Lens& lens = stack.camera->lens();
  std::vector<stack::PlotText> texts;
  // Answers that agree image at the same pixel: the first answer's cross is the largest and each
  // next one smaller, drawn over it, so that every cross shows at least its arms' ends.
  int radius = 5 + 3 * static_cast<int>(estimates.size());
  for (const PoleEstimate& e : estimates) {
    radius -= 3;
    const stack::Rgb colour = plot_colour(e.method);
    if (e.valid) {
      if (e.cone95_deg > 0) {
        for (auto& piece : projected_circle(lens, e.pole_camera, e.cone95_deg / kDegPerRad)) {
          if (!piece.empty()) p.lines.push_back({std::move(piece), scaled(colour, kPlotConeShade)});
        }
      }
      if (e.pixel) p.marks.push_back({*e.pixel, colour, stack::PlotMark::Shape::cross, radius});
    }
    texts.push_back({plot_ascii(describe(e, stack)), colour});
  }
  p.texts.insert(p.texts.end() - 1, texts.begin(), texts.end());
}

}  // namespace

stack::PlotFrame estimate_plot(const stack::Stack& stack, const std::vector<PoleEstimate>& estimates,
                               const InputOptions& input, const PlotOptions& options) {
  stack::PlotFrame p = plot_base(stack, estimates, input, options);
  add_answers(p, stack, estimates);
  return p;
}

void write_estimate_plot(const stack::Stack& stack, const std::vector<PoleEstimate>& estimates,
                         const InputOptions& input, const std::string& path, const PlotOptions& options) {
  stack::write_plot_png(estimate_plot(stack, estimates, input, options), path, options.max_panel_px);
}

std::vector<std::string> write_estimate_plots(const stack::Stack& stack, const std::vector<PoleEstimate>& estimates,
                                              const InputOptions& input, const std::string& target,
                                              const PlotOptions& options) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool folder = (!target.empty() && target.back() == '/') || fs::is_directory(target, ec);
  if (!folder) {
    write_estimate_plot(stack, estimates, input, target, options);
    return {target};
  }
  const stack::PlotFrame base = plot_base(stack, estimates, input, options);
  fs::create_directories(target, ec);
  if (!fs::is_directory(target, ec)) throw std::runtime_error("cannot write the estimate plots: cannot create the folder " + target);
  std::vector<std::string> written;
  for (const PoleEstimate& e : estimates) {
    const std::string path = (fs::path(target) / (e.method + ".png")).string();
    stack::PlotFrame p = base;
    add_answers(p, stack, {e});
    stack::write_plot_png(p, path, options.max_panel_px);
    written.push_back(path);
  }
  return written;
}

}  // namespace skypol::skypole
