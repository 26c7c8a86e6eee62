#include "stack/preview.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <system_error>

#include "sky/units.h"
#include "stack/colormap.h"
#include "stack/oiio_module.h"
#include "stack/polarization_math.h"
#include "scene/scene.h"
#include "stack/temp_files.h"

namespace skypol::stack {
namespace {

namespace fs = std::filesystem;

// Layout constants, pixels.
constexpr int kMargin = 14;
constexpr int kTitleH = 30;
constexpr int kLabelH = 24;
constexpr int kBarGap = 10;
constexpr int kBarH = 14;
constexpr int kTickH = 5;
constexpr int kTickLabelH = 18;
constexpr int kLegendH = 30;
constexpr int kFontPx = 15;
constexpr const char* kFont = "DejaVuSans";  // Debian's fonts-dejavu-core; without it, no text

const Rgb kBackground{0.13f, 0.13f, 0.13f};
const Rgb kText{0.92f, 0.92f, 0.92f};
const Rgb kOutside{0, 0, 0};
const Rgb kHatchA{0.30f, 0.30f, 0.30f};
const Rgb kHatchB{0.52f, 0.40f, 0.34f};  // brownish: no grey of the S0 panel looks like it

Rgb hatch(int x, int y) { return ((x + y) / 4) % 2 ? kHatchA : kHatchB; }

float srgb_encode(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f;
}

// The S0 that maps to white: the 99th percentile of S0 over pixels that see the sky.
float s0_white(const PreviewFrame& f) {
  std::vector<float> sky;
  for (std::size_t i = 0; i < f.s0.size(); ++i) {
    if (f.inside[i] && f.mask[i] > 0 && std::isfinite(f.s0[i])) sky.push_back(f.s0[i]);
  }
  if (sky.empty()) return 1;
  const auto k = static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(sky.size() - 1));
  std::nth_element(sky.begin(), sky.begin() + k, sky.end());
  const float v = sky[static_cast<std::size_t>(k)];
  return v > 0 ? v : 1;
}

std::string number_label(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

class Canvas {
 public:
  Canvas(int w, int h) : w_(w), h_(h), px_(3 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h)) {
    fill(0, 0, w, h, kBackground);
  }
  void set(int x, int y, const Rgb& c) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
    float* p = &px_[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(x))];
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
  }
  void fill(int x0, int y0, int w, int h, const Rgb& c) {
    for (int y = y0; y < y0 + h; ++y) {
      for (int x = x0; x < x0 + w; ++x) set(x, y, c);
    }
  }
  std::vector<float>& pixels() { return px_; }

 private:
  int w_, h_;
  std::vector<float> px_;
};

using Text = oiio::Label;  // x, y: the baseline anchor
constexpr auto kLeft = oiio::Align::Left;
constexpr auto kCentre = oiio::Align::Centre;
constexpr auto kRight = oiio::Align::Right;

// A colour bar with its ticks: value(t) for t in [0, 1] across the bar, labels at given t.
template <class Colour>
void draw_bar(Canvas& c, const PreviewLayout& l, int panel, Colour colour,
              const std::vector<std::pair<double, std::string>>& ticks, std::vector<Text>& texts) {
  const int x0 = l.panel_x[panel];
  for (int x = 0; x < l.panel_w; ++x) {
    const double t = l.panel_w > 1 ? static_cast<double>(x) / (l.panel_w - 1) : 0.0;
    c.fill(x0 + x, l.bar_y, 1, l.bar_h, colour(t));
  }
  for (const auto& [t, label] : ticks) {
    const int x = x0 + static_cast<int>(std::lround(t * (l.panel_w - 1)));
    c.fill(x, l.bar_y + l.bar_h, 1, kTickH, kText);
    // The end labels stay within the bar, so that neighbouring panels' labels never meet.
    texts.push_back({x, l.bar_y + l.bar_h + kTickH + kTickLabelH - 4, label, t <= 0 ? kLeft : (t >= 1 ? kRight : kCentre)});
  }
}

