// The VRTE table: its interpolation against direct solves at off-grid angles (the error bound
// vrte_table.h states), flux conservation through lookups integrated with a quadrature of the
// test's own, and the disk cache (naming by the inputs, atomic writes, validation on read).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "sky/units.h"
#include "sky/vrte/vrte_table.h"

using namespace skypol::sky;
using namespace skypol::sky::vrte;
using skypol::kPi;
namespace fs = std::filesystem;

namespace {

LayerOptics rayleigh(double tau) {
  LayerOptics o;
  o.tau_rayleigh = tau;
  o.depolarization = 0.0279;
  return o;
}

// A fresh empty directory under the system's temporary directory.
fs::path temp_dir(const std::string& name) {
  std::random_device rd;
  const fs::path p = fs::temp_directory_path() / ("skypol-vrte-" + name + "-" + std::to_string(rd()));
  fs::create_directories(p);
  return p;
}

// Worst interpolation error of table.down over off-grid (mu, mu0, dphi) against one direct solve.
struct Err {
  double abs = 0, rel = 0;            // everywhere
  double abs_high = 0, rel_high = 0;  // view and sun above 2.3° (μ, μ0 ≥ 0.04)
};
Err interpolation_error(const LayerOptics& o, double albedo) {
  const TableOptions opt;
  const VrteTable table = VrteTable::build(o, albedo, opt);
  const std::vector<double> mu{0.004, 0.017, 0.045, 0.09, 0.21, 0.38, 0.62, 0.81, 0.96, 0.995};
  const ScaledLayer layer = scale_layer(o, opt.streams);
  SolverOptions so;
  so.streams = opt.streams;
  const FourierSolution s = solve(layer, albedo, mu, so);
  Err e;
  for (std::size_t i = 0; i < mu.size(); ++i)
    for (std::size_t j = 0; j < mu.size(); ++j)
      for (double dphi : {0.0, 0.05, 0.6, 1.6, 2.5, kPi}) {
        double d[3] = {0, 0, 0};
        for (int m = 0; m < s.terms; ++m)
          for (int k = 0; k < 3; ++k)
            d[k] += s.down_at(m, i, j, k) * (k == 2 ? std::sin(m * dphi) : std::cos(m * dphi));
        // The table adds the untruncated single scattering; so does the reference.
        const StokesIQU st = single_scattering(layer, mu[i], mu[j], dphi, false);
        const StokesIQU se = single_scattering(table.exact(), mu[i], mu[j], dphi, false);
        d[0] += se.i - st.i, d[1] += se.q - st.q, d[2] += se.u - st.u;
        const StokesIQU t = table.down(mu[i], mu[j], dphi);
        const double err = std::max({std::abs(t.i - d[0]), std::abs(t.q - d[1]), std::abs(t.u - d[2])});
        if (std::getenv("VRTE_VERBOSE") && (err > e.abs || err / d[0] > e.rel))
          std::printf("  err %.2e rel %.2e at mu %.3f mu0 %.3f dphi %.2f I %.4e\n", err, err / d[0], mu[i], mu[j], dphi,
                      d[0]);
        e.abs = std::max(e.abs, err);
        e.rel = std::max(e.rel, err / d[0]);
        if (mu[i] >= 0.04 && mu[j] >= 0.04) {
          e.abs_high = std::max(e.abs_high, err);
          e.rel_high = std::max(e.rel_high, err / d[0]);
        }
      }
  return e;
}
}  // namespace

// The bound vrte_table.h states for the default grid: with view and sun above 2.3°, within 5e-5
// of I/F and 0.15 % of I; closer to the horizon (where multiple scattering has a logarithmic edge
// in μ) within 4e-4 and 1.5 %.
void check_bounds(const char* what, const Err& e) {
  std::printf("%s: max |error| %.2e (I/F), max relative %.2e; above 2.3 deg: %.2e, %.2e\n", what, e.abs, e.rel,
              e.abs_high, e.rel_high);
  CHECK(e.abs_high < 5e-5);
  CHECK(e.rel_high < 1.5e-3);
  CHECK(e.abs < 4e-4);
  CHECK(e.rel < 1.5e-2);
}

TEST_CASE("Table interpolation against direct solves off the grid, within the stated bounds", "[vrte][table]") {
  for (double tau : {0.02, 0.1, 0.5}) {
    const std::string what = "rayleigh tau " + std::to_string(tau);
    check_bounds(what.c_str(), interpolation_error(rayleigh(tau), 0.1));
  }
  LayerOptics o = rayleigh(0.1);
  o.tau_aerosol = 0.2;
  o.aerosol_ssa = 0.95;
  o.aerosol = synthetic_aerosol(0.7, 160, 0.2, 0.05);
  check_bounds("rayleigh 0.1 + aerosol 0.2 (g 0.7)", interpolation_error(o, 0.1));
}

