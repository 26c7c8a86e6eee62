// The calibration model of skypole/uncertainty.h, term by term, on values worked by hand: the σ
// floor's terms (floor, residual beyond the pixels, unpolarized share, the suns' elevation misfit,
// the model misfit), the sector factor with the unpolarized and clipped shares, the widening for few
// jackknife groups as the calibration applies it, each gate at its edge and their order, the
// uncertainty bound, the Wilson interval and auto's rule (auto_choice) on answers reduced to numbers.
// No stack is rendered: every case is arithmetic.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "sky/units.h"
#include "skypole/method_registry.h"
#include "skypole/uncertainty.h"

using namespace skypol;
using skypole::CalibrationReadings;
using skypole::Gate;
using skypole::MethodCalibration;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// −ln 0.05: the 95 % point of F(2, ∞) times 2/2, the widening's denominator (uncertainty.h).
const double kQ95Inf = -std::log(0.05);

// A calibration with every term and factor 0 (only what a case sets counts).
MethodCalibration bare() {
  MethodCalibration c;
  c.inflation = 0;
  return c;
}

}  // namespace

TEST_CASE("the σ floor: each term alone, then their root-sum-square", "[skypole][calibration]") {
  // Readings with every share non-zero, so that a term reading the wrong share shows.
  CalibrationReadings r;
  r.residual_deg = 1.0;
  r.pixel_deg = 0.2;
  r.unpolarized_share = 0.2;
  r.clipped_share = 0.1;
  r.sun_elevation_misfit_deg = 0.8;
  r.model_misfit = 0.005;
  r.ring_anisotropy = 0.7;
  r.window_min = 30;

  MethodCalibration floor = bare();
  floor.floor_deg = 0.3;
  CHECK(skypole::calibrated_floor_deg(floor, r) == Approx(0.3));

  // The residual beyond 2 pixels: 0.5 × (1.0° − 2 × 0.2°) = 0.3°.
  MethodCalibration residual = bare();
  residual.residual_share = 0.5;
  residual.residual_pixels = 2;
  CHECK(skypole::calibrated_floor_deg(residual, r) == Approx(0.3));
  // Within the pixels the residual says nothing: no term (not a negative one); nor without a residual.
  CalibrationReadings small = r;
  small.residual_deg = 0.3;
  CHECK(skypole::calibrated_floor_deg(residual, small) == 0.0);
  small.residual_deg = std::nan("");
  CHECK(skypole::calibrated_floor_deg(residual, small) == 0.0);

  // 2° per unit of unpolarized share: 2 × 0.2 = 0.4°. The clipped share (0.1) is not read by the
  // floor, only by the sector factor.
  MethodCalibration unpolarized = bare();
  unpolarized.unpolarized_deg = 2.0;
  CHECK(skypole::calibrated_floor_deg(unpolarized, r) == Approx(0.4));
  CalibrationReadings unclipped = r;
  unclipped.clipped_share = 0.0;
  CHECK(skypole::calibrated_floor_deg(unpolarized, unclipped) == Approx(0.4));
  CalibrationReadings clipped = r;
  clipped.clipped_share = 0.9;
  CHECK(skypole::calibrated_floor_deg(unpolarized, clipped) == Approx(0.4));

  // 0.25 × the suns' elevation misfit 0.8° = 0.2°; 40° per unit of model misfit × 0.005 = 0.2°.
  MethodCalibration elevation = bare();
  elevation.elevation_share = 0.25;
  CHECK(skypole::calibrated_floor_deg(elevation, r) == Approx(0.2));
  MethodCalibration misfit = bare();
  misfit.misfit_deg = 40;
  CHECK(skypole::calibrated_floor_deg(misfit, r) == Approx(0.2));

  // All five: √(0.3² + 0.3² + 0.4² + 0.2² + 0.2²) = √0.42.
  MethodCalibration all = bare();
  all.floor_deg = 0.3;
  all.residual_share = 0.5;
  all.residual_pixels = 2;
  all.unpolarized_deg = 2.0;
  all.elevation_share = 0.25;
  all.misfit_deg = 40;
  CHECK(skypole::calibrated_floor_deg(all, r) == Approx(std::sqrt(0.42)));
  // It is isotropic: with no jackknife, σ is the floor and the cone 2.4477 × it.
  const Eigen::Matrix2d c = skypole::calibrated_covariance(all, skypole::Jackknives{}, r);
  CHECK(c(0, 1) == 0.0);
  CHECK(c(0, 0) == Approx(0.42 * kRadPerDeg * kRadPerDeg));
  CHECK(c(1, 1) == Approx(0.42 * kRadPerDeg * kRadPerDeg));
  CHECK(skypole::sigma_deg_of(c) == Approx(std::sqrt(0.42)));
  CHECK(skypole::cone95_deg_of(c) == Approx(std::sqrt(5.991464547107979 * 0.42)));
}

