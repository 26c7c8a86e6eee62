// Mie theory for one sphere against published values (Wiscombe 1979, NCAR TN-140+STR, "Mie
// scattering calculations: advances in technique and fast, vector-speed computer codes", test
// cases and appendix tables; Bohren & Huffman 1983, appendix A), the Rayleigh limit, and the
// identities every sphere obeys. The published numbers were read from the test suites of
// miepython (S. Prahl) and MIEX-Python (M. Lietzow), which transcribe those tables.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "sky/vrte/mie.h"
#include "sky/units.h"

using namespace skypol::sky;
using cplx = std::complex<double>;
using skypol::kPi, skypol::rad_from_deg;

namespace {

std::vector<double> cos_deg(double step_deg, double last_deg = 180.0) {
  std::vector<double> mu;
  for (double t = 0.0; t <= last_deg + 1e-9; t += step_deg) mu.push_back(std::cos(rad_from_deg(t)));
  return mu;
}

double f11(cplx s1, cplx s2) { return 0.5 * (std::norm(s1) + std::norm(s2)); }
double f12(cplx s1, cplx s2) { return 0.5 * (std::norm(s2) - std::norm(s1)); }
}  // namespace

TEST_CASE("Qext, Qsca and g match Wiscombe's MIEV0 test cases", "[mie][published]") {
  // Wiscombe (1979) test cases: x, m (B&H sign, Im m ≥ 0), Qext, Qsca, g. Qext = 0 means not
  // published for that case.
  struct Case {
    double x;
    cplx m;
    double qext, qsca, g;
  };
  const Case cases[] = {
      {10.0, {1.5, 0.0}, 2.881999, 2.881999, 0.742913},
      {100.0, {1.5, 0.0}, 2.094388, 2.094388, 0.818246},
      {1000.0, {1.5, 0.0}, 2.013945, 2.013945, 0.827882},
      {5000.0, {1.5, 0.0}, 2.008650, 2.008650, 0.829592},
      {10.0, {1.5, 0.1}, 2.459791, 1.235144, 0.922350},
      {100.0, {1.5, 0.1}, 2.089822, 1.132134, 0.950392},
      {1000.0, {1.5, 0.1}, 2.019703, 1.106932, 0.950880},
      {0.099, {0.75, 0.0}, 7.417859e-06, 7.417859e-06, 0.001448},
      {0.101, {0.75, 0.0}, 8.033538e-06, 8.033538e-06, 0.001507},
      {10.0, {0.75, 0.0}, 2.232265, 2.232265, 0.896473},
      {1000.0, {0.75, 0.0}, 1.997908, 1.997908, 0.844944},
      {1.0, {1.33, 1e-5}, 0.0, 0.093923, 0.184517},
      {100.0, {1.33, 1e-5}, 2.101321, 2.096594, 0.868959},
      {10000.0, {1.33, 1e-5}, 2.004089, 1.723857, 0.907840},
      {0.055, {1.5, 1.0}, 0.10149104, 1.131687e-05, 0.000491},
      {0.056, {1.5, 1.0}, 0.1033467, 1.216311e-05, 0.000509},
      {1.0, {1.5, 1.0}, 2.336321, 0.6634538, 0.192136},
      {100.0, {1.5, 1.0}, 2.097502, 1.283697, 0.850252},
      {10000.0, {1.5, 1.0}, 2.004368, 1.236574, 0.846310},
      {1.0, {10.0, 10.0}, 2.532993, 2.049405, -0.110664},
      {100.0, {10.0, 10.0}, 2.071124, 1.836785, 0.556215},
      {10000.0, {10.0, 10.0}, 2.005914, 1.795393, 0.548194},
  };
  for (const Case& c : cases) {
    INFO("x = " << c.x << ", m = " << c.m);
    const MieSphere r = mie_sphere(c.m, c.x);
    // Published with 6 decimals (7 significant digits for the tiny ones): half a unit of the last.
    auto tol = [](double v) { return v > 0.01 ? 5.01e-7 / v + 1e-7 : 1e-6; };
    if (c.qext > 0.0) CHECK(r.qext == Approx(c.qext).epsilon(tol(c.qext)));
    CHECK(r.qsca == Approx(c.qsca).epsilon(tol(c.qsca)));
    CHECK(r.g == Approx(c.g).margin(1.5e-6));
    CHECK(r.qext >= r.qsca * (1.0 - 1e-12));
  }
}

