// The table: one solve on a grid in zenith angle (see grid_v) (the grid doubles as the solver's zero-weight nodes), the
// single-scattering part taken out, cubic Lagrange interpolation in μ and μ0 through that grid, and the disk cache.
#include "sky/vrte/vrte_table.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>

namespace skypol::sky::vrte {

namespace {

// 2: the solver's doubling starts from a layer correct to second order (values moved by ~1e-5).
constexpr std::uint32_t kFormatVersion = 2;
constexpr char kMagic[8] = {'S', 'K', 'Y', 'V', 'R', 'T', 'E', '\0'};

std::uint64_t fnv1a(const char* p, std::size_t n, std::uint64_t h = 1469598103934665603ull) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(p[i]);
    h *= 1099511628211ull;
  }
  return h;
}

template <class T>
void put(std::string& s, const T& v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
void put_vec(std::string& s, const std::vector<double>& v) {
  put(s, static_cast<std::uint64_t>(v.size()));
  s.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
}

// Four-point Lagrange interpolation on the uniform v grid, the stencil kept inside the grid.
struct Stencil {
  int base = 0;
  double w[4] = {0, 0, 0, 0};
};

Stencil stencil(double mu, int g) {
  const double u = grid_v(mu) * (g - 1);
  Stencil st;
  st.base = std::clamp(static_cast<int>(std::floor(u)) - 1, 0, g - 4);
  const double t = u - (st.base + 1);
  st.w[0] = -t * (t - 1) * (t - 2) / 6.0;
  st.w[1] = (t + 1) * (t - 1) * (t - 2) / 2.0;
  st.w[2] = -(t + 1) * t * (t - 2) / 2.0;
  st.w[3] = (t + 1) * t * (t - 1) / 6.0;
  return st;
}

void check_options(const TableOptions& o) {
  if (o.grid < 4) throw std::invalid_argument("vrte table: grid must be >= 4, got " + std::to_string(o.grid));
  if (o.streams < 2) throw std::invalid_argument("vrte table: streams must be >= 2");
}

}  // namespace

// The grid variable v ∈ [0, 1]: μ = sin(πv²/2), i.e. zenith angle θ = (π/2)(1 − v²). Near the
// horizon μ ≈ πv²/2, so nodes crowd where the sky changes fastest (μ ~ τ); near the zenith θ is
// linear in v, so the Fourier coefficients, which go as sin^m θ, stay smooth (in μ or √μ they have
// a square-root branch at μ = 1).
double grid_v(double mu) { return std::sqrt(2.0 * std::asin(std::clamp(mu, 0.0, 1.0)) / std::numbers::pi); }
double grid_mu(double v) { return std::sin(0.5 * std::numbers::pi * v * v); }

std::string VrteTable::cache_key(const LayerOptics& o, double albedo, const TableOptions& opt) {
  std::string k = "skypol-vrte-table";
  put(k, kFormatVersion);
  put(k, static_cast<std::int32_t>(opt.streams));
  put(k, static_cast<std::int32_t>(opt.grid));
  put(k, albedo);
  put(k, o.tau_rayleigh);
  put(k, o.depolarization);
  put(k, o.tau_aerosol);
  put(k, o.aerosol_ssa);
  const auto& a = o.aerosol;
  for (const auto* v : {&a.cos_theta, &a.weight, &a.f11, &a.f12, &a.f22, &a.f33, &a.f34, &a.f44}) put_vec(k, *v);
  return k;
}

std::string VrteTable::cache_file_name(const LayerOptics& o, double albedo, const TableOptions& opt) {
  const std::string k = cache_key(o, albedo, opt);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fnv1a(k.data(), k.size())));
  return "vrte-v" + std::to_string(kFormatVersion) + "-" + hex + ".bin";
}

VrteTable VrteTable::build(const LayerOptics& optics, double albedo, const TableOptions& opt) {
  check_options(opt);
  const ScaledLayer layer = scale_layer(optics, opt.streams);
  std::vector<double> nodes(static_cast<std::size_t>(opt.grid));
  for (int k = 0; k < opt.grid; ++k) {
    nodes[static_cast<std::size_t>(k)] = grid_mu(static_cast<double>(k) / (opt.grid - 1));
  }
  SolverOptions so;
  so.streams = opt.streams;
  so.threads = opt.threads;
  const FourierSolution s = solve(layer, albedo, nodes, so);
  VrteTable t;
  t.terms_ = s.terms;
  t.grid_ = opt.grid;
  t.down_.resize(s.down.size());
  t.up_.resize(s.up.size());
  for (std::size_t i = 0; i < s.down.size(); ++i) {
    t.down_[i] = s.down[i] - s.ss_down[i];
    t.up_[i] = s.up[i] - s.ss_up[i];
  }
  t.ground_ = s.ground;
  t.exact_ = exact_layer(optics);
  t.key_ = cache_key(optics, albedo, opt);
  return t;
}

