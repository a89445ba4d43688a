#include "io/output_layout.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace biota::io {

grid::Box OutputLayout::resolved(const core::Index3& cells) const {
  const auto e = region.extent();
  if (e.x <= 0 || e.y <= 0 || e.z <= 0) return {{0, 0, 0}, cells};
  return region;
}

core::Index3 OutputLayout::out_cells(const core::Index3& cells) const {
  const auto e = resolved(cells).extent();
  return {(e.x + stride - 1) / stride, (e.y + stride - 1) / stride, (e.z + stride - 1) / stride};
}

grid::Box OutputLayout::out_box(const core::Index3& cells, const grid::Box& block) const {
  const grid::Box r = resolved(cells);
  grid::Box out;
  for (int a = 0; a < 3; ++a) {
    const int lo = std::max(block.lo[a], r.lo[a]), hi = std::min(block.hi[a], r.hi[a]);
    // Output index m has source cell r.lo + m k; the cells in [lo, hi) are m in
    // [ceil((lo - r.lo) / k), ceil((hi - r.lo) / k)).
    out.lo[a] = hi > lo ? (lo - r.lo[a] + stride - 1) / stride : 0;
    out.hi[a] = hi > lo ? (hi - r.lo[a] + stride - 1) / stride : 0;
  }
  return out;
}

core::Vec3 OutputLayout::out_origin(const core::Index3& cells, double dx,
                                    const core::Vec3& origin) const {
  const grid::Box r = resolved(cells);
  core::Vec3 o;
  for (int a = 0; a < 3; ++a) o[a] = origin[a] + (r.lo[a] + 0.5 - 0.5 * stride) * dx;
  return o;
}

std::string OutputLayout::describe(const core::Index3& cells, double dx,
                                   const core::Vec3& origin) const {
  const grid::Box r = resolved(cells);
  const auto n = out_cells(cells);
  std::string s = fmt::format(
      "output: cells x [{}, {}) y [{}, {}) z [{}, {}) of {} x {} x {} (centres in [{:.6g}, {:.6g}] "
      "x [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] m), stride {} -> {} x {} x {} cells per field",
      r.lo.x, r.hi.x, r.lo.y, r.hi.y, r.lo.z, r.hi.z, cells.x, cells.y, cells.z,
      origin.x + (r.lo.x + 0.5) * dx, origin.x + (r.hi.x - 0.5) * dx,
      origin.y + (r.lo.y + 0.5) * dx, origin.y + (r.hi.y - 0.5) * dx,
      origin.z + (r.lo.z + 0.5) * dx, origin.z + (r.hi.z - 0.5) * dx, stride, n.x, n.y, n.z);
  if (chunk > 0)
    s += fmt::format("; HDF5 chunks of up to {}^3 cells", chunk);
  else
    s += "; HDF5 contiguous";
  if (compression > 0) s += fmt::format(", deflate level {} (HDF5 and VTK)", compression);
  return s;
}

void declare_output_layout_config(core::ConfigSchema& s) {
  s.add_real_list("output.region", std::nullopt, 6, "m",
                  "(optional) box [x_lo, y_lo, z_lo, x_hi, y_hi, z_hi] of grid field output: only "
                  "cells whose centres lie inside are written (clipped to the domain; must select "
                  "a cell). Unset: the whole grid");
  s.add_int("output.stride", 1, 1, 1'000'000,
            "write every k-th cell of grid fields along each axis, from the region's first cell");
  s.add_int("output.chunk", 32, 0, 512,
            "HDF5 chunk edge of grid field datasets in output cells (0: contiguous; chunks are "
            "needed for compression)");
  s.add_int("output.compression", 0, 0, 9,
            "deflate level of grid field datasets (HDF5, with shuffle; VTK pieces zlib) and of "
            "the particles' VTK pieces; 0: none. Parallel HDF5 >= 1.10.2 (collective filtered "
            "writes)");
}

namespace {
// A schema without these keys (a test building a scenario from its own keys only) gets defaults.
int int_or(const core::Config& cfg, const char* key, int def) {
  return cfg.schema().find(key) ? static_cast<int>(cfg.get_int(key)) : def;
}

OutputLayout storage(const core::Config& cfg) {
  OutputLayout l;
  l.chunk = int_or(cfg, "output.chunk", l.chunk);
  l.compression = int_or(cfg, "output.compression", l.compression);
  if (l.compression > 0 && l.chunk == 0)
    cfg.fail("output.compression",
             "needs chunked datasets: set output.chunk to 1-512 (HDF5 compresses chunk by chunk)");
  return l;
}
}  // namespace

OutputLayout output_layout(const core::Config& cfg, const core::Index3& cells, double dx,
                           const core::Vec3& origin) {
  OutputLayout l = storage(cfg);
  l.stride = int_or(cfg, "output.stride", 1);
  if (!cfg.has("output.region")) return l;
  const auto& b = cfg.get_real_list("output.region");
  const std::string domain = fmt::format(
      "the domain is [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] m ({} x {} "
      "x {} cells of {:.6g} m)",
      origin.x, origin.x + cells.x * dx, origin.y, origin.y + cells.y * dx, origin.z,
      origin.z + cells.z * dx, cells.x, cells.y, cells.z, dx);
  for (int a = 0; a < 3; ++a)
    if (!(b[a] <= b[a + 3]))
      cfg.fail("output.region", fmt::format("is not a box: give [x_lo, y_lo, z_lo, x_hi, y_hi, "
                                            "z_hi] with lo <= hi on every axis; {}",
                                            domain));
  // Cell i (centre origin + (i + 1/2) dx) is selected if lo <= centre <= hi (to 1e-9 dx).
  const double eps = 1e-9;
  for (int a = 0; a < 3; ++a) {
    const double lo = (b[a] - origin[a]) / dx - 0.5, hi = (b[a + 3] - origin[a]) / dx - 0.5;
    const double first = std::max(0.0, std::ceil(lo - eps));
    const double last = std::min(double(cells[a] - 1), std::floor(hi + eps));
    if (last < first)
      cfg.fail("output.region",
               fmt::format("selects no cell ({} axis: no cell centre in [{:.6g}, {:.6g}] m); {}",
                           "xyz"[a], b[a], b[a + 3], domain));
    l.region.lo[a] = static_cast<int>(first);
    l.region.hi[a] = static_cast<int>(last) + 1;
  }
  return l;
}

OutputLayout output_layout_whole(const core::Config& cfg, const std::string& why) {
  if (cfg.has("output.region")) cfg.fail("output.region", why);
  if (int_or(cfg, "output.stride", 1) != 1) cfg.fail("output.stride", why);
  return storage(cfg);
}

}  // namespace biota::io