TEST_CASE("Bohren & Huffman's appendix example: m = 1.55, r = 0.525 um, lambda = 0.6328 um", "[mie][published]") {
  const double x = 2.0 * kPi * 0.525 / 0.6328;
  const std::vector<double> mu = cos_deg(9.0);
  const MieSphere r = mie_sphere({1.55, 0.0}, x, mu);
  CHECK(r.qext == Approx(3.10543).margin(1e-5));
  CHECK(r.qsca == Approx(3.10543).margin(1e-5));
  CHECK(r.qback == Approx(2.92534).margin(1e-5));
  CHECK(r.g == Approx(0.63314).margin(1e-5));
  // B&H's table: S11/S11(0), POL = −S12/S11, S33/S11, S34/S11 at Θ = 0, 9, …, 180°.
  const std::array<double, 21> s11 = {1.0,         0.785390,    0.356897,    0.766119e-1, 0.355355e-1, 0.701845e-1,
                                      0.574313e-1, 0.219660e-1, 0.125959e-1, 0.173750e-1, 0.124601e-1, 0.679093e-2,
                                      0.954239e-2, 0.863419e-2, 0.227421e-2, 0.543998e-2, 0.160243e-1, 0.188852e-1,
                                      0.195254e-1, 0.301676e-1, 0.383189e-1};
  const std::array<double, 21> pol = {0.0,          -0.459811e-2, -0.458541e-1, -0.364744, -0.534997, 0.959953e-2,
                                      0.477927e-1,  -0.440604,    -0.831996,    0.341670e-1, 0.230462, -0.713472,
                                      -0.756255,    -0.281215,    -0.239612,    -0.850804,   -0.706334, -0.891081,
                                      -0.783319,    -0.196194,    0.0};
  const std::array<double, 21> s33 = {1.0,         0.999400,     0.986022,     0.843603, 0.686967,  0.959825, 0.985371,
                                      0.648043,    0.203255,     0.795354,     0.937497, -0.717397e-2, -0.394748e-1,
                                      0.536251,    0.967602,     0.187531,     0.495254, 0.453277,  -0.391613,
                                      -0.962069,   -1.0};
  const std::array<double, 21> s34 = {0.0,        0.343261e-1, 0.160184,   0.394076,    -0.491787, -0.280434, 0.163584,
                                      0.621216,   -0.516208,   -0.605182,  0.260742,    0.700647,  -0.653085, -0.795835,
                                      0.795798e-1, -0.490882,  -0.505781,  -0.226817e-1, 0.482752, 0.189556,  0.0};
  const double f0 = f11(r.s1[0], r.s2[0]);
  for (std::size_t i = 0; i < mu.size(); ++i) {
    INFO("theta = " << 9 * i << " deg");
    const double a = f11(r.s1[i], r.s2[i]);
    const cplx c = r.s2[i] * std::conj(r.s1[i]);
    CHECK(a / f0 == Approx(s11[i]).epsilon(4e-6));  // 6 significant digits
    // B&H's POL is −S12/S11 with S12 = ½(|S2|² − |S1|²): the header's F12 with the opposite sign.
    CHECK(-f12(r.s1[i], r.s2[i]) / a == Approx(pol[i]).margin(2e-6));
    CHECK(c.real() / a == Approx(s33[i]).margin(2e-6));
    CHECK(c.imag() / a == Approx(s34[i]).margin(2e-6));
  }
}

