#include "stack/stack_io.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <exception>
#include <functional>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <mutex>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <unistd.h>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenEXR/ImfVecAttribute.h>

#include "camera/orientation.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/truth.h"
#include "sky/units.h"
#include "stack/exr_ostream.h"
#include "stack/temp_files.h"
#include "stack/version.h"

namespace skypol::stack {
namespace {

// The mask is a coverage fraction (half would round 1/spp steps) and raw holds 12–16-bit counts
// (half is exact only to 2048): both stay float whatever the pixel type.
bool stays_float(const std::string& channel) { return channel == "mask" || channel == "raw"; }

// Half's largest finite value. A half stack clamps to ±kHalfMax rather than writing ±Inf (the sun
// disc's radiance, ~2e5, is beyond it); the header says so (skypol:halfClamp, docs/exr-format.md).
constexpr float kHalfMax = 65504.0f;

constexpr const char* kExposure = "skypol:exposureUs";
constexpr const char* kPolarizerAngles = "skypol:polarizerAngles";

// Each part's exposure, noted as its frame is written (StackHeader::exposures).
struct Exposures {
  bool wanted = false;
  std::vector<double> us;
  void note(std::size_t part, const Frame& frame) {
    if (!wanted) return;
    if (!frame.exposure_us || !std::isfinite(*frame.exposure_us) || !(*frame.exposure_us > 0)) {
      throw std::invalid_argument("frame " + std::to_string(part) + " has no exposure, and the stack's parts carry one");
    }
    us[part] = *frame.exposure_us;
  }
};

// Writes the parts' exposures into their reserved skypol:exposureUs attributes of the complete file
// at `path`. An EXR header stores an attribute as its name, NUL, its type name, NUL, the value's
// size (4 bytes, little-endian) and the value (a double: 8 bytes, little-endian), and every part's
// header comes before any pixel data, one header per part in part order: so the k-th occurrence of
// that name, type and size in the file is part k's.
void fill_exposures(const std::string& path, const std::vector<double>& us) {
  static const std::string key = std::string(kExposure) + '\0' + "double" + '\0' + std::string("\x08\0\0\0", 4);
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  if (!f) throw std::runtime_error("cannot reopen the stack to write its exposures");
  // The headers, read a block at a time until every part's attribute is found (the file's
  // beginning: a few kB per part, never its pixels).
  std::vector<std::streamoff> at;  // offsets of the values
  std::string head;
  std::vector<char> block(1 << 16);
  std::size_t from = 0;
  while (at.size() < us.size()) {
    f.read(block.data(), static_cast<std::streamsize>(block.size()));
    const std::streamsize got = f.gcount();
    if (got <= 0) break;
    head.append(block.data(), static_cast<std::size_t>(got));
    for (std::size_t k; at.size() < us.size() && (k = head.find(key, from)) != std::string::npos;) {
      if (k + key.size() + 8 > head.size()) break;  // the value is in the next block
      at.push_back(static_cast<std::streamoff>(k + key.size()));
      from = k + key.size() + 8;
    }
  }
  if (at.size() != us.size()) throw std::runtime_error("the stack's headers lack their reserved exposures");
  f.clear();
  for (std::size_t i = 0; i < us.size(); ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, &us[i], sizeof bits);
    char le[8];
    for (int b = 0; b < 8; ++b) le[b] = static_cast<char>((bits >> (8 * b)) & 0xff);
    f.seekp(at[i]);
    f.write(le, 8);
  }
  f.flush();
  if (!f) throw std::runtime_error("cannot write the stack's exposures");
}

Imf::Compression compression_of(const std::string& name) {
  if (name == "none") return Imf::NO_COMPRESSION;
  if (name == "rle") return Imf::RLE_COMPRESSION;
  if (name == "zips") return Imf::ZIPS_COMPRESSION;
  if (name == "zip") return Imf::ZIP_COMPRESSION;
  if (name == "piz") return Imf::PIZ_COMPRESSION;
  if (name == "pxr24") return Imf::PXR24_COMPRESSION;
  if (name == "b44") return Imf::B44_COMPRESSION;
  if (name == "b44a") return Imf::B44A_COMPRESSION;
  if (name == "dwaa") return Imf::DWAA_COMPRESSION;
  if (name == "dwab") return Imf::DWAB_COMPRESSION;
  throw std::invalid_argument("unknown compression '" + name + "'");
}

template <class A, class V>
void put(Imf::Header& h, const char* name, const V& v) {
  h.insert(name, A(v));
}

Imf::Header part_header(const scene::Truth& t, const std::vector<std::string>& channels, int width, int height,
                        const StackHeader& sh, const WriteOptions& o, std::size_t part) {
  Imf::Header h(width, height);
  h.setName(sky::format_iso8601(t.time));
  h.setType(Imf::SCANLINEIMAGE);
  h.compression() = compression_of(o.compression);
  if (o.zip_level > 0) h.zipCompressionLevel() = o.zip_level;  // read by zip and zips only
  const bool half = o.half;
  for (const std::string& c : channels) {
    h.channels().insert(c, Imf::Channel(half && !stays_float(c) ? Imf::HALF : Imf::FLOAT));
  }
  // OpenEXR's standard attributes where they exist (capDate in UTC, so utcOffset = 0).
  if (sh.site_known) {
    Imf::addLatitude(h, static_cast<float>(t.site.latitude_deg));
    Imf::addLongitude(h, static_cast<float>(t.site.longitude_deg));
    Imf::addAltitude(h, static_cast<float>(t.site.height_m));
  }
  const sky::CalendarUtc c = sky::to_calendar(t.time);
  char date[32];
  std::snprintf(date, sizeof date, "%04d:%02d:%02d %02d:%02d:%02d", c.year, c.month, c.day, c.hour, c.minute,
                static_cast<int>(c.second));
  Imf::addCapDate(h, date);
  Imf::addUtcOffset(h, 0.0f);
  // Exact values as skypol: attributes (docs/exr-format.md).
  put<Imf::StringAttribute>(h, "skypol:version", version_text());
  put<Imf::StringAttribute>(h, "skypol:time", sky::format_iso8601(t.time));
  put<Imf::DoubleAttribute>(h, "skypol:unixTime", t.time.unix_seconds);
  if (sh.site_known) {
    put<Imf::DoubleAttribute>(h, "skypol:latitudeDeg", t.site.latitude_deg);
    put<Imf::DoubleAttribute>(h, "skypol:longitudeDeg", t.site.longitude_deg);
    put<Imf::DoubleAttribute>(h, "skypol:heightM", t.site.height_m);
    put<Imf::DoubleAttribute>(h, "skypol:sunAzimuthDeg", t.sun.azimuth * kDegPerRad);
    put<Imf::DoubleAttribute>(h, "skypol:sunElevationDeg", t.sun.elevation * kDegPerRad);
    put<Imf::DoubleAttribute>(h, "skypol:sunDeclinationDeg", t.sun.declination * kDegPerRad);
    put<Imf::DoubleAttribute>(h, "skypol:sunHourAngleDeg", t.sun.hour_angle * kDegPerRad);
    put<Imf::V3dAttribute>(h, "skypol:sunDirectionENU",
                           Imath::V3d(t.sun.direction.x(), t.sun.direction.y(), t.sun.direction.z()));
  }
  if (!sh.truth_known) {
    // A capture: what the estimators are asked for is not in the file (docs/exr-format.md).
    put<Imf::StringAttribute>(h, "skypol:truth", std::string("unknown"));
    put<Imf::IntAttribute>(h, "skypol:siteKnown", sh.site_known ? 1 : 0);
  }
  put<Imf::DoubleAttribute>(h, "skypol:tiltDeg", t.tilt_deg);
  put<Imf::DoubleAttribute>(h, "skypol:rollDeg", t.roll_deg);
  if (sh.truth_known) {
    Imath::M33d m;
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) m[r][col] = t.world_from_camera(r, col);
    put<Imf::M33dAttribute>(h, "skypol:worldFromCamera", m);
    put<Imf::DoubleAttribute>(h, "skypol:headingDeg", t.heading_deg);
    put<Imf::V3dAttribute>(h, "skypol:poleENU", Imath::V3d(t.pole_enu.x(), t.pole_enu.y(), t.pole_enu.z()));
    put<Imf::IntAttribute>(h, "skypol:poleIsNorth", t.pole_is_north ? 1 : 0);
    if (t.pole_pixel) put<Imf::V2dAttribute>(h, "skypol:polePixel", Imath::V2d(t.pole_pixel->x(), t.pole_pixel->y()));
  }
  std::string bands;
  for (const std::string& b : sh.bands) bands += (bands.empty() ? "" : ",") + b;
  put<Imf::StringAttribute>(h, "skypol:bands", bands);
  put<Imf::StringAttribute>(h, "skypol:skyModel", sh.sky_model);
  put<Imf::StringAttribute>(h, "skypol:camera", sh.camera_description);
  put<Imf::StringAttribute>(h, "skypol:scene", sh.scene_text);
  if (half) put<Imf::DoubleAttribute>(h, "skypol:halfClamp", static_cast<double>(kHalfMax));
  // Reserved: the value is written when the part's frame is (fill_exposures).
  if (sh.exposures) put<Imf::DoubleAttribute>(h, kExposure, 0.0);
  if (sh.polarizer_angles != PolarizerAngles::none) {
    put<Imf::StringAttribute>(h, kPolarizerAngles, polarizer_angles_name(sh.polarizer_angles));
  }
  // A writer's own attributes may neither leave the skypol: namespace nor replace one of the above.
  const auto add = [&h](const std::pair<std::string, std::string>& a) {
    if (a.first.rfind("skypol:", 0) != 0 || h.find(a.first) != h.end()) {
      throw std::invalid_argument("header attribute '" + a.first +
                                  "': a writer's attributes are named skypol:… and not one the format writes");
    }
    put<Imf::StringAttribute>(h, a.first.c_str(), a.second);
  };
  for (const auto& a : sh.attributes) add(a);
  if (part < sh.part_attributes.size())
    for (const auto& a : sh.part_attributes[part]) add(a);
  return h;
}

