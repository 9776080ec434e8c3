// Typed errors: user input, meshing, solver. Caught once, in main.
#pragma once

#include <stdexcept>
#include <string>

namespace softflow {

/// Base of every error softflow reports to the user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad user input (case file or command line). The message names the key,
/// the offending value and what is allowed.
class InputError : public Error {
 public:
  using Error::Error;
};

/// The mesher could not build the requested geometry.
class MeshError : public Error {
 public:
  using Error::Error;
};

/// A linear or nonlinear solver failed.
class SolverError : public Error {
 public:
  using Error::Error;
};

/// A run left the range where its results can be trusted (e.g. an object's
/// volume drifted past the case's limit): the numbers are finite but wrong.
class AccuracyError : public Error {
 public:
  using Error::Error;
};

/// A run stopped on request (SIGINT, SIGTERM, SIGUSR1, the wall-time limit)
/// after writing a checkpoint: not a failure; `softflow restart` continues it.
class RunInterrupted : public Error {
 public:
  using Error::Error;
};

}  // namespace softflow
