// `skypol table` as a user runs it: the solver's I, Q, U against Coulson, Dave & Sekera's tables as
// Natraj, Li & Yung (2009) corrected them (τ = 0.5, μ0 = 0.2, μ = 0.4, Δφ = 60°, reflected at the
// top, ground albedo 0 and 0.8), in text and JSON, and bad arguments refused with exit code 2.
#include "cli_harness.h"

#include <sstream>
#include <string>
#include <vector>

using namespace skypol::test;

namespace {

// The numbers of the data line (not starting with '#') whose first five columns match.
std::vector<double> row(const std::string& out, double albedo) {
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream l(line);
    std::vector<double> v;
    for (double x; l >> x;) v.push_back(x);
    if (v.size() == 11 && v[1] == albedo) return v;
  }
  return {};
}

}  // namespace

TEST_CASE("skypol table prints Coulson's values up at the top", "[cli][table]") {
  const Result r = run("table --tau 0.5 --albedo 0 0.8 --mu0 0.2 --mu 0.4 --dphi 60 --streams 16");
  REQUIRE(r.code == 0);
  INFO(r.out);
  // Natraj et al. 2009 (Coulson's τ = 0.5 table, reflected): albedo 0 and 0.8.
  const std::vector<double> a0 = row(r.out, 0.0), a8 = row(r.out, 0.8);
  REQUIRE(a0.size() == 11);
  REQUIRE(a8.size() == 11);
  CHECK(a0[5] == Approx(0.12752450).margin(2e-5));
  CHECK(a0[6] == Approx(-0.06066038).margin(2e-5));
  CHECK(a0[7] == Approx(0.05293867).margin(2e-5));
  CHECK(a8[5] == Approx(0.18923236).margin(2e-5));
  CHECK(a8[6] == Approx(-0.06041229).margin(2e-5));
  CHECK(a8[7] == Approx(0.05293867).margin(2e-5));
  // The ground's diffuse light is there too, positive and finite.
  CHECK(a0[8] > 0);
}

TEST_CASE("skypol table --json gives the same numbers", "[cli][table]") {
  const Result r = run("table --tau 0.5 --mu0 0.2 --mu 0.4 --dphi 0 60 --json");
  REQUIRE(r.code == 0);
  INFO(r.out);
  CHECK(r.out.find("\"rows\"") != std::string::npos);
  // 16 streams: Coulson's I = 0.12752450, Q = −0.06066038 to within 1e-6.
  CHECK(r.out.find("\"dphi_deg\": 60, \"top_up\": {\"i\": 0.12752") != std::string::npos);
  CHECK(r.out.find("\"q\": -0.0606") != std::string::npos);
}

TEST_CASE("skypol table refuses a geometry out of range", "[cli][table][errors]") {
  const Result r = run("table --tau 0.5 --mu0 1.5 --mu 0.4");
  CHECK(r.code == 2);
  CHECK(r.out.find("mu0") != std::string::npos);
  CHECK(run("table --tau -1 --mu0 0.5 --mu 0.4").code != 0);
  CHECK(run("table --mu0 0.5 --mu 0.4").code != 0);
}
