// PNG previews of rendered frames, for a person to look at (the EXR stack stays the data). One
// picture per frame, three panels side by side, each with a colour bar (docs/scenes.md, [output]):
//   S0    tone-mapped: S0 / (99th percentile of the sky's S0), sRGB-encoded grey;
//   DoLP  perceptual colour map (stack/colormap.h) over [0, 1];
//   AoLP  cyclic colour map over (−90°, 90°].
// Occluded pixels (mask 0) are hatched in grey and brown, pixels outside the image circle are black,
// and a legend says so. Panels sample every k-th pixel (nearest, no averaging: AoLP is cyclic) so
// that neither side exceeds max_panel_px.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "stack/colormap.h"
#include "stack/frame.h"

namespace skypol::stack {

// One band of one frame, as the preview needs it.
struct PreviewFrame {
  int width = 0, height = 0;
  std::vector<float> s0, dolp, aolp;  // aolp in radians
  std::vector<float> mask;            // fraction of samples that see the sky
  std::vector<std::uint8_t> inside;   // 1 where the camera images the pixel's centre
  std::string title;                  // e.g. the time and the sun
};

// From a frame's channels of `band`: DoLP and AoLP are taken as written or derived from S0, S1,
// S2; a missing mask means every pixel inside the image circle sees the sky. Throws
// std::invalid_argument naming the channels that are missing.
// `inside`, if given, is the camera's image circle as preview_inside() computes it (saves
// recomputing it for every frame of a stack).
PreviewFrame preview_frame(const Frame& frame, const camera::Camera& camera, const std::string& band,
                           const std::vector<std::uint8_t>* inside = nullptr);
// 1 where the camera images the pixel's centre.
std::vector<std::uint8_t> preview_inside(const camera::Camera& camera);

// Where things are in the picture (for tests and for the drawing code alike).
struct PreviewLayout {
  int step = 1;                 // every step-th pixel of the frame
  int panel_w = 0, panel_h = 0;
  int panel_x[3] = {0, 0, 0};   // S0, DoLP, AoLP
  int panel_y = 0;
  int bar_y = 0, bar_h = 0;     // colour bars: same x and width as their panel
  int width = 0, height = 0;    // of the whole picture
};
PreviewLayout preview_layout(int frame_width, int frame_height, int max_panel_px = 512);

// The picture as sRGB-encoded floats in [0, 1], RGB interleaved, layout.width × layout.height.
std::vector<float> preview_pixels(const PreviewFrame& frame, const PreviewLayout& layout);

// Writes the picture as an 8-bit PNG (temporary name, renamed when complete). Throws
// std::runtime_error naming the path on failure.
void write_preview_png(const PreviewFrame& frame, const std::string& path, int max_panel_px = 512);

// The folder of a stack's previews: "out/x.exr" → "out/x-preview"; inside it, one
// "NNNN-YYYYMMDDTHHMMSSZ.png" per frame.
std::string preview_folder_for(const std::string& stack_path);
std::string preview_file_name(std::size_t index, const std::string& iso_time);

// The picture of an estimate (skypole/estimate_plot.h draws its content): three panels of one
// frame side by side — DoLP, AoLP, and the pixels the estimators read, each pixel in the colour of
// its category — with marks drawn over every panel (poles, cones, suns, tracks) and lines of text
// under them, each with a colour swatch. Positions are frame pixels (continuous, OpenCV's centres);
// a frame pixel (u, v) is drawn at panel pixel ((u − step/2) / step, (v − step/2) / step), rounded,
// where step/2 is an integer division (a panel samples the frame at k·step + step/2).
struct PlotCategory {
  Rgb colour{};
  std::string label;
};
struct PlotMark {
  enum class Shape { cross, plus, dot, square };  // cross: ×, plus: +, dot: filled disc, square: hollow
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  Rgb colour{};
  Shape shape = Shape::cross;
  int radius_px = 6;  // on the panel
};
struct PlotLine {
  std::vector<Eigen::Vector2d> points;  // a polyline; consecutive points are joined
  Rgb colour{};
};
struct PlotText {
  std::string text;
  std::optional<Rgb> swatch;  // drawn before the text
};
struct PlotFrame {
  PreviewFrame frame;                    // DoLP, AoLP, mask and inside of the frame shown; its title
  std::vector<std::uint8_t> category;    // per pixel, an index into categories (the third panel)
  std::vector<float> shade;              // per pixel in [0, 1]: a category's colour is scaled by 0.5 + 0.5·shade
  std::vector<PlotCategory> categories;  // listed in the legend under the third panel
  std::vector<PlotLine> lines;
  std::vector<PlotMark> marks;           // drawn after the lines, in order
  std::vector<PlotText> texts;           // under the panels, one line each (long lines wrap)
};

// Where the estimate picture's panels are: the preview's layout (same panel positions, step and
// bars), taller by the text lines under them.
PreviewLayout plot_layout(int frame_width, int frame_height, int max_panel_px = 512);
// The panel pixel that shows frame pixel `pixel` (the rule above), panel coordinates.
Eigen::Vector2i plot_panel_pixel(const PreviewLayout& layout, const Eigen::Vector2d& pixel);

// The picture as sRGB floats (RGB interleaved, layout's width × the returned height), without the
// text; and the same written as a PNG with the text (temporary name, renamed when complete).
// Throws std::invalid_argument for channels of the wrong size, std::runtime_error naming the path
// when the PNG cannot be written.
std::vector<float> plot_pixels(const PlotFrame& plot, int max_panel_px, int* height);
void write_plot_png(const PlotFrame& plot, const std::string& path, int max_panel_px = 512);

// Previews written while a stack is rendered, into a temporary folder that replaces `folder` on
// commit(); destroyed without commit, it leaves nothing behind.
class PreviewFolder {
 public:
  explicit PreviewFolder(std::string folder);
  ~PreviewFolder();
  PreviewFolder(const PreviewFolder&) = delete;
  PreviewFolder& operator=(const PreviewFolder&) = delete;
  void add(std::size_t index, const Frame& frame, const camera::Camera& camera, const std::string& band);
  void add(const std::string& file_name, const PreviewFrame& frame);
  void commit();

 private:
  std::string folder_, temp_;
  bool committed_ = false;
  std::vector<std::uint8_t> inside_;  // the image circle, from the first frame's camera
};

// Previews of every frame of a stack file, read one part at a time with OpenImageIO; the camera
// comes from the stack's header. Returns the number of pictures written.
std::size_t write_stack_previews(const std::string& stack_path, const std::string& folder);

}  // namespace skypol::stack
