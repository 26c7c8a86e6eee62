// studies/tradeoff_compression.cpp (`skypol tradeoff compression --small`): each setting's channel
// errors against bounds that come from the formats, not from the study (half keeps 10 mantissa
// bits; pxr24 keeps 15 of float's 23), the lossy ones seen to lose, the zip level seen
// to reach the file, and half's effect on every estimator far below a tenth of a degree.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "sky/units.h"
#include "studies/tradeoff_studies.h"
#include "csv_fields.h"

using skypol::deg_from_rad;

namespace fs = std::filesystem;

namespace {

using Row = std::map<std::string, std::string>;

std::vector<Row> read_csv(const fs::path& p) {
  std::ifstream in(p);
  REQUIRE(in);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> head = skypol::test::csv_fields(line);
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = skypol::test::csv_fields(line);
    REQUIRE(cells.size() == head.size());
    Row r;
    for (std::size_t i = 0; i < head.size(); ++i) r[head[i]] = cells[i];
    rows.push_back(r);
  }
  return rows;
}

const fs::path& small_run() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("skypol-compression-test-" + std::to_string(::getpid()));
    skypol::studies::tradeoff::StudyOptions o;
    o.out_dir = d.string();
    o.small = true;
    skypol::studies::tradeoff::study_compression(o);
    return d;
  }();
  return dir;
}

const Row& find(const std::vector<Row>& rows, const std::string& type, const std::string& compression,
                const std::string& stack, const std::string& zip_level = "") {
  for (const Row& r : rows)
    if (r.at("pixel_type") == type && r.at("compression") == compression && r.at("stack") == stack &&
        (zip_level.empty() || r.at("zip_level") == zip_level))
      return r;
  FAIL("no row " << type << " " << compression << " " << stack << " " << zip_level);
  throw;
}

double num(const Row& r, const std::string& col) { return std::stod(r.at(col)); }

constexpr double kUlpAtOne = 1.0 / 1024;  // half: 10 stored mantissa bits, so the ulp of [1, 2) is 2^-10

}  // namespace

TEST_CASE("compression study: lossless settings give back the floats or their half rounding", "[studies][compression]") {
  const std::vector<Row> t = read_csv(small_run() / "compression.csv");
  REQUIRE(t.size() == 14);  // --small: 7 settings × 2 stacks
  for (const char* stack : {"ideal", "sensor"}) {
    const Row& f = find(t, "float", "none", stack);
    CHECK(f.at("exact") == "1");
    CHECK(num(f, "DoLP_max") == 0);
    CHECK(num(f, "AoLP_deg_max") == 0);
    CHECK(num(f, "file_mb") >= num(f, "raw_mb"));  // none stores every byte, plus headers
    for (const char* c : {"none", "zip"}) {
      const Row& h = find(t, "half", c, stack);
      CHECK(h.at("exact") == "1");
      // Round to nearest: half an ulp. DoLP is below 1 (ulp 2^-11); AoLP below π/2 radians (ulp 2^-10).
      CHECK(num(h, "DoLP_max") > 0);
      CHECK(num(h, "DoLP_max") <= kUlpAtOne / 4 * 1.0001);
      CHECK(num(h, "AoLP_deg_max") <= deg_from_rad(kUlpAtOne / 2) * 1.0001);
    }
  }
  const Row& ideal_half = find(t, "half", "none", "ideal");
  CHECK(num(ideal_half, "S0_max") > 0);
}

TEST_CASE("compression study: the lossy settings are seen to lose, each by what its format implies", "[studies][compression]") {
  const std::vector<Row> t = read_csv(small_run() / "compression.csv");
  for (const char* stack : {"ideal", "sensor"}) {
    const Row& b44 = find(t, "half", "b44", stack);
    CHECK(b44.at("exact") == "0");
    CHECK(num(b44, "AoLP_deg_max") > 5);  // 4×4 blocks share an exponent: AoLP near ±90° loses degrees
    const Row& pxr = find(t, "float", "pxr24", stack);
    CHECK(pxr.at("exact") == "0");
    CHECK(num(pxr, "DoLP_max") > 0);
    CHECK(num(pxr, "DoLP_max") <= std::ldexp(1.0, -16));  // 15 stored mantissa bits: ulp of [0.5, 1) is 2^-16
  }
}

TEST_CASE("compression study: the zip level reaches the file, and half halves it at least", "[studies][compression]") {
  const std::vector<Row> t = read_csv(small_run() / "compression.csv");
  for (const char* stack : {"ideal", "sensor"}) {
    CHECK(num(find(t, "half", "zip", stack, "9"), "file_mb") < num(find(t, "half", "zip", stack, "4"), "file_mb"));
    CHECK(num(find(t, "half", "zip", stack, "4"), "file_mb") < 0.5 * num(find(t, "float", "zip", stack), "file_mb"));
    CHECK(num(find(t, "float", "zip", stack), "file_mb") < num(find(t, "float", "none", stack), "file_mb"));
  }
}

TEST_CASE("compression study: half changes no estimator's error by a tenth of a degree", "[studies][compression]") {
  const std::vector<Row> e = read_csv(small_run() / "compression_estimates.csv");
  std::map<std::string, double> float_error;
  for (const Row& r : e)
    if (r.at("pixel_type") == "float" && r.at("compression") == "lossless" && r.at("valid") == "1")
      float_error[r.at("stack") + "/" + r.at("method")] = std::stod(r.at("angular_error_deg"));
  REQUIRE(float_error.size() >= 10);
  int compared = 0;
  for (const Row& r : e) {
    if (r.at("pixel_type") != "half" || r.at("compression") != "lossless") continue;
    const std::string key = r.at("stack") + "/" + r.at("method");
    REQUIRE(float_error.count(key));
    REQUIRE(r.at("valid") == "1");
    CHECK(std::abs(std::stod(r.at("angular_error_deg")) - float_error[key]) < 0.1);
    ++compared;
  }
  CHECK(compared == static_cast<int>(float_error.size()));
  fs::remove_all(small_run());
}
