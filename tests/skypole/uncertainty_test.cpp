// The one meaning of "how sure": σ of bearing and latitude and the 95 % cone from a tangent-plane
// covariance (checked against the formulas of uncertainty.h worked by hand), the jackknife on
// stacks built to be easy or hard, the bound and its reason, and auto.
#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <stdexcept>

#include "sky/units.h"
#include "skypole/evaluate.h"
#include "skypole/uncertainty.h"
#include "fixtures.h"

using namespace skypol;

namespace {

using testing::pole_at;
}  // namespace

TEST_CASE("covariance to σ and cone: the formulas worked by hand", "[skypole][uncertainty]") {
  // Isotropic 1° at altitude 60°: σ_lat = 1°, σ_bearing = 1°/cos 60° = 2°, cone = √5.991 = 2.448°.
  skypole::PoleEstimate e = pole_at(30, 60);
  skypole::set_uncertainty(e, Eigen::Matrix2d::Identity() * kRadPerDeg * kRadPerDeg);
  CHECK(e.sigma_latitude_deg == Approx(1.0));
  CHECK(e.sigma_bearing_deg == Approx(2.0));
  CHECK(e.sigma_deg == Approx(1.0));
  CHECK(e.cone95_deg == Approx(2.4477).epsilon(1e-4));
  // Elongated: 3° along the azimuth axis, 1° along altitude, altitude 0: the cone holds the long axis.
  skypole::PoleEstimate f = pole_at(200, 0);
  Eigen::Matrix2d c;
  c << 9, 0, 0, 1;
  skypole::set_uncertainty(f, c * kRadPerDeg * kRadPerDeg);
  CHECK(f.sigma_bearing_deg == Approx(3.0));
  CHECK(f.sigma_latitude_deg == Approx(1.0));
  CHECK(f.cone95_deg == Approx(3 * 2.4477).epsilon(1e-4));
}

TEST_CASE("few jackknife groups widen the cone to the F(2, ν) quantile", "[skypole][uncertainty][dof]") {
  // Closed forms: q95(ν) = (ν/2)(0.05^(−2/ν) − 1), q95(∞) = −ln 0.05 = 2.99573.
  // 3 frames alone: ν = 2, q = 19, widening 19/2.99573.
  CHECK(skypole::few_groups_widening2(1.0, 3, 0.0, 0) == Approx(19.0 / 2.995732).epsilon(1e-6));
  // 6 sectors alone: ν = 5, q = 2.5·(0.05^−0.4 − 1) = 5.7861.
  CHECK(skypole::few_groups_widening2(0.0, 0, 2.0, 6) == Approx(2.5 * (std::pow(0.05, -0.4) - 1) / 2.995732));
  // Equal parts from 6 and 6 groups: Welch–Satterthwaite ν = (2A)²/(2A²/5) = 10, q = 5·(0.05^−0.2 − 1).
  CHECK(skypole::few_groups_widening2(0.3, 6, 0.3, 6) == Approx(5.0 * (std::pow(0.05, -0.2) - 1) / 2.995732));
  // Nothing measured, nothing widened; many groups, nearly nothing.
  CHECK(skypole::few_groups_widening2(0.0, 6, 0.0, 6) == 1.0);
  CHECK(skypole::few_groups_widening2(1.0, 10001, 0.0, 0) == Approx(1.0).epsilon(1e-3));
  CHECK(skypole::frame_jackknife_groups(3) == 3);
  CHECK(skypole::frame_jackknife_groups(24) == 6);
  // great_circle's delete-one jackknife (method_registry.h MethodTraits::frame_jackknife_max_groups): one frame a group,
  // up to 24.
  CHECK(skypole::frame_jackknife_groups(19, 24) == 19);
  CHECK(skypole::frame_jackknife_groups(30, 24) == 24);

  // An independent check by simulation: a 2-D error of σ 1 per axis, and a variance estimated
  // from ν degrees of freedom (σ̂² = χ²_ν/ν, independent of the error). The widened cone,
  // 2.4477·√(w²·σ̂²), holds the error 95 % of the time; the unwidened one much less.
  std::mt19937_64 rng(15);
  std::normal_distribution<double> normal;
  for (const int groups : {3, 4, 6}) {
    const int nu = groups - 1;
    const double w2 = skypole::few_groups_widening2(1.0, groups, 0.0, 0);
    const int n = 200000;
    int inside = 0, inside_bare = 0;
    for (int i = 0; i < n; ++i) {
      const double ex = normal(rng), ey = normal(rng);
      double chi2 = 0;
      for (int k = 0; k < nu; ++k) chi2 += std::pow(normal(rng), 2);
      const double var_hat = chi2 / nu;
      const double r2 = ex * ex + ey * ey;
      inside += r2 <= 5.991465 * w2 * var_hat ? 1 : 0;
      inside_bare += r2 <= 5.991465 * var_hat ? 1 : 0;
    }
    INFO("groups " << groups);
    CHECK(static_cast<double>(inside) / n == Approx(0.95).margin(0.003));
    CHECK(static_cast<double>(inside_bare) / n < 0.90);
  }
}

