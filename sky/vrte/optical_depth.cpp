#include "sky/vrte/optical_depth.h"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "sky/units.h"

namespace skypol::sky {
namespace {

constexpr double kAvogadro = 6.0221367e23;     // mol⁻¹, the value B99 use
constexpr double kLoschmidt288 = 2.546899e19;  // molecules cm⁻³ at 288.15 K, 1013.25 hPa (B99)

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

[[noreturn]] void bad(const std::string& field, const std::string& message) {
  throw std::invalid_argument(field + ": " + message);
}

void check_wavelength(double nm) {
  if (!(std::isfinite(nm) && nm >= 200.0 && nm <= 4000.0)) {
    bad("wavelength_nm", num(nm) + " is outside [200, 4000] nm (the range of the air refractivity formula)");
  }
}

void check_co2(double ppm) {
  if (!(std::isfinite(ppm) && ppm >= 0.0 && ppm <= 10000.0)) bad("co2_ppm", num(ppm) + " is outside [0, 10000]");
}

}  // namespace

double air_refractive_index(double wavelength_nm, double co2_ppm) {
  check_wavelength(wavelength_nm);
  check_co2(co2_ppm);
  const double s2 = 1.0 / ((wavelength_nm * 1e-3) * (wavelength_nm * 1e-3));  // µm⁻²
  const double n300 = (8060.51 + 2480990.0 / (132.274 - s2) + 17455.7 / (39.32957 - s2)) * 1e-8;
  return 1.0 + n300 * (1.0 + 0.54 * (co2_ppm * 1e-6 - 0.0003));
}

double king_factor_air(double wavelength_nm, double co2_ppm) {
  check_wavelength(wavelength_nm);
  check_co2(co2_ppm);
  const double s2 = 1.0 / ((wavelength_nm * 1e-3) * (wavelength_nm * 1e-3));
  const double f_n2 = 1.034 + 3.17e-4 * s2;
  const double f_o2 = 1.096 + 1.385e-3 * s2 + 1.448e-4 * s2 * s2;
  const double f_ar = 1.00, f_co2 = 1.15;
  const double c_co2 = co2_ppm * 1e-4;  // percent by volume
  return (78.084 * f_n2 + 20.946 * f_o2 + 0.934 * f_ar + c_co2 * f_co2) / (78.084 + 20.946 + 0.934 + c_co2);
}

double depolarization_from_king(double king_factor) {
  if (!(std::isfinite(king_factor) && king_factor >= 1.0)) {
    bad("king_factor", num(king_factor) + " must be finite and ≥ 1");
  }
  return 6.0 * (king_factor - 1.0) / (7.0 * king_factor + 3.0);
}

double rayleigh_cross_section_cm2(double wavelength_nm, double co2_ppm) {
  const double n = air_refractive_index(wavelength_nm, co2_ppm);
  const double lambda_cm = wavelength_nm * 1e-7;
  const double n2 = n * n;
  const double a = (n2 - 1.0) / (n2 + 2.0);
  const double l2 = lambda_cm * lambda_cm;
  return 24.0 * kPi * kPi * kPi * a * a / (l2 * l2 * kLoschmidt288 * kLoschmidt288) *
         king_factor_air(wavelength_nm, co2_ppm);
}

double rayleigh_cross_section_fit_cm2(double wavelength_nm) {
  check_wavelength(wavelength_nm);
  const double l = wavelength_nm * 1e-3, l2 = l * l;
  return (1.0455996 - 341.29061 / l2 - 0.90230850 * l2) / (1.0 + 0.0027059889 / l2 - 85.968563 * l2) * 1e-28;
}

double gravity_cm_s2(double latitude_deg, double altitude_m) {
  if (!(std::isfinite(latitude_deg) && std::abs(latitude_deg) <= 90.0)) {
    bad("latitude_deg", num(latitude_deg) + " is outside [−90, 90]");
  }
  if (!std::isfinite(altitude_m)) bad("altitude_m", num(altitude_m) + " is not finite");
  const double c2 = std::cos(rad_from_deg(2.0 * latitude_deg));
  const double g0 = 980.6160 * (1.0 - 0.0026373 * c2 + 0.0000059 * c2 * c2);
  const double z = altitude_m;
  return g0 - (3.085462e-4 + 2.27e-7 * c2) * z + (7.254e-11 + 1.0e-13 * c2) * z * z -
         (1.517e-17 + 6.0e-20 * c2) * z * z * z;
}

double air_molar_mass_g(double co2_ppm) {
  check_co2(co2_ppm);
  return 15.0556 * co2_ppm * 1e-6 + 28.9595;
}

double rayleigh_optical_depth(double wavelength_nm, double pressure_hpa, double altitude_m, double latitude_deg,
                              double co2_ppm) {
  check_wavelength(wavelength_nm);
  if (!(std::isfinite(pressure_hpa) && pressure_hpa > 0.0 && pressure_hpa <= 1200.0)) {
    bad("pressure_hpa", num(pressure_hpa) + " is outside (0, 1200] hPa");
  }
  if (!(std::isfinite(altitude_m) && altitude_m >= -500.0 && altitude_m <= 10000.0)) {
    bad("altitude_m", num(altitude_m) + " is outside [−500, 10000] m");
  }
  const double sigma = rayleigh_cross_section_cm2(wavelength_nm, co2_ppm);
  const double zc = 0.73737 * altitude_m + 5517.56;
  const double g = gravity_cm_s2(latitude_deg, zc);
  const double p_cgs = pressure_hpa * 1000.0;  // 1 hPa = 1000 dyn cm⁻²
  return sigma * p_cgs * kAvogadro / (air_molar_mass_g(co2_ppm) * g);
}

double angstrom_optical_depth(double tau_ref, double reference_nm, double wavelength_nm, double alpha) {
  if (!(std::isfinite(reference_nm) && reference_nm > 0.0)) bad("reference_nm", num(reference_nm) + " must be > 0");
  if (!(std::isfinite(wavelength_nm) && wavelength_nm > 0.0)) bad("wavelength_nm", num(wavelength_nm) + " must be > 0");
  if (!std::isfinite(alpha)) bad("angstrom", num(alpha) + " is not finite");
  if (!(std::isfinite(tau_ref) && tau_ref >= 0.0)) bad("tau", num(tau_ref) + " must be ≥ 0");
  return tau_ref * std::pow(wavelength_nm / reference_nm, -alpha);
}

double angstrom_exponent(double tau1, double wavelength1_nm, double tau2, double wavelength2_nm) {
  if (!(tau1 > 0.0 && tau2 > 0.0 && std::isfinite(tau1) && std::isfinite(tau2))) {
    bad("tau", "optical depths " + num(tau1) + ", " + num(tau2) + " must be > 0");
  }
  if (!(wavelength1_nm > 0.0 && wavelength2_nm > 0.0 && wavelength1_nm != wavelength2_nm)) {
    bad("wavelength_nm", "two different positive wavelengths needed, got " + num(wavelength1_nm) + ", " +
                             num(wavelength2_nm));
  }
  return -std::log(tau1 / tau2) / std::log(wavelength1_nm / wavelength2_nm);
}

double band_wavelength_nm(std::string_view band) {
  if (band == "R") return 610.0;
  if (band == "G") return 530.0;
  if (band == "B") return 465.0;
  if (band == "Y") return 550.0;
  bad("band", "\"" + std::string(band) + "\" is unknown (expected R, G, B or Y, or give wavelengths in nm)");
}

std::vector<std::string> band_names() { return {"R", "G", "B", "Y"}; }

}  // namespace skypol::sky
