// `skypol table`: the VRTE solver's I, Q, U for a molecular layer, up at the top and down at the
// ground, in the normalisation and signs of the Coulson, Dave & Sekera (1960) tables as Natraj et
// al. (2009) give them (sky/vrte/vrte_point.h), so that anyone can check it against published tables.
// Argument parsing only: the numbers come from sky::vrte::coulson_table.
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "sky/vrte/atmosphere_optics.h"
#include "sky/vrte/vrte_point.h"

namespace skypol::cli {
namespace {

void print_iqu(const char* name, const sky::vrte::CoulsonIQU& v, bool last) {
  std::printf("\"%s\": {\"i\": %.8f, \"q\": %.8f, \"u\": %.8f}%s", name, v.i, v.q, v.u, last ? "" : ", ");
}

}  // namespace

void add_table(CLI::App& app) {
  struct Args {
    std::vector<double> tau, albedo{0.0}, mu0, mu, dphi{0.0};
    double depolarization = 0.0;
    int streams = 32;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* table = app.add_subcommand(
      "table", "Print the VRTE solver's I, Q, U of a molecular layer in the Coulson tables' normalisation");
  table->add_option("--tau", a->tau, "Rayleigh optical depth(s) of the layer")->required()->check(CLI::Range(0.0, 100.0));
  table->add_option("--albedo", a->albedo, "Lambertian ground albedo(s), default 0")->check(CLI::Range(0.0, 1.0));
  table->add_option("--mu0", a->mu0, "Cosine(s) of the sun's zenith angle, (0, 1]")->required();
  table->add_option("--mu", a->mu, "Cosine(s) of the view's zenith (ground) / nadir (top) angle, [0, 1]")->required();
  table->add_option("--dphi", a->dphi,
                    "View azimuth minus sun azimuth, degrees (0: looking towards the sun's side), default 0");
  table->add_option("--depolarization", a->depolarization, "Molecular depolarization factor rho_n, default 0")
      ->check(CLI::Range(0.0, 0.5));
  table->add_option("--streams", a->streams, "Gauss nodes per hemisphere (accuracy), default 32")
      ->check(CLI::Range(4, 64));
  table->add_flag("--json", a->json, "Print one JSON object");
  table->callback([a] {
    auto check = [](const char* flag, const std::vector<double>& v, bool zero_ok) {
      for (double x : v) {
        if (!(x <= 1.0 && (zero_ok ? x >= 0.0 : x > 0.0))) {
          throw std::invalid_argument(std::string(flag) + ": " + std::to_string(x) + " is outside " +
                                      (zero_ok ? "[0, 1]" : "(0, 1]"));
        }
      }
    };
    check("--mu0", a->mu0, false);
    check("--mu", a->mu, true);
    for (double d : a->dphi) {
      if (!std::isfinite(d)) throw std::invalid_argument("--dphi: must be finite");
    }
    struct Row {
      double tau, albedo, mu0, mu, dphi;
      sky::vrte::PointResult r;
    };
    std::vector<Row> rows;
    for (double tau : a->tau) {
      sky::LayerOptics optics;
      optics.tau_rayleigh = tau;
      optics.depolarization = a->depolarization;
      for (double albedo : a->albedo) {
        const sky::vrte::CoulsonTable t = sky::vrte::coulson_table(optics, albedo, a->mu0, a->mu, a->dphi, a->streams);
        for (std::size_t i0 = 0; i0 < a->mu0.size(); ++i0)
          for (std::size_t i = 0; i < a->mu.size(); ++i)
            for (std::size_t k = 0; k < a->dphi.size(); ++k)
              rows.push_back({tau, albedo, a->mu0[i0], a->mu[i], a->dphi[k], t.at(i0, i, k)});
      }
    }
    const char* norm =
        "Coulson et al. 1960 / Natraj et al. 2009: incident flux pi (I = pi * radiance / solar irradiance), "
        "direct beam excluded; Q > 0 for E perpendicular to the view's meridian plane";
    if (a->json) {
      std::printf("{\"normalisation\": \"%s\", \"depolarization\": %.6g, \"streams\": %d, \"rows\": [\n", norm,
                  a->depolarization, a->streams);
      for (std::size_t j = 0; j < rows.size(); ++j) {
        const Row& r = rows[j];
        std::printf(" {\"tau\": %.6g, \"albedo\": %.6g, \"mu0\": %.6g, \"mu\": %.6g, \"dphi_deg\": %.6g, ", r.tau,
                    r.albedo, r.mu0, r.mu, r.dphi);
        print_iqu("top_up", r.r.top_up, false);
        print_iqu("ground_down", r.r.ground_down, true);
        std::printf("}%s\n", j + 1 < rows.size() ? "," : "");
      }
      std::printf("]}\n");
      return;
    }
    std::printf("# skypol table: %s\n# depolarization %.6g, %d streams per hemisphere\n", norm, a->depolarization,
                a->streams);
    std::printf("# %8s %7s %7s %7s %7s %12s %12s %12s %12s %12s %12s\n", "tau", "albedo", "mu0", "mu", "dphi",
                "I_top_up", "Q_top_up", "U_top_up", "I_ground_dn", "Q_ground_dn", "U_ground_dn");
    for (const Row& r : rows) {
      std::printf("  %8.5g %7.4g %7.4g %7.4g %7.4g %12.8f %12.8f %12.8f %12.8f %12.8f %12.8f\n", r.tau, r.albedo,
                  r.mu0, r.mu, r.dphi, r.r.top_up.i, r.r.top_up.q, r.r.top_up.u, r.r.ground_down.i,
                  r.r.ground_down.q, r.r.ground_down.u);
    }
  });
}

}  // namespace skypol::cli
