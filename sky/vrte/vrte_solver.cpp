// Doubling–adding per azimuthal Fourier term. The notation follows Hovenier et al. 2004 ch. 6 but
// the operators act on radiance amplitudes, not on μ-weighted reflection functions:
//
//   For Fourier term m a radiance field is L(μ, φ) = (I_m, Q_m) cos mφ + (U_m, V_m) sin mφ
//   (mirror symmetry about the sun's vertical). A layer maps an incident amplitude at μ' to
//   outgoing amplitudes at μ by r(μ, μ') (reflection) and t(μ, μ') (diffuse transmission);
//   composition is (a∘b)(μ, μ') = ∫₀¹ a(μ, μ'') b(μ'', μ') dμ'', done with Gauss weights. The
//   kernel of the RTE for term m, K(μ, μ') = (1/4π) ∫₀^{2π} ωZ(μ, μ', Δφ)·(cos/sin mΔφ) dΔφ, is
//   computed from the phase matrix built geometrically (rotation into and out of the scattering
//   plane, Hovenier et al. ch. 2) and summed over an azimuth grid that integrates it exactly
//   (Z is a trigonometric polynomial of degree lmax in Δφ).
//
//   Thin layer (single scattering, exact exponentials): with a = t/μ, b = t/μ',
//     r = K_up←down · μ'/(μ+μ')·(1 − e^{−a−b}),  t = K_down←down · μ'(e^{−a} − e^{−b})/(μ − μ');
//   the doubling starts from 2·D(thin(t/2)) − thin(t), D the doubling: correct to second order in t.
//   Adding a over b (light from above; E = e^{−τ/μ} the direct beam, * = lit from below):
//     D = t_a + r*_a∘r_b E_a(μ') + r*_a∘r_b∘D,    U = r_b E_a(μ') + r_b∘D,
//     R = r_a + E_a(μ) U + t*_a∘U,               T = E_b(μ) D + t_b∘D + t_b E_a(μ'),
//   and the mirror image for light from below (Hovenier et al. ch. 6, rewritten for radiance operators).
//   The Lambertian ground is one more layer, r_g = 2Aμ' on I (m = 0 only), t_g = 0.
//
// Zero-weight points (the asked-for μ) take part as rows and columns but never in the
// sums, so they cost O(n²N) per product, not O(n³). Only the I column is kept for them: the sun
// is unpolarized.
#include "sky/vrte/vrte_solver.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace skypol::sky::vrte {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// The geometry of the node set: n nodes (the first ng Gauss), ns Stokes elements, rows for every
// (node, element), columns for every Gauss (node, element) and the I of every extra node.
struct Layout {
  int ng = 0, n = 0, ns = 3;
  int rows() const { return ns * n; }
  int gauss() const { return ns * ng; }
  int cols() const { return ns * ng + (n - ng); }
  int row(int node, int s) const { return node * ns + s; }
  // −1 when the column is not kept (a polarized input at an extra node)
  int col(int node, int s) const {
    if (node < ng) return node * ns + s;
    return s == 0 ? ns * ng + (node - ng) : -1;
  }
};

struct Ops {
  MatrixXd r, t, rs, ts;  // reflection/transmission from above; rs, ts from below
  double tau = 0;
};

// A view direction d for node cosine mu, azimuth phi; up = +1: looking up (light going down).
struct Frame {
  Eigen::Vector3d d, e0, e90;
};

Frame frame(double mu, double c, double n, int up) {
  const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
  Frame f;
  f.d = {s * c, s * n, up * mu};
  f.e90 = {-n, c, 0.0};  // ẑ × d / |ẑ × d|, the limit along phi at the zenith
  f.e0 = f.e90.cross(f.d);
  return f;
}

Frame frame(double mu, double phi, int up) { return frame(mu, std::cos(phi), std::sin(phi), up); }