bool VrteTable::write(const std::filesystem::path& file) const {
  std::string b(kMagic, sizeof kMagic);
  put(b, kFormatVersion);
  put(b, static_cast<std::uint64_t>(key_.size()));
  b += key_;
  put(b, static_cast<std::int32_t>(terms_));
  put(b, static_cast<std::int32_t>(grid_));
  put_vec(b, down_);
  put_vec(b, up_);
  put_vec(b, ground_);
  put(b, fnv1a(b.data(), b.size()));

  std::random_device rd;
  const std::filesystem::path tmp = file.string() + ".tmp-" + std::to_string(rd()) + std::to_string(rd());
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(b.data(), static_cast<std::streamsize>(b.size()));
    f.close();
    if (!f) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return false;
  }
  return true;
}

std::optional<VrteTable> VrteTable::read(const std::filesystem::path& file, const LayerOptics& optics, double albedo,
                                         const TableOptions& opt) {
  std::ifstream f(file, std::ios::binary);
  if (!f) return std::nullopt;
  const std::string b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::size_t pos = 0;
  auto take = [&](void* dst, std::size_t n) {
    if (pos + n > b.size()) return false;
    std::memcpy(dst, b.data() + pos, n);
    pos += n;
    return true;
  };
  auto take_vec = [&](std::vector<double>& v, std::size_t expected) {
    std::uint64_t n = 0;
    if (!take(&n, sizeof n) || n != expected) return false;
    v.resize(expected);
    return take(v.data(), expected * sizeof(double));
  };
  char magic[8];
  std::uint32_t version = 0;
  std::uint64_t key_size = 0;
  if (!take(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof magic) != 0) return std::nullopt;
  if (!take(&version, sizeof version) || version != kFormatVersion) return std::nullopt;
  const std::string key = cache_key(optics, albedo, opt);
  if (!take(&key_size, sizeof key_size) || key_size != key.size() || pos + key_size > b.size()) return std::nullopt;
  if (b.compare(pos, key.size(), key) != 0) return std::nullopt;
  pos += key.size();
  std::int32_t terms = 0, grid = 0;
  if (!take(&terms, sizeof terms) || !take(&grid, sizeof grid)) return std::nullopt;
  if (terms < 1 || terms > 1000 || grid != opt.grid) return std::nullopt;
  VrteTable t;
  t.terms_ = terms;
  t.grid_ = grid;
  const auto n = static_cast<std::size_t>(terms) * static_cast<std::size_t>(grid) * static_cast<std::size_t>(grid) * 3;
  if (!take_vec(t.down_, n) || !take_vec(t.up_, n) || !take_vec(t.ground_, static_cast<std::size_t>(grid)))
    return std::nullopt;
  const std::size_t body = pos;
  std::uint64_t sum = 0;
  if (!take(&sum, sizeof sum) || pos != b.size() || sum != fnv1a(b.data(), body)) return std::nullopt;
  t.exact_ = exact_layer(optics);
  t.key_ = key;
  return t;
}

VrteTable VrteTable::cached(const LayerOptics& optics, double albedo, const TableOptions& opt,
                            const std::filesystem::path& dir, bool* hit) {
  check_options(opt);
  const std::filesystem::path file = dir / cache_file_name(optics, albedo, opt);
  if (auto t = read(file, optics, albedo, opt)) {
    if (hit) *hit = true;
    return std::move(*t);
  }
  if (hit) *hit = false;
  VrteTable t = build(optics, albedo, opt);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  t.write(file);  // a cache that cannot be written costs a rebuild next time, nothing else
  return t;
}

