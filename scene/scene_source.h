// Where a scene's TOML comes from before its keys are read: the file, the files it includes, and
// the command line's --set overrides, merged into one table whose nodes still carry the file and
// line they came from (so that errors point at the right place).
//
// Merging (docs/scenes.md, "include"): a top-level `include = "a.toml"` or `include = ["a.toml",
// "b.toml"]` names files relative to the including file; they are read first, in order, each
// with its own includes (a cycle is an error), and every later table overrides the earlier ones
// key by key: tables merge recursively, any other value (numbers, strings, arrays, arrays of
// tables) is replaced whole. The including file comes last, then the overrides, in order.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "scene/scene_error.h"

namespace skypol::scene {

// One `--set dotted.key=value` override. `value` is TOML ("3", "\"piz\"", "[1, 2]",
// "2022-09-23"), or a bare word ("equisolid", "out/x.exr") taken as a string; empty, the key is
// removed (whichever file wrote it; a key nothing wrote is an error). An override that sets
// sky.model drops the [sky] keys the files wrote that the new model does not take
// (SceneSource::notes says which); keys an override wrote are never dropped. Errors in the
// value (and in what the loader makes of it) are reported at `origin`, line 1, with the column
// counted in "key=value".
struct Override {
  std::string key;
  std::string value;
  std::string origin = "--set";
};

// "a.b.c=value" as typed on the command line; throws SceneError at "--set" when there is no '='.
Override parse_override(const std::string& assignment);

struct SceneSource {
  std::string file;   // the scene file as given
  // The scene as loaded, for provenance in the stack's headers: the file's own text when it
  // neither includes nor is overridden, else the merged table as TOML, under a comment that
  // names the files and overrides it came from. Either way it parses back to the same scene.
  std::string text;
  toml::table root;   // merged; the `include` key is consumed
  // What the merge did that the user did not write: [sky] keys dropped because an override
  // switched the sky model to one that does not take them. One line each, for stderr.
  std::vector<std::string> notes;
};

// Throws SceneError: file missing, TOML syntax, bad include (missing, wrong type, cycle), bad
// override.
SceneSource load_scene_source(const std::string& path, const std::vector<Override>& overrides = {});
// The same for text in memory; includes resolve against the folder of `file_name`.
SceneSource parse_scene_source(const std::string& text, const std::string& file_name,
                               const std::vector<Override>& overrides = {});

// Where the scene file `path` (includes followed) writes the dotted key ("camera.focal_mm"), for
// errors found after loading (a render that sees no sky). nullopt when the file cannot be read or
// does not write the key (a preset's or the default value).
std::optional<FileLoc> locate_key(const std::string& path, std::string_view dotted_key);

// TOML text → table, with syntax errors as SceneError at the file, line and column.
toml::table parse_toml(const std::string& text, const std::string& file_name);

// A table as TOML text: keys sorted, sub-tables under [headers], floats in the shortest form that
// parses back to the same double (0.1, not toml++'s 0.10000000000000001).
std::string to_toml(const toml::table& table);
// One value (a number, a string, an array, an inline table, a date) as TOML text.
std::string to_toml_value(const toml::node& value);
// `s` as a TOML basic string: " and \ escaped, \n \t \r by name, every other control character
// (U+0000–U+001F, U+007F) as \u00xx; other bytes (UTF-8) kept.
std::string toml_quoted(std::string_view s);

}  // namespace skypol::scene
