// DoFP sensor simulation and bilinear demosaic; the noise model is in dofp_sensor.h.
#include "camera/dofp_sensor.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sky/units.h"

namespace skypol::camera {

namespace {
// Rows in parallel: every pixel's value depends only on its own inputs and its (seed, frame,
// pixel) noise key, so the output is the same bytes on any number of threads.
template <class RowFn>
void for_each_row(int height, RowFn&& row) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 16), [&](const tbb::blocked_range<int>& rows) {
    for (int r = rows.begin(); r != rows.end(); ++r) row(r);
  });
}
}  // namespace
namespace {

// SplitMix64's finalizer (Steele, Lea, Flood 2014): a bijective 64-bit mixer, good enough to turn
// (seed, frame, pixel, draw) counters into independent uniform bits.
constexpr std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// Random numbers of one pixel of one frame: a pure function of its counters, no shared state.
class PixelRandom {
 public:
  PixelRandom(std::uint64_t seed, std::uint64_t frame, std::uint64_t pixel)
      : key_(mix(mix(mix(seed) ^ frame) ^ pixel)) {}
  double uniform() {  // [0, 1)
    return static_cast<double>(mix(key_ + 0x632BE59BD9B4E019ULL * ++count_) >> 11) * 0x1p-53;
  }
  double normal() {  // Box–Muller
    const double u1 = 1 - uniform(), u2 = uniform();
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * std::numbers::pi * u2);
  }
  // Poisson by inversion below 64 (exact); above, the Gaussian of the same mean and variance
  // rounded to an integer, indistinguishable from Poisson at those counts for this purpose.
  double poisson(double mean) {
    if (!(mean > 0)) return 0;
    if (mean >= 64) return std::max(0.0, std::round(mean + std::sqrt(mean) * normal()));
    const double u = uniform();
    double p = std::exp(-mean), cdf = p;
    int k = 0;
    while (u > cdf && k < 1000) {
      ++k;
      p *= mean / k;
      cdf += p;
    }
    return k;
  }

 private:
  std::uint64_t key_;
  std::uint64_t count_ = 0;
};

int mosaic_index(int row, int col) { return 2 * (row & 1) + (col & 1); }

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

void validate(const DofpSensor& s) {
  require(s.width >= 2, "width must be >= 2");
  require(s.height >= 2, "height must be >= 2");
  for (double a : s.mosaic_deg) require(std::isfinite(a), "mosaic_deg must be finite");
  for (double a : s.angle_error_deg) require(std::isfinite(a), "angle_error_deg must be finite");
  require(std::isfinite(s.extinction_ratio) && s.extinction_ratio > 1, "extinction_ratio must be > 1");
  require(std::isfinite(s.exposure_us) && s.exposure_us > 0, "exposure_us must be > 0");
  require(std::isfinite(s.electrons_per_radiance_s) && s.electrons_per_radiance_s > 0,
          "electrons_per_radiance_s must be > 0");
  require(std::isfinite(s.gain_dn_per_e) && s.gain_dn_per_e > 0, "gain_dn_per_e must be > 0");
  require(std::isfinite(s.black_level_dn) && s.black_level_dn >= 0, "black_level_dn must be >= 0");
  require(std::isfinite(s.read_noise_e) && s.read_noise_e >= 0, "read_noise_e must be >= 0");
  require(std::isfinite(s.dark_current_e_s) && s.dark_current_e_s >= 0, "dark_current_e_s must be >= 0");
  require(std::isfinite(s.full_well_e) && s.full_well_e > 0, "full_well_e must be > 0");
  require(std::isfinite(s.prnu_rms) && s.prnu_rms >= 0, "prnu_rms must be >= 0");
  require(std::isfinite(s.dsnu_e) && s.dsnu_e >= 0, "dsnu_e must be >= 0");
  require(s.adc_bits >= 1 && s.adc_bits <= 16, "adc_bits must be in [1, 16]");
  for (double k : s.band_response)
    require(std::isfinite(k) && k > 0, "band_response must be > 0");
}