StokesIQU VrteTable::table(const std::vector<double>& data, double mu, double mu0, double dphi) const {
  if (data.empty()) return {};
  const Stencil si = stencil(mu, grid_), sj = stencil(mu0, grid_);
  const auto g = static_cast<std::size_t>(grid_);
  StokesIQU r;
  for (int m = 0; m < terms_; ++m) {
    double c[3] = {0, 0, 0};
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const double w = si.w[a] * sj.w[b];
        const std::size_t o = ((static_cast<std::size_t>(m) * g + static_cast<std::size_t>(si.base + a)) * g +
                               static_cast<std::size_t>(sj.base + b)) *
                              3;
        for (int k = 0; k < 3; ++k) c[k] += w * data[o + static_cast<std::size_t>(k)];
      }
    const double cm = std::cos(m * dphi), sm = std::sin(m * dphi);
    r.i += c[0] * cm;
    r.q += c[1] * cm;
    r.u += c[2] * sm;
  }
  return r;
}

StokesIQU VrteTable::radiance(const std::vector<double>& multiple, bool up, double mu, double mu0, double dphi) const {
  if (!(mu0 > 0.0)) return {};
  mu = std::clamp(mu, 0.0, 1.0);
  mu0 = std::min(mu0, 1.0);
  const StokesIQU ms = table(multiple, mu, mu0, dphi);
  const StokesIQU ss = single_scattering(exact_, mu, mu0, dphi, up);
  return {ms.i + ss.i, ms.q + ss.q, ms.u + ss.u};
}

StokesIQU VrteTable::down(double mu, double mu0, double dphi) const { return radiance(down_, false, mu, mu0, dphi); }

StokesIQU VrteTable::up(double mu, double mu0, double dphi) const { return radiance(up_, true, mu, mu0, dphi); }

double VrteTable::ground(double mu0) const {
  if (!(mu0 > 0.0) || ground_.empty()) return 0.0;
  const Stencil sj = stencil(std::min(mu0, 1.0), grid_);
  double r = 0;
  for (int b = 0; b < 4; ++b) r += sj.w[b] * ground_[static_cast<std::size_t>(sj.base + b)];
  return r;
}

VrteTable::SunSlice VrteTable::slice(double mu0) const {
  SunSlice s;
  s.mu0 = std::clamp(mu0, 0.0, 1.0);
  if (!(mu0 > 0.0)) return s;
  const Stencil sj = stencil(s.mu0, grid_);
  const auto g = static_cast<std::size_t>(grid_);
  s.down.assign(static_cast<std::size_t>(terms_) * g * 3, 0.0);
  for (std::size_t m = 0; m < static_cast<std::size_t>(terms_); ++m)
    for (std::size_t k = 0; k < g; ++k)
      for (int b = 0; b < 4; ++b) {
        const std::size_t o = ((m * g + k) * g + static_cast<std::size_t>(sj.base + b)) * 3;
        for (std::size_t c = 0; c < 3; ++c) s.down[(m * g + k) * 3 + c] += sj.w[b] * down_[o + c];
      }
  s.ground = ground(mu0);
  return s;
}

StokesIQU VrteTable::down(const SunSlice& s, double mu, double cos_dphi, double sin_dphi) const {
  if (s.down.empty()) return {};
  mu = std::clamp(mu, 0.0, 1.0);
  const Stencil si = stencil(mu, grid_);
  const auto g = static_cast<std::size_t>(grid_);
  StokesIQU r;
  double cm = 1.0, sm = 0.0, cp = cos_dphi, sp = -sin_dphi;  // m = 0 and m = −1
  for (std::size_t m = 0; m < static_cast<std::size_t>(terms_); ++m) {
    const double* d = &s.down[(m * g + static_cast<std::size_t>(si.base)) * 3];
    const double ci = si.w[0] * d[0] + si.w[1] * d[3] + si.w[2] * d[6] + si.w[3] * d[9];
    const double cq = si.w[0] * d[1] + si.w[1] * d[4] + si.w[2] * d[7] + si.w[3] * d[10];
    const double cu = si.w[0] * d[2] + si.w[1] * d[5] + si.w[2] * d[8] + si.w[3] * d[11];
    r.i += ci * cm;
    r.q += cq * cm;
    r.u += cu * sm;
    // Chebyshev: cos (m+1)φ = 2 cos φ cos mφ − cos (m−1)φ, the same for sin.
    const double cn = 2.0 * cos_dphi * cm - cp, sn = 2.0 * cos_dphi * sm - sp;
    cp = cm, sp = sm, cm = cn, sm = sn;
  }
  const StokesIQU ss = single_scattering(exact_, mu, s.mu0, cos_dphi, sin_dphi, false);
  return {r.i + ss.i, r.q + ss.q, r.u + ss.u};
}

}  // namespace skypol::sky::vrte
