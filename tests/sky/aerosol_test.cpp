// Size-distribution averages (mie_ensemble), the named aerosol types and the assembly of a
// layer's optics. Truths: OPAC's own tabulated optics of its sulfate component (Hess et al. 1998,
// the "suso99" file), the Rayleigh limit, a monodisperse limit against mie_sphere (itself tested
// against Wiscombe 1979), exact Gauss–Legendre moments, and the inequalities of a scattering
// matrix of randomly oriented spheres.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <ctime>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "sky/vrte/aerosol_types.h"
#include "sky/vrte/mie.h"
#include "sky/vrte/optical_depth.h"

using namespace skypol::sky;

namespace {

void check_table_shape(const ScatteringMatrixTable& t, std::size_t n) {
  REQUIRE(t.cos_theta.size() == n);
  REQUIRE(t.weight.size() == n);
  REQUIRE(t.f11.size() == n);
  REQUIRE(t.f12.size() == n);
  REQUIRE(t.f22.size() == n);
  REQUIRE(t.f33.size() == n);
  REQUIRE(t.f34.size() == n);
  REQUIRE(t.f44.size() == n);
  double wsum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) CHECK(t.cos_theta[i] > t.cos_theta[i - 1]);
    CHECK(t.weight[i] > 0.0);
    wsum += t.weight[i];
  }
  CHECK(wsum == Approx(2.0).epsilon(1e-13));
  CHECK(t.cos_theta.front() > -1.0);
  CHECK(t.cos_theta.back() < 1.0);
}

// The inequalities of a mixture of spheres (Hovenier, van der Mee & Domke 2004, ch. 2): F11 > 0,
// |F12| ≤ F11, F12² + F33² + F34² ≤ F11² (equality for one sphere), F22 = F11, F44 = F33.
void check_sphere_matrix(const ScatteringMatrixTable& t) {
  for (std::size_t i = 0; i < t.f11.size(); ++i) {
    INFO("cos theta = " << t.cos_theta[i]);
    CHECK(t.f11[i] > 0.0);
    CHECK(std::abs(t.f12[i]) <= t.f11[i] * (1 + 1e-12));
    CHECK(t.f12[i] * t.f12[i] + t.f33[i] * t.f33[i] + t.f34[i] * t.f34[i] <= t.f11[i] * t.f11[i] * (1 + 1e-12));
    CHECK(t.f22[i] == t.f11[i]);
    CHECK(t.f44[i] == t.f33[i]);
  }
}

double table_g(const ScatteringMatrixTable& t) {
  double s = 0.0;
  for (std::size_t i = 0; i < t.f11.size(); ++i) s += t.weight[i] * t.cos_theta[i] * t.f11[i];
  return 0.5 * s;
}

