#include "io/output_step.hpp"

#include <fmt/format.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkXMLImageDataWriter.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "core/agreement.hpp"
#include "io/hdf5_util.hpp"
#include "io/pvd_series.hpp"
#include "io/write_file.hpp"
#include "io/xdmf_attribute.hpp"

namespace biota::io {

OutputStep::OutputStep(const grid::Decomposition& decomp, std::string dir, std::string prefix,
                       long long step, double time, double dx, core::Vec3 origin,
                       std::string effective_config, std::string units_note, OutputLayout layout)
    : decomp_(decomp),
      dir_(std::move(dir)),
      prefix_(std::move(prefix)),
      step_(step),
      time_(time),
      dx_(dx),
      origin_(origin),
      config_(std::move(effective_config)),
      units_(std::move(units_note)),
      layout_(layout) {}

void OutputStep::add_scalar(const std::string& name, std::vector<double> values,
                            const std::string& unit) {
  add(name, std::move(values), 1, unit);
}

void OutputStep::add_vector(const std::string& name, std::vector<double> values,
                            const std::string& unit) {
  add(name, std::move(values), 3, unit);
}

void OutputStep::add(const std::string& name, std::vector<double> values, int ncomp,
                     const std::string& unit) {
  if (static_cast<long long>(values.size()) != ncomp * decomp_.local_cells().product())
    throw std::logic_error("OutputStep: wrong size for " + name);
  arrays_.emplace_back(name, Array{select(std::move(values), ncomp), ncomp, unit});
}

std::vector<double> OutputStep::select(std::vector<double> local, int ncomp) const {
  const auto& g = decomp_.global_cells();
  const auto& box = decomp_.local_box();
  if (layout_.stride == 1 && layout_.resolved(g).extent() == g) return local;
  const grid::Box ob = layout_.out_box(g, box);
  const auto oe = ob.extent();
  const grid::Box r = layout_.resolved(g);
  const auto e = box.extent();
  const int k = layout_.stride;
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(std::max(0LL, oe.product())) * ncomp);
  for (int mz = ob.lo.z; mz < ob.hi.z; ++mz)
    for (int my = ob.lo.y; my < ob.hi.y; ++my)
      for (int mx = ob.lo.x; mx < ob.hi.x; ++mx) {
        // Source cell of output cell m: r.lo + m k (global), minus the block's first cell.
        const long long i = r.lo.x + mx * k - box.lo.x, j = r.lo.y + my * k - box.lo.y,
                        l = r.lo.z + mz * k - box.lo.z;
        const double* src = local.data() + ((l * e.y + j) * e.x + i) * ncomp;
        out.insert(out.end(), src, src + ncomp);
      }
  return out;
}

std::string OutputStep::h5_path() const {
  return fmt::format("{}/{}_{:06d}.h5", dir_, prefix_, step_);
}

void OutputStep::write() {
  const auto& g = decomp_.global_cells();
  const auto& box = decomp_.local_box();
  const std::string stem = fmt::format("{}_{:06d}", prefix_, step_);
  // The written grid: the selected cells (output.region, output.stride) as a grid of its own.
  const core::Index3 n = layout_.out_cells(g);
  const grid::Box ob = layout_.out_box(g, box);
  const auto oe = ob.extent();
  const bool have_cells = oe.x > 0 && oe.y > 0 && oe.z > 0;
  const core::Vec3 origin = layout_.out_origin(g, dx_, origin_);
  const double spacing = dx_ * layout_.stride;

  // --- HDF5: one file, global datasets [Z][Y][X](,3), collective hyperslab writes; chunks and
  // filters depend on the written grid only, so the file content is rank-independent.
  WriteFile h5_file(h5_path(), decomp_.comm(), "output");
  const hid_t file = h5_file.id();
  h5::write_string_attribute(file, "config", config_);
  h5::write_string_attribute(file, "units", units_);
  h5::write_double_attribute(file, "time", time_);
  h5::write_int_attribute(file, "step", step_);
  h5::write_double_attribute(file, "dx", spacing);
  h5::write_double_attribute(file, "source_dx", dx_);
  h5::write_int_attribute(file, "stride", layout_.stride);
  {
    const grid::Box r = layout_.resolved(g);
    std::vector<double> o = {origin.x, origin.y, origin.z};
    std::vector<double> first = {double(r.lo.x), double(r.lo.y), double(r.lo.z)};
    h5::write_double_list_attribute(file, "origin", o);
    h5::write_double_list_attribute(file, "first_cell", first);
  }
  for (const auto& [name, a] : arrays_) {
    std::vector<hsize_t> global = {hsize_t(n.z), hsize_t(n.y), hsize_t(n.x)};
    std::vector<hsize_t> offset = {hsize_t(ob.lo.z), hsize_t(ob.lo.y), hsize_t(ob.lo.x)};
    std::vector<hsize_t> count = {hsize_t(oe.z), hsize_t(oe.y), hsize_t(oe.x)};
    if (!have_cells) count = {0, 0, 0};
    std::vector<hsize_t> chunk;
    if (layout_.chunk > 0)
      for (hsize_t d : global) chunk.push_back(std::min<hsize_t>(d, hsize_t(layout_.chunk)));
    if (a.ncomp > 1) {
      global.push_back(a.ncomp);
      offset.push_back(0);
      count.push_back(a.ncomp);
      if (!chunk.empty()) chunk.push_back(a.ncomp);
    }
    h5_file.write_block("/fields/" + name, global, offset, count, a.data.data(), H5T_NATIVE_DOUBLE,
                        chunk, layout_.compression);
    hid_t ds = H5Dopen2(file, ("/fields/" + name).c_str(), H5P_DEFAULT);
    h5::write_string_attribute(ds, "unit", a.unit);
    H5Dclose(ds);
  }
  // A failed close (disk full) must not leave a file that looks like a finished output step.
  const double h5_bytes = h5_file.close();

  // --- VTK piece of this rank (point extents are cell extents + 1).
  std::filesystem::path vtk_dir = std::filesystem::path(dir_) / "vtk";
  const std::string piece = fmt::format("{}_{:04d}.vti", stem, decomp_.rank());
  // The pieces hold the values of the HDF5 file without its chunks' overhang (a tenth more for
  // their headers; compressed, at most as much as the HDF5 file).
  double raw_bytes = 0;
  for (const auto& [name, a] : arrays_)
    raw_bytes += 8.0 * a.ncomp * static_cast<double>(n.product());
  require_free_space(decomp_.comm(), (vtk_dir / piece).string(),
                     1.1 * std::min(raw_bytes, layout_.compression > 0 ? h5_bytes : raw_bytes),
                     "output", "the VTK pieces of " + stem);
  // A rank without selected cells writes no piece.
  run_agreed(decomp_.comm(), have_cells, [&] {
    vtkNew<vtkImageData> image;
    image->SetExtent(ob.lo.x, ob.hi.x, ob.lo.y, ob.hi.y, ob.lo.z, ob.hi.z);
    image->SetOrigin(origin.x, origin.y, origin.z);
    image->SetSpacing(spacing, spacing, spacing);
    for (auto& [name, a] : arrays_) {
      vtkNew<vtkDoubleArray> arr;
      arr->SetName(name.c_str());
      arr->SetNumberOfComponents(a.ncomp);
      // The writer reads the array in place (save = 1: VTK neither copies nor frees it), so an
      // output step holds its arrays once, not twice.
      arr->SetArray(a.data.data(), static_cast<vtkIdType>(a.data.size()), 1);
      image->GetCellData()->AddArray(arr);
    }
    vtkNew<vtkXMLImageDataWriter> writer;
    writer->SetInputData(image);
    write_vtk_checked(*writer, (vtk_dir / piece).string(), layout_.compression);
  });
  // The index files, rank 0.
  run_agreed(decomp_.comm(), decomp_.rank() == 0, [&] { write_indexes(stem, n, origin, spacing); });
}

