#pragma once
//! \file results.h The descriptions of the toolkit's results (core/results.h): what `geotex param --json`
//! writes and what Python's parametrization_quality() returns, declared once.

#include "geotex/core/results.h"
#include "geotex/toolkit/parametrization.h"

namespace geotex {

const ResultTable<ParamQuality>& param_quality_results();

}  // namespace geotex
