// A small read-only tree of a YAML (or JSON) document, built with libyaml, for the calibration
// importers: every node keeps its line so that an error points into the calibration file. OpenCV's
// FileStorage header "%YAML:1.0" (not valid YAML 1.1) is accepted; its tags (!!opencv-matrix) are
// kept. Not part of the camera interface.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace skypol::camera::detail {

struct YamlNode {
  enum class Kind { scalar, sequence, mapping } kind = Kind::scalar;
  std::string value;  // scalar text
  std::string tag;    // e.g. "tag:yaml.org,2002:opencv-matrix"
  int line = 0;       // 1-based
  std::vector<YamlNode> items;                           // sequence
  std::vector<std::pair<std::string, YamlNode>> fields;  // mapping, in file order

  // The value of a mapping key, or nullptr.
  const YamlNode* find(const std::string& key) const;
};

// Parses `text`; throws std::invalid_argument "NAME:LINE: YAML syntax error: ..." on bad syntax or
// an empty document.
YamlNode parse_yaml(const std::string& text, const std::string& name);

}  // namespace skypol::camera::detail
