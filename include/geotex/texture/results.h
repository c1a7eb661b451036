#pragma once
//! \file results.h The descriptions of the texture results (core/results.h): what `geotex texture extract |
//! transfer | atlas | synthesize --report` write and what the Python results hold, declared once.

#include "geotex/core/results.h"
#include "geotex/texture/synthesis.h"
#include "geotex/texture/texture.h"
#include "geotex/texture/transfer.h"

namespace geotex {

const ResultTable<TextureExtraction>& texture_extraction_results();
const ResultTable<TextureDamage>& texture_damage_results();  //!< part of the transfer's and the atlas'
const ResultTable<TransferResult>& transfer_results();
const ResultTable<AtlasResult>& atlas_results();
const ResultTable<SynthesisResult>& synthesis_results();
//! synthesis_quality()'s measures (the front ends measure every synthesis they run).
const ResultTable<SynthesisQuality>& synthesis_quality_results();

}  // namespace geotex