TEST_CASE("tangent offsets: a step up in altitude and a step east in azimuth", "[skypole][uncertainty]") {
  const skypole::PoleEstimate p = pole_at(10, 40);
  const Eigen::Vector2d up = skypole::tangent_offset(p, pole_at(10, 41));
  CHECK(up.x() == Approx(0).margin(1e-9));
  CHECK(up.y() == Approx(kRadPerDeg).epsilon(1e-6));
  // One degree of azimuth at altitude 40° is cos 40° degrees on the sphere (to first order).
  const Eigen::Vector2d east = skypole::tangent_offset(p, pole_at(11, 40));
  CHECK(east.x() == Approx(std::cos(40 * kRadPerDeg) * kRadPerDeg).epsilon(1e-3));
  // A step along a parallel leaves the great circle of the azimuth axis by ½·sin h·cos h·Δa²
  // (7.5e-5 rad here): second order.
  CHECK(east.y() == Approx(0.5 * std::sin(40 * kRadPerDeg) * std::cos(40 * kRadPerDeg) * kRadPerDeg * kRadPerDeg).epsilon(0.05));
}

TEST_CASE("every method states an uncertainty that holds its error on a noisy day",
          "[skypole][uncertainty]") {
  testing::SyntheticSpec spec;
  spec.times = testing::times_every("2022-09-23T08:00:00Z", "2022-09-23T16:00:00Z", 30);
  spec.size = 128;
  spec.heading_deg = 77;
  spec.noise = 0.01;
  spec.max_dolp = 0.7;
  spec.seed = 3;
  const stack::Stack stack = testing::make_stack(spec);
  for (const std::string& m : skypole::method_names()) {
    const skypole::PoleEstimate e = skypole::run_method(stack, m);
    INFO(m << ": " << e.why_invalid << " " << e.note);
    if (m == "classic" && !e.valid) continue;  // the paper's method may decline; never lie
    // invariance's and sun_vector's calibrations keep only fits with a residual under 0.05°, and
    // great_circle's under 2° (the multiple-scattering sky's biased fits look like noisy Rayleigh
    // ones above it): on this noisy day invariance's residual is 0.10°, so it may decline, for
    // that reason and no other.
    if ((m == "great_circle" || m == "invariance" || m == "sun_vector") && !e.valid) {
      CHECK_THAT(e.why_invalid, Catch::Contains("the fit's residual"));
      continue;
    }
    REQUIRE(e.valid);
    const skypole::Score s = skypole::score(e, stack.frames.front().truth);
    std::cout << m << ": error " << s.angular_error_deg << "°, cone95 " << e.cone95_deg << "°, σ bearing "
              << e.sigma_bearing_deg << "°, σ latitude " << e.sigma_latitude_deg << "°\n";
    CHECK(e.cone95_deg > 0);
    CHECK(s.angular_error_deg < 5 * e.sigma_deg + 0.05);  // not a lie
    // Inside its own cone on an easy day. great_circle's answer here is 2.5σ off, which a 95 % cone
    // misses one day in twenty: its coverage is checked over thirty such days below.
    if (m != "great_circle") CHECK(s.angular_error_deg < e.cone95_deg);
    // The methods whose calibration factor is modest state a useful cone; classic, great_circle
    // and sun_dolp carry the large factors their cloud and sky-model errors earned (their registry
    // entries, skypole/*_method.cpp).
    if (m == "invariance" || m == "sun_vector" || m == "sun_vector_ephemeris" || m == "auto")
      CHECK(e.cone95_deg < 5);
  }
}