void OutputStep::write_indexes(const std::string& stem, const core::Index3& n,
                               const core::Vec3& origin, double spacing) const {
  const std::filesystem::path vtk_dir = std::filesystem::path(dir_) / "vtk";
  const auto& g = decomp_.global_cells();
  // --- .pvti index of the pieces.
  {
    std::ostringstream out;
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PImageData\" version=\"1.0\" "
           "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    out << fmt::format(
        "<PImageData WholeExtent=\"0 {} 0 {} 0 {}\" GhostLevel=\"0\" "
        "Origin=\"{} {} {}\" Spacing=\"{} {} {}\">\n<PCellData>\n",
        n.x, n.y, n.z, origin.x, origin.y, origin.z, spacing, spacing, spacing);
    for (const auto& [name, a] : arrays_)
      out << fmt::format("<PDataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n",
                         name, a.ncomp);
    out << "</PCellData>\n";
    const auto& dims = decomp_.dims();
    for (int cz = 0; cz < dims.z; ++cz)
      for (int cy = 0; cy < dims.y; ++cy)
        for (int cx = 0; cx < dims.x; ++cx) {
          int coords[3] = {cx, cy, cz}, r = 0;
          MPI_Cart_rank(decomp_.comm(), coords, &r);
          const auto b = layout_.out_box(g, decomp_.box_of({cx, cy, cz}));
          const auto be = b.extent();
          if (be.x <= 0 || be.y <= 0 || be.z <= 0) continue;
          out << fmt::format("<Piece Extent=\"{} {} {} {} {} {}\" Source=\"{}_{:04d}.vti\"/>\n",
                             b.lo.x, b.hi.x, b.lo.y, b.hi.y, b.lo.z, b.hi.z, stem, r);
        }
    out << "</PImageData>\n</VTKFile>\n";
    write_text_file((vtk_dir / (stem + ".pvti")).string(), out.str());
  }
  update_pvd((std::filesystem::path(dir_) / (prefix_ + ".pvd")).string(), step_, time_,
             "vtk/" + stem + ".pvti");

  // --- XDMF index of the HDF5 file (3DCoRectMesh: point dims are cells + 1, data on cells).
  {
    std::ostringstream out;
    const std::string h5name = stem + ".h5";
    out << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n";
    out << fmt::format("<Grid Name=\"{}\" GridType=\"Uniform\">\n<Time Value=\"{:.17g}\"/>\n",
                       prefix_, time_);
    out << fmt::format("<Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"{} {} {}\"/>\n",
                       n.z + 1, n.y + 1, n.x + 1);
    out << "<Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n";
    out << fmt::format(
        "<DataItem Format=\"XML\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"3\">{:.17g} "
        "{:.17g} {:.17g}</DataItem>\n",
        origin.z, origin.y, origin.x);
    out << fmt::format(
        "<DataItem Format=\"XML\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"3\">{:.17g} "
        "{:.17g} {:.17g}</DataItem>\n",
        spacing, spacing, spacing);
    out << "</Geometry>\n";
    for (const auto& [name, a] : arrays_) {
      out << xdmf_attribute(name, a.ncomp > 1, "Cell",
                            fmt::format("{} {} {}{}", n.z, n.y, n.x, a.ncomp > 1 ? " 3" : ""),
                            h5name + ":/fields/" + name);
    }
    out << "</Grid>\n</Domain>\n</Xdmf>\n";
    write_text_file((std::filesystem::path(dir_) / (stem + ".xmf")).string(), out.str());
  }
}

}  // namespace biota::io
