// A sweep: one base scene and a grid of parameters, one stack per variant, for synthetic datasets
// (docs/datasets.md). Each variant is the base scene with a few keys overridden, so it is loaded,
// checked and rendered exactly like a scene with --set; every variant is checked before anything
// is written. Runs resume (a variant whose file exists is done: stacks are renamed into place
// only when whole) and split with --shard i/N, so any job runner can spread the work with no
// coordination between the runs.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "scene/truth.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/scene_source.h"

namespace skypol::scene {

// One axis of the grid: a dotted scene key and its values, as TOML text ("30", "\"equisolid\"",
// "\"2022-03-20\"").
struct SweepAxis {
  std::string key;
  std::vector<std::string> values;
  FileLoc where;  // the axis in the sweep file, where its errors are reported
};

struct Sweep {
  std::string file;                 // the sweep file as given
  std::string base;                 // the base scene, resolved against the sweep file's folder
  FileLoc base_where;               // where `base` is written (an unreadable base is reported there)
  std::vector<Override> set;        // [set]: the same for every variant
  std::vector<FileLoc> set_where;   // where each [set] entry is written
  std::vector<SweepAxis> axes;      // in the order written; the last one varies fastest
  std::size_t size() const;         // the number of variants (1 when there are no axes)
};

// Throws SceneError: missing file, TOML syntax, unknown key, an axis that is not a list or a
// range, an empty axis, more than kMaxVariants variants. The scene keys are checked when the
// variants are made.
Sweep load_sweep(const std::string& path);
Sweep parse_sweep(const std::string& text, const std::string& file_name);
inline constexpr std::size_t kMaxVariants = 100000;

struct Variant {
  std::size_t index = 0;
  std::vector<std::pair<std::string, std::string>> params;  // axis key → value (TOML text)
  Scene scene;
  std::string file;   // its stack's name in the output folder: "000042-1a2b3c4d.exr"
  Truth truth;        // at the first time: site, orientation, pole (the same for every frame)
};

// Variant `index` (0-based; axes in file order, the last varying fastest): the base scene with
// [set], then `extra` (the command line's --set), then the axis values. A problem with a [set]
// entry or an axis value is a SceneError at that entry in the sweep file. The file name is the
// index and a hash of the merged scene, so that a changed sweep never mistakes an old stack for
// one of its variants.
Variant make_variant(const Sweep& sweep, std::size_t index, const std::vector<Override>& extra = {});

// --shard i/N: variant k belongs to shard (k mod N) + 1, so every shard gets a similar mix.
struct Shard {
  std::size_t index = 1;  // 1-based
  std::size_t count = 1;
  bool has(std::size_t variant) const { return variant % count == index - 1; }
};
// "i/N" with 1 ≤ i ≤ N; throws std::invalid_argument saying what was expected.
Shard parse_shard(const std::string& text);

// One line of manifest.jsonl (JSON, no newline): index, file, params, truth.
std::string manifest_line(const Variant& v);

}  // namespace skypol::scene
