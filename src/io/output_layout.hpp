#pragma once
/// \file output_layout.hpp
/// \brief Which cells of a grid field an output step writes (`output.region`, `output.stride`) and
/// how its HDF5 datasets are stored (`output.chunk`, `output.compression`).
///
/// The selection is a box of global cells [lo, hi) and a stride k: the cells lo + m k (m = 0, 1,
/// ...) along each axis. Output cell m is centred on the centre of its source cell, with spacing
/// k dx, so ParaView overlays a strided field on the full one. Everything here depends only on the
/// global grid and the deck, never on the rank count: the written content is rank-independent.
#include <string>

#include "core/config.hpp"
#include "core/types.hpp"
#include "grid/decomposition.hpp"

namespace biota::io {

struct OutputLayout {
  /// Selected global cells [lo, hi). An empty box (the default) means the whole grid.
  grid::Box region{};
  int stride = 1;       ///< every k-th cell along each axis, starting at region.lo
  int chunk = 32;       ///< HDF5 chunk edge in output cells (0: contiguous datasets)
  int compression = 0;  ///< deflate level 0-9 of HDF5 datasets and VTK pieces (0: none)

  /// \brief The region resolved against a grid of `cells` (the whole grid when unset).
  grid::Box resolved(const core::Index3& cells) const;
  /// \brief Output cells along each axis for a grid of `cells`: ceil(extent / stride).
  core::Index3 out_cells(const core::Index3& cells) const;
  /// \brief The output-index box [lo, hi) of the selected cells inside the global cell box
  /// `block` (may be empty).
  grid::Box out_box(const core::Index3& cells, const grid::Box& block) const;
  /// \brief Origin of the output grid: output cell m is centred on source cell lo + m k.
  core::Vec3 out_origin(const core::Index3& cells, double dx, const core::Vec3& origin) const;
  /// \brief One line for the start-up log, e.g. "output: region ... stride 2 -> 12 x 10 x 9
  /// cells; HDF5 chunks of 32^3 cells, deflate 4".
  std::string describe(const core::Index3& cells, double dx, const core::Vec3& origin) const;
};

/// \brief Declare output.region, output.stride, output.chunk, output.compression.
void declare_output_layout_config(core::ConfigSchema& s);

/// \brief The layout of a grid of `cells` cubic cells of size `dx` (m) whose corner is `origin`:
/// `output.region` (physical box, cells selected by their centres, clipped to the domain) must
/// select at least one cell; otherwise one InputError naming the key, its value and the domain.
OutputLayout output_layout(const core::Config& cfg, const core::Index3& cells, double dx,
                           const core::Vec3& origin);

/// \brief Layout for an output that is always written whole (chunk and compression only);
/// `output.region` or `output.stride` in the deck is an InputError with `why` as the reason.
OutputLayout output_layout_whole(const core::Config& cfg, const std::string& why);

}  // namespace biota::io