TEST_CASE("the sector factor grows with the unpolarized and the clipped shares", "[skypole][calibration]") {
  MethodCalibration c = bare();
  c.sector_inflation = 0.25;
  CalibrationReadings r;
  r.unpolarized_share = 0.2;
  r.clipped_share = 0.4;
  CHECK(skypole::calibrated_sector_factor(c, r) == Approx(0.25));
  CHECK_FALSE(skypole::reads_unreadable_sky(c));
  c.sector_unpolarized = 1.0;  // + 1.0 × 0.2
  CHECK(skypole::calibrated_sector_factor(c, r) == Approx(0.45));
  CHECK(skypole::reads_unreadable_sky(c));
  c.sector_clipped = 0.5;  // + 0.5 × 0.4
  CHECK(skypole::calibrated_sector_factor(c, r) == Approx(0.65));

  // b scales the sector covariance squared: sectors 1 deg² isotropic, six groups (ν = 5), no frames:
  // C = w²(5)·0.65²·1 deg², w²(5) = 2.5·(0.05^−0.4 − 1)/(−ln 0.05).
  skypole::Jackknives j;
  j.sectors = Eigen::Matrix2d::Identity() * kRadPerDeg * kRadPerDeg;
  j.sector_groups = 6;
  j.frame_groups = 6;
  const double w2 = 2.5 * (std::pow(0.05, -0.4) - 1) / kQ95Inf;
  const Eigen::Matrix2d cov = skypole::calibrated_covariance(c, j, r);
  CHECK(cov(0, 0) / (kRadPerDeg * kRadPerDeg) == Approx(w2 * 0.65 * 0.65));
  CHECK(cov(1, 1) / (kRadPerDeg * kRadPerDeg) == Approx(w2 * 0.65 * 0.65));
}