TEST_CASE("great_circle's cone holds its error on 28 of 30 noisy days, and it never lies",
          "[skypole][uncertainty]") {
  // The noisy day above at thirty headings and noise draws (128 px, 17 frames over 8 h, DoLP noise
  // 0.01). Its delete-one frame jackknife and its calibration (great_circle_method.cpp) hold 28; a σ
  // half as large would hold some 20.
  int answers = 0, inside = 0;
  for (int seed = 1; seed <= 30; ++seed) {
    testing::SyntheticSpec spec;
    spec.times = testing::times_every("2022-09-23T08:00:00Z", "2022-09-23T16:00:00Z", 30);
    spec.size = 128;
    spec.heading_deg = 77 + seed;
    spec.noise = 0.01;
    spec.max_dolp = 0.7;
    spec.seed = static_cast<std::uint32_t>(seed);
    const stack::Stack stack = testing::make_stack(spec);
    const skypole::PoleEstimate e = skypole::run_method(stack, "great_circle");
    INFO("seed " << seed << ": " << e.why_invalid);
    REQUIRE(e.valid);
    CHECK(e.jackknife_frame_groups == 17);  // one frame a group
    const double err = skypole::score(e, stack.frames.front().truth).angular_error_deg;
    CHECK(err < 5 * e.sigma_deg);
    ++answers;
    inside += err < e.cone95_deg ? 1 : 0;
  }
  CHECK(answers == 30);
  CHECK(inside == 28);
}

TEST_CASE("declines, each with its true reason", "[skypole][uncertainty]") {
  testing::SyntheticSpec spec;
  spec.size = 96;
  spec.heading_deg = 200;
  SECTION("a bound the answer cannot meet") {
    spec.times = testing::paper_times();
    spec.noise = 0.01;
    spec.max_dolp = 0.7;
    const stack::Stack stack = testing::make_stack(spec);
    skypole::InputOptions in;
    in.max_uncertainty_deg = 1e-6;
    const skypole::PoleEstimate e = skypole::run_method(stack, "sun_vector", in);
    CHECK_FALSE(e.valid);
    CHECK_THAT(e.why_invalid, Catch::Contains("uncertainty above the bound") && Catch::Contains("95 % cone"));
    // The same stack with a loose bound answers.
    in.max_uncertainty_deg = 30;
    CHECK(skypole::run_method(stack, "sun_vector", in).valid);
  }
  SECTION("two frames: no uncertainty can be measured, so no answer is given") {
    spec.times = testing::times_every("2022-09-23T09:00:00Z", "2022-09-23T13:00:00Z", 240);
    const stack::Stack stack = testing::make_stack(spec);
    const skypole::PoleEstimate e = skypole::run_method(stack, "sun_vector_ephemeris");
    CHECK_FALSE(e.valid);
    CHECK_THAT(e.why_invalid, Catch::Contains("too few frames to measure the uncertainty"));
  }
  SECTION("a window shorter than the calibration's gate: declined for the window, not the field of view") {
    // 40 min, clean: sun_vector answers; a calibration that found it unpredictable under 2 h
    // declines it for the window, with the numbers; uncalibrated, the gates do not apply.
    spec.times = testing::times_every("2022-09-23T10:00:00Z", "2022-09-23T10:40:00Z", 10);
    const stack::Stack stack = testing::make_stack(spec);
    skypole::InputOptions uncalibrated;
    uncalibrated.calibrated = false;
    skypole::PoleEstimate sv = skypole::run_method(stack, "sun_vector", uncalibrated);
    REQUIRE(sv.valid);
    skypole::PoleEstimate raw = sv;
    const skypole::MethodCalibration c{.method = "sun_vector", .min_window_min = 120};
    skypole::apply_calibration_gates(sv, c, stack, {});
    CHECK_FALSE(sv.valid);
    CHECK_THAT(sv.why_invalid, Catch::Contains("window (40 min) is shorter than the 120 min"));
    skypole::apply_calibration_gates(raw, c, stack, uncalibrated);
    CHECK(raw.valid);
    // The committed calibration's own window gate (sun_vector's 60 min, sun_vector_method.cpp) says the same.
    const skypole::PoleEstimate committed = skypole::run_method(stack, "sun_vector");
    CHECK_FALSE(committed.valid);
    CHECK_THAT(committed.why_invalid, Catch::Contains("window (40 min) is shorter than the 60 min"));
    // sun_dolp's pole is the same axis of the sun's path, and its gate the same.
    REQUIRE(skypole::run_method(stack, "sun_dolp", uncalibrated).valid);
    const skypole::PoleEstimate dolp = skypole::run_method(stack, "sun_dolp");
    CHECK_FALSE(dolp.valid);
    CHECK_THAT(dolp.why_invalid, Catch::Contains("window (40 min) is shorter than the 60 min"));
  }
  SECTION("a short noisy window: the jackknife sees the answer move and the cone is wide or the method declines") {
    spec.times = testing::times_every("2022-09-23T11:00:00Z", "2022-09-23T11:20:00Z", 5);
    spec.noise = 0.03;
    spec.max_dolp = 0.5;
    const stack::Stack stack = testing::make_stack(spec);
    for (const char* m : {"great_circle", "sun_dolp", "sun_vector"}) {
      const skypole::PoleEstimate e = skypole::run_method(stack, m);
      INFO(m << ": " << e.why_invalid);
      if (!e.valid) continue;
      const skypole::Score s = skypole::score(e, stack.frames.front().truth);
      std::cout << "short noisy " << m << ": error " << s.angular_error_deg << "°, cone95 " << e.cone95_deg << "°\n";
      CHECK(s.angular_error_deg < 5 * e.sigma_deg + 0.05);
    }
  }
}

