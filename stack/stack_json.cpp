// `skypol info --json`: every attribute of every part, by its OpenEXR type, so that a new header
// field shows up without this file changing. Numbers at %.17g (a double read back is the same
// double); a non-finite number (none is ever written, but a foreign file may hold one) is null.
#include <cmath>
#include <cstdio>
#include <sstream>

#include <OpenEXR/ImfBoxAttribute.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChannelListAttribute.h>
#include <OpenEXR/ImfCompressionAttribute.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfVecAttribute.h>

#include "scene/json_text.h"
#include "scene/scene_error.h"
#include "stack/stack_io.h"

namespace skypol::stack {
namespace {

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

const char* compression_name(Imf::Compression c) {
  switch (c) {
    case Imf::NO_COMPRESSION: return "none";
    case Imf::RLE_COMPRESSION: return "rle";
    case Imf::ZIPS_COMPRESSION: return "zips";
    case Imf::ZIP_COMPRESSION: return "zip";
    case Imf::PIZ_COMPRESSION: return "piz";
    case Imf::PXR24_COMPRESSION: return "pxr24";
    case Imf::B44_COMPRESSION: return "b44";
    case Imf::B44A_COMPRESSION: return "b44a";
    case Imf::DWAA_COMPRESSION: return "dwaa";
    case Imf::DWAB_COMPRESSION: return "dwab";
    default: return "other";
  }
}

// One attribute's value as JSON; types skypol does not write are named rather than dropped.
std::string value_json(const Imf::Attribute& a) {
  if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&a)) return scene::json_quoted(s->value());
  if (const auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&a)) return num(d->value());
  if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&a)) return num(f->value());
  if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&a)) return std::to_string(i->value());
  if (const auto* v = dynamic_cast<const Imf::V2dAttribute*>(&a)) return "[" + num(v->value().x) + ", " + num(v->value().y) + "]";
  if (const auto* v = dynamic_cast<const Imf::V2fAttribute*>(&a)) return "[" + num(v->value().x) + ", " + num(v->value().y) + "]";
  if (const auto* v = dynamic_cast<const Imf::V3dAttribute*>(&a)) {
    return "[" + num(v->value().x) + ", " + num(v->value().y) + ", " + num(v->value().z) + "]";
  }
  if (const auto* m = dynamic_cast<const Imf::M33dAttribute*>(&a)) {
    std::string out = "[";
    for (int r = 0; r < 3; ++r) {
      out += r ? ", [" : "[";
      for (int c = 0; c < 3; ++c) out += (c ? ", " : "") + num(m->value()[r][c]);
      out += "]";
    }
    return out + "]";
  }
  if (const auto* b = dynamic_cast<const Imf::Box2iAttribute*>(&a)) {
    const Imath::Box2i& v = b->value();
    return "{\"min\": [" + std::to_string(v.min.x) + ", " + std::to_string(v.min.y) + "], \"max\": [" +
           std::to_string(v.max.x) + ", " + std::to_string(v.max.y) + "]}";
  }
  if (const auto* c = dynamic_cast<const Imf::CompressionAttribute*>(&a)) {
    return std::string("\"") + compression_name(c->value()) + "\"";
  }
  if (const auto* cl = dynamic_cast<const Imf::ChannelListAttribute*>(&a)) {
    std::string out = "{";
    bool first = true;
    for (auto it = cl->value().begin(); it != cl->value().end(); ++it) {
      const Imf::PixelType t = it.channel().type;
      out += (first ? "" : ", ") + scene::json_quoted(it.name()) + ": \"" +
             (t == Imf::HALF ? "half" : t == Imf::FLOAT ? "float" : "uint") + "\"";
      first = false;
    }
    return out + "}";
  }
  return "{\"type\": " + scene::json_quoted(a.typeName()) + "}";
}

}  // namespace

std::string describe_stack_json(const std::string& path) {
  std::ostringstream os;
  try {
    Imf::MultiPartInputFile file(path.c_str());
    const StackSummary s = peek_stack(path);  // checks that it is a skypol stack
    os << "{\"stack\": " << scene::json_quoted(path) << ", \"frames\": " << s.frames << ", \"width\": " << s.width
       << ", \"height\": " << s.height << ", \"truth_known\": " << (s.truth_known ? "true" : "false")
       << ", \"site_known\": " << (s.site_known ? "true" : "false") << ",\n \"parts\": [";
    for (int i = 0; i < file.parts(); ++i) {
      const Imf::Header& h = file.header(i);
      os << (i ? ",\n  {" : "\n  {");
      bool first = true;
      for (auto it = h.begin(); it != h.end(); ++it) {
        os << (first ? "" : ",\n   ") << scene::json_quoted(it.name()) << ": " << value_json(it.attribute());
        first = false;
      }
      os << "}";
    }
    os << "]}\n";
  } catch (const scene::SceneError&) {
    throw;
  } catch (const std::exception& e) {
    throw scene::SceneError(scene::FileLoc{path, 0, 0}, std::string("cannot read stack: ") + e.what());
  }
  return os.str();
}

}  // namespace skypol::stack