// Z = L(χ_out)·ωF(Θ)·L(χ_in), ns×ns, row-major into z.
template <class OmegaF>
void phase_matrix(const Frame& in, const Frame& out, const OmegaF& omega_f, int ns, double* z) {
  Eigen::Vector3d nrm = in.d.cross(out.d);
  const double nn = nrm.squaredNorm();
  if (nn < 1e-24) {
    nrm = in.e90;  // forward or backward: any normal gives the same Z
  } else {
    nrm /= std::sqrt(nn);
  }
  const double x = std::clamp(in.d.dot(out.d), -1.0, 1.0);
  const Elements f = omega_f(x);
  const Eigen::Vector3d a_in = nrm.cross(in.d);
  const double ci = a_in.dot(in.e0), si = a_in.dot(in.e90);
  const double c2i = ci * ci - si * si, s2i = 2.0 * si * ci;
  const Eigen::Vector3d a_out = nrm.cross(out.d);
  const double co = out.e0.dot(a_out), so = out.e0.dot(nrm);
  const double c2o = co * co - so * so, s2o = 2.0 * so * co;
  // A = F·L(χ_in)
  const double A[4][4] = {{f.f11, f.f12 * c2i, f.f12 * s2i, 0.0},
                          {f.f12, f.f22 * c2i, f.f22 * s2i, 0.0},
                          {0.0, -f.f33 * s2i, f.f33 * c2i, f.f34},
                          {0.0, f.f34 * s2i, -f.f34 * c2i, f.f44}};
  for (int j = 0; j < ns; ++j) {
    z[0 * ns + j] = A[0][j];
    z[1 * ns + j] = c2o * A[1][j] + s2o * A[2][j];
    z[2 * ns + j] = -s2o * A[1][j] + c2o * A[2][j];
    if (ns == 4) z[3 * ns + j] = A[3][j];
  }
}

