#pragma once
/// \file ghost_fold.hpp
/// \brief The push-side halo: values a rank wrote into its ghost layer are moved onto the owned
/// cells of the neighbour (or periodic image) they belong to, overwriting them.
///
/// The in-place LBM (AA pattern) streams post-collision populations straight into the neighbour
/// cell, so on every other step a population leaving the rank lands in its ghost layer. Each ghost
/// location has exactly one writer (the owned cell it was streamed from), so assignment is exact.
/// Three passes, z then y then x; every pass covers the full ghosted extent of the other two axes,
/// so a value in an edge or corner ghost travels on to the diagonal neighbour, and a value in a
/// ghost outside a non-periodic face (the LBM's free-slip source of a neighbour's cell) reaches the
/// rank next to it along the face.
#include <mpi.h>

#include <array>
#include <vector>

#include "grid/decomposition.hpp"
#include "grid/field.hpp"
#include "grid/halo_exchange.hpp"

namespace biota::grid {

class GhostFold {
 public:
  /// \brief `faces[a][s]`: components carried from my ghost layer at side s (0 = low) of axis a.
  GhostFold(const Decomposition& decomp, Field<core::Real>& field, FaceComponents faces);
  ~GhostFold();
  GhostFold(const GhostFold&) = delete;
  GhostFold& operator=(const GhostFold&) = delete;

  /// \brief Move the listed ghost components onto the neighbours' owned cells (ghosts unchanged).
  void fold() {
    begin();
    end();
  }
  /// \brief The fold split for overlap with computation: `begin` completes the passes before the
  /// last one with a neighbour (lowest such axis, `overlap_axis`), then packs and starts that one;
  /// `end` waits and writes the owned layers next to its faces.
  void begin();
  void end();
  int overlap_axis() const { return overlap_axis_; }

 private:
  struct Pass {
    std::array<std::vector<core::Real>, 2> send, recv;
    std::array<MPI_Request, 4> requests{MPI_REQUEST_NULL, MPI_REQUEST_NULL, MPI_REQUEST_NULL,
                                        MPI_REQUEST_NULL};
  };
  template <class F>
  void for_slab(int axis, int start, const std::vector<int>& comps, F&& f);
  void start_pass(int axis);
  void finish_pass(int axis);

  const Decomposition& decomp_;
  Field<core::Real>* field_;
  FaceComponents faces_;
  std::array<Pass, 3> passes_;
  int overlap_axis_ = -1;
};

}  // namespace biota::grid