std::vector<float> draw(const PreviewFrame& f, const PreviewLayout& l, std::vector<Text>* texts_out) {
  Canvas c(l.width, l.height);
  std::vector<Text> texts;
  texts.push_back({kMargin, kTitleH - 8, f.title});
  const float white = s0_white(f);
  // ASCII only: OpenImageIO 2.4's render_text draws "°" as a zero.
  const char* names[3] = {"S0 (tone-mapped)", "DoLP", "AoLP (degrees)"};
  for (int panel = 0; panel < 3; ++panel) {
    texts.push_back({l.panel_x[panel] + l.panel_w / 2, l.panel_y - 7, names[panel], kCentre});
    for (int py = 0; py < l.panel_h; ++py) {
      const int y = std::min(f.height - 1, py * l.step + l.step / 2);
      for (int px = 0; px < l.panel_w; ++px) {
        const int x = std::min(f.width - 1, px * l.step + l.step / 2);
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(x);
        Rgb colour;
        if (!f.inside[i]) {
          colour = kOutside;
        } else if (!(f.mask[i] > 0)) {
          colour = hatch(px, py);
        } else if (panel == 0) {
          const float v = srgb_encode(std::isfinite(f.s0[i]) ? f.s0[i] / white : 0.0f);
          colour = {v, v, v};
        } else if (panel == 1) {
          colour = perceptual_colour(f.dolp[i]);
        } else {
          colour = cyclic_colour(static_cast<double>(f.aolp[i]) / std::numbers::pi + 0.5);
        }
        c.set(l.panel_x[panel] + px, l.panel_y + py, colour);
      }
    }
  }
  draw_bar(c, l, 0, [](double t) { const float v = srgb_encode(static_cast<float>(t)); return Rgb{v, v, v}; },
           {{0, "0"}, {0.5, number_label(0.5 * double{white})}, {1, number_label(white)}}, texts);
  draw_bar(c, l, 1, [](double t) { return perceptual_colour(t); },
           {{0, "0"}, {0.25, "0.25"}, {0.5, "0.5"}, {0.75, "0.75"}, {1, "1"}}, texts);
  draw_bar(c, l, 2, [](double t) { return cyclic_colour(t); },
           {{0, "-90"}, {0.25, "-45"}, {0.5, "0"}, {0.75, "45"}, {1, "90"}}, texts);
  // Legend.
  const int ly = l.height - kLegendH + 6;
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 28; ++x) c.set(kMargin + x, ly + y, hatch(x, y));
  }
  texts.push_back({kMargin + 36, ly + 13, "occluded (mask 0)"});
  const int lx = kMargin + 220;
  c.fill(lx, ly, 28, 16, kOutside);
  texts.push_back({lx + 36, ly + 13, "outside the image circle"});
  if (texts_out) *texts_out = std::move(texts);
  return std::move(c.pixels());
}

std::string compact_time(const std::string& iso) {
  std::string out;
  for (char ch : iso) {
    if (ch != '-' && ch != ':') out += ch;
  }
  return out;
}

std::string title_of(const std::string& time, double sun_az_deg, double sun_el_deg) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s   sun azimuth %.2f deg, elevation %.2f deg", time.c_str(), sun_az_deg, sun_el_deg);
  return buf;
}

void write_png_file(const std::string& what, const std::string& path, int width, int height,
                    std::vector<float>& pixels, const std::vector<Text>& texts);

}  // namespace

std::vector<std::uint8_t> preview_inside(const camera::Camera& cam) {
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(cam.width()) * static_cast<std::size_t>(cam.height()));
  for (int y = 0; y < cam.height(); ++y) {
    for (int x = 0; x < cam.width(); ++x) {
      inside[static_cast<std::size_t>(y) * static_cast<std::size_t>(cam.width()) + static_cast<std::size_t>(x)] =
          cam.ray(Eigen::Vector2d(x, y)) ? 1 : 0;
    }
  }
  return inside;
}

namespace {

// Fills the derived quantities of a PreviewFrame whose s0 / dolp / aolp / mask may be partial.
void complete(PreviewFrame& p, const std::vector<float>* s1, const std::vector<float>* s2, const std::string& what) {
  const std::size_t n = static_cast<std::size_t>(p.width) * static_cast<std::size_t>(p.height);
  if (p.s0.size() != n) throw std::invalid_argument(what + ": a preview needs the S0 channel");
  if (p.dolp.size() != n || p.aolp.size() != n) {
    if (!s1 || !s2) throw std::invalid_argument(what + ": a preview needs DoLP and AoLP, or S1 and S2, besides S0");
    p.dolp.resize(n);
    p.aolp.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      p.dolp[i] = dolp_of(p.s0[i], (*s1)[i], (*s2)[i]);
      p.aolp[i] = aolp_of((*s1)[i], (*s2)[i]);
    }
  }
  if (p.mask.size() != n) p.mask.assign(n, 1.0f);
}

}  // namespace