TEST_CASE("auto: the ephemeris' answer when it agrees, else the inverse-variance mean with the sharpest σ",
          "[skypole][uncertainty][auto]") {
  testing::SyntheticSpec spec = testing::paper_day(96, 300, 0.01);
  stack::Stack stack = testing::make_stack(spec);
  std::vector<skypole::PoleEstimate> all;
  for (const std::string& m : skypole::method_names())
    if (m != "auto") all.push_back(skypole::run_method(stack, m));
  const auto find = [&](const std::string& m) -> const skypole::PoleEstimate& {
    for (const auto& e : all)
      if (e.method == m) return e;
    throw std::logic_error(m);
  };
  // On this clear noisy day every valid answer is within a fraction of a degree of the truth, so
  // all agree.
  const skypole::PoleEstimate a = skypole::combine_estimates(stack, {}, all);
  INFO(a.why_invalid << " / " << a.note);
  REQUIRE(a.valid);
  CHECK(a.method == "auto");
  CHECK(a.note.find("outvoted") == std::string::npos);
  // The stack knows its site: sun_vector_ephemeris takes part and its answer is returned as it
  // stands (its pole, its σ).
  const skypole::PoleEstimate& eph = find("sun_vector_ephemeris");
  REQUIRE(eph.valid);
  CHECK_THAT(a.note, Catch::StartsWith("the answer of sun_vector_ephemeris"));
  CHECK(a.sigma_deg == eph.sigma_deg);
  CHECK(a.cone95_deg == eph.cone95_deg);
  CHECK(a.heading_deg == eph.heading_deg);
  CHECK(a.latitude_deg == eph.latitude_deg);
  CHECK(skypole::score(a, stack.frames.front().truth).angular_error_deg < 0.5);

  SECTION("a capture without its site: the inverse-variance mean of the others, with the sharpest σ") {
    stack.site_known = false;
    const skypole::PoleEstimate b = skypole::combine_estimates(stack, {}, all);
    REQUIRE(b.valid);
    CHECK(b.note.find("sun_vector_ephemeris") == std::string::npos);
    // The mean, found here from the members themselves: Σ wᵢ·offsetᵢ / Σ wᵢ about the sharpest,
    // wᵢ = 1/σᵢ², every site-free method that answered (all agree on this day).
    const skypole::PoleEstimate* sharpest = nullptr;
    int members = 0;
    for (const auto& e : all)
      if (e.valid && e.method != "sun_vector_ephemeris") {
        ++members;
        if (!sharpest || e.sigma_deg < sharpest->sigma_deg) sharpest = &e;
      }
    REQUIRE(members >= 2);
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    double weights = 0;
    for (const auto& e : all)
      if (e.valid && e.method != "sun_vector_ephemeris") {
        sum += skypole::tangent_offset(*sharpest, e) / (e.sigma_deg * e.sigma_deg);
        weights += 1 / (e.sigma_deg * e.sigma_deg);
      }
    const Eigen::Vector2d expected = sum / weights;
    const Eigen::Vector2d got = skypole::tangent_offset(*sharpest, b);
    CHECK(got.x() == Approx(expected.x()).margin(1e-9));
    CHECK(got.y() == Approx(expected.y()).margin(1e-9));
    CHECK(expected.norm() > 1e-7);  // the members differ: the mean is not the sharpest's answer
    CHECK(b.sigma_deg == sharpest->sigma_deg);
    CHECK(b.cone95_deg == sharpest->cone95_deg);
    CHECK_THAT(b.note, Catch::StartsWith("the inverse-variance mean of the agreeing answers, with the σ of the "
                                         "sharpest, " + sharpest->method));
    CHECK(skypole::score(b, stack.frames.front().truth).angular_error_deg < 0.5);
  }

  SECTION("no method answers: auto declines and lists why") {
    std::vector<skypole::PoleEstimate> none = all;
    for (auto& e : none) {
      e.valid = false;
      e.why_invalid = "test";
    }
    const skypole::PoleEstimate d = skypole::combine_estimates(stack, {}, none);
    CHECK_FALSE(d.valid);
    CHECK_THAT(d.why_invalid, Catch::Contains("no method could answer") && Catch::Contains("great_circle: test"));
  }
}