// Kernels K[m] for one combination of directions (out_up, in_up) on the layout's rows and kept
// columns, all m at once.
void kernels(const Layout& lay, const std::vector<double>& mu, const ScaledLayer& layer, int terms, int out_up,
             int in_up, std::vector<MatrixXd>& K, int threads) {
  const int nphi = 2 * layer.lmax + 2;
  const int ns = lay.ns;
  std::vector<double> cs(static_cast<std::size_t>(terms * nphi)), sn(cs.size());
  for (int m = 0; m < terms; ++m)
    for (int k = 0; k < nphi; ++k) {
      const double a = 2.0 * std::numbers::pi * k / nphi;
      cs[static_cast<std::size_t>(m * nphi + k)] = std::cos(m * a);
      sn[static_cast<std::size_t>(m * nphi + k)] = std::sin(m * a);
    }
  K.assign(static_cast<std::size_t>(terms), MatrixXd::Zero(lay.rows(), lay.cols()));
  const double norm = 1.0 / (2.0 * nphi);
  std::atomic<int> next{0};
  auto work = [&] {
    std::vector<double> z(static_cast<std::size_t>(nphi * ns * ns));
    for (int i = next++; i < lay.n; i = next++) {
      for (int j = 0; j < lay.n; ++j) {
        const Frame in = frame(mu[static_cast<std::size_t>(j)], 0.0, in_up);
        for (int k = 0; k < nphi; ++k) {
          const Frame out = frame(mu[static_cast<std::size_t>(i)], 2.0 * std::numbers::pi * k / nphi, out_up);
          phase_matrix(
              in, out, [&](double x) { return layer.omega_f(x); }, ns, &z[static_cast<std::size_t>(k * ns * ns)]);
        }
        for (int m = 0; m < terms; ++m) {
          MatrixXd& km = K[static_cast<std::size_t>(m)];
          const double* c = &cs[static_cast<std::size_t>(m * nphi)];
          const double* s = &sn[static_cast<std::size_t>(m * nphi)];
          for (int a = 0; a < ns; ++a) {
            for (int b = 0; b < ns; ++b) {
              const int col = lay.col(j, b);
              if (col < 0) continue;
              const bool row_iq = a < 2, col_iq = b < 2;
              if (m == 0 && (!row_iq || !col_iq)) continue;  // U, V carry sin 0φ = 0
              double acc = 0.0;
              if (row_iq == col_iq) {
                for (int k = 0; k < nphi; ++k) acc += z[static_cast<std::size_t>(k * ns * ns + a * ns + b)] * c[k];
              } else {
                for (int k = 0; k < nphi; ++k) acc += z[static_cast<std::size_t>(k * ns * ns + a * ns + b)] * s[k];
                if (row_iq) acc = -acc;
              }
              km(lay.row(i, a), col) = acc * norm;
            }
          }
        }
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
}

// μ'/(μ+μ')·(1 − e^{−t/μ − t/μ'}): a thin layer's single-scattering reflection factor.
double reflect_factor(double mu, double mu0, double t) {
  if (mu + mu0 <= 0.0) return 0.0;
  const double x = (mu == 0.0 || mu0 == 0.0) ? std::numeric_limits<double>::infinity() : t * (mu + mu0) / (mu * mu0);
  return mu0 / (mu + mu0) * -std::expm1(-x);
}

// (1 − e^{−x})/x, 1 at 0.
double phi1(double x) { return x < 1e-8 ? 1.0 - 0.5 * x : -std::expm1(-x) / x; }

// μ'(e^{−t/μ} − e^{−t/μ'})/(μ − μ'): the same for transmission, stable at μ = μ'.
double transmit_factor(double mu, double mu0, double t) {
  if (mu0 == 0.0) return 0.0;
  if (mu == 0.0) return std::exp(-t / mu0);
  const double a = t / mu, b = t / mu0;
  const double lo = std::min(a, b), hi = std::max(a, b);
  if (std::isinf(hi)) return 0.0;
  return a * std::exp(-lo) * phi1(hi - lo);
}

struct Solver {
  Layout lay;
  std::vector<double> mu;  // all nodes, Gauss first
  VectorXd wrow;           // Gauss weights per Gauss row (length lay.gauss())
  std::vector<int> row_node, col_node;

  // a∘b
  MatrixXd comp(const MatrixXd& a, const MatrixXd& b) const {
    const int g = lay.gauss();
    return a.leftCols(g) * (wrow.asDiagonal() * b.topRows(g));
  }
  // exp(−τ/μ) of each row's (e_rows) or column's (e_cols) node; 0 for a node at μ = 0.
  VectorXd attenuation(const std::vector<int>& node, double tau) const {
    VectorXd e(static_cast<Eigen::Index>(node.size()));
    for (std::size_t r = 0; r < node.size(); ++r) {
      const double m = mu[static_cast<std::size_t>(node[r])];
      e(static_cast<Eigen::Index>(r)) = m > 0.0 ? std::exp(-tau / m) : 0.0;
    }
    return e;
  }
  VectorXd e_rows(double tau) const { return attenuation(row_node, tau); }
  VectorXd e_cols(double tau) const { return attenuation(col_node, tau); }
  // X = C + P∘X, solved on the Gauss rows first.
  MatrixXd solve_series(const MatrixXd& p, const MatrixXd& c) const {
    const int g = lay.gauss(), rows = lay.rows();
    MatrixXd a = MatrixXd::Identity(g, g) - p.topLeftCorner(g, g) * wrow.asDiagonal();
    MatrixXd x(rows, lay.cols());
    x.topRows(g) = a.partialPivLu().solve(c.topRows(g));
    if (rows > g)
      x.bottomRows(rows - g) =
          c.bottomRows(rows - g) + p.bottomLeftCorner(rows - g, g) * (wrow.asDiagonal() * x.topRows(g));
    return x;
  }

  // The layer of depth t in single scattering (exact exponentials): r, t from above, rs, ts from
  // below, from the four kernels of this Fourier term.
  Ops single_scattering_layer(const MatrixXd& kud, const MatrixXd& kdd, const MatrixXd& kdu, const MatrixXd& kuu,
                              double t) const {
    const int rows = lay.rows(), cols = lay.cols();
    Ops o;
    o.tau = t;
    o.r.resize(rows, cols);
    o.t.resize(rows, cols);
    o.rs.resize(rows, cols);
    o.ts.resize(rows, cols);
    for (int r = 0; r < rows; ++r) {
      const double mr = mu[static_cast<std::size_t>(row_node[static_cast<std::size_t>(r)])];
      for (int c = 0; c < cols; ++c) {
        const double mc = mu[static_cast<std::size_t>(col_node[static_cast<std::size_t>(c)])];
        const double fr = reflect_factor(mr, mc, t), ft = transmit_factor(mr, mc, t);
        o.r(r, c) = kud(r, c) * fr;
        o.t(r, c) = kdd(r, c) * ft;
        o.rs(r, c) = kdu(r, c) * fr;
        o.ts(r, c) = kuu(r, c) * ft;
      }
    }
    return o;
  }

  // The start of the doubling, correct to second order in its depth t: single scattering in t
  // (`one`) misses the second order, c·t² + O(t³); the same depth made of two single-scattering
  // halves (`two`) misses 2·c·(t/2)² + O(t³), so 2·two − one leaves O(t³) (Richardson). What a
  // single-scattering start costs, a systematic low bias ∝ τ·t in I and a flux loss of the same
  // order, becomes ∝ τ·t².
  static Ops second_order_start(const Ops& one, const Ops& two) {
    Ops o;
    o.tau = one.tau;
    o.r = 2.0 * two.r - one.r;
    o.t = 2.0 * two.t - one.t;
    o.rs = 2.0 * two.rs - one.rs;
    o.ts = 2.0 * two.ts - one.ts;
    return o;
  }

  // D·X·D with D = diag(1, 1, −1, −1) per node: a homogeneous layer lit from below is its mirror
  // image in the horizontal plane, which keeps I and Q and turns U and V (Hovenier et al. 2004,
  // ch. 6: R* = ΔRΔ, T* = ΔTΔ for a homogeneous, mirror-symmetric layer).
  MatrixXd mirror(const MatrixXd& x) const {
    VectorXd dr(lay.rows()), dc(lay.cols());
    for (int r = 0; r < lay.rows(); ++r) dr(r) = (r % lay.ns) < 2 ? 1.0 : -1.0;
    for (int c = 0; c < lay.cols(); ++c) dc(c) = (c < lay.gauss() && (c % lay.ns) >= 2) ? -1.0 : 1.0;
    return dr.asDiagonal() * x * dc.asDiagonal();
  }

  // Doubling a homogeneous layer: only the light-from-above half is computed; the other half is
  // its mirror image (halves the cost; tests/sky/vrte_solver_test checks it against add()).
  Ops double_layer(const Ops& a) const {
    const VectorXd er = e_rows(a.tau), ec = e_cols(a.tau);
    Ops o;
    o.tau = 2.0 * a.tau;
    const MatrixXd p = comp(a.rs, a.r);
    const MatrixXd d = solve_series(p, a.t + p * ec.asDiagonal());
    const MatrixXd u = a.r * ec.asDiagonal() + comp(a.r, d);
    o.r = a.r + er.asDiagonal() * u + comp(a.ts, u);
    o.t = er.asDiagonal() * d + comp(a.t, d) + a.t * ec.asDiagonal();
    o.rs = mirror(o.r);
    o.ts = mirror(o.t);
    return o;
  }

  Ops add(const Ops& a, const Ops& b) const {
    const VectorXd era = e_rows(a.tau), eca = e_cols(a.tau), erb = e_rows(b.tau), ecb = e_cols(b.tau);
    Ops o;
    o.tau = a.tau + b.tau;
    {
      const MatrixXd p = comp(a.rs, b.r);
      const MatrixXd d = solve_series(p, a.t + p * eca.asDiagonal());
      const MatrixXd u = b.r * eca.asDiagonal() + comp(b.r, d);
      o.r = a.r + era.asDiagonal() * u + comp(a.ts, u);
      o.t = erb.asDiagonal() * d + comp(b.t, d) + b.t * eca.asDiagonal();
    }
    {
      const MatrixXd p = comp(b.r, a.rs);
      const MatrixXd u = solve_series(p, b.ts + p * ecb.asDiagonal());
      const MatrixXd d = a.rs * ecb.asDiagonal() + comp(a.rs, u);
      o.rs = b.rs + erb.asDiagonal() * d + comp(b.t, d);
      o.ts = era.asDiagonal() * u + comp(a.ts, u) + a.ts * ecb.asDiagonal();
    }
    return o;
  }
};

}  // namespace

template <class OmegaF>
StokesIQU single_scattering(const OmegaF& omega_f, double tau, double mu, double mu0, double cos_dphi, double sin_dphi,
                            bool up) {
  if (!(mu0 > 0.0) || !(tau > 0.0)) return {};
  double z[9];
  phase_matrix(frame(mu0, 1.0, 0.0, +1), frame(mu, cos_dphi, sin_dphi, up ? -1 : +1), omega_f, 3, z);
  const double g = single_scattering_factor(tau, mu, mu0, up);
  return {z[0] * g, z[3] * g, z[6] * g};
}

double single_scattering_factor(double tau, double mu, double mu0, bool up) {
  return (up ? reflect_factor(mu, mu0, tau) : transmit_factor(mu, mu0, tau)) / (4.0 * std::numbers::pi);
}

StokesIQU single_scattering(const ScaledLayer& layer, double mu, double mu0, double dphi, bool up) {
  return single_scattering([&](double x) { return layer.omega_f(x); }, layer.tau, mu, mu0, std::cos(dphi),
                           std::sin(dphi), up);
}

StokesIQU single_scattering(const ExactLayer& layer, double mu, double mu0, double dphi, bool up) {
  return single_scattering(layer, mu, mu0, std::cos(dphi), std::sin(dphi), up);
}

StokesIQU single_scattering(const ExactLayer& layer, double mu, double mu0, double cos_dphi, double sin_dphi, bool up) {
  return single_scattering([&](double x) { return layer.omega_f(x); }, layer.tau, mu, mu0, cos_dphi, sin_dphi, up);
}

FourierSolution solve(const ScaledLayer& layer, double albedo, std::span<const double> mu_out,
                      const SolverOptions& opt) {
  if (opt.streams < 2) throw std::invalid_argument("vrte: streams must be >= 2, got " + std::to_string(opt.streams));
  if (!(albedo >= 0.0 && albedo <= 1.0)) throw std::invalid_argument("vrte: albedo must be in [0, 1]");
  if (!(opt.initial_tau > 0.0)) throw std::invalid_argument("vrte: initial_tau must be > 0");
  for (double m : mu_out)
    if (!(m >= 0.0 && m <= 1.0)) throw std::invalid_argument("vrte: mu must be in [0, 1], got " + std::to_string(m));

  Solver s;
  std::vector<double> gx, gw;
  gauss_legendre01(opt.streams, gx, gw);
  s.lay.ng = opt.streams;
  s.lay.n = opt.streams + static_cast<int>(mu_out.size());
  s.lay.ns = (layer.has_aerosol) ? 4 : 3;  // molecules alone never make V from unpolarized light
  s.mu = gx;
  s.mu.insert(s.mu.end(), mu_out.begin(), mu_out.end());
  s.wrow.resize(s.lay.gauss());
  for (int i = 0; i < s.lay.gauss(); ++i) s.wrow(i) = gw[static_cast<std::size_t>(i / s.lay.ns)];
  for (int i = 0; i < s.lay.n; ++i)
    for (int k = 0; k < s.lay.ns; ++k) {
      s.row_node.push_back(i);
      if (s.lay.col(i, k) >= 0) s.col_node.push_back(i);
    }

  int terms = layer.lmax + 1;
  if (opt.max_fourier >= 0) terms = std::min(terms, opt.max_fourier + 1);
  const int threads =
      opt.threads > 0 ? opt.threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));

  FourierSolution out;
  out.mu.assign(mu_out.begin(), mu_out.end());
  out.terms = terms;
  out.scaled_tau = layer.tau;
  const std::size_t nx = mu_out.size();
  out.down.assign(static_cast<std::size_t>(terms) * nx * nx * 3, 0.0);
  out.up.assign(out.down.size(), 0.0);
  out.ground.assign(nx, 0.0);
  out.ss_down.assign(out.down.size(), 0.0);
  out.ss_up.assign(out.down.size(), 0.0);
  out.gauss_mu = gx;
  out.gauss_w = gw;
  out.stokes = s.lay.ns;
  if (opt.keep_gauss_matrices) {
    out.gauss_reflection.assign(static_cast<std::size_t>(terms), MatrixXd::Zero(s.lay.gauss(), s.lay.gauss()));
    out.gauss_transmission = out.gauss_reflection;
  }

  // Kernels for the four direction pairs: down←down, up←down, up←up, down←up.
  std::vector<MatrixXd> kdd, kud, kuu, kdu;
  if (layer.tau > 0.0) {
    kernels(s.lay, s.mu, layer, terms, +1, +1, kdd, threads);
    kernels(s.lay, s.mu, layer, terms, -1, +1, kud, threads);
    kernels(s.lay, s.mu, layer, terms, -1, -1, kuu, threads);
    kernels(s.lay, s.mu, layer, terms, +1, -1, kdu, threads);
  }

  int doublings = 0;
  double t0 = layer.tau;
  while (t0 > opt.initial_tau) {
    t0 *= 0.5;
    ++doublings;
  }

  std::atomic<int> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    try {
      for (int m = next++; m < terms; m = next++) {
        const int rows = s.lay.rows(), cols = s.lay.cols();
        Ops atm;
        atm.tau = layer.tau;
        atm.r = atm.t = atm.rs = atm.ts = MatrixXd::Zero(rows, cols);
        if (layer.tau > 0.0) {
          const auto mi = static_cast<std::size_t>(m);
          atm = s.single_scattering_layer(kud[mi], kdd[mi], kdu[mi], kuu[mi], t0);
          if (opt.second_order_start) {
            const Ops half = s.single_scattering_layer(kud[mi], kdd[mi], kdu[mi], kuu[mi], 0.5 * t0);
            atm = s.second_order_start(atm, opt.symmetric_doubling ? s.double_layer(half) : s.add(half, half));
          }
          for (int k = 0; k < doublings; ++k) atm = opt.symmetric_doubling ? s.double_layer(atm) : s.add(atm, atm);
        }
        MatrixXd down = atm.t, up = atm.r;
        MatrixXd ground_up;
        if (m == 0 && albedo > 0.0) {
          // The ground as a layer under the atmosphere: r_g(μ, μ') = 2Aμ' on I.
          MatrixXd rg = MatrixXd::Zero(rows, cols);
          for (int r = 0; r < rows; r += s.lay.ns)
            for (int c = 0; c < cols; ++c) {
              const int node = s.col_node[static_cast<std::size_t>(c)];
              if (s.lay.col(node, 0) == c) rg(r, c) = 2.0 * albedo * s.mu[static_cast<std::size_t>(node)];
            }
          const VectorXd era = s.e_rows(atm.tau), eca = s.e_cols(atm.tau);
          const MatrixXd p = s.comp(atm.rs, rg);
          down = s.solve_series(p, atm.t + p * eca.asDiagonal());
          ground_up = rg * eca.asDiagonal() + s.comp(rg, down);
          up = atm.r + era.asDiagonal() * ground_up + s.comp(atm.ts, ground_up);
        }
        const double sun = (m == 0 ? 1.0 : 2.0) / (2.0 * std::numbers::pi);
        for (std::size_t i = 0; i < nx; ++i)
          for (std::size_t j = 0; j < nx; ++j) {
            const int c = s.lay.col(s.lay.ng + static_cast<int>(j), 0);
            for (int k = 0; k < 3; ++k) {
              const int r = s.lay.row(s.lay.ng + static_cast<int>(i), k);
              const std::size_t o = ((static_cast<std::size_t>(m) * nx + i) * nx + j) * 3 + static_cast<std::size_t>(k);
              out.down[o] = down(r, c) * sun;
              out.up[o] = up(r, c) * sun;
              if (layer.tau > 0.0) {
                const double mv = s.mu[static_cast<std::size_t>(s.lay.ng) + i];
                const double ms = s.mu[static_cast<std::size_t>(s.lay.ng) + j];
                const auto mi = static_cast<std::size_t>(m);
                out.ss_down[o] = kdd[mi](r, c) * transmit_factor(mv, ms, layer.tau) * sun;
                out.ss_up[o] = kud[mi](r, c) * reflect_factor(mv, ms, layer.tau) * sun;
              }
            }
          }
        if (m == 0) {
          for (std::size_t j = 0; j < nx; ++j) {
            const int c = s.lay.col(s.lay.ng + static_cast<int>(j), 0);
            out.ground[j] = ground_up.size() > 0 ? ground_up(0, c) * sun : 0.0;
          }
        }
        if (opt.keep_gauss_matrices) {
          const int g = s.lay.gauss();
          out.gauss_reflection[static_cast<std::size_t>(m)] = up.topLeftCorner(g, g);
          out.gauss_transmission[static_cast<std::size_t>(m)] = down.topLeftCorner(g, g);
        }
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex);
      error = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::min(threads, terms); ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  return out;
}

}  // namespace skypol::sky::vrte
