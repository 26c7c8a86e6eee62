// auto's combination of the methods' answers (auto.h).
#include "skypole/auto.h"

#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sky/units.h"
#include "skypole/method_registry.h"
#include "skypole/sky_images.h"
#include "skypole/uncertainty.h"

namespace skypol::skypole {
namespace {

double angle_deg(const PoleEstimate& a, const PoleEstimate& b) {
  return deg_from_rad(tangent_offset(a, b).norm());
}

}  // namespace

bool used_by_auto(std::string_view method, bool site_usable) {
  const Method* m = find_method(method);
  return m && m->traits.used_by_auto && (!m->traits.needs_site || site_usable);
}

PoleEstimate combine_estimates(const stack::Stack& stack, const InputOptions& input,
                               const std::vector<PoleEstimate>& estimates) {
  std::vector<PoleEstimate> all;
  double total_seconds = 0;
  const bool site = site_usable(stack, input);
  for (const PoleEstimate& e : estimates)
    if (used_by_auto(e.method, site)) {
      all.push_back(e);
      total_seconds += e.seconds;
    }
  std::vector<const PoleEstimate*> valid;
  std::string declined;
  for (const PoleEstimate& e : all) {
    if (e.valid)
      valid.push_back(&e);
    else
      declined += (declined.empty() ? "" : "; ") + e.method + ": " + e.why_invalid;
  }
  PoleEstimate out;
  out.method = "auto";
  out.seconds = total_seconds;
  if (valid.empty()) {
    out.why_invalid = "no method could answer (" + declined + ")";
    return out;
  }
  // Two answers agree unless they are apart by more than the 99.9 % level of their combined
  // uncertainty (√χ²₂(0.999) = 3.72 σ against the 95 % cone's 2.45 σ: the root-sum-square of their
  // 95 % cones × 1.52); at the 95 % level one answer in ten of two calibrated methods would be
  // called a disagreement by chance. The centre is the answer with the most agreeing others
  // (ties: the narrowest cone); the rule is auto_choice (uncertainty.h).
  std::vector<AutoCandidate> candidates;
  for (const PoleEstimate* b : valid) {
    const Method* m = find_method(b->method);
    candidates.push_back({b->cone95_deg, b->sigma_deg, m && m->traits.auto_answers_alone});
  }
  const AutoChoice choice =
      auto_choice(candidates, [&](std::size_t a, std::size_t b) { return angle_deg(*valid[a], *valid[b]); });
  const PoleEstimate* centre = valid[choice.centre];
  std::vector<const PoleEstimate*> members, dissent;
  for (const std::size_t b : choice.members) members.push_back(valid[b]);
  for (const std::size_t b : choice.dissent) dissent.push_back(valid[b]);
  // A dissenting method that is as sure as the group and outvotes it cannot be told apart: the
  // data do not decide, so auto declines rather than pick.
  if (!choice.decided) {
    std::string who;
    for (const PoleEstimate* b : valid) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "%s %.1f° from %s (cones %.1f°, %.1f°)", b->method.c_str(),
                    angle_deg(*centre, *b), centre->method.c_str(), b->cone95_deg, centre->cone95_deg);
      if (b != centre) who += (who.empty() ? "" : "; ") + std::string(buf);
    }
    out.why_invalid = "the methods disagree beyond their 95 % cones: " + who;
    return out;
  }
  // The answer. That of a method whose answer stands alone when it agrees (auto_answers_alone,
  // method_registry.h: sun_vector_ephemeris), as it stands (its pole and its σ). Without it (a
  // capture without its site, or the ephemeris declined or outvoted), the inverse-variance mean of
  // the agreeing answers, stated with the σ of the sharpest of them: the methods read the same
  // frames, so their errors are correlated, and the mean's own σ would claim more than the data
  // hold (docs/calibration-history.md, "auto's rule", compares it with the alternatives).
  const PoleEstimate* sharpest = valid[choice.sharpest];
  const PoleEstimate* chosen = valid[choice.chosen];
  out = *chosen;
  std::string how = "the answer of " + chosen->method;
  if (choice.mean) {
    std::vector<Eigen::Vector2d> offsets;
    std::vector<double> sigmas;
    for (const PoleEstimate* b : members) {
      offsets.push_back(tangent_offset(*sharpest, *b));
      sigmas.push_back(b->sigma_deg);
    }
    const SkyImages frame = sky_geometry(stack, input);
    const Eigen::Vector3d end_level = tangent_moved(*sharpest, inverse_variance_mean(offsets, sigmas));
    const Eigen::Vector3d ncp_level = sharpest->is_north ? end_level : Eigen::Vector3d(-end_level);
    // The sharpest's answer moved to the mean: its σ stays, its position is the mean's (out.note is
    // written below from `how`; place_pole fills it only when the bearing is undefined).
    place_pole(out, frame, frame.level_from_camera.transpose() * ncp_level, input);
    how = "the inverse-variance mean of the agreeing answers, with the σ of the sharpest, " + sharpest->method;
    if (!out.heading_deg) how += " (" + out.note + ")";  // the mean's pole is near the zenith
  }
  out.method = "auto";
  out.seconds = total_seconds;
  std::string used, others;
  for (const PoleEstimate* b : members)
    if (b != chosen) used += ", " + b->method;
  for (const PoleEstimate* b : dissent) others += (others.empty() ? "" : ", ") + b->method;
  const std::string note = how + (used.empty() ? "" : " (agreeing: " + used.substr(2) + ")") +
                           (others.empty() ? "" : "; outvoted: " + others) +
                           (declined.empty() ? "" : "; declined: " + declined);
  out.note = chosen->note.empty() ? note : note + "; " + chosen->note;
  apply_uncertainty_bound(out, input.max_uncertainty_deg);
  return out;
}

}  // namespace skypol::skypole
