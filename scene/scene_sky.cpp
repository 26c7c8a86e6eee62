// The [sky] section (and its sub-tables, [sky.clouds], [sky.aerosol]): the model is looked up in
// the sky models' registry (sky/sky_model_registry.h), which says which keys it takes, their kind
// and range; they are read here with file:line errors, then sky::validate checks what a range
// cannot say (Preetham's turbidity range). A key another model takes is an error at the key that
// names the model(s) it belongs to; a key no model takes is an unknown key.
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "sky/sky_model_registry.h"

#include "scene/scene.h"

namespace skypol::scene {
namespace {

std::string quoted_list(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    out += std::string(i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + "\"" + names[i] + "\"";
  }
  return out;
}

// Reads `keys` from table f into s: every key is read (so that finish() can suggest it for a
// typo), a given one is stored, and then each given key's refuse() is asked.
void read_keys(Fields& f, const std::vector<sky::SkyKey>& keys, sky::SkySpec& s) {
  using Kind = sky::SkyKey::Kind;
  for (const sky::SkyKey& k : keys) {
    const bool given = f.has(k.name);
    sky::SkyValue v;
    switch (k.kind) {
      case Kind::boolean: v = f.boolean(k.name, std::get<bool>(k.get(s))); break;
      case Kind::integer:
        v = f.integer(k.name, std::get<long long>(k.get(s)), static_cast<long long>(k.lo),
                       k.hi >= 9.2e18 ? std::numeric_limits<long long>::max() : static_cast<long long>(k.hi));
        break;
      case Kind::number:
        if (k.optional) {
          if (std::optional<double> d = f.optional_number(k.name, k.lo, k.hi)) v = *d;
        } else {
          v = f.number(k.name, std::get<double>(k.get(s)), k.lo, k.hi);
        }
        break;
      case Kind::choice: v = f.choice(k.name, std::get<std::string>(k.get(s)), k.legal); break;
      case Kind::numbers: {
        const std::vector<double> a = f.numbers(k.name, std::get<std::vector<double>>(k.get(s)));
        for (double x : a) {
          if (!(x >= k.lo && x <= k.hi)) {
            char range[96];
            std::snprintf(range, sizeof range, "each value must be in [%g, %g]", k.lo, k.hi);
            f.fail(k.name, range + (k.range_note.empty() ? std::string() : " (" + k.range_note + ")"));
          }
        }
        v = a;
        break;
      }
      case Kind::table:
        if (std::optional<Fields> t = f.table(k.name)) {
          if (k.on_table) k.on_table(s);
          read_keys(*t, k.keys, s);
          t->finish();
        }
        continue;
    }
    if (given) k.set(s, v);
  }
  for (const sky::SkyKey& k : keys) {
    if (!f.has(k.name) || !k.refuse) continue;
    if (const std::string why = k.refuse(s); !why.empty()) f.fail(k.name, why);
  }
}

[[noreturn]] void fail_sky_field(const Fields& sky_table, const std::string& message) {
  // "sky.<key>: …" or "sky.<table>.<key>: …" (sky/spec_errors.h); anything else lands on model.
  const std::string prefix = "sky.";
  const std::size_t colon = message.find(": ");
  if (message.rfind(prefix, 0) != 0 || colon == std::string::npos) sky_table.fail("model", message);
  const std::string field = message.substr(prefix.size(), colon - prefix.size());
  const std::string rest = message.substr(colon + 2);
  const std::size_t dot = field.find('.');
  if (dot != std::string::npos) {
    if (const toml::table* sub = sky_table.raw().get_as<toml::table>(field.substr(0, dot))) {
      Fields(*sub, sky_table.file(), sky_table.dotted(field.substr(0, dot))).fail(field.substr(dot + 1), rest);
    }
  }
  sky_table.fail(field.substr(0, dot), rest);
}

}  // namespace

sky::SkySpec read_sky(Fields& f) {
  sky::SkySpec s;
  s.model = f.choice("model", s.model, sky::sky_model_names());
  const sky::SkyModelEntry& model = sky::sky_model_entry(s.model);
  read_keys(f, model.keys, s);
  read_keys(f, sky::every_model_keys(), s);
  for (const auto& [key, node] : f.raw()) {
    const std::string name(key.str());
    if (name == "model" || sky::find_key(model, name)) continue;
    const std::vector<std::string> owners = sky::models_taking(name);
    if (owners.empty()) continue;  // no model takes it: finish() reports it as unknown
    f.fail(name, "not used by model \"" + s.model + "\" (used only by model" + (owners.size() > 1 ? "s " : " ") +
                     quoted_list(owners) + ")");
  }
  f.finish();
  try {
    sky::validate(s);
  } catch (const std::invalid_argument& e) {
    fail_sky_field(f, e.what());
  }
  return s;
}

void check_sky_for_scene(const Fields& sky_table, const Scene& scene) {
  try {
    sky::validate_for_scene(scene.sky, scene.render.bands, site_atmosphere(scene));
  } catch (const std::invalid_argument& e) {
    fail_sky_field(sky_table, e.what());
  }
}

std::unique_ptr<sky::SkyModel> build_sky(const sky::SkySpec& spec) { return sky::make_sky(spec); }

sky::SiteAtmosphere site_atmosphere(const Scene& scene) {
  sky::SiteAtmosphere a;
  if (scene.sun_options.pressure_hpa > 0) a.pressure_hpa = scene.sun_options.pressure_hpa;  // else 1013.25
  a.altitude_m = scene.site.height_m;
  a.latitude_deg = scene.site.latitude_deg;
  return a;
}

sky::BandSkies build_band_skies(const Scene& scene, const std::filesystem::path& cache_dir) {
  return sky::make_band_skies(scene.sky, scene.render.bands, site_atmosphere(scene), cache_dir);
}

}  // namespace skypol::scene