PreviewFrame preview_frame(const Frame& frame, const camera::Camera& camera, const std::string& band,
                           const std::vector<std::uint8_t>* inside) {
  PreviewFrame p;
  p.width = frame.width;
  p.height = frame.height;
  auto take = [&](const std::string& name, std::vector<float>& dst) {
    if (frame.has(name)) dst = frame.channel(name);
  };
  take("S0." + band, p.s0);
  take("DoLP." + band, p.dolp);
  take("AoLP." + band, p.aolp);
  take("mask", p.mask);
  const std::vector<float>* s1 = frame.has("S1." + band) ? &frame.channel("S1." + band) : nullptr;
  const std::vector<float>* s2 = frame.has("S2." + band) ? &frame.channel("S2." + band) : nullptr;
  complete(p, s1, s2, "frame " + sky::format_iso8601(frame.truth.time));
  p.inside = inside ? *inside : preview_inside(camera);
  p.title = title_of(sky::format_iso8601(frame.truth.time), frame.truth.sun.azimuth * kDegPerRad,
                     frame.truth.sun.elevation * kDegPerRad);
  return p;
}

PreviewLayout preview_layout(int frame_width, int frame_height, int max_panel_px) {
  PreviewLayout l;
  const int longest = std::max(frame_width, frame_height);
  l.step = std::max(1, (longest + max_panel_px - 1) / max_panel_px);
  l.panel_w = (frame_width + l.step - 1) / l.step;
  l.panel_h = (frame_height + l.step - 1) / l.step;
  // Room for the labels under a very narrow panel.
  const int column = std::max(l.panel_w, 180);
  for (int i = 0; i < 3; ++i) l.panel_x[i] = kMargin + i * (column + kMargin) + (column - l.panel_w) / 2;
  l.panel_y = kTitleH + kLabelH;
  l.bar_y = l.panel_y + l.panel_h + kBarGap;
  l.bar_h = kBarH;
  l.width = kMargin + 3 * (column + kMargin);
  l.height = l.bar_y + l.bar_h + kTickH + kTickLabelH + kLegendH + kMargin / 2;
  return l;
}

std::vector<float> preview_pixels(const PreviewFrame& frame, const PreviewLayout& layout) {
  return draw(frame, layout, nullptr);
}

void write_preview_png(const PreviewFrame& frame, const std::string& path, int max_panel_px) {
  const PreviewLayout l = preview_layout(frame.width, frame.height, max_panel_px);
  std::vector<Text> texts;
  std::vector<float> pixels = draw(frame, l, &texts);
  write_png_file("preview", path, l.width, l.height, pixels, texts);
}