std::string message_of(const AerosolSpec& s) {
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("Gauss-Legendre nodes integrate polynomials up to degree 2N-1 exactly", "[aerosol][quadrature]") {
  for (int n : {1, 2, 5, 16, 255, 256}) {
    std::vector<double> x, w;
    gauss_legendre(n, x, w);
    REQUIRE(x.size() == static_cast<std::size_t>(n));
    for (int k = 0; k <= 2 * n - 1 && k <= 40; ++k) {
      double s = 0.0;
      for (std::size_t i = 0; i < x.size(); ++i) s += w[i] * std::pow(x[i], k);
      const double exact = (k % 2 == 1) ? 0.0 : 2.0 / (k + 1);
      INFO("N = " << n << ", k = " << k);
      CHECK(s == Approx(exact).margin(2e-14));
    }
    for (std::size_t i = 0; i < x.size(); ++i) CHECK(x[i] == Approx(-x[x.size() - 1 - i]).margin(1e-15));
  }
}

TEST_CASE("Tiny particles: the ensemble table is Rayleigh's matrix", "[aerosol][limit]") {
  // r ≪ λ: F11 = ¾(1 + μ²), F12 = −¾(1 − μ²), F33 = (3/2)μ, F34 = 0 (Rayleigh's matrix without
  // depolarization), g = 0; the quadrature sum is exact (a quadratic in μ).
  MieComponent c;
  c.m = {1.5, 0.0};
  c.size = {0.0005, 1.3, 0.0, 0.0};
  MieQuadrature q;
  q.angle_nodes = 32;
  const MieEnsemble e = mie_ensemble({&c, 1}, 550.0, q);
  check_table_shape(e.table, 32);
  check_sphere_matrix(e.table);
  CHECK(e.ssa == Approx(1.0).margin(1e-12));
  CHECK(std::abs(e.g) < 1e-3);
  CHECK(quadrature_norm(e.table) == Approx(1.0).epsilon(1e-12));
  for (std::size_t i = 0; i < 32; ++i) {
    const double mu = e.table.cos_theta[i];
    CHECK(e.table.f11[i] == Approx(0.75 * (1 + mu * mu)).margin(2e-3));
    CHECK(e.table.f12[i] == Approx(-0.75 * (1 - mu * mu)).margin(2e-3));
    CHECK(e.table.f33[i] == Approx(1.5 * mu).margin(2e-3));
    CHECK(std::abs(e.table.f34[i]) < 2e-3);
  }
}

TEST_CASE("A narrow distribution is one sphere", "[aerosol][limit]") {
  // σ_g = 1.002 around r = 0.5 µm at 550 nm (x ≈ 5.7): cross sections and the normalised matrix
  // must match mie_sphere's within the distribution's own spread (±0.8 % in r).
  const std::complex<double> m(1.5, 0.01);
  MieComponent c;
  c.m = m;
  c.size = {0.5, 1.002, 0.0, 0.0};
  MieQuadrature q;
  q.angle_nodes = 64;
  const MieEnsemble e = mie_ensemble({&c, 1}, 550.0, q);
  const double x = 2 * std::numbers::pi * 0.5 / 0.55;
  const MieSphere s = mie_sphere(m, x, e.table.cos_theta);
  const double area = std::numbers::pi * 0.25;
  CHECK(e.c_ext_um2 == Approx(s.qext * area).epsilon(5e-4));
  CHECK(e.c_sca_um2 == Approx(s.qsca * area).epsilon(5e-4));
  CHECK(e.g == Approx(s.g).margin(5e-4));
  for (std::size_t i = 0; i < e.table.f11.size(); i += 7) {
    // F11 = 4π·½(|S1|²+|S2|²)/(k²C_sca) = 4·½(|S1|²+|S2|²)/(x²Qsca), so that ½∫F11 dμ = 1.
    const double f11 = 4.0 * 0.5 * (std::norm(s.s1[i]) + std::norm(s.s2[i])) / (x * x * s.qsca);
    INFO("cos theta = " << e.table.cos_theta[i]);
    CHECK(e.table.f11[i] == Approx(f11).epsilon(5e-3));
  }
}

TEST_CASE("Averaging reproduces OPAC's tabulated optics of its sulfate component", "[aerosol][published]") {
  // OPAC (Hess et al. 1998) data file suso99 (sulfate droplets at 99 % RH): log-normal with
  // r_mod = 0.231 µm, σ = 2.03, 0.0103–81.8 µm; per particle per cm³ the extinction coefficient
  // (1/km) and the asymmetry parameter at three wavelengths, with OPAC's refractive indices.
  struct Row {
    double nm, n, k, ext_per_km, g;
  };
  const Row rows[] = {{400.0, 1.342, 2.082e-9, 1.199e-3, 0.791},
                      {550.0, 1.336, 2.179e-9, 1.209e-3, 0.797},
                      {700.0, 1.334, 3.315e-8, 1.166e-3, 0.801}};
  for (const Row& r : rows) {
    MieComponent c;
    c.m = {r.n, r.k};
    c.size = {0.231, 2.03, 0.0103, 81.8};
    MieQuadrature q;
    q.angle_nodes = 64;
    const MieEnsemble e = mie_ensemble({&c, 1}, r.nm, q);
    // 1 particle cm⁻³ with C µm² gives C·10⁻⁸ cm⁻¹ = C·10⁻³ km⁻¹. OPAC prints 4 digits.
    INFO(r.nm << " nm");
    CHECK(e.c_ext_um2 * 1e-3 == Approx(r.ext_per_km).epsilon(2e-3));
    CHECK(e.g == Approx(r.g).margin(1.5e-3));
    CHECK(e.ssa == Approx(1.0).margin(1e-5));
  }
}

TEST_CASE("Averaging reproduces OPAC's tabulated optics of the components the types are made of", "[aerosol][published]") {
  // OPAC data files of the dry (0 % RH) components (as distributed with OPAC 4.0; read from the
  // copies in the AeroMix package): per particle per cm³ the extinction coefficient (1/km), the
  // single-scattering albedo and g at 550 nm, computed by OPAC with Mie theory for the same
  // log-normal, range and refractive index as aerosol_types.cpp. (OPAC's mineral files in that
  // copy are for spheroids, so the mineral components are not compared.)
  struct Row {
    const char* name;
    double rmod, sigma, rmax, n, k;
    double ext_per_km, ssa, g;
  };
  const Row rows[] = {
      {"WASO", 0.0212, 2.24, 20.0, 1.530, 6.0e-3, 3.905e-6, 0.9615, 0.614},
      {"INSO", 0.471, 2.51, 20.0, 1.530, 8.0e-3, 8.496e-3, 0.7300, 0.831},
      {"SOOT", 0.0118, 2.00, 20.0, 1.750, 0.44, 5.540e-7, 0.2088, 0.336},
      {"SSAM", 0.209, 2.03, 20.0, 1.500, 1.0e-8, 1.028e-3, 1.0, 0.691},
      {"SSCM", 1.75, 2.03, 60.0, 1.500, 1.0e-8, 5.667e-2, 1.0, 0.795},
  };
  for (const Row& r : rows) {
    INFO(r.name);
    MieComponent c;
    c.m = {r.n, r.k};
    c.size = {r.rmod, r.sigma, 0.005, r.rmax};
    const MieEnsemble e = mie_ensemble_cross_sections({&c, 1}, 550.0);
    CHECK(e.c_ext_um2 * 1e-3 == Approx(r.ext_per_km).epsilon(3e-3));
    CHECK(e.ssa == Approx(r.ssa).margin(1e-3));
    // OPAC's g differs from ours by up to 0.0047 (INSO 0.831 vs 0.8263, SSCM 0.795 vs 0.7913,
    // SSAM 0.691 vs 0.6923) while its extinction and albedo agree to its 4 digits. Ours is
    // converged to 1e-4 (refining both radius steps 20× moves it less) and single-sphere g
    // matches Wiscombe to 1e-6 (mie_test), so the difference is taken to be OPAC's own
    // (its g is likely integrated from its tabulated phase function): allowed 6e-3.
    CHECK(e.g == Approx(r.g).margin(6e-3));
  }
}

TEST_CASE("Every named type: a normalised table obeying the sphere inequalities", "[aerosol][types]") {
  for (const std::string& name : aerosol_type_names()) {
    for (double nm : {465.0, 610.0}) {
      INFO(name << " at " << nm << " nm");
      const MieEnsemble e = mie_ensemble(aerosol_type(name).components, nm);
      check_table_shape(e.table, static_cast<std::size_t>(MieQuadrature{}.angle_nodes));
      check_sphere_matrix(e.table);
      CHECK(e.c_ext_um2 >= e.c_sca_um2);
      CHECK(e.ssa > 0.5);
      CHECK(e.ssa <= 1.0);
      // ½∫F11 dμ = 1 in the continuum; the 256-node sum misses a little of the sharpest forward
      // peak: 1.8·10⁻³ for desert's coarse mode at 465 nm, ≤ 5·10⁻⁵ for the others.
      CHECK(quadrature_norm(e.table) == Approx(1.0).margin(name == "desert" ? 2e-3 : 5e-5));
      // g from the partial-wave sums and from the table: two independent routes.
      CHECK(table_g(e.table) == Approx(e.g).margin(3e-3));
      CHECK(e.g > 0.55);
      CHECK(e.g < 0.8);
      // Aerosol polarizes less than molecules: |F12/F11| at 90° well below Rayleigh's 1.
      const std::size_t mid = e.table.f11.size() / 2;
      CHECK(std::abs(e.table.f12[mid] / e.table.f11[mid]) < 0.6);
    }
  }
}

TEST_CASE("The default radius quadrature is converged to the stated accuracy", "[aerosol][convergence]") {
  // Desert at 465 nm is the hardest absorbing case (coarse mode up to x ≈ 800): default against a
  // 4× finer ln r step, a 4× finer size step and no tail stretching.
  const auto& mix = aerosol_type("desert").components;
  MieQuadrature q;
  q.angle_nodes = 64;
  MieQuadrature fine = q;
  fine.ln_r_step = q.ln_r_step / 4;
  fine.size_step = q.size_step / 4;
  fine.tail_fraction = 0.0;
  const MieEnsemble a = mie_ensemble(mix, 465.0, q);
  const MieEnsemble b = mie_ensemble(mix, 465.0, fine);
  CHECK(a.c_ext_um2 == Approx(b.c_ext_um2).epsilon(1e-3));
  CHECK(a.ssa == Approx(b.ssa).margin(5e-4));
  CHECK(a.g == Approx(b.g).margin(5e-4));
  for (std::size_t i = 0; i < a.table.f11.size(); ++i) {
    INFO("cos theta = " << a.table.cos_theta[i]);
    CHECK(a.table.f11[i] == Approx(b.table.f11[i]).epsilon(0.01));
    CHECK(a.table.f12[i] / a.table.f11[i] == Approx(b.table.f12[i] / b.table.f11[i]).margin(0.01));
  }
}

TEST_CASE("Named types behave as their composition says", "[aerosol][types]") {
  auto ssa = [](const char* n) { return mie_ensemble_cross_sections(aerosol_type(n).components, 550.0).ssa; };
  // More soot, darker (Hess et al. 1998 Table 4 mixes).
  CHECK(ssa("continental_clean") > ssa("continental_average"));
  CHECK(ssa("continental_average") > ssa("continental_polluted"));
  CHECK(ssa("continental_polluted") > ssa("urban"));
  CHECK(ssa("maritime_clean") > 0.98);
  // Small particles give steep spectra, sea salt and dust flat ones (the well-known ranges:
  // continental α ≈ 1–1.5, maritime ≲ 0.5, desert ≲ 0.4).
  for (const char* n : {"continental_clean", "continental_average", "continental_polluted", "urban"}) {
    INFO(n);
    const double a = mie_angstrom_exponent(aerosol_type(n).components);
    CHECK(a > 1.1);
    CHECK(a < 1.6);
  }
  CHECK(mie_angstrom_exponent(aerosol_type("maritime_clean").components) < 0.5);
  CHECK(mie_angstrom_exponent(aerosol_type("desert").components) < 0.4);
  CHECK_THROWS_AS(aerosol_type("volcanic"), std::invalid_argument);
}

TEST_CASE("layer_optics assembles Rayleigh and aerosol at one wavelength", "[aerosol][layer]") {
  AerosolSpec spec;
  spec.type = "continental_average";
  spec.tau_550 = 0.2;
  spec.angle_nodes = 64;
  const LayerOptics l = layer_optics(465.0, 1013.25, 0.0, 45.0, spec);
  CHECK(l.wavelength_nm == 465.0);
  CHECK(l.tau_rayleigh == rayleigh_optical_depth(465.0, 1013.25, 0.0, 45.0));
  CHECK(l.depolarization == depolarization_from_king(king_factor_air(465.0)));
  const double alpha = effective_angstrom(spec);
  CHECK(l.tau_aerosol == Approx(0.2 * std::pow(465.0 / 550.0, -alpha)).epsilon(1e-12));
  // Ångström round trip through two layers.
  const LayerOptics r = layer_optics(610.0, 1013.25, 0.0, 45.0, spec);
  CHECK(angstrom_exponent(l.tau_aerosol, 465.0, r.tau_aerosol, 610.0) == Approx(alpha).epsilon(1e-12));
  CHECK(l.aerosol.f11.size() == 64);
  CHECK(l.aerosol_ssa ==
        Approx(mie_ensemble_cross_sections(aerosol_type("continental_average").components, 465.0).ssa).epsilon(1e-12));

  AerosolSpec over = spec;
  over.ssa = 0.9;
  over.angstrom = 1.0;
  const LayerOptics o = layer_optics(610.0, 900.0, 1000.0, -30.0, over);
  CHECK(o.aerosol_ssa == 0.9);
  CHECK(o.tau_aerosol == Approx(0.2 * 550.0 / 610.0).epsilon(1e-12));
  CHECK(o.tau_rayleigh == rayleigh_optical_depth(610.0, 900.0, 1000.0, -30.0));

  AerosolSpec none = spec;
  none.type = "none";
  const LayerOptics n = layer_optics(550.0, 1013.25, 0.0, 45.0, none);
  CHECK(n.tau_aerosol == 0.0);
  CHECK(n.aerosol.f11.empty());
  AerosolSpec zero = spec;
  zero.tau_550 = 0.0;
  CHECK(layer_optics(550.0, 1013.25, 0.0, 45.0, zero).aerosol.f11.empty());

  // A list of wavelengths gives the layers in order, each the single-wavelength result.
  const std::vector<double> bands = {band_wavelength_nm("R"), band_wavelength_nm("G"), band_wavelength_nm("B")};
  const std::vector<LayerOptics> rgb = layer_optics(bands, 1013.25, 0.0, 45.0, spec);
  REQUIRE(rgb.size() == 3);
  CHECK(rgb[2].wavelength_nm == 465.0);
  CHECK(rgb[2].tau_aerosol == l.tau_aerosol);
  CHECK(rgb[2].aerosol.f11 == l.aerosol.f11);
  CHECK(rgb[0].tau_rayleigh < rgb[1].tau_rayleigh);
  CHECK(rgb[1].tau_rayleigh < rgb[2].tau_rayleigh);

  // A custom mode is mie_ensemble of that mode.
  AerosolSpec custom;
  custom.type = "custom";
  custom.median_radius_um = 0.15;
  custom.geometric_std = 1.8;
  custom.refractive_real = 1.45;
  custom.refractive_imag = 0.002;
  custom.angle_nodes = 32;
  const LayerOptics cu = layer_optics(550.0, 1013.25, 0.0, 45.0, custom);
  MieComponent c;
  c.m = {1.45, 0.002};
  c.size = {0.15, 1.8, 0.0, 0.0};
  MieQuadrature q;
  q.angle_nodes = 32;
  const MieEnsemble e = mie_ensemble({&c, 1}, 550.0, q);
  CHECK(cu.aerosol_ssa == e.ssa);
  CHECK(cu.aerosol.f11 == e.table.f11);
  CHECK(cu.tau_aerosol == Approx(0.1).epsilon(1e-14));  // at 550 nm τ = tau_550 whatever α
}

TEST_CASE("Aerosol spec errors start with the field's key", "[aerosol][errors]") {
  auto starts = [](const AerosolSpec& s, const std::string& key) {
    const std::string m = message_of(s);
    INFO(m);
    return m.rfind("sky.aerosol." + key + ": ", 0) == 0;
  };
  AerosolSpec s;
  CHECK(message_of(s).empty());
  s.type = "smog";
  CHECK(starts(s, "type"));
  CHECK(message_of(s).find("continental_clean") != std::string::npos);  // lists the legal names
  s = {};
  s.tau_550 = -0.1;
  CHECK(starts(s, "tau_550"));
  s = {};
  s.angstrom = 7.0;
  CHECK(starts(s, "angstrom"));
  s = {};
  s.ssa = 1.2;
  CHECK(starts(s, "ssa"));
  s = {};
  s.angle_nodes = 4;
  CHECK(starts(s, "angle_nodes"));
  s = {};
  s.type = "custom";
  s.median_radius_um = 0.0;
  CHECK(starts(s, "median_radius_um"));
  s = {};
  s.type = "custom";
  s.geometric_std = 1.0;
  CHECK(starts(s, "geometric_std"));
  s = {};
  s.type = "custom";
  s.refractive_real = 0.5;
  CHECK(starts(s, "refractive_real"));
  s = {};
  s.type = "custom";
  s.refractive_imag = -0.01;
  CHECK(starts(s, "refractive_imag"));
  s = {};
  s.type = "custom";
  s.refractive_real = 1.0;
  s.refractive_imag = 0.0;
  CHECK(starts(s, "refractive_real"));  // m = 1 scatters nothing: no phase function to normalise
  MieComponent air;
  air.m = {1.0, 0.0};
  CHECK_THROWS_AS(mie_ensemble({&air, 1}, 550.0), std::invalid_argument);
  // The custom fields are checked only for custom.
  s = {};
  s.refractive_imag = -0.01;
  CHECK(message_of(s).empty());
  AerosolSpec smog;
  smog.type = "smog";
  CHECK_THROWS_AS(layer_optics(550.0, 1013.25, 0.0, 45.0, smog), std::invalid_argument);
}

TEST_CASE("timing of one band's aerosol table (informational)", "[.][benchmark]") {
  // CPU time (std::clock), so a busy shared machine inflates it less than wall time.
  for (const std::string& name : aerosol_type_names()) {
    for (const char* band : {"B", "G", "R"}) {
      const double nm = band_wavelength_nm(band);
      const auto& mix = aerosol_type(name).components;
      const std::clock_t c0 = std::clock();
      const auto w0 = std::chrono::steady_clock::now();
      const MieEnsemble e = mie_ensemble(mix, nm);
      const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
      std::printf("%-21s %s %3.0f nm: %5d radii, %d nodes, cpu %.3f s, wall %.3f s, ssa %.4f, g %.4f, 1 - norm %+.1e\n",
                  name.c_str(), band, nm, e.radius_nodes, MieQuadrature{}.angle_nodes, cpu, wall, e.ssa, e.g,
                  1.0 - quadrature_norm(e.table));
    }
  }
}
