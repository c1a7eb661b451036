// Cancellation points (progress.h).

#include "geotex/core/progress.h"

#include <omp.h>

namespace geotex {

void check_interrupt() {
  const std::atomic<bool>* flag = InterruptScope::current();
  if (flag && flag->load(std::memory_order_relaxed) && !omp_in_parallel()) throw Interrupted();
}

}  // namespace geotex
