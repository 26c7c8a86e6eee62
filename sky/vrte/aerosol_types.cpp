#include "sky/vrte/aerosol_types.h"

#include <cmath>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "sky/vrte/optical_depth.h"
#include "sky/spec_errors.h"

namespace skypol::sky {
namespace {

// The field names below are relative to "sky.aerosol" (sky/spec_errors.h words the message).
[[noreturn]] void bad(const std::string& field, const std::string& message) { spec_error("sky.aerosol." + field, message); }

// OPAC components, dry (Hess et al. 1998, Table 1): median radius r_mod (µm), σ, r_min, r_max (µm);
// refractive index at 550 nm (OPAC/GADS, Koepke et al. 1997; the WMO (1986, WCP-112) values for
// water-soluble, dust-like and soot are the same).
struct Component {
  const char* name;
  double rmod_um, sigma, rmin_um, rmax_um;
  double n, k;
};
constexpr Component kWaso{"WASO", 0.0212, 2.24, 0.005, 20.0, 1.530, 6.0e-3};   // water-soluble
constexpr Component kInso{"INSO", 0.471, 2.51, 0.005, 20.0, 1.530, 8.0e-3};    // insoluble
constexpr Component kSoot{"SOOT", 0.0118, 2.00, 0.005, 20.0, 1.750, 0.44};     // soot
constexpr Component kSsam{"SSAM", 0.209, 2.03, 0.005, 20.0, 1.500, 1.0e-8};    // sea salt, accumulation
constexpr Component kSscm{"SSCM", 1.75, 2.03, 0.005, 60.0, 1.500, 1.0e-8};     // sea salt, coarse
constexpr Component kMinm{"MINM", 0.07, 1.95, 0.005, 20.0, 1.530, 5.5e-3};     // mineral, nucleation
constexpr Component kMiam{"MIAM", 0.39, 2.00, 0.005, 20.0, 1.530, 5.5e-3};     // mineral, accumulation
constexpr Component kMicm{"MICM", 1.90, 2.15, 0.005, 60.0, 1.530, 5.5e-3};     // mineral, coarse

AerosolType make(const char* name, std::initializer_list<std::pair<Component, double>> parts) {
  AerosolType t;
  t.name = name;
  for (const auto& [c, density_cm3] : parts) {
    MieComponent m;
    m.m = {c.n, c.k};
    m.size = {c.rmod_um, c.sigma, c.rmin_um, c.rmax_um};
    m.number_density = density_cm3;
    t.components.push_back(m);
    t.component_names.emplace_back(c.name);
  }
  return t;
}

// Hess et al. (1998), Table 4: number densities in cm⁻³.
const std::vector<AerosolType>& types() {
  static const std::vector<AerosolType> all = {
      make("continental_clean", {{kWaso, 2600.0}, {kInso, 0.15}}),
      make("continental_average", {{kWaso, 7000.0}, {kInso, 0.4}, {kSoot, 8300.0}}),
      make("continental_polluted", {{kWaso, 15700.0}, {kInso, 0.6}, {kSoot, 34300.0}}),
      make("urban", {{kWaso, 28000.0}, {kInso, 1.5}, {kSoot, 130000.0}}),
      make("maritime_clean", {{kWaso, 1500.0}, {kSsam, 20.0}, {kSscm, 3.2e-3}}),
      make("maritime_polluted", {{kWaso, 3800.0}, {kSsam, 20.0}, {kSscm, 3.2e-3}, {kSoot, 5180.0}}),
      make("desert", {{kWaso, 2000.0}, {kMinm, 269.5}, {kMiam, 30.5}, {kMicm, 0.142}}),
  };
  return all;
}

std::string legal_names() {
  std::string s;
  for (const AerosolType& t : types()) s += t.name + ", ";
  return s + "custom or none";
}

}  // namespace

std::vector<std::string> aerosol_type_names() {
  std::vector<std::string> names;
  for (const AerosolType& t : types()) names.push_back(t.name);
  return names;
}

const AerosolType& aerosol_type(std::string_view name) {
  for (const AerosolType& t : types()) {
    if (t.name == name) return t;
  }
  bad("type", "\"" + std::string(name) + "\" is unknown (expected " + legal_names() + ")");
}

void validate(const AerosolSpec& s) {
  const bool custom = s.type == "custom";
  if (!custom && s.type != "none") (void)aerosol_type(s.type);
  if (custom) {
    if (!(std::isfinite(s.median_radius_um) && s.median_radius_um >= 1e-4 && s.median_radius_um <= 20.0)) {
      bad("median_radius_um", spec_number(s.median_radius_um) + " is outside [0.0001, 20] µm");
    }
    if (!(std::isfinite(s.geometric_std) && s.geometric_std > 1.0 && s.geometric_std <= 3.0)) {
      bad("geometric_std", spec_number(s.geometric_std) + " is outside (1, 3]");
    }
    if (!(std::isfinite(s.refractive_real) && s.refractive_real >= 1.0 && s.refractive_real <= 3.0)) {
      bad("refractive_real", spec_number(s.refractive_real) + " is outside [1, 3]");
    }
    if (!(std::isfinite(s.refractive_imag) && s.refractive_imag >= 0.0 && s.refractive_imag <= 2.0)) {
      bad("refractive_imag", spec_number(s.refractive_imag) + " is outside [0, 2] (k ≥ 0: absorption)");
    }
    if (s.refractive_real == 1.0 && s.refractive_imag == 0.0) {
      bad("refractive_real", "1 with refractive_imag 0 is the medium itself: such particles scatter nothing");
    }
  }
  if (!(std::isfinite(s.tau_550) && s.tau_550 >= 0.0 && s.tau_550 <= 10.0)) {
    bad("tau_550", spec_number(s.tau_550) + " is outside [0, 10]");
  }
  if (s.angstrom && !(std::isfinite(*s.angstrom) && *s.angstrom >= -1.0 && *s.angstrom <= 4.0)) {
    bad("angstrom", spec_number(*s.angstrom) + " is outside [−1, 4]");
  }
  if (s.ssa && !(std::isfinite(*s.ssa) && *s.ssa >= 0.0 && *s.ssa <= 1.0)) {
    bad("ssa", spec_number(*s.ssa) + " is outside [0, 1]");
  }
  if (!(s.angle_nodes >= 16 && s.angle_nodes <= 4096)) {
    bad("angle_nodes", std::to_string(s.angle_nodes) + " is outside [16, 4096]");
  }
}

std::vector<MieComponent> aerosol_components(const AerosolSpec& s) {
  if (s.type == "none") return {};
  if (s.type == "custom") {
    MieComponent c;
    c.m = {s.refractive_real, s.refractive_imag};
    c.size.median_radius_um = s.median_radius_um;
    c.size.geometric_std = s.geometric_std;
    return {c};
  }
  return aerosol_type(s.type).components;
}

double mie_angstrom_exponent(const std::vector<MieComponent>& mixture) {
  const double e440 = mie_ensemble_cross_sections(mixture, 440.0).c_ext_um2;
  const double e870 = mie_ensemble_cross_sections(mixture, 870.0).c_ext_um2;
  return angstrom_exponent(e440, 440.0, e870, 870.0);
}

namespace {

// A named type's Ångström exponent never changes: computed once per type (two Mie runs, ~20 ms
// for desert), behind a mutex so concurrent band tables may ask.
double type_angstrom(const std::string& type) {
  static std::mutex mutex;
  static std::map<std::string, double> cache;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = cache.find(type);
    if (it != cache.end()) return it->second;
  }
  const double alpha = mie_angstrom_exponent(aerosol_type(type).components);
  const std::lock_guard<std::mutex> lock(mutex);
  cache.emplace(type, alpha);
  return alpha;
}

}  // namespace