template <class A>
const A& need(const Imf::Header& h, const char* name, const std::string& path, int part) {
  const A* a = h.findTypedAttribute<A>(name);
  if (!a) {
    throw scene::SceneError(scene::FileLoc{path, 0, 0}, "part " + std::to_string(part) + " has no '" + name +
                                              "' attribute: not a skypol stack, or written by another tool");
  }
  return *a;
}

// What a part's header says it knows (StackHeader::truth_known, site_known).
struct Known {
  bool truth = true;
  bool site = true;
};
Known known_of(const Imf::Header& h) {
  Known k;
  const auto* truth = h.findTypedAttribute<Imf::StringAttribute>("skypol:truth");
  k.truth = !truth || truth->value() != "unknown";
  const auto* site = h.findTypedAttribute<Imf::IntAttribute>("skypol:siteKnown");
  k.site = k.truth || (site && site->value() != 0);
  return k;
}

// The site and the sun a part's header records (a capture has them only when its site was given).
void read_site_and_sun(const Imf::Header& h, const std::string& path, int part, scene::Truth& t) {
  t.site.latitude_deg = need<Imf::DoubleAttribute>(h, "skypol:latitudeDeg", path, part).value();
  t.site.longitude_deg = need<Imf::DoubleAttribute>(h, "skypol:longitudeDeg", path, part).value();
  t.site.height_m = need<Imf::DoubleAttribute>(h, "skypol:heightM", path, part).value();
  t.sun.azimuth = need<Imf::DoubleAttribute>(h, "skypol:sunAzimuthDeg", path, part).value() / kDegPerRad;
  t.sun.elevation = need<Imf::DoubleAttribute>(h, "skypol:sunElevationDeg", path, part).value() / kDegPerRad;
  t.sun.declination = need<Imf::DoubleAttribute>(h, "skypol:sunDeclinationDeg", path, part).value() / kDegPerRad;
  t.sun.hour_angle = need<Imf::DoubleAttribute>(h, "skypol:sunHourAngleDeg", path, part).value() / kDegPerRad;
  const Imath::V3d s = need<Imf::V3dAttribute>(h, "skypol:sunDirectionENU", path, part).value();
  t.sun.direction = Eigen::Vector3d(s.x, s.y, s.z);
}

