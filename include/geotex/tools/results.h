#pragma once
//! \file results.h The descriptions of the metrics' results (core/results.h): what `geotex compare --json`
//! writes and what Python's compare() and score_edge_labels() return, declared once.

#include "geotex/core/results.h"
#include "geotex/tools/metrics.h"

namespace geotex {

const ResultTable<Comparison>& comparison_results();
const ResultTable<LabelScore>& label_score_results();

}  // namespace geotex