double effective_angstrom(const AerosolSpec& s) {
  validate(s);
  if (s.angstrom) return *s.angstrom;
  if (s.type == "none") return 0.0;
  if (s.type == "custom") return mie_angstrom_exponent(aerosol_components(s));
  return type_angstrom(s.type);
}

LayerOptics layer_optics(double wavelength_nm, double pressure_hpa, double altitude_m, double latitude_deg,
                         const AerosolSpec& spec) {
  validate(spec);
  LayerOptics out;
  out.wavelength_nm = wavelength_nm;
  out.tau_rayleigh = rayleigh_optical_depth(wavelength_nm, pressure_hpa, altitude_m, latitude_deg);
  out.depolarization = depolarization_from_king(king_factor_air(wavelength_nm));
  const std::vector<MieComponent> mixture = aerosol_components(spec);
  if (mixture.empty() || spec.tau_550 == 0.0) return out;

  const double alpha = effective_angstrom(spec);
  out.tau_aerosol = angstrom_optical_depth(spec.tau_550, 550.0, wavelength_nm, alpha);
  MieQuadrature q;
  q.angle_nodes = spec.angle_nodes;
  MieEnsemble e = mie_ensemble(mixture, wavelength_nm, q);
  out.aerosol_ssa = spec.ssa ? *spec.ssa : e.ssa;
  out.aerosol = std::move(e.table);
  return out;
}

std::vector<LayerOptics> layer_optics(std::span<const double> wavelengths_nm, double pressure_hpa,
                                      double altitude_m, double latitude_deg, const AerosolSpec& spec) {
  std::vector<LayerOptics> out;
  out.reserve(wavelengths_nm.size());
  for (double nm : wavelengths_nm) out.push_back(layer_optics(nm, pressure_hpa, altitude_m, latitude_deg, spec));
  return out;
}

}  // namespace skypol::sky
