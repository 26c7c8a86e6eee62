// stack::BackgroundFileStream: the bytes a stack's writer hands it reach the file at their offsets,
// a stack written through it is byte for byte the file OpenEXR's own file stream writes, and its
// failures name the file.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <unistd.h>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>

#include "scene/truth.h"
#include "stack/exr_ostream.h"
#include "stack/stack_io.h"
#include "test_files.h"

using namespace skypol;
namespace fs = std::filesystem;

namespace {
fs::path temp_dir() { return test::temp_dir("skypol-ostream-test"); }
using test::file_bytes;
}  // namespace

TEST_CASE("the background stream puts every byte where it was written, across blocks and seeks back", "[stack][ostream]") {
  const fs::path dir = temp_dir();
  const fs::path path = dir / "bytes.bin";
  // Small blocks, two of them: most writes span blocks and the caller waits for the thread.
  std::mt19937 rng(7);
  std::string expected;
  {
    stack::BackgroundFileStream out(path.string(), 1000, 2);
    for (int k = 0; k < 400; ++k) {
      const int n = std::uniform_int_distribution<int>(0, 2500)(rng);
      std::string chunk(static_cast<std::size_t>(n), '\0');
      for (char& c : chunk) c = static_cast<char>(rng());
      CHECK(out.tellp() == expected.size());
      out.write(chunk.data(), n);
      expected += chunk;
    }
    // OpenEXR seeks back to fill in its offset tables, then forward to the end again.
    const std::string table = "offset-table";
    out.seekp(8);
    CHECK(out.tellp() == 8);
    out.write(table.data(), static_cast<int>(table.size()));
    expected.replace(8, table.size(), table);
    out.seekp(expected.size());
    out.write("end", 3);
    expected += "end";
    out.finish();
  }
  CHECK(expected.size() > 400000);
  CHECK(file_bytes(path) == expected);
  fs::remove_all(dir);
}

TEST_CASE("a stack written through the background stream is the file OpenEXR's own stream writes", "[stack][ostream]") {
  // The same headers (read back from the stack) and pixels, written by OpenEXR to a file name (its
  // std::ofstream, its thread pool as it is set), must give the same bytes, for compressions that
  // encode per scanline (and run without the pool) and per chunk of lines (with it).
  const fs::path dir = temp_dir();
  const int w = 301, h = 203;  // more lines than a zip or piz chunk, and not a multiple of either
  std::vector<scene::Truth> truths(3);
  for (std::size_t i = 0; i < truths.size(); ++i) truths[i].time.unix_seconds = 1.6e9 + 1800.0 * static_cast<double>(i);
  const std::vector<std::string> channels{"AoLP.Y", "DoLP.Y", "mask"};
  auto fill = [&](std::size_t i, stack::Frame& f) {
    f.width = w, f.height = h;
    for (std::size_t k = 0; k < channels.size(); ++k) {
      std::vector<float>& v = f.channels[channels[k]];
      v.resize(static_cast<std::size_t>(w) * h);
      for (std::size_t j = 0; j < v.size(); ++j) v[j] = std::sin(0.001f * static_cast<float>(j * (k + 1) + 97 * i));
    }
  };
  for (const char* compression : {"none", "rle", "zips", "zip", "piz"}) {
    for (const bool as_half : {false, true}) {
      INFO(compression << (as_half ? " half" : " float"));
      const fs::path ours = dir / "ours.exr", theirs = dir / "theirs.exr";
      stack::WriteOptions o;
      o.compression = compression;
      o.half = as_half;
      stack::Frame frame;
      stack::write_stack_reusing(ours.string(), truths, channels, w, h, {}, o, [&](std::size_t i) -> const stack::Frame& {
        fill(i, frame);
        return frame;
      });
      {
        Imf::MultiPartInputFile in(ours.string().c_str());
        std::vector<Imf::Header> headers;
        for (int p = 0; p < in.parts(); ++p) headers.push_back(in.header(p));
        Imf::MultiPartOutputFile out(theirs.string().c_str(), headers.data(), static_cast<int>(headers.size()));
        for (int p = 0; p < in.parts(); ++p) {
          fill(static_cast<std::size_t>(p), frame);
          Imf::FrameBuffer fb;
          std::vector<std::vector<Imath::half>> halves(channels.size());
          for (std::size_t k = 0; k < channels.size(); ++k) {
            const std::string& c = channels[k];
            std::vector<float>& v = frame.channels[c];
            if (headers[static_cast<std::size_t>(p)].channels().findChannel(c)->type == Imf::HALF) {
              // Imath's rounding; the values are far inside half's range, so skypol's clamp
              // changes nothing.
              halves[k].assign(v.begin(), v.end());
              fb.insert(c, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves[k].data()), sizeof(Imath::half),
                                      sizeof(Imath::half) * w));
            } else {
              fb.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(v.data()), sizeof(float), sizeof(float) * w));
            }
          }
          Imf::OutputPart part(out, p);
          part.setFrameBuffer(fb);
          part.writePixels(h);
        }
      }
      const std::string a = file_bytes(ours), b = file_bytes(theirs);
      CHECK(a.size() > 1000);
      CHECK(a == b);
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("the background stream names the file it cannot create or write", "[stack][ostream][errors]") {
  const fs::path dir = temp_dir();
  const std::string missing = (dir / "no-such-folder" / "x.exr").string();
  try {
    stack::BackgroundFileStream out(missing);
    FAIL("no error");
  } catch (const std::runtime_error& e) {
    CHECK_THAT(e.what(), Catch::Contains(missing) && Catch::Contains("No such file"));
  }
  // /dev/full refuses every write (ENOSPC): the failure comes back from finish(), or from a
  // later write, naming the file; destroying a stream that failed does not throw.
  if (fs::exists("/dev/full")) {
    stack::BackgroundFileStream out("/dev/full", 64, 2);
    const std::string bytes(1000, 'x');
    try {
      for (int k = 0; k < 100; ++k) out.write(bytes.data(), static_cast<int>(bytes.size()));
      out.finish();
      FAIL("no error");
    } catch (const std::runtime_error& e) {
      CHECK_THAT(e.what(), Catch::Contains("/dev/full") && Catch::Contains("No space"));
    }
  }
  fs::remove_all(dir);
}