TEST_CASE("Through the table's lookups, a conservative atmosphere returns all the incident flux", "[vrte][table]") {
  // Fluxes by a 48-point Gauss rule in μ and 48 azimuths (the test's own quadrature): over a black
  // ground reflected + transmitted + direct = μ0; over a white ground all of it leaves the top.
  std::vector<double> x, w;
  gauss_legendre01(48, x, w);
  for (double albedo : {0.0, 1.0}) {
    const double tau = 0.3;
    const VrteTable t = VrteTable::build(rayleigh(tau), albedo, {});
    for (double mu0 : {0.15, 0.5, 0.9}) {
      double up = 0, down = 0;
      for (std::size_t i = 0; i < x.size(); ++i)
        for (int k = 0; k < 48; ++k) {
          const double phi = 2 * kPi * k / 48;
          up += w[i] * x[i] * t.up(x[i], mu0, phi).i * 2 * kPi / 48;
          down += w[i] * x[i] * t.down(x[i], mu0, phi).i * 2 * kPi / 48;
        }
      INFO("albedo " << albedo << " mu0 " << mu0);
      if (albedo == 0.0) CHECK(up + down + mu0 * std::exp(-tau / mu0) == Approx(mu0).epsilon(1e-4));
      if (albedo == 1.0) CHECK(up == Approx(mu0).epsilon(1e-4));
    }
  }
}

TEST_CASE("Cache: named by every input, reused, written atomically, and validated on read", "[vrte][table]") {
  const fs::path dir = temp_dir("cache");
  TableOptions opt;
  opt.grid = 9;
  opt.streams = 6;
  const LayerOptics o = rayleigh(0.2);
  bool hit = true;
  const VrteTable a = VrteTable::cached(o, 0.1, opt, dir, &hit);
  CHECK_FALSE(hit);
  const fs::path file = dir / VrteTable::cache_file_name(o, 0.1, opt);
  REQUIRE(fs::exists(file));
  const VrteTable b = VrteTable::cached(o, 0.1, opt, dir, &hit);
  CHECK(hit);
  for (double mu : {0.0, 0.3, 1.0}) {
    const StokesIQU sa = a.down(mu, 0.4, 0.5), sb = b.down(mu, 0.4, 0.5);
    CHECK(sa.i == sb.i);
    CHECK(sa.q == sb.q);
    CHECK(sa.u == sb.u);
  }
  // Every input that changes the table changes the name.
  std::vector<std::string> names{VrteTable::cache_file_name(o, 0.1, opt)};
  LayerOptics o2 = o;
  o2.tau_rayleigh = 0.21;
  names.push_back(VrteTable::cache_file_name(o2, 0.1, opt));
  o2 = o;
  o2.depolarization = 0.03;
  names.push_back(VrteTable::cache_file_name(o2, 0.1, opt));
  o2 = o;
  o2.tau_aerosol = 0.1;
  o2.aerosol = synthetic_aerosol(0.6, 160, 0.2, 0.05);
  names.push_back(VrteTable::cache_file_name(o2, 0.1, opt));
  LayerOptics o3 = o2;
  o3.aerosol.f12[5] += 1e-9;
  names.push_back(VrteTable::cache_file_name(o3, 0.1, opt));
  o3 = o2;
  o3.aerosol_ssa = 0.9;
  names.push_back(VrteTable::cache_file_name(o3, 0.1, opt));
  names.push_back(VrteTable::cache_file_name(o, 0.2, opt));
  TableOptions opt2 = opt;
  opt2.streams = 7;
  names.push_back(VrteTable::cache_file_name(o, 0.1, opt2));
  opt2 = opt;
  opt2.grid = 10;
  names.push_back(VrteTable::cache_file_name(o, 0.1, opt2));
  std::sort(names.begin(), names.end());
  CHECK(std::unique(names.begin(), names.end()) == names.end());
  // The wavelength alone does not change the physics the solver sees, nor the name.
  o2 = o;
  o2.wavelength_nm = 450;
  CHECK(VrteTable::cache_file_name(o2, 0.1, opt) == VrteTable::cache_file_name(o, 0.1, opt));

  // A truncated file, a flipped byte and another table's file under this name are all refused.
  const std::uintmax_t size = fs::file_size(file);
  fs::resize_file(file, size - 3);
  CHECK_FALSE(VrteTable::read(file, o, 0.1, opt));
  VrteTable::cached(o, 0.1, opt, dir, &hit);  // rebuilt and rewritten
  CHECK_FALSE(hit);
  CHECK(fs::file_size(file) == size);
  CHECK(VrteTable::read(file, o, 0.1, opt));
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.put('\x7f');
  }
  CHECK_FALSE(VrteTable::read(file, o, 0.1, opt));
  const fs::path other = dir / VrteTable::cache_file_name(o2, 0.1, opt);
  REQUIRE(VrteTable::build(rayleigh(0.3), 0.1, opt).write(other));
  CHECK_FALSE(VrteTable::read(other, rayleigh(0.2), 0.1, opt));  // key mismatch
  CHECK_FALSE(VrteTable::read(dir / "missing.bin", o, 0.1, opt));
  // Nothing half-written is left behind: only finished .bin files in the directory.
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().extension() == ".bin");
  // An unwritable place: write() says so and leaves nothing.
  CHECK_FALSE(a.write(dir / "no-such-dir" / "t.bin"));
  fs::remove_all(dir);
}

TEST_CASE("Table inputs out of range are refused", "[vrte][table]") {
  TableOptions opt;
  opt.grid = 3;
  CHECK_THROWS(VrteTable::build(rayleigh(0.1), 0.1, opt));
  CHECK_THROWS(VrteTable::build(rayleigh(0.1), -0.1, {}));
  CHECK_THROWS(VrteTable::build(rayleigh(-0.1), 0.1, {}));
}
