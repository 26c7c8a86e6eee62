// LensSpec → Lens: the model's entry (lens_registry.h) is looked up, the optional fields it does
// not read are refused, and its factory checks the rest and builds it; binning comes last.
#include "camera/lens_factory.h"

#include <algorithm>
#include <stdexcept>

#include "camera/intrinsics.h"
#include "camera/lens_registry.h"

namespace skypol::camera {
namespace {

[[noreturn]] void fail(const std::string& msg) { throw std::invalid_argument(msg); }

struct Registry {
  std::vector<LensModel> models;
  std::vector<std::string_view> names;
};

void add(Registry& r, LensModel m) {
  if (m.name.empty()) fail("register_lens_model: an entry needs a name");
  for (const LensModel& o : r.models)
    if (o.name == m.name) fail("register_lens_model: \"" + m.name + "\" is registered already");
  if (!m.make) fail("register_lens_model: " + m.name + " has no make");
  r.models.push_back(std::move(m));
  r.names.clear();
  for (const LensModel& o : r.models) r.names.emplace_back(o.name);
}

Registry& registry() {
  static Registry r = [] {
    Registry built;
#define SKYPOL_LENS(name) add(built, name##_lens_model());
#include "camera/lens_list.h"
#undef SKYPOL_LENS
    return built;
  }();
  return r;
}

// Whether the spec gives `f`, and its name in messages.
std::pair<bool, const char*> given(const LensSpec& s, LensField f) {
  switch (f) {
    case LensField::coefficients: return {!s.coefficients.empty(), "coefficients"};
    case LensField::skew: return {s.skew.has_value(), "skew"};
    case LensField::table: return {!s.table.empty(), "table"};
    case LensField::ocamcalib_path: return {!s.ocamcalib_path.empty() || !s.ocamcalib_text.empty(), "ocamcalib_path"};
    case LensField::clamp_fov_to_monotone: return {s.clamp_fov_to_monotone, "clamp_fov_to_monotone"};
  }
  return {false, ""};
}

std::shared_ptr<const Lens> build(const LensSpec& s) {
  const LensModel* m = find_lens_model(s.model);
  if (!m) {
    std::string legal;
    for (auto n : lens_model_names()) legal += (legal.empty() ? "" : ", ") + std::string(n);
    fail("unknown lens model \"" + s.model + "\" (expected one of " + legal + ")");
  }
  for (LensField f : {LensField::coefficients, LensField::skew, LensField::table, LensField::ocamcalib_path,
                      LensField::clamp_fov_to_monotone}) {
    const auto [is_given, name] = given(s, f);
    if (is_given && std::find(m->fields.begin(), m->fields.end(), f) == m->fields.end())
      fail(std::string(name) + ": not used by model " + s.model);
  }
  return m->make(s);
}

}  // namespace

const std::vector<LensModel>& lens_models() { return registry().models; }

const LensModel* find_lens_model(std::string_view name) {
  for (const LensModel& m : registry().models)
    if (m.name == name) return &m;
  return nullptr;
}

bool register_lens_model(LensModel entry) {
  add(registry(), std::move(entry));
  return true;
}

const std::vector<std::string_view>& lens_model_names() { return registry().names; }

std::shared_ptr<const Lens> make_lens(const LensSpec& spec) {
  if (spec.binning < 1) fail("binning must be >= 1, got " + std::to_string(spec.binning));
  auto lens = build(spec);
  return spec.binning == 1 ? lens : binned(*lens, spec.binning);
}

}  // namespace skypol::camera
