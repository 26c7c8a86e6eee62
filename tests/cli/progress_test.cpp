// The progress line's arithmetic: rate and time left from the count and the elapsed time.
#include <catch2/catch.hpp>

#include "cli/commands.h"

using skypol::cli::progress_line;

TEST_CASE("the progress line states the rate and the time left", "[cli][progress]") {
  // 3 of 10 in 2 s: 1.5 a second, 7 more take 4.67 s.
  CHECK(progress_line(3, 10, 2.0, "frames") == "[#########                     ] 3/10 frames, 1.5/s, 5 s left");
  // Slower than one a second reads as seconds each; 9 left at 10 s each is 1 min 30 s.
  CHECK(progress_line(1, 10, 10.0, "methods") == "[###                           ] 1/10 methods, 10.0 s each, 1 min 30 s left");
  // Done: the time it took instead of the time left.
  CHECK(progress_line(4, 4, 7200.0, "variants") == "[##############################] 4/4 variants, 1800.0 s each, 2 h 00 min");
  // Nothing done yet: no rate to state.
  CHECK(progress_line(0, 5, 1.0, "frames") == "[                              ] 0/5 frames");
}