void validate(const AutoExposure& m) {
  require(std::isfinite(m.percentile) && m.percentile > 0 && m.percentile <= 100, "percentile must be in (0, 100]");
  require(std::isfinite(m.target) && m.target > 0 && m.target <= 1, "target must be in (0, 1]");
  require(std::isfinite(m.min_us) && m.min_us > 0, "min_us must be > 0");
  require(std::isfinite(m.max_us) && m.max_us >= m.min_us, "max_us must be >= min_us");
  require(std::isfinite(m.step_us) && m.step_us >= 0, "step_us must be >= 0");
}

double full_scale_e(const DofpSensor& s) {
  const double adc_top_e = (std::ldexp(1.0, s.adc_bits) - 1 - s.black_level_dn) / s.gain_dn_per_e;
  return std::min(s.full_well_e, adc_top_e);
}

double percentile_of(std::span<float> v, double percentile) {
  if (v.empty()) return 0;
  const double rank = std::clamp(percentile, 0.0, 100.0) / 100 * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(lo), v.end());
  const double below = v[lo];
  if (lo + 1 >= v.size()) return below;
  // The next order statistic is the smallest of the values after the lo-th.
  const double above = *std::min_element(v.begin() + static_cast<std::ptrdiff_t>(lo + 1), v.end());
  return below + (rank - static_cast<double>(lo)) * (above - below);
}

double metered_exposure_us(const DofpSensor& s, const AutoExposure& m, double sky_s0) {
  if (!(sky_s0 > 0)) return m.max_us;  // NaN too; an infinite S0 meters to min_us
  double t_us = m.target * full_scale_e(s) / (s.electrons_per_radiance_s * sky_s0) * 1e6;
  if (m.step_us > 0) t_us = std::floor(t_us / m.step_us) * m.step_us;
  return std::clamp(t_us, m.min_us, m.max_us);
}

double polarizer_radiance(const DofpSensor& s, int row, int col, double s0, double s1, double s2) {
  const int i = mosaic_index(row, col);
  const double th = (s.mosaic_deg[i] + s.angle_error_deg[i]) * kRadPerDeg;
  const double tmin = 1 / s.extinction_ratio;  // Tmax = 1
  return 0.5 * ((1 + tmin) * s0 + (1 - tmin) * (s1 * std::cos(2 * th) + s2 * std::sin(2 * th)));
}

std::uint16_t simulate_pixel(const DofpSensor& s, int row, int col, double s0, double s1, double s2,
                             std::uint64_t frame) {
  double radiance = polarizer_radiance(s, row, col, s0, s1, s2);
  if (!std::isfinite(radiance) || radiance < 0) radiance = 0;  // masked or unphysical input
  const double t = s.exposure_us * 1e-6;
  const auto pixel = static_cast<std::uint64_t>(row) * static_cast<std::uint64_t>(s.width) +
                     static_cast<std::uint64_t>(col);
  // Fixed pattern: a per-pixel draw keyed without the frame, so every frame sees the same one.
  double response = 1, offset_e = 0;
  if (s.prnu_rms > 0 || s.dsnu_e > 0) {
    PixelRandom fixed(mix(s.seed ^ 0xF1C5ED9A77E2B3D1ULL), 0, pixel);
    response = std::max(0.0, 1 + s.prnu_rms * fixed.normal());
    offset_e = s.dsnu_e * fixed.normal();
  }
  const double mean_e = radiance * s.electrons_per_radiance_s * response * t + s.dark_current_e_s * t;
  PixelRandom rng(s.seed, frame, pixel);
  double e = s.shot_noise ? rng.poisson(mean_e) : mean_e;
  e = std::max(0.0, e + offset_e);
  e = std::min(e, s.full_well_e);
  if (s.read_noise_e > 0) e += s.read_noise_e * rng.normal();
  const double max_dn = std::ldexp(1.0, s.adc_bits) - 1;
  const double dn = std::clamp(std::round(s.gain_dn_per_e * e + s.black_level_dn), 0.0, max_dn);
  return static_cast<std::uint16_t>(dn);
}

