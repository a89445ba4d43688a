#pragma once
/// \file lsystem_command.hpp
/// \brief `biota lsystem FILE`: derive an L-system and print its string and turtle summary.
#include <cstdint>
#include <string>

namespace biota::app {

/// \brief Options of `biota lsystem`.
struct LSystemCommandOptions {
  std::string file;
  int derivations = -1;  ///< < 0: the file's
  std::uint64_t seed = 1;
  std::uint64_t tree_id = 0;
  long long max_modules = 10'000'000;
  std::string vtk;  ///< write the segments as polylines with radius (.vtp)
  bool print_string = false;
};

/// \brief Print the summary (rank 0 only). Throws core::InputError on a bad grammar.
int run_lsystem_command(const LSystemCommandOptions& opt, bool root);

}  // namespace biota::app
