#include "stack/export.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "scene/scene_error.h"
#include "stack/npy.h"
#include "stack/oiio_module.h"
#include "stack/stack_io.h"
#include "stack/temp_files.h"

namespace skypol::stack {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw scene::SceneError(scene::FileLoc{path, 0, 0}, what);
}

// "S0" → "S0.<band>"; raw, mask and full names stay.
std::string full_name(const std::string& c, const std::string& band) {
  static const std::vector<std::string> per_band{"S0", "S1", "S2", "S3", "DoLP", "AoLP"};
  return std::find(per_band.begin(), per_band.end(), c) != per_band.end() ? c + "." + band : c;
}

std::string compact_time(sky::Instant t) {
  const sky::CalendarUtc c = sky::to_calendar(t);
  char buf[48];
  const double whole = std::floor(c.second);
  if (c.second - whole > 5e-4) {
    std::snprintf(buf, sizeof buf, "%04d%02d%02dT%02d%02d%06.3fZ", c.year, c.month, c.day, c.hour, c.minute, c.second);
  } else {
    std::snprintf(buf, sizeof buf, "%04d%02d%02dT%02d%02d%02dZ", c.year, c.month, c.day, c.hour, c.minute,
                  static_cast<int>(whole));
  }
  return buf;
}

std::string exif_time(sky::Instant t) {
  const sky::CalendarUtc c = sky::to_calendar(t);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%04d:%02d:%02d %02d:%02d:%02d", c.year, c.month, c.day, c.hour, c.minute,
                static_cast<int>(std::floor(c.second)));
  return buf;
}

// PNG's integer form of a channel (ExportOptions says which mapping).
std::uint16_t png_value(const std::string& name, float v) {
  const double d = static_cast<double>(v);
  double u = d;
  if (name.rfind("AoLP", 0) == 0) u = (d + std::numbers::pi / 2) / std::numbers::pi * 65535.0;
  else if (name != "raw") u = d * 65535.0;
  return static_cast<std::uint16_t>(std::clamp(std::round(u), 0.0, 65535.0));
}

void commit(const std::string& tmp, const std::string& path, const std::string& error) {
  std::error_code ec;
  if (!error.empty()) {
    fs::remove(tmp, ec);
    fail(path, "cannot write: " + error);
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    fail(path, "cannot write: " + ec.message());
  }
}

}  // namespace

