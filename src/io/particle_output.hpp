#pragma once
/// \file particle_output.hpp
/// \brief Output of one particle set at one output step: VTK PolyData (.vtp piece per rank +
/// .pvtp, appended to <dir>/<prefix>.pvd) and the particles in an HDF5 file as global datasets
/// gathered by offsets (exclusive scan), with an XDMF (Polyvertex / Polyline) index beside it.
///
/// Files: <dir>/<prefix>_<step>.h5 (+ .xmf), <dir>/vtk/<prefix>_<step>.pvtp (+ one .vtp per
/// rank), <dir>/<prefix>.pvd. HDF5 layout: /points/{position,id,<scalars>,<vectors>} with the
/// owned points in rank order; /lines/{position (2 rows per line), connectivity, id (2 per line),
/// <line scalars>}; with a surface: /surface/{position, triangles, <cell scalars>}, a third XDMF
/// grid "surface", and <dir>/vtk/<prefix>_<step>_surface.vtp in <dir>/<prefix>_surface.pvd.
#include <mpi.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace biota::io {

/// \brief A triangle surface written with the particles (e.g. the moss terrain with its per-face
/// soil state). Replicated data: rank 0's copy is written; the other ranks leave `positions` and
/// `triangles` empty (cell_scalars may be empty there too).
struct SurfaceData {
  std::vector<double> positions;         ///< 3 per vertex, SI [m]
  std::vector<std::uint64_t> triangles;  ///< 3 vertex indices per triangle
  std::vector<std::pair<std::string, std::vector<double>>> cell_scalars;  ///< 1 per triangle
};

/// \brief This rank's particles for one output step. Points may include ghost copies when a line
/// needs both ends; `owned` says how many leading points are owned (only those go to HDF5).
struct ParticleData {
  std::vector<double> positions;   ///< 3 per point, SI [m]
  std::vector<std::uint64_t> ids;  ///< global id per point
  std::size_t owned = 0;           ///< points [0, owned) are owned by this rank
  std::vector<std::pair<std::string, std::vector<double>>> scalars;  ///< 1 value per point
  std::vector<std::pair<std::string, std::vector<double>>> vectors;  ///< 3 values per point
  std::vector<std::array<std::uint32_t, 2>> lines;  ///< segments between local point indices
  std::vector<std::pair<std::string, std::vector<double>>> line_scalars;  ///< 1 per line
  SurfaceData surface;  ///< optional; rank 0 only (see SurfaceData)
};

/// \brief Writes one particle output step. Collective over `comm`.
class ParticleOutput {
 public:
  /// `vtk_compression`: zlib level of the VTK pieces (output.compression; 0: none).
  ParticleOutput(MPI_Comm comm, std::string dir, std::string prefix, long long step, double time,
                 std::string effective_config, int vtk_compression);
  /// \brief Write VTK (.vtp/.pvtp/.pvd) and HDF5 <dir>/<prefix>_<step>.h5 (+ .xmf).
  void write(const ParticleData& data);

 private:
  /// Global counts of the written rows.
  struct Totals {
    unsigned long long points, lines, surface_vertices, surface_triangles;
  };
  /// \brief Rank 0: the .pvtp of the pieces, the .pvd entries, the surface piece and the .xmf.
  void write_indexes(const ParticleData& d, const std::string& stem, const Totals& totals) const;

  MPI_Comm comm_;
  std::string dir_, prefix_;
  long long step_;
  double time_;
  std::string config_;
  int vtk_compression_;
};

}  // namespace biota::io
