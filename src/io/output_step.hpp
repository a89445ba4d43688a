#pragma once
/// \file output_step.hpp
/// \brief One output step of a scenario: a parallel HDF5 file with an XDMF index beside it, and VTK
/// image pieces (.vti per rank, .pvti) appended to a .pvd time series, all ParaView-readable.
///
/// Usage per output step: construct, add cell arrays (owned cells only, x fastest), `write()`.
/// The `OutputLayout` selects the written cells (output.region, output.stride) and the HDF5
/// storage (chunks, deflate); the arrays are always given for every owned cell.
/// Files: <dir>/<prefix>_<step>.h5 / .xmf, <dir>/vtk/<prefix>_<step>.pvti (+ pieces),
/// <dir>/<prefix>.pvd (rewritten by rank 0 with every step written so far).
#include <map>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "grid/decomposition.hpp"
#include "io/output_layout.hpp"

namespace biota::io {

/// \brief Output for one step of a cell grid with physical spacing `dx` (m) and `origin` (m).
class OutputStep {
 public:
  OutputStep(const grid::Decomposition& decomp, std::string dir, std::string prefix, long long step,
             double time, double dx, core::Vec3 origin, std::string effective_config,
             std::string units_note, OutputLayout layout = {});
  /// \brief A scalar cell array: local owned cells, x fastest (size = product of local cells).
  void add_scalar(const std::string& name, std::vector<double> values, const std::string& unit);
  /// \brief A 3-vector cell array: local owned cells, interleaved xyz (size = 3 * cells).
  void add_vector(const std::string& name, std::vector<double> values, const std::string& unit);
  /// \brief Write HDF5 (collective), XDMF and VTK; updates the .pvd on rank 0. Collective.
  void write();
  /// \brief Path of the HDF5 file (so other writers, e.g. particles, can add groups to it later).
  std::string h5_path() const;

 private:
  struct Array {
    std::vector<double> data;
    int ncomp;
    std::string unit;
  };
  void add(const std::string& name, std::vector<double> values, int ncomp, const std::string& unit);
  /// \brief The selected cells of a local owned-cell array (x fastest, `ncomp` interleaved);
  /// `local` itself when every cell is selected. Applied as an array is added, so that a step
  /// with output.stride or output.region keeps only the selection.
  std::vector<double> select(std::vector<double> local, int ncomp) const;
  /// \brief Rank 0: the .pvti of the pieces, the .pvd entry and the .xmf of the HDF5 file.
  void write_indexes(const std::string& stem, const core::Index3& n, const core::Vec3& origin,
                     double spacing) const;

  const grid::Decomposition& decomp_;
  std::string dir_, prefix_;
  long long step_;
  double time_, dx_;
  core::Vec3 origin_;
  std::string config_, units_;
  OutputLayout layout_;
  std::vector<std::pair<std::string, Array>> arrays_;
};

}  // namespace biota::io