TEST_CASE("the jackknives' factors and the widening for few groups, as the calibration applies them",
          "[skypole][calibration][dof]") {
  skypole::Jackknives j;
  j.frames << 1.0, 0.0, 0.0, 0.25;  // deg²: 1° along the azimuth axis, 0.5° along altitude
  j.frames *= kRadPerDeg * kRadPerDeg;
  j.frame_groups = 3;  // ν = 2: the 95 % point of F(2, 2) is 19
  j.sectors = Eigen::Matrix2d::Identity() * kRadPerDeg * kRadPerDeg;
  j.sector_groups = 6;
  const CalibrationReadings none;

  // Frames only (b = 0: the sectors count neither their covariance nor their groups): a = 2, so
  // A = 4 deg², ν = 2, w² = 19/(−ln 0.05) = 6.3424; σ = √(6.3424·4) = 5.037°.
  MethodCalibration frames = bare();
  frames.inflation = 2;
  const Eigen::Matrix2d cf = skypole::calibrated_covariance(frames, j, none);
  CHECK(cf(0, 0) / (kRadPerDeg * kRadPerDeg) == Approx(19.0 / kQ95Inf * 4.0));
  CHECK(cf(1, 1) / (kRadPerDeg * kRadPerDeg) == Approx(19.0 / kQ95Inf * 1.0));
  CHECK(skypole::sigma_deg_of(cf) == Approx(std::sqrt(19.0 / kQ95Inf * 4.0)));

  // Both, a = 1 with six frame groups and b = 1 from the unpolarized share alone (sector_inflation
  // 0, sector_unpolarized 2, share 0.5), equal parts: A = B = 1 deg², ν = (A + B)²/(A²/5 + B²/5) = 10,
  // w² = 5·(0.05^−0.2 − 1)/(−ln 0.05) = 1.3696; C_az = w²·(1 + 1), C_alt = w²·(0.25 + 1).
  j.frame_groups = 6;
  MethodCalibration both = bare();
  both.inflation = 1;
  both.sector_unpolarized = 2;
  CalibrationReadings half;
  half.unpolarized_share = 0.5;
  const double w2 = 5 * (std::pow(0.05, -0.2) - 1) / kQ95Inf;
  const Eigen::Matrix2d cb = skypole::calibrated_covariance(both, j, half);
  CHECK(cb(0, 0) / (kRadPerDeg * kRadPerDeg) == Approx(w2 * 2.0));
  CHECK(cb(1, 1) / (kRadPerDeg * kRadPerDeg) == Approx(w2 * 1.25));

  // A floor adds s² after the widening, unwidened: floor 1° on the same answer.
  both.floor_deg = 1.0;
  CHECK(skypole::calibrated_covariance(both, j, half)(0, 0) / (kRadPerDeg * kRadPerDeg) == Approx(w2 * 2.0 + 1.0));

  // The uncalibrated statement: both jackknives as measured, unwidened, floor 0.05°.
  const Eigen::Matrix2d cu = skypole::uncalibrated_covariance(j);
  CHECK(cu(0, 0) / (kRadPerDeg * kRadPerDeg) == Approx(1.0 + 1.0 + 0.0025));
  CHECK(cu(1, 1) / (kRadPerDeg * kRadPerDeg) == Approx(0.25 + 1.0 + 0.0025));
}

TEST_CASE("each gate declines beyond its bound and only there, in run_method's order", "[skypole][calibration][gates]") {
  CalibrationReadings pass;
  pass.residual_deg = 0.4;
  pass.model_misfit = 0.004;
  pass.window_min = 90;
  pass.unpolarized_share = 0.2;
  pass.clipped_share = 0.1;
  pass.ring_anisotropy = 0.15;
  MethodCalibration c;  // every gate unbounded
  for (const Gate g : {Gate::residual, Gate::model_misfit, Gate::window, Gate::unpolarized, Gate::clipped,
                       Gate::ring_anisotropy})
    CHECK_FALSE(skypole::gate_set(g, c));
  CHECK(skypole::first_declining_gate(c, pass) == Gate::none);

  c.max_residual_deg = 0.5;
  c.max_model_misfit = 0.005;
  c.min_window_min = 60;
  c.max_unpolarized_share = 0.3;
  c.max_clipped_share = 0.2;
  c.max_ring_anisotropy = 0.2;
  CHECK(skypole::first_declining_gate(c, pass) == Gate::none);

  struct Edge {
    Gate gate;
    double CalibrationReadings::*reading;
    double at, beyond;  // at the bound the gate passes; beyond it, it declines
    const char* field;
  };
  const Edge edges[] = {
      {Gate::residual, &CalibrationReadings::residual_deg, 0.5, 0.5001, "max_residual_deg"},
      {Gate::model_misfit, &CalibrationReadings::model_misfit, 0.005, 0.0051, "max_model_misfit"},
      {Gate::window, &CalibrationReadings::window_min, 60, 59.9, "min_window_min"},
      {Gate::unpolarized, &CalibrationReadings::unpolarized_share, 0.3, 0.31, "max_unpolarized_share"},
      {Gate::clipped, &CalibrationReadings::clipped_share, 0.2, 0.21, "max_clipped_share"},
      {Gate::ring_anisotropy, &CalibrationReadings::ring_anisotropy, 0.2, 0.21, "max_ring_anisotropy"},
  };
  for (const Edge& e : edges) {
    INFO(e.field);
    CHECK(skypole::gate_set(e.gate, c));
    CHECK(std::string(skypole::gate_field(e.gate)) == e.field);
    CalibrationReadings r = pass;
    r.*e.reading = e.at;
    CHECK_FALSE(skypole::gate_declines(e.gate, c, r));
    CHECK(skypole::first_declining_gate(c, r) == Gate::none);
    r.*e.reading = e.beyond;
    CHECK(skypole::gate_declines(e.gate, c, r));
    CHECK(skypole::first_declining_gate(c, r) == e.gate);
    // A reading that is not a number passes (the gate has nothing to compare).
    r.*e.reading = std::nan("");
    CHECK_FALSE(skypole::gate_declines(e.gate, c, r));
  }
  // The order: residual before misfit before window before the sky's shares.
  CalibrationReadings all_fail;
  all_fail.residual_deg = 1;
  all_fail.model_misfit = 1;
  all_fail.window_min = 0;
  all_fail.unpolarized_share = 1;
  all_fail.clipped_share = 1;
  all_fail.ring_anisotropy = 1;
  CHECK(skypole::first_declining_gate(c, all_fail) == Gate::residual);
  all_fail.residual_deg = 0;
  CHECK(skypole::first_declining_gate(c, all_fail) == Gate::model_misfit);
  all_fail.model_misfit = 0;
  CHECK(skypole::first_declining_gate(c, all_fail) == Gate::window);
  all_fail.window_min = 600;
  CHECK(skypole::first_declining_gate(c, all_fail) == Gate::unpolarized);
  // Without the cloud gate (InputOptions::cloud_gate = false) the unpolarized share declines nothing.
  CHECK(skypole::first_declining_gate(c, all_fail, false) == Gate::clipped);
  all_fail.clipped_share = 0;
  CHECK(skypole::first_declining_gate(c, all_fail, false) == Gate::ring_anisotropy);
  // A window gate of 0 is unset.
  c.min_window_min = 0;
  CHECK_FALSE(skypole::gate_set(Gate::window, c));
}