scene::Truth read_truth(const Imf::Header& h, const std::string& path, int part) {
  scene::Truth t;
  t.time = sky::Instant{need<Imf::DoubleAttribute>(h, "skypol:unixTime", path, part).value()};
  const Known k = known_of(h);
  if (!k.truth) {
    // A capture: its time and attitude; the site and the sun when known; heading 0 and no pole.
    t.tilt_deg = need<Imf::DoubleAttribute>(h, "skypol:tiltDeg", path, part).value();
    t.roll_deg = need<Imf::DoubleAttribute>(h, "skypol:rollDeg", path, part).value();
    t.world_from_camera = camera::world_from_heading_tilt_roll(0.0, t.tilt_deg, t.roll_deg);
    if (k.site) {
      read_site_and_sun(h, path, part, t);
      t.pole_enu = scene::visible_pole(t.site.latitude_deg);
      t.pole_is_north = t.site.latitude_deg >= 0;
    }
    return t;
  }
  read_site_and_sun(h, path, part, t);
  const Imath::M33d m = need<Imf::M33dAttribute>(h, "skypol:worldFromCamera", path, part).value();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) t.world_from_camera(r, c) = m[r][c];
  t.heading_deg = need<Imf::DoubleAttribute>(h, "skypol:headingDeg", path, part).value();
  t.tilt_deg = need<Imf::DoubleAttribute>(h, "skypol:tiltDeg", path, part).value();
  t.roll_deg = need<Imf::DoubleAttribute>(h, "skypol:rollDeg", path, part).value();
  const Imath::V3d p = need<Imf::V3dAttribute>(h, "skypol:poleENU", path, part).value();
  t.pole_enu = Eigen::Vector3d(p.x, p.y, p.z);
  t.pole_is_north = need<Imf::IntAttribute>(h, "skypol:poleIsNorth", path, part).value() != 0;
  if (const auto* px = h.findTypedAttribute<Imf::V2dAttribute>("skypol:polePixel")) {
    t.pole_pixel = Eigen::Vector2d(px->value().x, px->value().y);
  }
  return t;
}

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(item);
  return out;
}

}  // namespace