std::vector<std::string> export_stack(const std::string& stack_path, const ExportOptions& o) {
  static const std::vector<std::string> formats{"exr", "tiff", "npy", "png"};
  if (std::find(formats.begin(), formats.end(), o.format) == formats.end()) {
    throw std::invalid_argument("--format '" + o.format + "': expected exr, tiff, npy or png");
  }
  if (o.channels.empty()) throw std::invalid_argument("--channels: name at least one channel");
  const StackSummary summary = peek_stack(stack_path);
  const std::string band = o.band.empty() ? summary.bands.front() : o.band;
  if (std::find(summary.bands.begin(), summary.bands.end(), band) == summary.bands.end()) {
    std::string have;
    for (const std::string& b : summary.bands) have += (have.empty() ? "" : ", ") + b;
    throw std::invalid_argument("--band '" + band + "': the stack's bands are " + have);
  }
  // Every channel is checked before anything is written.
  std::vector<std::string> names;
  for (const std::string& c : o.channels) {
    const std::string n = full_name(c, band);
    if (std::find(summary.channels.begin(), summary.channels.end(), n) == summary.channels.end()) {
      std::string have;
      for (const std::string& h : summary.channels) have += " " + h;
      fail(stack_path, "has no channel '" + n + "' to export (it has:" + have + ")" +
                           (n == "raw" ? "; render with [output] channels including \"raw\" and a [sensor]" : ""));
    }
    if (o.format == "png" && n.rfind("S", 0) == 0) {
      throw std::invalid_argument("--format png holds integers; '" + n +
                                  "' is a radiance: export it as exr, tiff or npy");
    }
    names.push_back(n);
  }
  const bool raw_only = names == std::vector<std::string>{"raw"};

  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec || !fs::is_directory(o.out_dir)) fail(o.out_dir, "cannot create the output folder");
  const std::string stem = fs::path(stack_path).stem().string();
  std::vector<std::string> written;
  std::string csv = "file,time\n";
  // One frame in memory at a time: each is written as soon as it is read. A frame that cannot be
  // read or written takes the files already written with it: an export is whole or absent.
  try {
    read_stack_frames(stack_path, names, [&](std::size_t i, Frame&& f) {
      const std::size_t n = static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height);
      char index[32];
      std::snprintf(index, sizeof index, "%03zu", i);
      const std::string base = stem + "_" + index + "_" + compact_time(f.truth.time);
      std::vector<std::pair<std::string, std::string>> attrs{{"DateTime", exif_time(f.truth.time)},
                                                            {"Exif:DateTimeOriginal", exif_time(f.truth.time)}};
      if (o.format == "exr" || o.format == "tiff") attrs.emplace_back("compression", "zip");
      const auto add = [&](const std::string& file) {
        written.push_back((fs::path(o.out_dir) / file).string());
        csv += file + "," + sky::format_iso8601(f.truth.time) + "\n";
      };
      if (o.format == "png" || (o.format == "tiff" && !raw_only)) {
        // One channel per file: what every reader of docs/exr-format.md opens (OpenCV 4.6 opens no
        // float TIFF of 2, 4 or 5 channels).
        for (const std::string& c : names) {
          const std::string file = base + (names.size() > 1 ? "." + c : "") + "." + o.format;
          const std::string path = (fs::path(o.out_dir) / file).string();
          const std::vector<float>& v = f.channel(c);
          const std::string tmp = temp_name(path);
          if (o.format == "tiff") {
            commit(tmp, path, oiio::write_float_image(path, tmp, f.width, f.height, {c}, v.data(), attrs));
          } else {
            std::vector<unsigned short> px(n);
            for (std::size_t k = 0; k < n; ++k) px[k] = png_value(c, v[k]);
            commit(tmp, path, oiio::write_u16_image(path, tmp, f.width, f.height, {c}, px.data(), attrs));
          }
          add(file);
        }
        return;
      }
      const std::string file = base + "." + o.format;
      const std::string path = (fs::path(o.out_dir) / file).string();
      const std::string tmp = temp_name(path);
      const std::size_t nc = names.size();
      if (raw_only && o.format != "exr") {
        const std::vector<float>& v = f.channel("raw");
        std::vector<unsigned short> px(n);
        for (std::size_t k = 0; k < n; ++k) px[k] = static_cast<unsigned short>(std::clamp(v[k], 0.0f, 65535.0f));
        const std::string error =
            o.format == "npy" ? (write_npy(tmp, {static_cast<std::size_t>(f.height), static_cast<std::size_t>(f.width)},
                                           px.data()) ? "" : "I/O error")
                              : oiio::write_u16_image(path, tmp, f.width, f.height, names, px.data(), attrs);
        commit(tmp, path, error);
        add(file);
        return;
      }
      std::vector<float> px(n * nc);  // interleaved: (rows, cols, channels)
      for (std::size_t c = 0; c < nc; ++c) {
        const std::vector<float>& v = f.channel(names[c]);
        for (std::size_t k = 0; k < n; ++k) px[k * nc + c] = v[k];
      }
      std::string error;
      if (o.format == "npy") {
        std::vector<std::size_t> shape{static_cast<std::size_t>(f.height), static_cast<std::size_t>(f.width)};
        if (nc > 1) shape.push_back(nc);
        error = write_npy(tmp, shape, px.data()) ? "" : "I/O error";
      } else {
        error = oiio::write_float_image(path, tmp, f.width, f.height, names, px.data(), attrs);
      }
      commit(tmp, path, error);
      add(file);
    });
  } catch (...) {
    for (const std::string& file : written) fs::remove(file, ec);
    throw;
  }
  const std::string csv_path = (fs::path(o.out_dir) / "times.csv").string();
  const std::string tmp = temp_name(csv_path);
  {
    std::ofstream out(tmp, std::ios::binary);
    out << csv;
    out.close();
    commit(tmp, csv_path, out ? "" : "I/O error");
  }
  return written;
}

}  // namespace skypol::stack
