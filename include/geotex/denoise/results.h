#pragma once
//! \file results.h The descriptions of the denoising results (core/results.h): what `geotex denoise
//! --report` writes and what the Python results hold, for each method, declared once.

#include <string>

#include "geotex/core/results.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/surfel.h"

namespace geotex {

//! What every denoising run reports besides its method's result (each front end times the call).
struct DenoiseRun {
  std::string method;  //!< the method's name (auto, mrf, mrf-normal, surfel)
  double seconds = 0;  //!< wall time of the denoising call
};

const ResultTable<DenoiseRun>& denoise_run_results();
const ResultTable<AutoDenoiseResult>& auto_denoise_results();
const ResultTable<MrfResult>& mrf_results();  //!< mrf and mrf-normal
const ResultTable<SurfelDenoiseResult>& surfel_denoise_results();

}  // namespace geotex
