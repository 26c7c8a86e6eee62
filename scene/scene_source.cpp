#include "scene/scene_source.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/scene_error.h"
#include "sky/sky_model_registry.h"

namespace skypol::scene {
namespace {

namespace fs = std::filesystem;

std::string read_text(const std::string& path, const FileLoc& where, const std::string& what) {
  // The error_code overloads: a name the file system refuses (too long, a component that is a
  // file) is the user's bad path, reported at `where`, not a filesystem_error.
  std::error_code ec;
  std::ifstream in(path, std::ios::binary);
  if (!in || fs::is_directory(path, ec)) throw SceneError(where, what);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

FileLoc loc_of(const toml::node& node, const std::string& fallback_file) {
  const toml::source_region& src = node.source();
  const std::string& file = src.path && !src.path->empty() ? *src.path : fallback_file;
  return FileLoc{file, static_cast<int>(src.begin.line), static_cast<int>(src.begin.column)};
}

// `src` over `dst`, key by key: tables merge recursively, anything else replaces. Nodes are moved,
// never copied, because toml++ drops a node's source region on copy and the errors need it.
void merge_into(toml::table& dst, toml::table&& src) {
  for (auto&& [key, node] : src) {
    toml::node* existing = dst.get(key.str());
    if (existing && existing->is_table() && node.is_table()) {
      merge_into(*existing->as_table(), std::move(*node.as_table()));
      continue;
    }
    dst.erase(key.str());
    dst.insert(toml::key(key), std::move(node));  // the key keeps its source too
  }
}

// The folder a file's relative includes resolve against.
fs::path folder_of(const std::string& file) { return fs::path(file).parent_path(); }

struct Resolver {
  std::vector<fs::path> chain;       // files being resolved, outermost first (cycle detection)
  std::vector<std::string> read;     // every included file, in the order read (provenance)

  // Consumes root's `include`, returns the included files merged with root over them.
  toml::table resolve(toml::table root, const std::string& file) {
    std::vector<const toml::node*> names;
    if (toml::node* inc = root.get("include")) {
      if (inc->is_string()) {
        names.push_back(inc);
      } else if (const toml::array* a = inc->as_array()) {
        for (const toml::node& e : *a) {
          if (!e.is_string()) {
            throw SceneError(loc_of(e, file), "key 'include': expected a file name (a string), found an element that is not");
          }
          names.push_back(&e);
        }
      } else {
        throw SceneError(loc_of(*inc, file), "key 'include': expected a file name or an array of file names");
      }
    }
    toml::table merged;
    for (const toml::node* name_node : names) {
      const std::string name = *name_node->value<std::string>();
      const FileLoc at = loc_of(*name_node, file);
      fs::path path(name);
      if (path.is_relative()) path = folder_of(file) / path;
      path = path.lexically_normal();
      std::error_code ec;
      const fs::path identity = fs::weakly_canonical(path, ec);
      if (ec) {
        throw SceneError(at, "key 'include': cannot open included file '" + name + "': " + ec.message());
      }
      if (std::find(chain.begin(), chain.end(), identity) != chain.end()) {
        std::string cycle;
        for (const fs::path& p : chain) cycle += p.filename().string() + " -> ";
        throw SceneError(at, "key 'include': include cycle: " + cycle + identity.filename().string());
      }
      const std::string text =
          read_text(path.string(), at, "key 'include': cannot open included file '" + name + "' (looked for " +
                                           path.string() + ")");
      read.push_back(path.string());
      chain.push_back(identity);
      merge_into(merged, resolve(parse_toml(text, path.string()), path.string()));
      chain.pop_back();
    }
    root.erase("include");
    merge_into(merged, std::move(root));
    return merged;
  }
};

// A bare word on the command line (a model name, a path, spaces allowed) is a string; anything
// with TOML's punctuation is left to the parser so that its syntax errors are reported.
bool is_bare_word(const std::string& v) {
  if (v.empty()) return false;
  return std::none_of(v.begin(), v.end(), [](char c) {
    return std::iscntrl(static_cast<unsigned char>(c)) ||
           std::string_view("\"'[]{}#=,\\").find(c) != std::string_view::npos;
  });
}

toml::table override_table(const Override& o) {
  const std::string text = o.key + "=" + o.value;
  if (is_bare_word(o.value)) {
    try {
      return toml::parse(text, o.origin);
    } catch (const toml::parse_error&) {
      return parse_toml(o.key + "=\"" + o.value + "\"", o.origin);
    }
  }
  return parse_toml(text, o.origin);  // a syntax error is reported with toml++'s message and column
}

// `--set KEY=` (an empty value): the key is removed from the merged table, whatever wrote it.
void unset_key(toml::table& root, const Override& o) {
  toml::table* t = &root;
  std::string_view rest = o.key;
  while (true) {
    const std::size_t dot = rest.find('.');
    const std::string part(rest.substr(0, dot));
    if (dot == std::string_view::npos) {
      if (!t->contains(part)) break;
      t->erase(part);
      return;
    }
    t = t->get_as<toml::table>(part);
    if (!t) break;
    rest.remove_prefix(dot + 1);
  }
  throw SceneError(FileLoc{o.origin, 1, 1}, "key '" + o.key + "': nothing to unset (no file and no earlier override sets it)");
}

// Every dotted key an override's table writes ("sky.clouds.coverage"), tables included.
void written_keys(const toml::table& t, const std::string& path, std::vector<std::string>& out) {
  for (auto&& [k, v] : t) {
    const std::string dotted = path.empty() ? std::string(k.str()) : path + "." + std::string(k.str());
    out.push_back(dotted);
    if (const toml::table* sub = v.as_table()) written_keys(*sub, dotted, out);
  }
}

// Switching a scene's sky model by an override ("this scene, under that sky"): the [sky] keys
// that the files wrote for the old model and that the new one does not take are dropped, each
// with a note. A key an override wrote, or one no model takes, stays, so that the scene language
// reports it (docs/scenes.md, "--set").
void drop_other_models_keys(toml::table& root, const std::vector<std::string>& overridden,
                            const std::string& switched_by, std::vector<std::string>& notes) {
  toml::table* sky_table = root.get_as<toml::table>("sky");
  if (!sky_table) return;
  const std::optional<std::string> model = sky_table->get("model") ? sky_table->get("model")->value<std::string>() : std::nullopt;
  const sky::SkyModelEntry* entry = model ? sky::find_sky_model(*model) : nullptr;
  if (!entry) return;  // an unknown model: the scene language reports it
  std::vector<std::string> drop;
  for (auto&& [k, v] : *sky_table) {
    const std::string key(k.str());
    if (key == "model" || sky::find_key(*entry, key) || sky::models_taking(key).empty()) continue;
    const std::string dotted = "sky." + key;
    const bool by_override = std::any_of(overridden.begin(), overridden.end(), [&](const std::string& w) {
      return w == dotted || w.rfind(dotted + ".", 0) == 0;
    });
    if (by_override) continue;
    const toml::source_region& src = v.source();
    std::string where = src.path && !src.path->empty() ? *src.path : std::string();
    if (src.begin.line) where += ":" + std::to_string(src.begin.line);
    notes.push_back("sky." + key + (where.empty() ? "" : " (" + where + ")") + " dropped: model \"" + *model +
                    "\" (" + switched_by + ") does not take it");
    drop.push_back(key);
  }
  for (const std::string& key : drop) sky_table->erase(key);
}

SceneSource assemble(const std::string& own_text, const std::string& file, const std::vector<Override>& overrides) {
  Resolver resolver;
  std::error_code ec;
  const fs::path identity = fs::weakly_canonical(fs::path(file), ec);
  resolver.chain.push_back(ec ? fs::path(file) : identity);
  SceneSource source;
  source.file = file;
  source.root = resolver.resolve(parse_toml(own_text, file), file);
  std::vector<std::string> overridden;
  std::string model_switched_by;  // the last override that set sky.model
  for (const Override& o : overrides) {
    if (o.value.empty()) {
      unset_key(source.root, o);
      continue;
    }
    toml::table patch = override_table(o);
    if (patch.contains("include")) {
      throw SceneError(FileLoc{o.origin, 1, 1}, "key 'include': includes belong in a scene file, not in an override");
    }
    written_keys(patch, "", overridden);
    if (patch.at_path("sky.model")) model_switched_by = "set by " + o.origin + " " + o.key + "=" + o.value;
    merge_into(source.root, std::move(patch));
  }
  if (!model_switched_by.empty()) drop_other_models_keys(source.root, overridden, model_switched_by, source.notes);
  if (resolver.read.empty() && overrides.empty()) {
    source.text = own_text;
  } else {
    std::string head = "# skypol: the scene " + file + " as loaded";
    for (const std::string& f : resolver.read) head += "\n#   include " + f;
    for (const Override& o : overrides) {
      std::string line = o.key + "=" + o.value + "   (" + o.origin + ")";
      std::replace_if(line.begin(), line.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
      head += "\n#   " + line;
    }
    for (const std::string& n : source.notes) head += "\n#   " + n;
    source.text = head + "\n" + to_toml(source.root);
  }
  return source;
}


// TOML text, written here rather than by toml++'s formatter, whose floats carry 17 significant
// digits (43.286990000000003): these are the shortest that parse back to the same double.
bool is_bare_key(std::string_view k) {
  return !k.empty() && std::all_of(k.begin(), k.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

std::string key_text(std::string_view k) { return is_bare_key(k) ? std::string(k) : toml_quoted(k); }

std::string float_text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v < 0 ? "-inf" : "inf";
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string value_text(const toml::node& n) {
  if (const auto* s = n.as_string()) return toml_quoted(s->get());
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (const auto* f = n.as_floating_point()) return float_text(f->get());
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* a = n.as_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < a->size(); ++i) out += (i ? ", " : "") + value_text(*a->get(i));
    return out + "]";
  }
  if (const auto* t = n.as_table()) {
    std::string out = "{";
    bool first = true;
    for (auto&& [k, v] : *t) {
      out += std::string(first ? " " : ", ") + key_text(k.str()) + " = " + value_text(v);
      first = false;
    }
    return out + (first ? "}" : " }");
  }
  std::ostringstream os;  // dates and times: toml++ writes them as written
  os << toml::toml_formatter(n);
  return os.str();
}

// Plain keys first, then each sub-table under its [header], then arrays of tables.
void emit_table(const toml::table& t, const std::string& path, std::string& out) {
  auto header_path = [&path](std::string_view k) { return path.empty() ? key_text(k) : path + "." + key_text(k); };
  for (auto&& [k, v] : t) {
    const toml::array* a = v.as_array();
    if (v.is_table() || (a && a->is_array_of_tables())) continue;
    out += key_text(k.str()) + " = " + value_text(v) + "\n";
  }
  for (auto&& [k, v] : t) {
    if (const toml::table* sub = v.as_table()) {
      out += "\n[" + header_path(k.str()) + "]\n";
      emit_table(*sub, header_path(k.str()), out);
    }
  }
  for (auto&& [k, v] : t) {
    const toml::array* a = v.as_array();
    if (!a || !a->is_array_of_tables()) continue;
    for (const toml::node& e : *a) {
      out += "\n[[" + header_path(k.str()) + "]]\n";
      emit_table(*e.as_table(), header_path(k.str()), out);
    }
  }
}

}  // namespace

std::string toml_quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

Override parse_override(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw SceneError(FileLoc{"--set", 0, 0}, "expected key=value (e.g. camera.heading_deg=30), got '" + assignment + "'");
  }
  auto trim = [](std::string s) {
    const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
  };
  return Override{trim(assignment.substr(0, eq)), trim(assignment.substr(eq + 1))};
}

toml::table parse_toml(const std::string& text, const std::string& file_name) {
  try {
    return toml::parse(text, file_name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw SceneError(FileLoc{file_name, static_cast<int>(b.line), static_cast<int>(b.column)},
                     "TOML syntax: " + std::string(e.description()));
  }
}

std::string to_toml_value(const toml::node& value) { return value_text(value); }

std::string to_toml(const toml::table& table) {
  std::string out;
  emit_table(table, "", out);
  return out;
}

SceneSource parse_scene_source(const std::string& text, const std::string& file_name,
                               const std::vector<Override>& overrides) {
  return assemble(text, file_name, overrides);
}

SceneSource load_scene_source(const std::string& path, const std::vector<Override>& overrides) {
  return assemble(read_text(path, FileLoc{path, 0, 0}, "cannot open scene file"), path, overrides);
}

std::optional<FileLoc> locate_key(const std::string& path, std::string_view dotted_key) {
  try {
    const SceneSource source = load_scene_source(path);
    const toml::node* n = source.root.at_path(dotted_key).node();
    if (!n || n->source().begin.line == 0) return std::nullopt;
    const toml::source_region& src = n->source();
    return FileLoc{src.path && !src.path->empty() ? *src.path : path, static_cast<int>(src.begin.line),
                   static_cast<int>(src.begin.column)};
  } catch (const SceneError&) {
    return std::nullopt;
  }
}

}  // namespace skypol::scene
