#pragma once
//! \file error.h Typed errors. Every geotex function reports failure by throwing one of these;
//! the CLI turns them into one line on stderr and a non-zero exit code.

#include <stdexcept>
#include <string>

namespace geotex {

//! Base of every geotex error.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

//! The caller's data or parameters cannot be used (empty mesh, NaN coordinates, not a disk, …).
class InvalidInput : public Error {
 public:
  using Error::Error;
};

//! A file could not be read or written (missing, unreadable, malformed, truncated, …).
class IoError : public Error {
 public:
  using Error::Error;
};

//! A numerical solve failed (matrix not positive definite, no convergence, …).
class SolverError : public Error {
 public:
  using Error::Error;
};

}  // namespace geotex