TEST_CASE("S1 and S2 match Wiscombe's published amplitudes (complex conjugates: his exp(+iwt))", "[mie][published]") {
  // MIEV0 test case 14: m = 1.5 − 1i in Wiscombe's sign, x = 1, Θ = 0, 30, …, 180°; his S1, S2.
  const std::array<cplx, 7> w1 = {cplx(0.584080, 0.190515), cplx(0.565702, 0.187200), cplx(0.517525, 0.178443),
                                  cplx(0.456340, 0.167167), cplx(0.400212, 0.156643), cplx(0.362157, 0.149391),
                                  cplx(0.348844, 0.146829)};
  const std::array<cplx, 7> w2 = {cplx(0.584080, 0.190515),  cplx(0.500161, 0.145611),   cplx(0.287964, 0.041054),
                                  cplx(0.0362285, -0.0618265), cplx(-0.174875, -0.122959), cplx(-0.305682, -0.143846),
                                  cplx(-0.348844, -0.146829)};
  const std::vector<double> mu = cos_deg(30.0);
  const MieSphere r = mie_sphere({1.5, 1.0}, 1.0, mu);
  for (std::size_t i = 0; i < mu.size(); ++i) {
    INFO("theta = " << 30 * i << " deg");
    CHECK(r.s1[i].real() == Approx(w1[i].real()).margin(1e-6));
    CHECK(r.s1[i].imag() == Approx(-w1[i].imag()).margin(1e-6));
    CHECK(r.s2[i].real() == Approx(w2[i].real()).margin(1e-6));
    CHECK(r.s2[i].imag() == Approx(-w2[i].imag()).margin(1e-6));
  }
  // Forward and backward amplitudes of other MIEV0 cases (conjugated likewise).
  const double ends[] = {1.0, -1.0};
  const MieSphere water = mie_sphere({1.33, 1e-5}, 100.0, ends);  // case 10, S1(0°)
  CHECK(water.s1[0].real() == Approx(5.253302e3).epsilon(1e-6));
  CHECK(water.s1[0].imag() == Approx(1.243188e2).epsilon(1e-6));
  const MieSphere small = mie_sphere({0.75, 0.0}, 0.099, ends);  // case 5, S1(180°)
  CHECK(small.s1[1].real() == Approx(1.81756e-8).epsilon(1e-5));
  CHECK(small.s1[1].imag() == Approx(1.64810e-4).epsilon(1e-5));
  const MieSphere bubble = mie_sphere({0.75, 0.0}, 10.0, ends);  // case 7, S1(180°)
  CHECK(bubble.s1[1].real() == Approx(-1.07857).epsilon(1e-5));
  CHECK(bubble.s1[1].imag() == Approx(3.60881e-2).epsilon(1e-5));
}