TEST_CASE("tangent_moved is tangent_offset's inverse", "[skypole][uncertainty]") {
  // A pole at altitude 40°, azimuth 70°, reported as the SCP end: move it by (0.3°, −1.2°) in its
  // tangent plane and read the offset back.
  skypole::PoleEstimate at;
  const double az = 70 * kRadPerDeg, alt = 40 * kRadPerDeg;
  at.pole_level = Eigen::Vector3d(std::sin(az) * std::cos(alt), std::cos(az) * std::cos(alt), std::sin(alt));
  at.is_north = false;
  const Eigen::Vector2d d(0.3 * kRadPerDeg, -1.2 * kRadPerDeg);
  skypole::PoleEstimate moved = at;
  moved.pole_level = skypole::tangent_moved(at, d);
  const Eigen::Vector2d back = skypole::tangent_offset(at, moved);
  CHECK(back.x() == Approx(d.x()).margin(1e-12));
  CHECK(back.y() == Approx(d.y()).margin(1e-12));
  // The altitude axis points up: a move of +1° along it raises the pole by 1°.
  const Eigen::Vector3d up = skypole::tangent_moved(at, Eigen::Vector2d(0, 1 * kRadPerDeg));
  CHECK(std::asin(up.z()) / kRadPerDeg == Approx(41.0).margin(1e-9));
  CHECK(skypole::tangent_moved(at, Eigen::Vector2d::Zero()).isApprox(at.pole_level));
}

TEST_CASE("pixel_angle_deg is 1/fx radians for an equidistant lens", "[skypole][uncertainty]") {
  testing::SyntheticSpec spec = testing::paper_spec(0);
  spec.size = 96;
  const stack::Stack stack = testing::make_stack(spec);
  // synthetic_stack: fx = size/2 / θmax, θmax = 92.5°; equidistant: r = fx·θ, so one pixel from
  // the principal point is 1/fx rad.
  const double fx = 0.5 * 96 / rad_from_deg(92.5);
  CHECK(skypole::pixel_angle_deg(*stack.camera) == Approx(kDegPerRad / fx).epsilon(1e-9));
}