void use_all_cores_for_exr() {
  static const bool once = [] {
    Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
    return true;
  }();
  (void)once;
}

void write_stack(const std::string& path, const std::vector<scene::Truth>& truths, const std::vector<std::string>& channels,
                 int width, int height, const StackHeader& header, const WriteOptions& options,
                 const std::function<Frame(std::size_t)>& produce) {
  Frame held;  // the previous part's frame is released when the next one arrives, as before
  write_stack_reusing(path, truths, channels, width, height, header, options, [&](std::size_t i) -> const Frame& {
    held = produce(i);
    return held;
  });
}

namespace {

// Slices for rows [y0, y0 + frame.height) of a part from `frame` (the whole part when y0 = 0, or a
// band of it); half conversions go into half_buffers, reused. OpenEXR addresses a slice's pixel
// (x, y) at base + y·yStride, so a band's base is set y0 rows before its first row (OpenEXR's
// documented way to hand it a window; it reads only the rows written).
Imf::FrameBuffer slices(const Frame& frame, int y0, const std::vector<std::string>& channels, int width,
                        const WriteOptions& options, std::vector<std::vector<Imath::half>>& half_buffers) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(frame.height);
  Imf::FrameBuffer fb;
  for (std::size_t k = 0; k < channels.size(); ++k) {
    const std::string& c = channels[k];
    const std::vector<float>& data = frame.channel(c);
    if (data.size() != n || frame.width != width) throw std::logic_error("channel " + c + " has the wrong size");
    const char* base = nullptr;
    Imf::PixelType type = Imf::FLOAT;
    std::size_t size = sizeof(float);
    if (options.half && !stays_float(c)) {
      std::vector<Imath::half>& hb = half_buffers[k];
      hb.resize(data.size());
      for (std::size_t j = 0; j < data.size(); ++j) hb[j] = Imath::half(std::clamp(data[j], -kHalfMax, kHalfMax));
      base = reinterpret_cast<const char*>(hb.data());
      type = Imf::HALF;
      size = sizeof(Imath::half);
    } else {
      base = reinterpret_cast<const char*>(data.data());
    }
    const std::size_t stride = size * static_cast<std::size_t>(width);
    const auto origin = reinterpret_cast<std::uintptr_t>(base) - static_cast<std::uintptr_t>(y0) * stride;
    // An output slice is only read; Imf::Slice takes a non-const pointer for both directions.
    fb.insert(c, Imf::Slice(type, reinterpret_cast<char*>(origin), size, stride));
  }
  return fb;
}

// Part i's pixels from `frame` into the open file.
void write_part(Imf::MultiPartOutputFile& file, std::size_t i, const Frame& frame, const std::vector<std::string>& channels,
                int width, int height, const WriteOptions& options, std::vector<std::vector<Imath::half>>& half_buffers,
                Exposures& exposures) {
  if (frame.height != height) throw std::logic_error("frame has the wrong height");
  exposures.note(i, frame);
  Imf::OutputPart part(file, static_cast<int>(i));
  part.setFrameBuffer(slices(frame, 0, channels, width, options, half_buffers));
  part.writePixels(height);
}

// OpenEXR encodes each line buffer as a task of its global thread pool. An uncompressed file's
// line buffer is one scanline, so the pool is woken 2048 times per part for a copy of a few
// microseconds: on 2 cores a third of an uncompressed stack's CPU went to those wake-ups (perf,
// docs/benchmarks.md section 9). Such files are encoded on the calling thread (a pool of none).
// rle and zips also encode a line at a time, but their compression is worth spreading over the
// cores (the paper's scene, DoLP and AoLP as float: 5 frames of rle 0.70-0.76 s wall with the
// pool, 0.82-0.89 s without; 3 of zips 1.33 s and 1.69 s); the rest encode 16 or more lines per task.
bool only_copies(const std::string& compression) { return compression == "none"; }
}  // namespace

bool encodes_on_calling_thread(const WriteOptions& options) { return only_copies(options.compression); }