TEST_CASE("F11 and F12/F11 match Wiscombe's appendix tables every 5 degrees", "[mie][published]") {
  // Wiscombe (1979) appendix: ½(|S1|²+|S2|²) and the degree of polarization F12/F11 (the sign of
  // the header: negative for perpendicular polarization) at Θ = 0, 5, …, 180°.
  struct Table {
    double x;
    cplx m;
    std::array<double, 37> f11;
    std::array<double, 37> pol;
  };
  const Table tables[] = {
      {10.0,
       {1.5, 0.0},
       {0.520856e04, 0.428132e04, 0.234775e04, 0.818121e03, 0.149547e03, 0.139195e02, 0.768071e02, 0.128393e03, 0.789487e02, 0.293697e02, 0.518546e02, 0.631908e02, 0.341567e02, 0.256714e02, 0.320167e02, 0.235919e02, 0.194168e02, 0.184988e02, 0.917521e01, 0.963035e01, 0.136986e02, 0.485859e01, 0.280440e01, 0.853248e01, 0.439826e01, 0.570995e01, 0.113872e02, 0.304142e01, 0.675713e01, 0.242055e02, 0.159589e02, 0.161562e02, 0.582167e02, 0.679231e02, 0.286866e02, 0.249122e02, 0.423766e02},
       {0.0000, -0.0239, -0.0963, -0.2080, -0.2887, 0.4685, 0.0005, -0.0892, -0.0767, 0.7251, 0.4834, -0.0592, -0.0163, 0.9793, 0.3242, -0.3951, 0.5014, 0.9514, -0.0269, 0.1127, 0.7525, 0.7257, 0.8993, 0.5987, -0.4844, 0.3364, 0.9396, 0.6460, 0.6282, 0.9286, 0.7664, -0.4108, 0.2385, 0.5276, 0.6986, 0.0830, 0.0000}},
      {100.0,
       {1.5, 0.0},
       {0.275508e08, 0.106440e06, 0.586911e05, 0.258367e05, 0.202131e05, 0.192755e05, 0.159327e05, 0.538269e04, 0.866710e04, 0.540267e04, 0.305275e04, 0.510959e04, 0.167021e04, 0.202680e04, 0.960828e03, 0.122361e04, 0.394465e03, 0.254063e03, 0.505356e03, 0.507283e03, 0.131614e03, 0.222694e03, 0.133922e03, 0.705029e02, 0.401041e02, 0.100503e03, 0.167811e03, 0.232785e03, 0.243533e03, 0.235398e03, 0.186086e03, 0.121783e04, 0.353283e04, 0.239888e04, 0.272592e04, 0.622951e03, 0.434048e04},
       {0.0000, -0.0107, 0.0098, 0.0712, -0.0248, -0.0730, -0.0540, 0.2001, 0.0919, -0.1301, 0.4545, 0.1026, 0.4679, -0.2130, 0.7357, -0.0054, 0.8365, -0.2535, -0.0016, -0.4214, -0.5649, -0.3412, 0.3830, -0.0700, -0.8726, 0.1822, 0.5235, 0.4015, 0.3292, 0.0578, 0.5225, -0.8534, -0.8664, 0.6181, 0.8582, 0.5069, 0.0000}},
      {10.0,
       {1.5, 0.1},
       {0.379171e04, 0.300320e04, 0.141624e04, 0.313014e03, 0.124235e02, 0.296988e02, 0.273164e02, 0.112113e02, 0.109517e02, 0.607843e01, 0.220902e01, 0.632075e01, 0.646946e01, 0.225394e01, 0.215826e01, 0.392848e01, 0.299433e01, 0.163623e01, 0.183556e01, 0.209544e01, 0.166228e01, 0.137914e01, 0.153058e01, 0.147431e01, 0.116521e01, 0.135300e01, 0.174359e01, 0.136826e01, 0.798073e00, 0.974236e00, 0.133396e01, 0.141816e01, 0.148012e01, 0.126487e01, 0.106733e01, 0.172292e01, 0.231818e01},
       {0.0000, -0.0014, -0.0068, -0.0301, -0.6183, -0.2518, -0.2817, -0.7359, -0.6378, -0.5132, -0.9235, -0.7194, -0.6077, -0.1744, -0.2426, -0.7454, -0.6373, 0.3019, -0.0893, -0.8614, -0.6653, 0.2706, 0.0790, -0.7132, -0.8966, 0.1033, 0.3819, -0.0370, -0.6271, 0.0599, 0.3753, 0.1218, -0.2643, -0.6463, -0.8175, -0.2177, 0.0000}},
      {100.0,
       {1.5, 0.1},
       {0.273645e08, 0.911574e05, 0.130172e05, 0.314304e04, 0.121824e04, 0.911319e03, 0.801673e03, 0.629347e03, 0.465786e03, 0.370932e03, 0.317391e03, 0.269848e03, 0.230451e03, 0.202758e03, 0.180401e03, 0.162813e03, 0.149203e03, 0.138475e03, 0.130113e03, 0.123599e03, 0.118559e03, 0.114659e03, 0.111687e03, 0.109437e03, 0.107749e03, 0.106503e03, 0.105600e03, 0.104961e03, 0.104521e03, 0.104229e03, 0.104044e03, 0.103935e03, 0.103877e03, 0.103850e03, 0.103840e03, 0.103837e03, 0.103837e03},
       {0.0000, -0.0247, -0.0848, -0.2375, -0.4798, -0.5484, -0.5537, -0.6268, -0.7490, -0.8418, -0.8905, -0.9395, -0.9797, -0.9960, -0.9944, -0.9750, -0.9395, -0.8885, -0.8273, -0.7576, -0.6831, -0.6072, -0.5316, -0.4586, -0.3897, -0.3257, -0.2673, -0.2148, -0.1684, -0.1278, -0.0932, -0.0643, -0.0409, -0.0229, -0.0101, -0.0025, 0.0000}},
  };
  const std::vector<double> mu = cos_deg(5.0);
  for (const Table& t : tables) {
    const MieSphere r = mie_sphere(t.m, t.x, mu);
    for (std::size_t i = 0; i < mu.size(); ++i) {
      INFO("x = " << t.x << ", m = " << t.m << ", theta = " << 5 * i << " deg");
      const double a = f11(r.s1[i], r.s2[i]);
      CHECK(a == Approx(t.f11[i]).epsilon(1e-5));
      CHECK(f12(r.s1[i], r.s2[i]) / a == Approx(t.pol[i]).margin(1.0001e-4));
    }
  }
}

