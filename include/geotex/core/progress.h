#pragma once
//! \file progress.h Progress reporting and cancellation for long operations: an optional callback in
//! options structs, and cancellation points (check_interrupt()) between the steps of every long loop.

#include <atomic>
#include <functional>
#include <string_view>

#include "geotex/core/error.h"

namespace geotex {

//! Called with the fraction done in [0, 1] and a short name of the current stage.
using ProgressFn = std::function<void(double fraction, std::string_view stage)>;

//! Thrown by check_interrupt() when the computation was asked to stop (the caller turns it into its
//! own notion of an interrupt: Python's KeyboardInterrupt).
class Interrupted : public Error {
 public:
  Interrupted() : Error("interrupted") {}
};

//! While alive, computations on the calling thread stop at their next check_interrupt() once \p flag
//! is set (a front end sets it from its signal handler: one relaxed atomic load per check). Scopes nest;
//! other threads (OpenMP's workers included) are unaffected.
class InterruptScope {
 public:
  explicit InterruptScope(const std::atomic<bool>& flag) noexcept : previous_(current()) { current() = &flag; }
  ~InterruptScope() { current() = previous_; }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
  //! The flag of the innermost scope of this thread, or null.
  static const std::atomic<bool>*& current() noexcept {
    thread_local const std::atomic<bool>* flag = nullptr;
    return flag;
  }

 private:
  const std::atomic<bool>* previous_;
};

//! A cancellation point: throws Interrupted when this thread's InterruptScope flag is set. Cheap (call it
//! every few milliseconds of work); a no-op inside an OpenMP parallel region, which an exception must not leave.
void check_interrupt();

//! For loops inside an OpenMP parallel region, which no exception may leave and whose workers have no
//! InterruptScope of their own: take the calling thread's flag before the region (InterruptScope::current()),
//! skip the remaining work once interrupt_requested(flag), and call check_interrupt() after the region.
inline bool interrupt_requested(const std::atomic<bool>* flag) noexcept {
  return flag && flag->load(std::memory_order_relaxed);
}

//! A progress report, which is also a cancellation point.
inline void report(const ProgressFn& fn, double fraction, std::string_view stage) {
  check_interrupt();
  if (fn) fn(fraction, stage);
}

}  // namespace geotex