std::vector<std::uint16_t> simulate_raw(const DofpSensor& s, std::span<const float> s0,
                                        std::span<const float> s1, std::span<const float> s2,
                                        std::uint64_t frame) {
  std::vector<std::uint16_t> raw;
  simulate_raw_into(s, s0, s1, s2, frame, raw);
  return raw;
}

void simulate_raw_into(const DofpSensor& s, std::span<const float> s0, std::span<const float> s1,
                       std::span<const float> s2, std::uint64_t frame, std::vector<std::uint16_t>& raw) {
  validate(s);
  const auto n = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
  if (s0.size() != n || s1.size() != n || s2.size() != n)
    throw std::invalid_argument("Stokes images must hold width*height values");
  raw.resize(n);
  for_each_row(s.height, [&](int r) {
    for (int c = 0; c < s.width; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * static_cast<std::size_t>(s.width) + c;
      raw[i] = simulate_pixel(s, r, c, s0[i], s1[i], s2[i], frame);
    }
  });
}

namespace {

// Where 0°, 45°, 90°, 135° sit in the mosaic (−1: absent).
std::array<int, 4> nominal_positions(const DofpSensor& s) {
  std::array<int, 4> pos{-1, -1, -1, -1};
  for (int i = 0; i < 4; ++i) {
    const double a = std::fmod(std::fmod(s.mosaic_deg[i], 180.0) + 180.0, 180.0);
    for (int k = 0; k < 4; ++k)
      if (std::abs(a - 45.0 * k) < 1e-9) pos[k] = i;
  }
  return pos;
}

// Least-squares inverse (AᵀA)⁻¹Aᵀ (3 × 4) of the sensor's analyzer A (I = A·S, the coefficients
// of polarizer_radiance per mosaic position).
std::array<std::array<double, 4>, 3> analyzer_inverse(const DofpSensor& s) {
  const double tmin = 1 / s.extinction_ratio;
  std::array<std::array<double, 3>, 4> a{};
  for (int i = 0; i < 4; ++i) {
    const double th = (s.mosaic_deg[i] + s.angle_error_deg[i]) * kRadPerDeg;
    a[i] = {0.5 * (1 + tmin), 0.5 * (1 - tmin) * std::cos(2 * th), 0.5 * (1 - tmin) * std::sin(2 * th)};
  }
  double ata[3][3] = {};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 4; ++i) ata[r][c] += a[i][r] * a[i][c];
  const double det = ata[0][0] * (ata[1][1] * ata[2][2] - ata[1][2] * ata[2][1]) -
                     ata[0][1] * (ata[1][0] * ata[2][2] - ata[1][2] * ata[2][0]) +
                     ata[0][2] * (ata[1][0] * ata[2][1] - ata[1][1] * ata[2][0]);
  if (!(std::abs(det) > 1e-12))
    throw std::invalid_argument("mosaic_deg: the four polarizer angles do not determine S1 and S2");
  double ai[3][3];  // inverse by cofactors (symmetric matrix)
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      ai[r][c] = (ata[r1][c1] * ata[r2][c2] - ata[r1][c2] * ata[r2][c1]) / det;
    }
  std::array<std::array<double, 4>, 3> inv{};
  for (int r = 0; r < 3; ++r)
    for (int i = 0; i < 4; ++i) inv[r][i] = ai[r][0] * a[i][0] + ai[r][1] * a[i][1] + ai[r][2] * a[i][2];
  return inv;
}

// A rectangular sampling lattice: rows oy + period·i, columns ox + period·j.
struct Lattice {
  int oy, ox;
};

