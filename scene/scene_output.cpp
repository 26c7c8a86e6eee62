// The [output] section: where the stack goes, which channels, and how they are stored. The
// defaults and the lossy list come from `skypol tradeoff compression` (docs/benchmarks.md,
// "Recommended defaults"): a stack is evidence for an estimator's error, so a compression that
// changes Stokes values is written only when the scene says it accepts that.
#include <algorithm>

#include "scene/output_defaults.h"
#include "scene/scene.h"

namespace skypol::scene {

std::string lossy_compression_loss(const std::string& compression, bool half) {
  // Measured on the paper's day at 153×128 (docs/benchmarks.md, "Pixel type and compression"):
  // the largest error over the sky pixels of the stack read back against the floats written.
  // b44 and b44a pack half channels only (float ones are stored as they are); pxr24 rounds float
  // to 24 bits and leaves half alone; DWA quantizes channels named *.R, *.G, *.B and *.Y whatever
  // their type.
  if (compression == "b44" || compression == "b44a") {
    return half ? "AoLP errors up to 29°, DoLP up to 0.08" : "";
  }
  if (compression == "dwaa" || compression == "dwab") return "AoLP errors up to 1.4°, DoLP up to 0.011";
  if (compression == "pxr24" && !half) return "relative errors up to 2^-16 (it rounds float to 24 bits)";
  return "";
}

OutputSpec read_output(Fields& o, const std::string& stem, bool has_sensor) {
  OutputSpec out;
  out.path = o.string("path", "out/" + stem + ".exr");
  out.channels = o.strings("channels", out.channels);
  bool stokes = false;
  for (const std::string& ch : out.channels) {
    static const std::vector<std::string> legal{"S0", "S1", "S2", "S3", "DoLP", "AoLP", "mask", "raw"};
    if (std::find(legal.begin(), legal.end(), ch) == legal.end()) {
      o.fail("channels", "unknown channel '" + ch + "' (expected S0, S1, S2, S3, DoLP, AoLP, mask, raw)");
    }
    if (ch == "raw" && !has_sensor) o.fail("channels", "'raw' is the sensor's mosaic: it needs a [sensor] section");
    stokes = stokes || (ch != "mask" && ch != "raw");  // mask and raw stay float and lossless
  }
  out.half = o.choice("pixel_type", kDefaultHalf ? "half" : "float", {"float", "half"}) == "half";
  out.compression = o.choice("compression", out.compression,
                             {"none", "zip", "zips", "piz", "rle", "pxr24", "b44", "b44a", "dwaa", "dwab"});
  if (o.has("zip_level")) {
    if (out.compression != "zip" && out.compression != "zips")
      o.fail("zip_level", "is the deflate level of zip and zips; compression is \"" + out.compression + "\"");
    out.zip_level = static_cast<int>(o.integer("zip_level", 0, 1, 9));
  }
  out.allow_lossy = o.boolean("allow_lossy", false);
  out.previews = o.boolean("previews", false);
  if (const std::string loss = lossy_compression_loss(out.compression, out.half); stokes && !loss.empty() &&
                                                                                   !out.allow_lossy) {
    o.fail(o.has("compression") ? "compression" : "pixel_type",
           "\"" + out.compression + "\" on " + (out.half ? "half" : "float") + " channels is lossy (" + loss +
               " in docs/benchmarks.md's compression study): set allow_lossy = true to accept that, or use a "
               "lossless compression (none, zip, zips, piz, rle" + (out.half ? ", pxr24" : "") + ")");
  }
  o.finish();
  return out;
}

}  // namespace skypol::scene
