#include "studies/tradeoff_studies.h"

namespace skypol::studies::tradeoff {

const std::vector<Study>& studies() {
  static const std::vector<Study> all = {
      {"spp", "samples per pixel: Stokes error against a high-sample reference vs ms per frame", study_spp},
      {"resolution", "binning: every estimator's error vs its time", study_resolution},
      {"window", "number of frames and observation window: every estimator's error", study_window},
      {"noise", "exposure of the DoFP sensor (shot and read noise): every estimator's error", study_noise},
      {"lens_inverse", "Newton iterations of a Kannala-Brandt inverse: round-trip error vs time",
       study_lens_inverse},
      {"sky_precision", "float vs double sky evaluation: error vs time", study_sky_precision},
      {"throughput", "sky Mpix/s, EXR write and read MB/s, estimator s/stack, by size and frames",
       study_throughput},
      {"calibration",
       "random scenes (sites, dates, windows, tilts, lenses, sensors, clouds, skies): every method's yield, "
       "lie rate and 95 % cone coverage",
       study_calibration},
      {"compression",
       "pixel type x compression (zip levels too): file size, write and read time, channel errors and every "
       "estimator's error on the stack read back",
       study_compression},
  };
  return all;
}

}  // namespace skypol::studies::tradeoff