namespace {

constexpr int kTextLineH = 20;
constexpr int kSwatchW = 22;
constexpr double kCharPx = 8.2;  // DejaVuSans at kFontPx: an average character's advance

// Panel pixel of frame pixel `p` (preview.h: a panel samples the frame at k·step + step/2).
Eigen::Vector2i panel_pixel(const PreviewLayout& l, const Eigen::Vector2d& p) {
  const double half = l.step / 2;
  return {static_cast<int>(std::lround((p.x() - half) / l.step)), static_cast<int>(std::lround((p.y() - half) / l.step))};
}

// A canvas seen through one panel: set() in panel coordinates, nothing drawn outside the panel.
struct PanelPen {
  Canvas& c;
  const PreviewLayout& l;
  int panel;
  void set(int x, int y, const Rgb& colour) const {
    if (x < 0 || y < 0 || x >= l.panel_w || y >= l.panel_h) return;
    c.set(l.panel_x[panel] + x, l.panel_y + y, colour);
  }
  // Bresenham's line between panel pixels a and b.
  void line(Eigen::Vector2i a, const Eigen::Vector2i& b, const Rgb& colour) const {
    const int dx = std::abs(b.x() - a.x()), dy = -std::abs(b.y() - a.y());
    const int sx = a.x() < b.x() ? 1 : -1, sy = a.y() < b.y() ? 1 : -1;
    // Points far outside the panel (a projected cone's far side) are not walked pixel by pixel.
    if (std::max(dx, -dy) > 4 * (l.panel_w + l.panel_h)) return;
    int err = dx + dy;
    for (;;) {
      set(a.x(), a.y(), colour);
      if (a == b) break;
      const int e2 = 2 * err;
      if (e2 >= dy) err += dy, a.x() += sx;
      if (e2 <= dx) err += dx, a.y() += sy;
    }
  }
  void mark(const PlotMark& m) const {
    const Eigen::Vector2i p = panel_pixel(l, m.pixel);
    const int r = m.radius_px;
    switch (m.shape) {
      case PlotMark::Shape::cross:
        for (int k = -r; k <= r; ++k) set(p.x() + k, p.y() + k, m.colour), set(p.x() + k, p.y() - k, m.colour);
        break;
      case PlotMark::Shape::plus:
        for (int k = -r; k <= r; ++k) set(p.x() + k, p.y(), m.colour), set(p.x(), p.y() + k, m.colour);
        break;
      case PlotMark::Shape::dot:
        for (int y = -r; y <= r; ++y) {
          for (int x = -r; x <= r; ++x) {
            if (x * x + y * y <= r * r) set(p.x() + x, p.y() + y, m.colour);
          }
        }
        break;
      case PlotMark::Shape::square:
        for (int k = -r; k <= r; ++k) {
          set(p.x() + k, p.y() - r, m.colour), set(p.x() + k, p.y() + r, m.colour);
          set(p.x() - r, p.y() + k, m.colour), set(p.x() + r, p.y() + k, m.colour);
        }
        break;
    }
  }
};

// `text` cut at spaces into lines of at most `chars` characters (a longer word stays whole).
std::vector<std::string> wrap(const std::string& text, std::size_t chars) {
  std::vector<std::string> lines;
  std::string line;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find(' ', at);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(at, end - at);
    if (!line.empty() && line.size() + 1 + word.size() > chars) {
      lines.push_back(line);
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    at = end + 1;
  }
  if (!line.empty() || lines.empty()) lines.push_back(line);
  return lines;
}

// The legend's lines: the categories, then the plot's texts, wrapped; a swatch on each first line.
std::vector<PlotText> legend_lines(const PlotFrame& p, const PreviewLayout& l) {
  const auto chars = static_cast<std::size_t>(std::max(20.0, (l.width - 2 * kMargin - kSwatchW - 8) / kCharPx));
  std::vector<PlotText> out;
  auto add = [&](const std::string& text, const std::optional<Rgb>& swatch) {
    const std::vector<std::string> lines = wrap(text, chars);
    for (std::size_t i = 0; i < lines.size(); ++i) out.push_back({lines[i], i == 0 ? swatch : std::nullopt});
  };
  for (const PlotCategory& c : p.categories) add(c.label, c.colour);
  for (const PlotText& t : p.texts) add(t.text, t.swatch);
  return out;
}

std::vector<float> draw_plot(const PlotFrame& p, const PreviewLayout& base, std::vector<Text>* texts_out, int* height) {
  const PreviewFrame& f = p.frame;
  const std::size_t n = static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height);
  if (f.dolp.size() != n || f.aolp.size() != n || f.mask.size() != n || f.inside.size() != n ||
      p.category.size() != n || (!p.shade.empty() && p.shade.size() != n)) {
    throw std::invalid_argument("estimate plot: a channel's size differs from the frame's");
  }
  for (std::uint8_t k : p.category) {
    if (k >= p.categories.size()) throw std::invalid_argument("estimate plot: a pixel's category is not listed");
  }
  PreviewLayout l = base;
  const std::vector<PlotText> legend = legend_lines(p, l);
  const int text_y = base.bar_y + base.bar_h + kTickH + kTickLabelH + 8;
  l.height = text_y + static_cast<int>(legend.size()) * kTextLineH + kMargin;
  if (height) *height = l.height;
  Canvas c(l.width, l.height);
  std::vector<Text> texts;
  texts.push_back({kMargin, kTitleH - 8, f.title});
  const char* names[3] = {"DoLP", "AoLP (degrees)", "pixels the estimators read"};
  for (int panel = 0; panel < 3; ++panel) {
    texts.push_back({l.panel_x[panel] + l.panel_w / 2, l.panel_y - 7, names[panel], kCentre});
    for (int py = 0; py < l.panel_h; ++py) {
      const int y = std::min(f.height - 1, py * l.step + l.step / 2);
      for (int px = 0; px < l.panel_w; ++px) {
        const int x = std::min(f.width - 1, px * l.step + l.step / 2);
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(x);
        Rgb colour;
        if (!f.inside[i]) {
          colour = kOutside;
        } else if (panel == 2) {
          colour = p.categories[p.category[i]].colour;
          if (!p.shade.empty()) {
            const float k = 0.5f + 0.5f * std::clamp(p.shade[i], 0.0f, 1.0f);
            for (float& v : colour) v *= k;
          }
        } else if (!(f.mask[i] > 0)) {
          colour = hatch(px, py);
        } else if (panel == 0) {
          colour = perceptual_colour(f.dolp[i]);
        } else {
          colour = cyclic_colour(static_cast<double>(f.aolp[i]) / std::numbers::pi + 0.5);
        }
        c.set(l.panel_x[panel] + px, l.panel_y + py, colour);
      }
    }
    const PanelPen pen{c, l, panel};
    for (const PlotLine& line : p.lines) {
      for (std::size_t k = 1; k < line.points.size(); ++k) {
        pen.line(panel_pixel(l, line.points[k - 1]), panel_pixel(l, line.points[k]), line.colour);
      }
      if (line.points.size() == 1) pen.set(panel_pixel(l, line.points[0]).x(), panel_pixel(l, line.points[0]).y(), line.colour);
    }
    for (const PlotMark& m : p.marks) pen.mark(m);
  }
  draw_bar(c, l, 0, [](double t) { return perceptual_colour(t); },
           {{0, "0"}, {0.25, "0.25"}, {0.5, "0.5"}, {0.75, "0.75"}, {1, "1"}}, texts);
  draw_bar(c, l, 1, [](double t) { return cyclic_colour(t); },
           {{0, "-90"}, {0.25, "-45"}, {0.5, "0"}, {0.75, "45"}, {1, "90"}}, texts);
  for (std::size_t k = 0; k < legend.size(); ++k) {
    const int y = text_y + static_cast<int>(k) * kTextLineH;
    if (legend[k].swatch) c.fill(kMargin, y + 3, kSwatchW, 12, *legend[k].swatch);
    texts.push_back({kMargin + kSwatchW + 8, y + 14, legend[k].text});
  }
  if (texts_out) *texts_out = std::move(texts);
  return std::move(c.pixels());
}

