#pragma once
/// \file error.hpp
/// \brief Error types and the exit codes they map to.
#include <stdexcept>
#include <string>

namespace biota::core {

/// \brief Exit codes of the biota executable.
enum ExitCode : int { kExitOk = 0, kExitRuntime = 1, kExitInput = 2, kExitUnstable = 3 };

/// \brief Bad user input (deck, command line, files named by them). Exit code 2, before any output.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief The simulation became unphysical (non-finite values, density out of bounds). Exit code 3.
class UnstableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace biota::core
