#pragma once
//! \file progress.h Progress reporting for long operations: an optional callback in options structs.

#include <functional>
#include <string_view>

namespace geotex {

//! Called with the fraction done in [0, 1] and a short name of the current stage.
using ProgressFn = std::function<void(double fraction, std::string_view stage)>;

inline void report(const ProgressFn& fn, double fraction, std::string_view stage) {
  if (fn) fn(fraction, stage);
}

}  // namespace geotex