// Writes pixels with their texts as a PNG at `path` (temporary name first); `what` names the picture.
void write_png_file(const std::string& what, const std::string& path, int width, int height,
                    std::vector<float>& pixels, const std::vector<Text>& texts) {
  const fs::path final_path(path);
  const fs::path temp = final_path.parent_path() / ("." + final_path.filename().string() + ".tmp.png");
  const oiio::Font font{kFont, kFontPx, {kText[0], kText[1], kText[2]}};
  if (const std::string error = oiio::write_png(temp.string(), width, height, pixels.data(), texts, font); !error.empty()) {
    std::error_code ec;
    fs::remove(temp, ec);
    throw std::runtime_error("cannot write " + what + " " + path + ": " + error);
  }
  std::error_code ec;
  fs::rename(temp, final_path, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw std::runtime_error("cannot write " + what + " " + path + ": " + ec.message());
  }
}

}  // namespace

PreviewLayout plot_layout(int frame_width, int frame_height, int max_panel_px) {
  return preview_layout(frame_width, frame_height, max_panel_px);
}

Eigen::Vector2i plot_panel_pixel(const PreviewLayout& layout, const Eigen::Vector2d& pixel) {
  return panel_pixel(layout, pixel);
}

std::vector<float> plot_pixels(const PlotFrame& plot, int max_panel_px, int* height) {
  return draw_plot(plot, plot_layout(plot.frame.width, plot.frame.height, max_panel_px), nullptr, height);
}

void write_plot_png(const PlotFrame& plot, const std::string& path, int max_panel_px) {
  const PreviewLayout l = plot_layout(plot.frame.width, plot.frame.height, max_panel_px);
  std::vector<Text> texts;
  int height = 0;
  std::vector<float> pixels = draw_plot(plot, l, &texts, &height);
  write_png_file("the estimate plot", path, l.width, height, pixels, texts);
}

std::string preview_folder_for(const std::string& stack_path) {
  fs::path p(stack_path);
  return (p.parent_path() / (p.stem().string() + "-preview")).string();
}

std::string preview_file_name(std::size_t index, const std::string& iso_time) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04zu", index);
  return std::string(buf) + (iso_time.empty() ? "" : "-" + compact_time(iso_time)) + ".png";
}

