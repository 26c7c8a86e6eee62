// E-vectors once per frame (e_vectors.h).
#include "skypole/e_vectors.h"

#include <cmath>

namespace skypol::skypole {

std::optional<Eigen::Vector3d> e_vector(const Eigen::Vector3d& d, double a, camera::Transport t) {
  if (t == camera::Transport::meridional) {
    const Eigen::Vector3d e0 = camera::meridional_e0(d);
    return Eigen::Vector3d(std::cos(a) * e0 + std::sin(a) * d.cross(e0));
  }
  if (std::abs(d.z()) < 1e-3) return std::nullopt;  // E along the axis: the sensor angle says nothing
  Eigen::Vector3d e(std::cos(a), std::sin(a), -(std::cos(a) * d.x() + std::sin(a) * d.y()) / d.z());
  return Eigen::Vector3d(e.normalized());
}

EVectorTurn e_vector_turn(const Eigen::Vector3d& d, const Eigen::Vector3d& e, camera::Transport t) {
  EVectorTurn out;
  if (t == camera::Transport::meridional) {
    // e = cos a·e0 + sin a·d×e0, so ∂e/∂a = −sin a·e0 + cos a·d×e0 = d × e.
    const Eigen::Vector3d e0 = camera::meridional_e0(d);
    out.cos_a = e.dot(e0);
    out.sin_a = e.dot(d.cross(e0));
    out.turn = d.cross(e);
    return out;
  }
  // e = u/|u| with u = (cos a, sin a, −(cos a·d_x + sin a·d_y)/d_z): the sensor angle is e's in the
  // sensor plane, and ∂e/∂a is ∂u/∂a without its part along e, over |u|.
  const double h = std::hypot(e.x(), e.y());
  out.cos_a = e.x() / h;
  out.sin_a = e.y() / h;
  const double ca = out.cos_a, sa = out.sin_a;
  const Eigen::Vector3d u(ca, sa, -(ca * d.x() + sa * d.y()) / d.z());
  const Eigen::Vector3d du(-sa, ca, -(-sa * d.x() + ca * d.y()) / d.z());
  out.turn = (du - e * e.dot(du)) / u.norm();
  return out;
}

FrameEVectors frame_e_vectors(const SkyImages& sky, const std::vector<float>& dolp, const std::vector<float>& aolp,
                              camera::Transport transport, double min_dolp, PolarizerFit polarizer) {
  FrameEVectors out;
  out.min_dolp = min_dolp;
  out.polarizer = polarizer;
  const bool turns = polarizer == PolarizerFit::modelled;
  // Counted first and reserved exactly: a day's frames hold some thirty bytes per sky pixel each,
  // and grown by push_back the vectors would hold up to twice that.
  const auto kept = [&](std::size_t i) { return sky.valid[i] && static_cast<double>(dolp[i]) >= min_dolp; };
  std::size_t n = 0;
  for (std::size_t i = 0; i < sky.pixels(); ++i) n += kept(i) ? 1 : 0;
  out.pixel.reserve(n);
  out.e.reserve(n);
  out.flags.reserve(n);
  if (turns) out.turns.reserve(n);
  for (std::size_t i = 0; i < sky.pixels(); ++i) {
    if (!kept(i)) continue;
    const auto e = e_vector(to_double(sky.ray_camera[i]), aolp[i], transport);
    out.pixel.push_back(static_cast<std::uint32_t>(i));
    out.e.push_back(e.value_or(Eigen::Vector3d::Zero()));
    out.flags.push_back(static_cast<std::uint8_t>((e ? FrameEVectors::kDefined : 0) |
                                                  (std::isfinite(aolp[i]) ? FrameEVectors::kFiniteAolp : 0)));
    if (!turns) continue;
    FrameEVectors::Turn& t = out.turns.emplace_back();
    if (!e) continue;
    const EVectorTurn d = e_vector_turn(to_double(sky.ray_camera[i]), *e, transport);
    t = {d.turn.cast<float>(), static_cast<float>(d.cos_a * d.cos_a - d.sin_a * d.sin_a),
         static_cast<float>(2 * d.cos_a * d.sin_a)};
  }
  return out;
}

}  // namespace skypol::skypole