TEST_CASE("the uncertainty bound keeps a cone at the bound and declines one beyond", "[skypole][calibration]") {
  CHECK(skypole::within_uncertainty_bound(2.5, 2.5));
  CHECK_FALSE(skypole::within_uncertainty_bound(2.5000001, 2.5));
  CHECK(skypole::within_uncertainty_bound(170, kInf));
}

TEST_CASE("the 95 % Wilson interval", "[skypole][calibration]") {
  // 8 of 10: 0.4902–0.9433 (Newcombe, Stat. Med. 17, 857 (1998), table I's Wilson score interval).
  const auto [lo, hi] = skypole::wilson_interval95(8, 10);
  CHECK(lo == Approx(0.4902).margin(5e-5));
  CHECK(hi == Approx(0.9433).margin(5e-5));
  // 23 of 23: the interval is not empty at the top; its bottom is n/(n + z²) = 23/26.8415.
  const auto [lo23, hi23] = skypole::wilson_interval95(23, 23);
  CHECK(lo23 == Approx(23.0 / (23.0 + 1.959963984540054 * 1.959963984540054)));
  CHECK(hi23 == Approx(1.0).epsilon(1e-15));
  // 0 of 5: from 0 to z²/(n + z²).
  const auto [lo0, hi0] = skypole::wilson_interval95(0, 5);
  CHECK(lo0 == Approx(0.0).margin(1e-15));
  CHECK(hi0 == Approx(3.841459 / (5 + 3.841459)).epsilon(1e-6));
  CHECK(std::isnan(skypole::wilson_interval95(0, 0).first));
}

