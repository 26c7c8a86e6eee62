// YAML → YamlNode with libyaml's document API (yaml_tree.h).
#include "camera/detail/yaml_tree.h"

#include <memory>
#include <stdexcept>

#include <yaml.h>

namespace skypol::camera::detail {
namespace {

YamlNode convert(yaml_document_t& doc, yaml_node_t* n, int depth) {
  if (depth > 64) throw std::invalid_argument("YAML nesting deeper than 64 levels");
  YamlNode out;
  out.line = static_cast<int>(n->start_mark.line) + 1;
  if (n->tag) out.tag = reinterpret_cast<const char*>(n->tag);
  switch (n->type) {
    case YAML_SCALAR_NODE:
      out.value.assign(reinterpret_cast<const char*>(n->data.scalar.value), n->data.scalar.length);
      break;
    case YAML_SEQUENCE_NODE:
      out.kind = YamlNode::Kind::sequence;
      for (yaml_node_item_t* i = n->data.sequence.items.start; i < n->data.sequence.items.top; ++i)
        out.items.push_back(convert(doc, yaml_document_get_node(&doc, *i), depth + 1));
      break;
    case YAML_MAPPING_NODE:
      out.kind = YamlNode::Kind::mapping;
      for (yaml_node_pair_t* p = n->data.mapping.pairs.start; p < n->data.mapping.pairs.top; ++p) {
        YamlNode key = convert(doc, yaml_document_get_node(&doc, p->key), depth + 1);
        out.fields.emplace_back(key.value, convert(doc, yaml_document_get_node(&doc, p->value), depth + 1));
      }
      break;
    default:
      break;
  }
  return out;
}

}  // namespace

const YamlNode* YamlNode::find(const std::string& key) const {
  for (const auto& [k, v] : fields)
    if (k == key) return &v;
  return nullptr;
}

YamlNode parse_yaml(const std::string& text_in, const std::string& name) {
  std::string text = text_in;
  // OpenCV writes "%YAML:1.0" (its own reader skips the line); blank it, keeping line numbers.
  if (text.rfind("%YAML:", 0) == 0) text.replace(0, text.find('\n') == std::string::npos ? text.size() : text.find('\n'), "");
  yaml_parser_t parser;
  if (!yaml_parser_initialize(&parser)) throw std::runtime_error("libyaml: cannot initialise a parser");
  std::unique_ptr<yaml_parser_t, void (*)(yaml_parser_t*)> guard(&parser, yaml_parser_delete);
  yaml_parser_set_input_string(&parser, reinterpret_cast<const unsigned char*>(text.data()), text.size());
  yaml_document_t doc;
  if (!yaml_parser_load(&parser, &doc)) {
    const int line = static_cast<int>(parser.problem_mark.line) + 1;
    throw std::invalid_argument(name + ":" + std::to_string(line) + ": YAML syntax error: " +
                                (parser.problem ? parser.problem : "unreadable") +
                                (parser.context ? std::string(" ") + parser.context : std::string()));
  }
  std::unique_ptr<yaml_document_t, void (*)(yaml_document_t*)> doc_guard(&doc, yaml_document_delete);
  yaml_node_t* root = yaml_document_get_root_node(&doc);
  if (!root) throw std::invalid_argument(name + ":1: empty YAML document");
  return convert(doc, root, 0);
}

}  // namespace skypol::camera::detail