namespace {

// The global pool's size for the lifetime of a write, restored afterwards. The pool is the
// process's: an EXR read or write on another thread meanwhile runs without it (slower, not wrong).
class ExrPoolForWrite {
 public:
  explicit ExrPoolForWrite(const std::string& compression) : saved_(Imf::globalThreadCount()) {
    if (only_copies(compression)) Imf::setGlobalThreadCount(0);
  }
  ~ExrPoolForWrite() {
    if (Imf::globalThreadCount() != saved_) Imf::setGlobalThreadCount(saved_);
  }
  ExrPoolForWrite(const ExrPoolForWrite&) = delete;
  ExrPoolForWrite& operator=(const ExrPoolForWrite&) = delete;

 private:
  int saved_;
};

// The temporary file, its parts written by write_parts(file), renamed to path when complete;
// removed on any error, which is rethrown as a SceneError naming path.
void write_to_temporary(const std::string& path, const std::vector<scene::Truth>& truths,
                        const std::vector<std::string>& channels, int width, int height, const StackHeader& header,
                        const WriteOptions& options,
                        const std::function<void(Imf::MultiPartOutputFile&, Exposures&)>& write_parts) {
  use_all_cores_for_exr();
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  remove_stale_temporaries(path);  // a killed render's leftovers (stack/temp_files.h)
  const std::string tmp = temp_name(path);
  try {
    std::vector<Imf::Header> headers;
    headers.reserve(truths.size());
    for (std::size_t i = 0; i < truths.size(); ++i)
      headers.push_back(part_header(truths[i], channels, width, height, header, options, i));
    Exposures exposures{header.exposures, std::vector<double>(truths.size(), 0.0)};
    const ExrPoolForWrite pool(options.compression);
    BackgroundFileStream out(tmp);
    {
      Imf::MultiPartOutputFile file(out, headers.data(), static_cast<int>(headers.size()), false,
                                    Imf::globalThreadCount());
      write_parts(file, exposures);
    }
    out.finish();  // every byte in the file, or the write's error
    if (exposures.wanted) fill_exposures(tmp, exposures.us);
    fs::rename(tmp, target);
  } catch (const scene::SceneError&) {
    fs::remove(tmp, ec);
    throw;
  } catch (const std::exception& e) {
    fs::remove(tmp, ec);
    throw scene::SceneError(scene::FileLoc{path, 0, 0}, std::string("cannot write stack: ") + e.what());
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

}  // namespace

void write_stack_reusing(const std::string& path, const std::vector<scene::Truth>& truths,
                         const std::vector<std::string>& channels, int width, int height, const StackHeader& header,
                         const WriteOptions& options, const std::function<const Frame&(std::size_t)>& produce) {
  write_to_temporary(path, truths, channels, width, height, header, options, [&](Imf::MultiPartOutputFile& file, Exposures& exposures) {
    // Half conversions reuse their buffers from part to part, like the caller's frame.
    std::vector<std::vector<Imath::half>> half_buffers(channels.size());
    for (std::size_t i = 0; i < truths.size(); ++i)
      write_part(file, i, produce(i), channels, width, height, options, half_buffers, exposures);
  });
}

double write_stack_overlapped(const std::string& path, const std::vector<scene::Truth>& truths,
                            const std::vector<std::string>& channels, int width, int height, const StackHeader& header,
                            const WriteOptions& options, std::array<Frame, 2>& frames,
                            const std::function<void(std::size_t, Frame&)>& fill) {
  double writing_s = 0;
  write_to_temporary(path, truths, channels, width, height, header, options, [&](Imf::MultiPartOutputFile& file,
                                                                                Exposures& exposures) {
    std::vector<std::vector<Imath::half>> half_buffers(channels.size());
    const std::size_t parts = truths.size();
    if (parts == 0) return;
    fill(0, frames[0]);
    for (std::size_t i = 0; i < parts; ++i) {
      // Part i + 1 renders on a second thread while part i is encoded and written here; the join
      // (get) comes before either frame is touched again, and rethrows what fill threw.
      std::future<void> next;
      if (i + 1 < parts) next = std::async(std::launch::async, [&, i] { fill(i + 1, frames[(i + 1) % 2]); });
      try {
        const auto t0 = std::chrono::steady_clock::now();
        write_part(file, i, frames[i % 2], channels, width, height, options, half_buffers, exposures);
        writing_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      } catch (...) {
        if (next.valid()) next.wait();  // never leave the thread writing into a frame being unwound
        throw;
      }
      if (next.valid()) next.get();
    }
  });
  return writing_s;
}

double write_stack_banded(const std::string& path, const std::vector<scene::Truth>& truths,
                          const std::vector<std::string>& channels, int width, int height, const StackHeader& header,
                          const WriteOptions& options, int band_rows, std::array<Frame, 2>& bands,
                          const std::function<void(std::size_t, int, int, Frame&)>& fill) {
  if (band_rows < 1) throw std::invalid_argument("write_stack_banded: band_rows must be >= 1");
  double writing_s = 0;
  write_to_temporary(path, truths, channels, width, height, header, options, [&](Imf::MultiPartOutputFile& file,
                                                                                Exposures& exposures) {
    std::vector<std::vector<Imath::half>> half_buffers(channels.size());
    const std::size_t per_part = static_cast<std::size_t>((height + band_rows - 1) / band_rows);
    const std::size_t jobs = truths.size() * per_part;
    if (jobs == 0) return;
    auto rows_of = [&](std::size_t j) {
      const int y0 = static_cast<int>(j % per_part) * band_rows;
      return std::pair{y0, std::min(height, y0 + band_rows)};
    };
    auto run = [&](std::size_t j) {
      const auto [y0, y1] = rows_of(j);
      fill(j / per_part, y0, y1, bands[j % 2]);
    };
    // One thread fills band j + 1 while this one writes band j; they hand over through the
    // mutex (a thread per band would cost more than the handover).
    std::mutex m;
    std::condition_variable cv;
    std::size_t asked = 0, done = 0;  // bands asked of the filler, and filled
    bool quit = false;
    std::exception_ptr failed;
    std::thread filler([&] {
      for (std::size_t j = 1; j < jobs; ++j) {
        {
          std::unique_lock lock(m);
          cv.wait(lock, [&] { return asked >= j || quit; });
          if (quit) return;
        }
        try {
          run(j);
        } catch (...) {
          std::lock_guard lock(m);
          failed = std::current_exception();
          quit = true;
          cv.notify_all();
          return;
        }
        std::lock_guard lock(m);
        done = j;
        cv.notify_all();
      }
    });
    auto stop = [&] {
      {
        std::lock_guard lock(m);
        quit = true;
      }
      cv.notify_all();
      filler.join();
    };
    try {
      run(0);
      std::unique_ptr<Imf::OutputPart> part;
      for (std::size_t j = 0; j < jobs; ++j) {
        if (j > 0) {  // band j is filled (band j − 1 was written: its buffer is free for band j + 1)
          std::unique_lock lock(m);
          cv.wait(lock, [&] { return done >= j || failed; });
          if (failed) std::rethrow_exception(failed);
        }
        if (j + 1 < jobs) {
          std::lock_guard lock(m);
          asked = j + 1;
          cv.notify_all();
        }
        // Band j + 1 fills the other buffer meanwhile; band j is written from this one.
        const auto t0 = std::chrono::steady_clock::now();
        const auto [y0, y1] = rows_of(j);
        if (y0 == 0) {
          part = std::make_unique<Imf::OutputPart>(file, static_cast<int>(j / per_part));
          exposures.note(j / per_part, bands[j % 2]);
        }
        part->setFrameBuffer(slices(bands[j % 2], y0, channels, width, options, half_buffers));
        part->writePixels(y1 - y0);
        writing_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
    } catch (...) {
      stop();
      throw;
    }
    stop();
  });
  return writing_s;
}

Stack read_stack_frames(const std::string& path, const std::vector<std::string>& only_channels,
                        const std::function<void(std::size_t, Frame&&)>& each) {
  return read_stack_frames(path, only_channels, nullptr, each);
}

Stack read_stack_frames(const std::string& path, const std::vector<std::string>& only_channels,
                        const std::function<void(const Stack&)>& facts,
                        const std::function<void(std::size_t, Frame&&)>& each) {
  use_all_cores_for_exr();
  Stack stack;
  std::exception_ptr callers;  // what `each` threw: passed on as it is, not as a read error
  try {
    Imf::MultiPartInputFile file(path.c_str());
    int parts = file.parts();
    if (parts < 1) throw scene::SceneError(scene::FileLoc{path, 0, 0}, "the file has no parts");
    const Imf::Header& h0 = file.header(0);
    stack.camera_description = need<Imf::StringAttribute>(h0, "skypol:camera", path, 0).value();
    stack.scene_text = need<Imf::StringAttribute>(h0, "skypol:scene", path, 0).value();
    stack.bands = split_commas(need<Imf::StringAttribute>(h0, "skypol:bands", path, 0).value());
    stack.camera = scene::build_camera(scene::parse_camera(stack.camera_description, path + " [skypol:camera]"));
    const Known known = known_of(h0);
    stack.truth_known = known.truth;
    stack.site_known = known.site;
    if (facts) {
      try {
        facts(stack);
      } catch (...) {
        callers = std::current_exception();
        parts = 0;
      }
    }
    for (int i = 0; i < parts; ++i) {
      const Imf::Header& h = file.header(i);
      Frame frame;
      frame.truth = read_truth(h, path, i);
      if (const auto* e = h.findTypedAttribute<Imf::DoubleAttribute>(kExposure)) {
        if (!(std::isfinite(e->value()) && e->value() > 0)) {
          throw scene::SceneError(scene::FileLoc{path, 0, 0}, "part " + std::to_string(i) + "'s '" + kExposure +
                                                                   "' is not a positive exposure");
        }
        frame.exposure_us = e->value();
      }
      if (const auto* a = h.findTypedAttribute<Imf::StringAttribute>(kPolarizerAngles)) {
        const std::optional<PolarizerAngles> angles = polarizer_angles_named(a->value());
        if (!angles || *angles == PolarizerAngles::none) {
          throw scene::SceneError(scene::FileLoc{path, 0, 0}, "part " + std::to_string(i) + "'s '" + kPolarizerAngles +
                                                                   "' is '" + a->value() +
                                                                   "', not \"calibrated\" or \"nominal\"");
        }
        frame.polarizer_angles = *angles;
      }
      const Imath::Box2i dw = h.dataWindow();
      frame.width = dw.max.x - dw.min.x + 1;
      frame.height = dw.max.y - dw.min.y + 1;
      const std::size_t n = static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height);
      std::vector<std::string> names;
      if (only_channels.empty()) {
        for (auto it = h.channels().begin(); it != h.channels().end(); ++it) names.emplace_back(it.name());
      } else {
        for (const std::string& c : only_channels) {
          if (!h.channels().findChannel(c)) {
            std::string have;
            for (auto it = h.channels().begin(); it != h.channels().end(); ++it) have += std::string(" ") + it.name();
            throw scene::SceneError(scene::FileLoc{path, 0, 0}, "part " + std::to_string(i) + " has no channel '" + c +
                                                      "' (it has:" + have + ")");
          }
          names.push_back(c);
        }
      }
      Imf::FrameBuffer fb;
      for (const std::string& c : names) {
        std::vector<float>& data = frame.channels[c];
        data.assign(n, 0.0f);
        // OpenEXR converts half to float on read; the data window origin is (0, 0) for skypol files.
        char* base = reinterpret_cast<char*>(data.data()) -
                     (static_cast<std::ptrdiff_t>(dw.min.x) + static_cast<std::ptrdiff_t>(dw.min.y) * frame.width) *
                         static_cast<std::ptrdiff_t>(sizeof(float));
        fb.insert(c, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * static_cast<std::size_t>(frame.width)));
      }
      {
        Imf::InputPart part(file, i);
        part.setFrameBuffer(fb);
        part.readPixels(dw.min.y, dw.max.y);
      }
      // OpenEXR keeps each part it opened, with its line buffers, until the file closes: some
      // megabytes a part at full resolution, which a stack read part by part would hold for every
      // part. Let it go.
      file.flushPartCache();
      try {
        each(static_cast<std::size_t>(i), std::move(frame));
      } catch (...) {
        callers = std::current_exception();
        break;
      }
    }
  } catch (const scene::SceneError&) {
    throw;
  } catch (const std::exception& e) {
    throw scene::SceneError(scene::FileLoc{path, 0, 0}, std::string("cannot read stack: ") + e.what());
  }
  if (callers) std::rethrow_exception(callers);
  return stack;
}

Stack read_stack(const std::string& path, const std::vector<std::string>& only_channels) {
  std::vector<Frame> frames;
  Stack stack = read_stack_frames(path, only_channels, [&](std::size_t, Frame&& f) { frames.push_back(std::move(f)); });
  stack.frames = std::move(frames);
  return stack;
}

StackSummary peek_stack(const std::string& path) {
  StackSummary s;
  try {
    Imf::MultiPartInputFile file(path.c_str());
    const Imf::Header& h0 = file.header(0);
    const Imath::Box2i dw = h0.dataWindow();
    s.frames = file.parts();
    s.width = dw.max.x - dw.min.x + 1;
    s.height = dw.max.y - dw.min.y + 1;
    s.bands = split_commas(need<Imf::StringAttribute>(h0, "skypol:bands", path, 0).value());
    for (auto it = h0.channels().begin(); it != h0.channels().end(); ++it) s.channels.emplace_back(it.name());
    const Known known = known_of(h0);
    s.truth_known = known.truth;
    s.site_known = known.site;
  } catch (const scene::SceneError&) {
    throw;
  } catch (const std::exception& e) {
    throw scene::SceneError(scene::FileLoc{path, 0, 0}, std::string("cannot read stack: ") + e.what());
  }
  return s;
}

std::string describe_stack(const std::string& path) {
  std::ostringstream os;
  try {
    Imf::MultiPartInputFile file(path.c_str());
    const Imf::Header& h0 = file.header(0);
    const Imath::Box2i dw = h0.dataWindow();
    os << path << ": " << file.parts() << " frame(s), " << (dw.max.x - dw.min.x + 1) << "x" << (dw.max.y - dw.min.y + 1)
       << " px, bands " << need<Imf::StringAttribute>(h0, "skypol:bands", path, 0).value() << ", sky "
       << need<Imf::StringAttribute>(h0, "skypol:skyModel", path, 0).value() << "\nchannels:";
    for (auto it = h0.channels().begin(); it != h0.channels().end(); ++it) {
      os << " " << it.name() << (it.channel().type == Imf::HALF ? "(half)" : "");
    }
    os << "\ncamera:\n" << need<Imf::StringAttribute>(h0, "skypol:camera", path, 0).value();
    const Known known = known_of(h0);
    char line[512];
    // A sensor's exposures: one line for the whole stack, the range when the meter set them.
    if (h0.findTypedAttribute<Imf::DoubleAttribute>(kExposure)) {
      double lo = 0, hi = 0;
      for (int i = 0; i < file.parts(); ++i) {
        const double e = need<Imf::DoubleAttribute>(file.header(i), kExposure, path, i).value();
        lo = i == 0 ? e : std::min(lo, e);
        hi = i == 0 ? e : std::max(hi, e);
      }
      if (lo == hi) {
        std::snprintf(line, sizeof line, "exposure: %.6g us, every frame\n", lo);
      } else {
        std::snprintf(line, sizeof line, "exposure: %.6g to %.6g us (per frame: skypol:exposureUs)\n", lo, hi);
      }
      os << line;
    }
    if (const auto* a = h0.findTypedAttribute<Imf::StringAttribute>(kPolarizerAngles)) {
      os << "polarizer angles: " << a->value()
         << (a->value() == "nominal" ? " (the AoLP assumes them: the estimators fit the polarizers' error)\n"
                                     : " (the AoLP assumes the polarizers' own)\n");
    }
    if (!known.truth) {
      // A capture: times and, when given, the site and the sun; the heading is what it is for.
      os << "truth: unknown (an imported capture: heading and pole are for the estimators to find"
         << (known.site ? "" : "; site unknown") << ")\n";
      os << "frames (degrees):\n";
      std::snprintf(line, sizeof line, "%-3s %-22s %9s %9s %8s %8s %8s %8s\n", "#", "time (UTC)", "lat", "lon",
                    "sun az", "sun el", "tilt", "roll");
      os << line;
      for (int i = 0; i < file.parts(); ++i) {
        const scene::Truth t = read_truth(file.header(i), path, i);
        if (known.site) {
          std::snprintf(line, sizeof line, "%-3d %-22s %9.5f %9.5f %8.3f %8.3f %8.3f %8.3f\n", i,
                        sky::format_iso8601(t.time).c_str(), t.site.latitude_deg, t.site.longitude_deg,
                        t.sun.azimuth * kDegPerRad, t.sun.elevation * kDegPerRad, t.tilt_deg, t.roll_deg);
        } else {
          std::snprintf(line, sizeof line, "%-3d %-22s %9s %9s %8s %8s %8.3f %8.3f\n", i,
                        sky::format_iso8601(t.time).c_str(), "?", "?", "?", "?", t.tilt_deg, t.roll_deg);
        }
        os << line;
      }
      return os.str();
    }
    os << "frames (degrees; pole = the celestial pole the site sees):\n";
    std::snprintf(line, sizeof line, "%-3s %-22s %9s %9s %8s %8s %9s %8s %8s %8s %17s\n", "#", "time (UTC)", "lat",
                  "lon", "sun az", "sun el", "sun dec", "hour ang", "heading", "pole", "pole pixel");
    os << line;
    for (int i = 0; i < file.parts(); ++i) {
      const scene::Truth t = read_truth(file.header(i), path, i);
      char px[64] = "outside";
      if (t.pole_pixel) std::snprintf(px, sizeof px, "(%.2f, %.2f)", t.pole_pixel->x(), t.pole_pixel->y());
      std::snprintf(line, sizeof line, "%-3d %-22s %9.5f %9.5f %8.3f %8.3f %9.4f %8.3f %8.3f %8s %17s\n", i,
                    sky::format_iso8601(t.time).c_str(), t.site.latitude_deg, t.site.longitude_deg, t.sun.azimuth * kDegPerRad,
                    t.sun.elevation * kDegPerRad, t.sun.declination * kDegPerRad, t.sun.hour_angle * kDegPerRad, t.heading_deg,
                    t.pole_is_north ? "north" : "south", px);
      os << line;
    }
  } catch (const scene::SceneError&) {
    throw;
  } catch (const std::exception& e) {
    throw scene::SceneError(scene::FileLoc{path, 0, 0}, std::string("cannot read stack: ") + e.what());
  }
  return os.str();
}

}  // namespace skypol::stack