// Stokes of one band from a raw mosaic. Mosaic position p's samples lie on the lattices
// lattices[p] (one for a mono sensor or the R and B of a colour one, two for G); each lattice is
// interpolated bilinearly (nearest row/column repeated beyond its edge) and the lattices averaged.
// T: uint16_t (DN as the ADC gives them) or float (DN after a dark or flat correction).
template <class T>
void demosaic_core(const DofpSensor& s, std::span<const T> raw, Demosaic mode,
                   int period, const std::array<std::vector<Lattice>, 4>& lattices, double response,
                   StokesPlanes& out) {
  const int w = s.width, h = s.height;
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (raw.size() != n) throw std::invalid_argument("raw mosaic must hold width*height values");
  const std::array<int, 4> pos = nominal_positions(s);
  if (mode == Demosaic::nominal)
    for (int k : pos)
      if (k < 0) throw std::invalid_argument("mosaic_deg must hold 0, 45, 90 and 135");
  const auto inv = mode == Demosaic::calibrated ? analyzer_inverse(s)
                                                : std::array<std::array<double, 4>, 3>{};

  const double t = s.exposure_us * 1e-6;
  const double dark_e = s.dark_current_e_s * t;
  const double scale = 1 / (s.electrons_per_radiance_s * response * t);
  auto radiance = [&](int r, int c) {
    const auto dn = static_cast<double>(raw[static_cast<std::size_t>(r) * static_cast<std::size_t>(w) + c]);
    return ((dn - s.black_level_dn) / s.gain_dn_per_e - dark_e) * scale;
  };
  auto on_lattice = [&](const Lattice& l, int r, int c) {
    const int ny = (h - l.oy + period - 1) / period, nx = (w - l.ox + period - 1) / period;
    const double y = static_cast<double>(r - l.oy) / period, x = static_cast<double>(c - l.ox) / period;
    const int i0 = static_cast<int>(std::floor(y)), j0 = static_cast<int>(std::floor(x));
    const double fy = y - i0, fx = x - j0;
    auto at = [&](int i, int j) {
      i = std::clamp(i, 0, ny - 1);
      j = std::clamp(j, 0, nx - 1);
      return radiance(l.oy + period * i, l.ox + period * j);
    };
    return (1 - fy) * ((1 - fx) * at(i0, j0) + fx * at(i0, j0 + 1)) +
           fy * ((1 - fx) * at(i0 + 1, j0) + fx * at(i0 + 1, j0 + 1));
  };
  auto channel = [&](int p, int r, int c) {
    double sum = 0;
    for (const Lattice& l : lattices[static_cast<std::size_t>(p)]) sum += on_lattice(l, r, c);
    return sum / static_cast<double>(lattices[static_cast<std::size_t>(p)].size());
  };

  out.s0.resize(n);
  out.s1.resize(n);
  out.s2.resize(n);
  for_each_row(h, [&](int r) {
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * static_cast<std::size_t>(w) + c;
      if (mode == Demosaic::calibrated) {
        std::array<double, 4> v;
        for (int k = 0; k < 4; ++k) v[static_cast<std::size_t>(k)] = channel(k, r, c);
        double st[3];
        for (int q = 0; q < 3; ++q)
          st[q] = inv[q][0] * v[0] + inv[q][1] * v[1] + inv[q][2] * v[2] + inv[q][3] * v[3];
        out.s0[i] = static_cast<float>(st[0]);
        out.s1[i] = static_cast<float>(st[1]);
        out.s2[i] = static_cast<float>(st[2]);
        continue;
      }
      const double i0 = channel(pos[0], r, c), i45 = channel(pos[1], r, c);
      const double i90 = channel(pos[2], r, c), i135 = channel(pos[3], r, c);
      out.s0[i] = static_cast<float>(0.5 * (i0 + i45 + i90 + i135));
      out.s1[i] = static_cast<float>(i0 - i90);
      out.s2[i] = static_cast<float>(i45 - i135);
    }
  });
}