TEST_CASE("sector_of deals the image into equal azimuth sectors about a centre", "[skypole][uncertainty][sectors]") {
  const Eigen::Vector2d c(47.5, 47.5);
  // atan2(y − cy, x − cx) from −180° in six 60° parts: right of the centre is 0°, the start of
  // sector 3; straight up in the image (y smaller) is −90°, sector 1; 45° down-right, sector 3;
  // just above the left-pointing ray (−179°), sector 0; just below it (+179°), sector 5.
  CHECK(skypole::sector_of(50, 47.5, c, 6) == 3);
  CHECK(skypole::sector_of(47.5, 40, c, 6) == 1);
  CHECK(skypole::sector_of(52, 52, c, 6) == 3);
  CHECK(skypole::sector_of(40, 47.4, c, 6) == 0);
  CHECK(skypole::sector_of(40, 47.6, c, 6) == 5);
  // sector_left_out masks that sector's pixels in every frame and touches nothing else. Four
  // sectors of a square image about its centre are equal by symmetry (no pixel centre lies on a
  // boundary ray when the centre is between pixels): exactly a quarter of the 96×96 pixels.
  testing::SyntheticSpec spec = testing::paper_spec(0);
  spec.size = 96;
  const stack::Stack stack = testing::make_stack(spec);
  const stack::Stack sub = skypole::sector_left_out(stack, c, 2, 4);
  REQUIRE(sub.frames.size() == stack.frames.size());
  for (std::size_t f = 0; f < sub.frames.size(); ++f) {
    const auto& before = stack.frames[f].channels.at("mask");
    const auto& after = sub.frames[f].channels.at("mask");
    std::size_t cleared = 0, other = 0;
    for (int y = 0; y < 96; ++y)
      for (int x = 0; x < 96; ++x) {
        const std::size_t i = static_cast<std::size_t>(y * 96 + x);
        if (skypole::sector_of(x, y, c, 4) == 2) {
          CHECK(after[i] == 0.0f);
          ++cleared;
        } else {
          other += after[i] != before[i] ? 1 : 0;
        }
      }
    CHECK(other == 0);
    CHECK(cleared == 96 * 96 / 4);
    CHECK(sub.frames[f].channels.at("DoLP.Y") == stack.frames[f].channels.at("DoLP.Y"));
  }
}

TEST_CASE("the sector jackknife sees a bias that stays in one part of the sky; the frame jackknife does not",
          "[skypole][uncertainty][sectors]") {
  // A thin veil with the wrong E-vectors (DoLP a tenth, AoLP turned by 40°: what no clear sky shows)
  // over a 25° disc, 60° from the axis, in the middle of sector 3, in every frame; the sky mask is
  // off so that the veil reaches sun_vector's fits (sky_mask_test: it moves them by degrees).
  testing::SyntheticSpec spec = testing::paper_day(96, 30, 0.01);
  const stack::Stack clear = testing::make_stack(spec);
  stack::Stack veiled = clear;
  const double a = 30 * kRadPerDeg, z = 60 * kRadPerDeg;  // image angle 30° (x right, y down), 60° off axis
  const Eigen::Vector3d centre(std::cos(a) * std::sin(z), std::sin(a) * std::sin(z), std::cos(z));
  testing::veil_disc(veiled, centre, 25, [](std::size_t, const Eigen::Vector3d&, float& dolp, float& aolp) {
    dolp *= 0.1f;
    aolp = static_cast<float>(std::remainder(static_cast<double>(aolp) + 40 * kRadPerDeg, std::numbers::pi));
  });
  const testing::ClearAndVeiled r =
      testing::read_clear_and_veiled("sun_vector", clear, veiled, testing::uncalibrated_unmasked());
  const auto [err_c, frames_c, sectors_c] = r.c;
  const auto [err_v, frames_v, sectors_v] = r.v;
  // The veil moves the answer well beyond the clear day's error (0.03° on this stack) ...
  CHECK(err_v > 10 * err_c);
  // ... the frame groups all carry it, so their scatter stays far below the error ...
  CHECK(frames_v < err_v / 3);
  // ... and the sector that holds it, left out, moves the answer: the sector σ grows with the veil
  // and is of the error's size.
  CHECK(sectors_v > 5 * sectors_c);
  CHECK(sectors_v > err_v / 3);
  // Uncalibrated, the stated σ is both jackknives' and the 0.05° floor: the veiled day's cone holds
  // what the frame jackknife alone would have stated too narrow.
  CHECK(r.veiled.sigma_deg >= sectors_v * (1 - 1e-9));
  CHECK(r.veiled.sigma_deg <= std::sqrt(frames_v * frames_v + sectors_v * sectors_v + 0.05 * 0.05) * (1 + 1e-9));
}