TEST_CASE("Small spheres: the Rayleigh limit of Qsca, Qabs and the polarization", "[mie][limit]") {
  const cplx m(1.5, 0.01);
  const cplx alpha = (m * m - 1.0) / (m * m + 2.0);
  for (double x : {1e-3, 1e-2}) {
    const std::vector<double> mu = cos_deg(15.0);
    const MieSphere r = mie_sphere(m, x, mu);
    // B&H ch. 5: Qsca = (8/3)x⁴|α|², Qabs = 4x Im α, both with relative corrections O(x²).
    CHECK(r.qsca == Approx(8.0 / 3.0 * std::pow(x, 4) * std::norm(alpha)).epsilon(3 * x * x));
    CHECK(r.qext - r.qsca == Approx(4.0 * x * alpha.imag()).epsilon(3 * x * x));
    CHECK(std::abs(r.g) < x * x);
    for (std::size_t i = 0; i < mu.size(); ++i) {
      const double c = mu[i], s2 = 1.0 - c * c;
      const double ratio = f12(r.s1[i], r.s2[i]) / f11(r.s1[i], r.s2[i]);
      CHECK(ratio == Approx(-s2 / (1.0 + c * c)).margin(3 * x * x));
      // Header convention: negative (perpendicular) at 90°, F12 = −¾ sin²Θ when F11 = ¾(1+cos²Θ).
      if (std::abs(c) < 1e-9) CHECK(ratio < -0.999);
    }
  }
}

TEST_CASE("Every sphere obeys F11^2 = F12^2 + F33^2 + F34^2, and Qext >= Qsca", "[mie][identity]") {
  const std::vector<double> mu = cos_deg(7.5);
  for (cplx m : {cplx(1.33, 0.0), cplx(1.53, 0.008), cplx(1.75, 0.44), cplx(1.5, 1.0)}) {
    for (double x : {0.3, 2.0, 17.0, 140.0}) {
      INFO("x = " << x << ", m = " << m);
      const MieSphere r = mie_sphere(m, x, mu);
      CHECK(r.qext >= r.qsca * (1.0 - 1e-12));
      if (m.imag() == 0.0) CHECK(r.qext == Approx(r.qsca).epsilon(1e-12));
      for (std::size_t i = 0; i < mu.size(); ++i) {
        const double a = f11(r.s1[i], r.s2[i]), b = f12(r.s1[i], r.s2[i]);
        const cplx c = r.s2[i] * std::conj(r.s1[i]);
        CHECK(a * a == Approx(b * b + std::norm(c)).epsilon(1e-10));
        CHECK(std::abs(b) <= a * (1 + 1e-12));
      }
      // S1 = S2 in the forward and backward directions (up to the sign convention at 180°).
      CHECK(std::abs(r.s1[0] - r.s2[0]) <= 1e-9 * std::abs(r.s1[0]));
      CHECK(std::abs(r.s1.back() + r.s2.back()) <= 1e-9 * std::abs(r.s1.back()) + 1e-300);
      // The optical theorem: Qext = (4/x²) Re S(0°).
      CHECK(r.qext == Approx(4.0 / (x * x) * r.s1[0].real()).epsilon(1e-10));
    }
  }
}

TEST_CASE("Wiscombe's term count", "[mie]") {
  // N = x + 4x^⅓ + 1 (x ≤ 8), x + 4.05x^⅓ + 2 (8 < x < 4200): hand-computed values.
  CHECK(mie_term_count(1.0) == 6);       // 1 + 4 + 1
  CHECK(mie_term_count(8.0) == 17);      // 8 + 8 + 1
  CHECK(mie_term_count(1000.0) == 1042);  // 1000 + 40.5 + 2
  CHECK(mie_term_count(1e-4) >= 2);
}

TEST_CASE("Mie rejects what it cannot compute", "[mie][errors]") {
  CHECK_THROWS_AS(mie_sphere({1.5, -0.1}, 1.0), std::invalid_argument);  // gain medium
  CHECK_THROWS_AS(mie_sphere({0.0, 0.0}, 1.0), std::invalid_argument);
  CHECK_THROWS_AS(mie_sphere({1.5, 0.0}, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(mie_sphere({1.5, 0.0}, std::nan("")), std::invalid_argument);
  CHECK_THROWS_AS(mie_sphere({1.5, 0.0}, 3e4), std::invalid_argument);
  const double bad_mu[] = {1.5};
  CHECK_THROWS_AS(mie_sphere({1.5, 0.0}, 1.0, bad_mu), std::invalid_argument);
}