// Colour blocks of an RGGB-of-2×2-blocks filter: (block row, block col) parities per band.
const std::array<std::vector<std::pair<int, int>>, 3> kBandBlocks = {{
    {{0, 0}},          // R
    {{0, 1}, {1, 0}},  // G
    {{1, 1}},          // B
}};

template <class T>
void mono_into(const DofpSensor& s, std::span<const T> raw, Demosaic mode, StokesPlanes& out) {
  validate(s);
  if (s.color_filter != ColorFilter::none)
    throw std::invalid_argument("color_filter: a colour sensor needs demosaic_color_bilinear");
  std::array<std::vector<Lattice>, 4> lattices;
  for (int p = 0; p < 4; ++p) lattices[static_cast<std::size_t>(p)] = {Lattice{p >> 1, p & 1}};
  demosaic_core(s, raw, mode, 2, lattices, 1.0, out);
}

template <class T>
void color_into(const DofpSensor& s, std::span<const T> raw, Demosaic mode, std::array<StokesPlanes, 3>& out) {
  validate(s);
  if (s.color_filter == ColorFilter::none)
    throw std::invalid_argument("color_filter: demosaic_color_bilinear needs a colour sensor (rggb_blocks)");
  if (s.width < 4 || s.height < 4) throw std::invalid_argument("a colour sensor needs width, height >= 4");
  for (std::size_t b = 0; b < 3; ++b) {
    std::array<std::vector<Lattice>, 4> lattices;
    for (int p = 0; p < 4; ++p)
      for (const auto& [by, bx] : kBandBlocks[b])
        lattices[static_cast<std::size_t>(p)].push_back(Lattice{2 * by + (p >> 1), 2 * bx + (p & 1)});
    demosaic_core(s, raw, mode, 4, lattices, s.band_response[b], out[b]);
  }
}

}  // namespace

StokesPlanes demosaic_bilinear(const DofpSensor& s, std::span<const std::uint16_t> raw,
                               Demosaic mode) {
  StokesPlanes out;
  demosaic_bilinear_into(s, raw, mode, out);
  return out;
}

StokesPlanes demosaic_bilinear(const DofpSensor& s, std::span<const float> raw, Demosaic mode) {
  StokesPlanes out;
  mono_into(s, raw, mode, out);
  return out;
}

void demosaic_bilinear_into(const DofpSensor& s, std::span<const std::uint16_t> raw, Demosaic mode,
                            StokesPlanes& out) {
  mono_into(s, raw, mode, out);
}

int band_of_pixel(const DofpSensor& s, int row, int col) {
  if (s.color_filter == ColorFilter::none) return -1;
  const int by = (row >> 1) & 1, bx = (col >> 1) & 1;
  return by == bx ? (by == 0 ? 0 : 2) : 1;
}

std::vector<std::uint16_t> simulate_raw_color(const DofpSensor& s, const std::array<BandStokes, 3>& rgb,
                                              std::uint64_t frame) {
  std::vector<std::uint16_t> raw;
  simulate_raw_color_into(s, rgb, frame, raw);
  return raw;
}

void simulate_raw_color_into(const DofpSensor& s, const std::array<BandStokes, 3>& rgb,
                             std::uint64_t frame, std::vector<std::uint16_t>& raw) {
  validate(s);
  if (s.color_filter == ColorFilter::none)
    throw std::invalid_argument("color_filter: simulate_raw_color needs a colour sensor (rggb_blocks)");
  const auto n = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
  for (const auto& b : rgb)
    if (b.s0.size() != n || b.s1.size() != n || b.s2.size() != n)
      throw std::invalid_argument("Stokes images must hold width*height values");
  raw.resize(n);
  for_each_row(s.height, [&](int r) {
    for (int c = 0; c < s.width; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * static_cast<std::size_t>(s.width) + c;
      const auto b = static_cast<std::size_t>(band_of_pixel(s, r, c));
      const double k = s.band_response[b];
      raw[i] = simulate_pixel(s, r, c, k * double{rgb[b].s0[i]}, k * double{rgb[b].s1[i]},
                              k * double{rgb[b].s2[i]}, frame);
    }
  });
}

