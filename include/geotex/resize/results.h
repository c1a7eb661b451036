#pragma once
//! \file results.h The descriptions of the resizing results (core/results.h): what `geotex resize --report`
//! writes and what Python's resize() and feature_map() results hold, declared once.

#include "geotex/core/results.h"
#include "geotex/resize/feature_map.h"
#include "geotex/resize/resize.h"

namespace geotex {

const ResultTable<FeatureSummary>& feature_summary_results();  //!< part of the two below
const ResultTable<ResizeResult>& resize_results();
const ResultTable<FeatureMap>& feature_map_results();

}  // namespace geotex
