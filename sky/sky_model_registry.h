// The sky models as one registry: each model is one entry (its name, a line saying what it is, the
// [sky] keys it takes with their ranges and checks, and how it is built), and everything that
// lists, reads or builds sky models asks it: the scene language (which keys a model takes, and
// which to drop when a scene's model is switched by an override), validate, make_sky and
// make_band_skies (sky_spec.h).
//
// Adding a sky model: write its files (e.g. sky/foo.h, foo.cpp: the SkyModel) and, in a file of its
// own (e.g. sky/foo_model.cpp), a function `SkyModelEntry foo_sky_model()` returning its entry;
// then add the one line `SKYPOL_SKY_MODEL(foo)` to sky/sky_model_list.h (and the .cpp files to
// sky/CMakeLists.txt). A key the model alone reads can live in SkySpec::params (SkyKey::param), so
// that SkySpec needs no new field. A test or a program may also add an entry at run time with
// register_sky_model (tests/scene/registry_test.cpp).
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sky/sky_model.h"
#include "sky/sky_spec.h"

namespace skypol::sky {

// One key of [sky] (or of a sub-table such as [sky.aerosol]): its TOML name, the kind and range of
// its value, and where in a SkySpec the value lives. Both the scene language (which reads it, with
// file:line errors) and validate (which checks a spec built in code) use the same range.
struct SkyKey {
  enum class Kind { boolean, integer, number, choice, numbers, table };
  std::string name;
  Kind kind = Kind::number;
  double lo = 0, hi = 0;               // integer, number, numbers (each element): the closed range
  std::string range_note;              // said after the range in validate's message ("nm, Bodhaine's formula")
  std::vector<std::string> legal;      // choice: the legal values
  bool optional = false;               // number: no default (the value stays unset unless given)
  // The range binds what a scene writes, not a spec built in code: the clouds' seed is any 64-bit
  // value there (a study draws it), while TOML integers stop at 2^63 − 1.
  bool scene_range_only = false;
  std::function<SkyValue(const SkySpec&)> get;            // the value in a spec (its default in SkySpec{})
  std::function<void(SkySpec&, const SkyValue&)> set;     // stores a value of the key's kind
  // When the key is given: why it may not be, given the rest of the spec ("" when it may).
  std::function<std::string(const SkySpec&)> refuse;
  // table: its own keys; what the table's presence sets before they are read ([sky.clouds]:
  // coverage 0.3); checks over the whole table, throwing std::invalid_argument("sky.<table>.<key>: …").
  std::vector<SkyKey> keys;
  std::function<void(SkySpec&)> on_table;
  std::function<void(const SkySpec&)> check;
};

// Key makers. `ref` returns a reference to the field in a spec (e.g. [](SkySpec& s) -> double& {
// return s.max_dolp; }); param_* keep the value in SkySpec::params under the key's name.
SkyKey number_key(std::string name, double lo, double hi, std::function<double&(SkySpec&)> ref);
SkyKey optional_number_key(std::string name, double lo, double hi, std::function<std::optional<double>&(SkySpec&)> ref);
SkyKey integer_key(std::string name, long long lo, long long hi, std::function<int&(SkySpec&)> ref);
SkyKey boolean_key(std::string name, std::function<bool&(SkySpec&)> ref);
SkyKey choice_key(std::string name, std::vector<std::string> legal, std::function<std::string&(SkySpec&)> ref);
SkyKey numbers_key(std::string name, double lo, double hi, std::function<std::vector<double>&(SkySpec&)> ref);
SkyKey table_key(std::string name, std::vector<SkyKey> keys);
SkyKey param_number_key(std::string name, double fallback, double lo, double hi);

// The value of a number key kept in params (param_number_key): the spec's, else the key's default.
double param_number(const SkySpec& spec, std::string_view key);

struct SkyModelEntry {
  std::string name;
  std::string description;             // one line, for help and docs
  std::vector<SkyKey> keys;            // the keys it takes besides `model` and every_model_keys()
  // Checks that a range cannot say (Preetham's turbidity range); throws
  // std::invalid_argument("sky.<field>: …"). Optional.
  std::function<void(const SkySpec&)> validate;
  // One model for every band (grey models): the bare model, before clouds and the sun's disc.
  std::function<std::unique_ptr<SkyModel>(const SkySpec&)> make;
  // Or one model per band, each bare (make_band_skies wraps them); exactly one of make, make_bands.
  std::function<BandSkies(const SkySpec&, std::span<const std::string> bands, const SiteAtmosphere& site,
                          const std::filesystem::path& cache_dir, int threads)>
      make_bands;
  // What the scene around the sky must satisfy (its bands, its site), checked when a scene is
  // loaded; throws std::invalid_argument("sky.<field>: …"). Optional.
  std::function<void(const SkySpec&, std::span<const std::string> bands, const SiteAtmosphere& site)> check_scene;
};

// The keys every model takes: the wrappers' (sun_disc, sun_disc_radiance, [sky.clouds]).
const std::vector<SkyKey>& every_model_keys();

// The entries in registration order (sky_model_list.h, then register_sky_model's).
const std::vector<SkyModelEntry>& sky_models();
std::vector<std::string> sky_model_names();
// "rayleigh, berry or vrte", for messages.
std::string sky_model_names_text();
const SkyModelEntry* find_sky_model(std::string_view name);
// Throws std::invalid_argument("sky.model: \"x\" is unknown (expected …)").
const SkyModelEntry& sky_model_entry(std::string_view name);

// The top-level [sky] key `key` of model `m` (its own or every model's), or nullptr.
const SkyKey* find_key(const SkyModelEntry& m, std::string_view key);
// The registered models that take `key` at the top level of [sky] ("model" excluded).
std::vector<std::string> models_taking(std::string_view key);

// Adds an entry; throws std::invalid_argument for an empty or taken name, or an entry that has not
// exactly one of make and make_bands. Returns true, so that a file can register at static init.
bool register_sky_model(SkyModelEntry entry);

// The entry functions named in sky_model_list.h.
#define SKYPOL_SKY_MODEL(name) SkyModelEntry name##_sky_model();
#include "sky/sky_model_list.h"
#undef SKYPOL_SKY_MODEL

}  // namespace skypol::sky