std::array<StokesPlanes, 3> demosaic_color_bilinear(const DofpSensor& s,
                                                    std::span<const std::uint16_t> raw,
                                                    Demosaic mode) {
  std::array<StokesPlanes, 3> out;
  demosaic_color_bilinear_into(s, raw, mode, out);
  return out;
}

std::array<StokesPlanes, 3> demosaic_color_bilinear(const DofpSensor& s, std::span<const float> raw, Demosaic mode) {
  std::array<StokesPlanes, 3> out;
  color_into(s, raw, mode, out);
  return out;
}

void demosaic_color_bilinear_into(const DofpSensor& s, std::span<const std::uint16_t> raw,
                                  Demosaic mode, std::array<StokesPlanes, 3>& out) {
  color_into(s, raw, mode, out);
}

int demosaic_reach(const DofpSensor& s) { return s.color_filter == ColorFilter::none ? 1 : 3; }

// A separable erosion: along the rows, then down the columns.
void erode_mask(std::vector<float>& mask, int w, int h, int reach) {
  thread_local std::vector<std::uint8_t> rows;  // reused frame after frame
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  rows.assign(n, 1);
  for (int y = 0; y < h; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    for (int x = 0; x < w; ++x) {
      if (mask[row + x] > 0.0f) continue;
      for (int k = std::max(0, x - reach); k <= std::min(w - 1, x + reach); ++k) rows[row + k] = 0;
    }
  }
  for (int y = 0; y < h; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    for (int k = std::max(0, y - reach); k <= std::min(h - 1, y + reach); ++k) {
      const std::size_t other = static_cast<std::size_t>(k) * static_cast<std::size_t>(w);
      for (int x = 0; x < w; ++x)
        if (!rows[other + x]) mask[row + x] = 0.0f;
    }
  }
}

double clip_level_dn(const DofpSensor& s) {
  const double max_dn = std::ldexp(1.0, s.adc_bits) - 1;
  const double well_dn = s.gain_dn_per_e * (s.full_well_e - 4 * s.read_noise_e) + s.black_level_dn;
  return std::min(max_dn, std::floor(well_dn));
}

std::vector<std::uint8_t> clipped_pixels(const DofpSensor& s, std::span<const std::uint16_t> raw) {
  const int w = s.width, h = s.height;
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (raw.size() != n) throw std::invalid_argument("raw mosaic must hold width*height values");
  const double level = clip_level_dn(s);
  const int reach = demosaic_reach(s);
  // A separable dilation: along the rows, then down the columns.
  std::vector<std::uint8_t> rows(n, 0), out(n, 0);
  for_each_row(h, [&](int r) {
    const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(w);
    for (int c = 0; c < w; ++c) {
      if (!(raw[row + c] >= level)) continue;
      for (int k = std::max(0, c - reach); k <= std::min(w - 1, c + reach); ++k) rows[row + k] = 1;
    }
  });
  for_each_row(h, [&](int r) {
    const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(w);
    for (int k = std::max(0, r - reach); k <= std::min(h - 1, r + reach); ++k) {
      const std::size_t other = static_cast<std::size_t>(k) * static_cast<std::size_t>(w);
      for (int c = 0; c < w; ++c) out[row + c] |= rows[other + c];
    }
  });
  return out;
}

void mask_clipped(std::span<const std::uint8_t> clipped, std::vector<float>& mask, std::vector<float>& clipped_sky) {
  if (clipped.size() != mask.size()) throw std::invalid_argument("clipped pixels and mask differ in size");
  clipped_sky.assign(mask.size(), 0.0f);
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!clipped[i]) continue;
    if (mask[i] > 0.0f) clipped_sky[i] = 1.0f;
    mask[i] = 0.0f;
  }
}

}  // namespace skypol::camera