PreviewFolder::PreviewFolder(std::string folder) : folder_(std::move(folder)) {
  // The folder name without a trailing slash ("out/p/" names the folder "p").
  fs::path f = fs::path(folder_).lexically_normal();
  if (!f.has_filename()) f = f.parent_path();
  // .NAME.tmp-HOST-PID (stack/temp_files.h): two renders to one path never share it, and a
  // killed render's folder is removed by the next one on this host.
  const std::string hidden = (f.parent_path() / ("." + f.filename().string())).string();
  remove_stale_temporaries(hidden);
  temp_ = temp_name(hidden);
  std::error_code ec;
  fs::create_directories(temp_, ec);
  if (ec || !fs::is_directory(temp_, ec)) {
    // A folder the user cannot write into (read-only, a parent that is a file) is the user's.
    throw scene::SceneError(scene::FileLoc{folder_, 0, 0},
                            "cannot write the previews: cannot create " + temp_ + (ec ? ": " + ec.message() : ""));
  }
}

PreviewFolder::~PreviewFolder() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(temp_, ec);
}

void PreviewFolder::add(std::size_t index, const Frame& frame, const camera::Camera& camera, const std::string& band) {
  if (inside_.empty()) inside_ = preview_inside(camera);
  add(preview_file_name(index, sky::format_iso8601(frame.truth.time)), preview_frame(frame, camera, band, &inside_));
}

void PreviewFolder::add(const std::string& file_name, const PreviewFrame& frame) {
  write_preview_png(frame, (fs::path(temp_) / file_name).string());
}

void PreviewFolder::commit() {
  std::error_code ec;
  fs::remove_all(folder_, ec);  // previews of an earlier render of the same stack
  fs::rename(temp_, folder_, ec);
  if (ec) throw scene::SceneError(scene::FileLoc{folder_, 0, 0}, "cannot move the previews there: " + ec.message());
  committed_ = true;
}

std::size_t write_stack_previews(const std::string& stack_path, const std::string& folder) {
  std::string open_error;
  auto in = oiio::open(stack_path, &open_error);
  if (!in) throw scene::SceneError(scene::FileLoc{stack_path, 0, 0}, "cannot open the stack: " + open_error);
  const oiio::Reader& first = *in;
  const std::string camera_text = first.string_attribute("skypol:camera", "");
  if (camera_text.empty()) throw scene::SceneError(scene::FileLoc{stack_path, 0, 0}, "not a skypol stack (no skypol:camera attribute)");
  const auto cam = scene::build_camera(scene::parse_camera(camera_text, stack_path + " [skypol:camera]"));
  std::string band = first.string_attribute("skypol:bands", "Y");
  band = band.substr(0, band.find(','));
  const std::vector<std::uint8_t> inside = preview_inside(*cam);

  PreviewFolder out(folder);
  std::size_t count = 0;
  for (int part = 0; in->seek(part); ++part) {
    const oiio::Reader& spec = *in;
    const std::string what = stack_path + " part " + std::to_string(part);
    if (spec.width() != cam->width() || spec.height() != cam->height()) {
      throw scene::SceneError(scene::FileLoc{stack_path, 0, 0}, what + ": size differs from the camera in the header");
    }
    std::vector<float> all(static_cast<std::size_t>(spec.width()) * static_cast<std::size_t>(spec.height()) *
                           static_cast<std::size_t>(spec.nchannels()));
    if (!in->read(part, all.data())) {
      throw scene::SceneError(scene::FileLoc{stack_path, 0, 0}, what + ": " + in->error());
    }
    auto channel = [&](const std::string& name) {
      std::vector<float> v;
      const int c = spec.channel_index(name);
      if (c < 0) return v;
      const std::size_t nc = static_cast<std::size_t>(spec.nchannels());
      v.resize(all.size() / nc);
      for (std::size_t i = 0; i < v.size(); ++i) v[i] = all[i * nc + static_cast<std::size_t>(c)];
      return v;
    };
    PreviewFrame p;
    p.width = spec.width();
    p.height = spec.height();
    p.s0 = channel("S0." + band);
    p.dolp = channel("DoLP." + band);
    p.aolp = channel("AoLP." + band);
    p.mask = channel("mask");
    const std::vector<float> s1 = channel("S1." + band), s2 = channel("S2." + band);
    try {
      complete(p, s1.empty() ? nullptr : &s1, s2.empty() ? nullptr : &s2, what);
    } catch (const std::invalid_argument& e) {
      throw scene::SceneError(scene::FileLoc{stack_path, 0, 0}, e.what());
    }
    p.inside = inside;
    const std::string time = spec.string_attribute("skypol:time", "");
    p.title = title_of(time, spec.float_attribute("skypol:sunAzimuthDeg"),
                       spec.float_attribute("skypol:sunElevationDeg"));
    out.add(preview_file_name(static_cast<std::size_t>(part), time), p);
    ++count;
  }
  out.commit();
  return count;
}

}  // namespace skypol::stack
