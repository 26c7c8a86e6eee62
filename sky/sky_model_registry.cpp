// The sky models' registry (sky_model_registry.h) and the keys every model takes.
#include "sky/sky_model_registry.h"

#include <limits>
#include <stdexcept>


namespace skypol::sky {
namespace {

struct Registry {
  std::vector<SkyModelEntry> models;
};

void add(Registry& r, SkyModelEntry m) {
  if (m.name.empty()) throw std::invalid_argument("register_sky_model: an entry needs a name");
  for (const SkyModelEntry& o : r.models)
    if (o.name == m.name) throw std::invalid_argument("register_sky_model: \"" + m.name + "\" is registered already");
  if (bool(m.make) == bool(m.make_bands))
    throw std::invalid_argument("register_sky_model: " + m.name + " needs exactly one of make and make_bands");
  r.models.push_back(std::move(m));
}

Registry& registry() {
  static Registry r = [] {
    Registry built;
#define SKYPOL_SKY_MODEL(name) add(built, name##_sky_model());
#include "sky/sky_model_list.h"
#undef SKYPOL_SKY_MODEL
    return built;
  }();
  return r;
}

// get/set over a field reference, for a field of type T stored as SkyValue alternative V.
template <class V, class T>
void bind(SkyKey& k, std::function<T&(SkySpec&)> ref) {
  k.get = [ref](const SkySpec& s) { return SkyValue(static_cast<V>(ref(const_cast<SkySpec&>(s)))); };
  k.set = [ref](SkySpec& s, const SkyValue& v) { ref(s) = static_cast<T>(std::get<V>(v)); };
}

SkyKey key_of(std::string name, SkyKey::Kind kind, double lo = 0, double hi = 0) {
  SkyKey k;
  k.name = std::move(name);
  k.kind = kind;
  k.lo = lo;
  k.hi = hi;
  return k;
}

}  // namespace

SkyKey number_key(std::string name, double lo, double hi, std::function<double&(SkySpec&)> ref) {
  SkyKey k = key_of(std::move(name), SkyKey::Kind::number, lo, hi);
  bind<double>(k, std::move(ref));
  return k;
}

SkyKey optional_number_key(std::string name, double lo, double hi, std::function<std::optional<double>&(SkySpec&)> ref) {
  SkyKey k = key_of(std::move(name), SkyKey::Kind::number, lo, hi);
  k.optional = true;
  k.get = [ref](const SkySpec& s) {
    const std::optional<double>& v = ref(const_cast<SkySpec&>(s));
    return v ? SkyValue(*v) : SkyValue();
  };
  k.set = [ref](SkySpec& s, const SkyValue& v) {
    if (const double* d = std::get_if<double>(&v)) ref(s) = *d; else ref(s).reset();
  };
  return k;
}

SkyKey integer_key(std::string name, long long lo, long long hi, std::function<int&(SkySpec&)> ref) {
  SkyKey k = key_of(std::move(name), SkyKey::Kind::integer, static_cast<double>(lo), static_cast<double>(hi));
  bind<long long>(k, std::move(ref));
  return k;
}

SkyKey boolean_key(std::string name, std::function<bool&(SkySpec&)> ref) {
  SkyKey k = key_of(std::move(name), SkyKey::Kind::boolean);
  bind<bool>(k, std::move(ref));
  return k;
}

SkyKey choice_key(std::string name, std::vector<std::string> legal, std::function<std::string&(SkySpec&)> ref) {
  SkyKey k = key_of(std::move(name), SkyKey::Kind::choice);
  k.legal = std::move(legal);
  bind<std::string>(k, std::move(ref));
  return k;
}

SkyKey numbers_key(std::string name, double lo, double hi, std::function<std::vector<double>&(SkySpec&)> ref) {
  SkyKey k = key_of(std::move(name), SkyKey::Kind::numbers, lo, hi);
  bind<std::vector<double>>(k, std::move(ref));
  return k;
}

SkyKey table_key(std::string name, std::vector<SkyKey> keys) {
  SkyKey k = key_of(std::move(name), SkyKey::Kind::table);
  k.keys = std::move(keys);
  return k;
}

SkyKey param_number_key(std::string name, double fallback, double lo, double hi) {
  SkyKey k = key_of(name, SkyKey::Kind::number, lo, hi);
  k.get = [name, fallback](const SkySpec& s) {
    const auto it = s.params.find(name);
    return it == s.params.end() ? SkyValue(fallback) : it->second;
  };
  k.set = [name](SkySpec& s, const SkyValue& v) { s.params[name] = v; };
  return k;
}

double param_number(const SkySpec& spec, std::string_view key) {
  const SkyKey* k = find_key(sky_model_entry(spec.model), key);
  if (!k || !k->get) throw std::invalid_argument("sky." + std::string(key) + ": not a key of model " + spec.model);
  return std::get<double>(k->get(spec));
}

const std::vector<SkyKey>& every_model_keys() {
  static const std::vector<SkyKey> keys = [] {
    std::vector<SkyKey> k;
    k.push_back(boolean_key("sun_disc", [](SkySpec& s) -> bool& { return s.sun_disc; }));
    k.push_back(number_key("sun_disc_radiance", 0, 1e12, [](SkySpec& s) -> double& { return s.sun_disc_radiance; }));
    SkyKey seed = key_of("seed", SkyKey::Kind::integer, 0, static_cast<double>(std::numeric_limits<long long>::max()));
    seed.scene_range_only = true;
    seed.get = [](const SkySpec& s) { return SkyValue(static_cast<long long>(s.clouds.seed)); };
    seed.set = [](SkySpec& s, const SkyValue& v) { s.clouds.seed = static_cast<std::uint64_t>(std::get<long long>(v)); };
    SkyKey clouds = table_key(
        "clouds",
        {number_key("coverage", 0, 1, [](SkySpec& s) -> double& { return s.clouds.coverage; }), seed,
         number_key("scale_deg", 1, 90, [](SkySpec& s) -> double& { return s.clouds.scale_deg; }),
         number_key("softness", 1e-6, 1, [](SkySpec& s) -> double& { return s.clouds.softness; }),
         number_key("brightness", 1, 1e6, [](SkySpec& s) -> double& { return s.clouds.brightness; })});
    clouds.on_table = [](SkySpec& s) { s.clouds.coverage = 0.3; };  // a [sky.clouds] table: some cloud
    k.push_back(std::move(clouds));
    return k;
  }();
  return keys;
}

const std::vector<SkyModelEntry>& sky_models() { return registry().models; }

std::vector<std::string> sky_model_names() {
  std::vector<std::string> out;
  for (const SkyModelEntry& m : sky_models()) out.push_back(m.name);
  return out;
}

std::string sky_model_names_text() {
  const std::vector<std::string> names = sky_model_names();
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  }
  return out;
}

const SkyModelEntry* find_sky_model(std::string_view name) {
  for (const SkyModelEntry& m : sky_models())
    if (m.name == name) return &m;
  return nullptr;
}

const SkyModelEntry& sky_model_entry(std::string_view name) {
  if (const SkyModelEntry* m = find_sky_model(name)) return *m;
  throw std::invalid_argument("sky.model: \"" + std::string(name) + "\" is unknown (expected " +
                              sky_model_names_text() + ")");
}

const SkyKey* find_key(const SkyModelEntry& m, std::string_view key) {
  for (const std::vector<SkyKey>* keys : {&m.keys, &every_model_keys()})
    for (const SkyKey& k : *keys)
      if (k.name == key) return &k;
  return nullptr;
}

std::vector<std::string> models_taking(std::string_view key) {
  std::vector<std::string> out;
  for (const SkyModelEntry& m : sky_models())
    if (find_key(m, key)) out.push_back(m.name);
  return out;
}

bool register_sky_model(SkyModelEntry entry) {
  add(registry(), std::move(entry));
  return true;
}

}  // namespace skypol::sky