TEST_CASE("auto's rule on numbers: agreement, centre, decline, the answer that stands alone, the mean",
          "[skypole][calibration][auto]") {
  // Agreement at 1.5185 × the root-sum-square of the cones: cones 3° and 4°, 5° × 1.5185 = 7.5925°.
  CHECK(skypole::answers_agree(7.59249, 3, 4));
  CHECK_FALSE(skypole::answers_agree(7.59251, 3, 4));

  // Answers on a line (degrees): 0, 1.5, 3 with cones 1° (agree within 2.1475°) — neighbours agree,
  // the ends do not; the middle one is agreed with by three and is the centre.
  std::vector<double> at = {0.0, 1.5, 3.0};
  const auto angle = [&](std::size_t a, std::size_t b) { return std::abs(at[a] - at[b]); };
  std::vector<skypole::AutoCandidate> row = {{1.0, 0.3, false}, {1.0, 0.6, false}, {1.0, 0.6, false}};
  skypole::AutoChoice c = skypole::auto_choice(row, angle);
  CHECK(c.decided);
  CHECK(c.centre == 1);
  CHECK(c.members == std::vector<std::size_t>{0, 1, 2});
  CHECK(c.dissent.empty());
  CHECK(c.sharpest == 0);
  CHECK_FALSE(c.alone);
  CHECK(c.chosen == 0);
  CHECK(c.mean);
  // The mean about 0: weights 1/0.09, 1/0.36, 1/0.36: (1.5 + 3)·(1/0.36)/(1/0.09 + 2/0.36) = 0.75.
  const std::vector<Eigen::Vector2d> offsets = {{0, 0}, {0, 1.5}, {0, 3.0}};
  const std::vector<double> sigmas = {0.3, 0.6, 0.6};
  const Eigen::Vector2d mean = skypole::inverse_variance_mean(offsets, sigmas);
  CHECK(mean.x() == 0.0);
  CHECK(mean.y() == Approx(0.75));
  // A σ of 0 weighs 10¹²: the mean is that answer's.
  CHECK(skypole::inverse_variance_mean(offsets, std::vector<double>{1.0, 0.0, 1.0}).y() == Approx(1.5).margin(1e-9));

  // The third answers alone (the ephemeris): it is chosen, as it stands, though not the sharpest.
  row[2].answers_alone = true;
  c = skypole::auto_choice(row, angle);
  REQUIRE(c.alone);
  CHECK(*c.alone == 2);
  CHECK(c.chosen == 2);
  CHECK(c.sharpest == 0);
  CHECK_FALSE(c.mean);

  // Ties in agreement go to the narrowest cone: 0 and 0.5 agree, 10 agrees with none; counts 2, 2, 1,
  // and the second has the narrower cone.
  at = {0.0, 0.5, 10.0};
  row = {{1.0, 0.3, false}, {0.8, 0.3, false}, {0.1, 0.01, false}};
  c = skypole::auto_choice(row, angle);
  CHECK(c.decided);
  CHECK(c.centre == 1);
  CHECK(c.members == std::vector<std::size_t>{0, 1});
  CHECK(c.dissent == std::vector<std::size_t>{2});
  CHECK(c.sharpest == 0);  // equal σ: the first

  // One against one: the group is no larger than the dissent, auto declines; one answer alone stands.
  at = {0.0, 5.0};
  row = {{0.5, 0.2, false}, {0.5, 0.2, false}};
  CHECK_FALSE(skypole::auto_choice(row, angle).decided);
  row.resize(1);
  c = skypole::auto_choice(row, angle);
  CHECK(c.decided);
  CHECK_FALSE(c.mean);
  CHECK_FALSE(skypole::auto_choice(std::vector<skypole::AutoCandidate>{}, angle).decided);
}

TEST_CASE("the calibration's fields are the registry's JSON keys, each read from its own member",
          "[skypole][calibration][registry]") {
  const std::string json = skypole::methods_json();
  MethodCalibration c;
  double v = 1.0;
  for (const auto& [name, member] : skypole::calibration_fields()) {
    INFO(name);
    CHECK(json.find(std::string("\"") + name + "\": ") != std::string::npos);
    c.*member = (v += 1.0);
  }
  // Distinct values prove distinct members: 16 fields, 16 different numbers.
  CHECK(skypole::calibration_fields().size() == 16);
  CHECK(c.inflation != c.floor_deg);
  CHECK(c.max_ring_anisotropy != c.max_model_misfit);
  CHECK(c.misfit_deg == v);
}
