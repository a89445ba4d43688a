#include "io/output_step.hpp"

#include <fmt/format.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkXMLImageDataWriter.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/agreement.hpp"
#include "io/hdf5_util.hpp"
#include "io/pvd_series.hpp"
#include "io/xdmf_attribute.hpp"

namespace biota::io {

OutputStep::OutputStep(const grid::Decomposition& decomp, std::string dir, std::string prefix,
                       long long step, double time, double dx, core::Vec3 origin,
                       std::string effective_config, std::string units_note)
    : decomp_(decomp),
      dir_(std::move(dir)),
      prefix_(std::move(prefix)),
      step_(step),
      time_(time),
      dx_(dx),
      origin_(origin),
      config_(std::move(effective_config)),
      units_(std::move(units_note)) {}

void OutputStep::add_scalar(const std::string& name, std::vector<double> values,
                            const std::string& unit) {
  if (static_cast<long long>(values.size()) != decomp_.local_cells().product())
    throw std::logic_error("OutputStep::add_scalar: wrong size for " + name);
  arrays_.push_back({name, {std::move(values), 1, unit}});
}

void OutputStep::add_vector(const std::string& name, std::vector<double> values,
                            const std::string& unit) {
  if (static_cast<long long>(values.size()) != 3 * decomp_.local_cells().product())
    throw std::logic_error("OutputStep::add_vector: wrong size for " + name);
  arrays_.push_back({name, {std::move(values), 3, unit}});
}

std::string OutputStep::h5_path() const {
  return fmt::format("{}/{}_{:06d}.h5", dir_, prefix_, step_);
}

void OutputStep::write() {
  const auto& g = decomp_.global_cells();
  const auto& box = decomp_.local_box();
  const auto e = box.extent();
  const std::string stem = fmt::format("{}_{:06d}", prefix_, step_);

  // --- HDF5: one file, global datasets [Z][Y][X](,3), collective hyperslab writes.
  hid_t file = h5::create_parallel(h5_path(), decomp_.comm());
  h5::write_string_attribute(file, "config", config_);
  h5::write_string_attribute(file, "units", units_);
  h5::write_double_attribute(file, "time", time_);
  h5::write_int_attribute(file, "step", step_);
  h5::write_double_attribute(file, "dx", dx_);
  for (const auto& [name, a] : arrays_) {
    std::vector<hsize_t> global = {hsize_t(g.z), hsize_t(g.y), hsize_t(g.x)};
    std::vector<hsize_t> offset = {hsize_t(box.lo.z), hsize_t(box.lo.y), hsize_t(box.lo.x)};
    std::vector<hsize_t> count = {hsize_t(e.z), hsize_t(e.y), hsize_t(e.x)};
    if (a.ncomp > 1) {
      global.push_back(a.ncomp);
      offset.push_back(0);
      count.push_back(a.ncomp);
    }
    h5::write_block(file, "/fields/" + name, global, offset, count, a.data.data());
    hid_t ds = H5Dopen2(file, ("/fields/" + name).c_str(), H5P_DEFAULT);
    h5::write_string_attribute(ds, "unit", a.unit);
    H5Dclose(ds);
  }
  // A failed close (disk full) must not leave a file that looks like a finished output step.
  int status = H5Fclose(file) < 0 ? 1 : 0, any = 0;
  if (core::fault_injected("output_close", decomp_.rank())) status = 1;
  MPI_Allreduce(&status, &any, 1, MPI_INT, MPI_MAX, decomp_.comm());
  if (any) {
    if (decomp_.rank() == 0) std::filesystem::remove(h5_path());
    MPI_Barrier(decomp_.comm());
    throw std::runtime_error("output: writing " + h5_path() +
                             " failed (HDF5 close reported an error: disk full or I/O error); "
                             "the partial file was removed");
  }

  // --- VTK piece of this rank (point extents are cell extents + 1).
  std::filesystem::path vtk_dir = std::filesystem::path(dir_) / "vtk";
  const std::string piece = fmt::format("{}_{:04d}.vti", stem, decomp_.rank());
  {
    vtkNew<vtkImageData> image;
    image->SetExtent(box.lo.x, box.hi.x, box.lo.y, box.hi.y, box.lo.z, box.hi.z);
    image->SetOrigin(origin_.x, origin_.y, origin_.z);
    image->SetSpacing(dx_, dx_, dx_);
    for (const auto& [name, a] : arrays_) {
      vtkNew<vtkDoubleArray> arr;
      arr->SetName(name.c_str());
      arr->SetNumberOfComponents(a.ncomp);
      arr->SetNumberOfTuples(static_cast<vtkIdType>(a.data.size() / a.ncomp));
      std::copy(a.data.begin(), a.data.end(), arr->GetPointer(0));
      image->GetCellData()->AddArray(arr);
    }
    vtkNew<vtkXMLImageDataWriter> writer;
    writer->SetInputData(image);
    writer->SetFileName((vtk_dir / piece).string().c_str());
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetHeaderTypeToUInt64();  // 32-bit headers cap an appended array at 4 GiB
    writer->SetIdTypeToInt64();
    if (!writer->Write())
      throw std::runtime_error("VTK: cannot write " + (vtk_dir / piece).string());
  }
  MPI_Barrier(decomp_.comm());
  if (decomp_.rank() != 0) return;

  // --- .pvti index of the pieces.
  {
    std::ofstream out(vtk_dir / (stem + ".pvti"));
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PImageData\" version=\"1.0\" "
           "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    out << fmt::format(
        "<PImageData WholeExtent=\"0 {} 0 {} 0 {}\" GhostLevel=\"0\" "
        "Origin=\"{} {} {}\" Spacing=\"{} {} {}\">\n<PCellData>\n",
        g.x, g.y, g.z, origin_.x, origin_.y, origin_.z, dx_, dx_, dx_);
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
          auto b = decomp_.box_of({cx, cy, cz});
          out << fmt::format("<Piece Extent=\"{} {} {} {} {} {}\" Source=\"{}_{:04d}.vti\"/>\n",
                             b.lo.x, b.hi.x, b.lo.y, b.hi.y, b.lo.z, b.hi.z, stem, r);
        }
    out << "</PImageData>\n</VTKFile>\n";
  }
  update_pvd((std::filesystem::path(dir_) / (prefix_ + ".pvd")).string(), step_, time_,
             "vtk/" + stem + ".pvti");

  // --- XDMF index of the HDF5 file (3DCoRectMesh: point dims are cells + 1, data on cells).
  {
    std::ofstream out(std::filesystem::path(dir_) / (stem + ".xmf"));
    const std::string h5name = stem + ".h5";
    out << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n";
    out << fmt::format("<Grid Name=\"{}\" GridType=\"Uniform\">\n<Time Value=\"{:.17g}\"/>\n",
                       prefix_, time_);
    out << fmt::format("<Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"{} {} {}\"/>\n",
                       g.z + 1, g.y + 1, g.x + 1);
    out << "<Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n";
    out << fmt::format("<DataItem Format=\"XML\" Dimensions=\"3\">{} {} {}</DataItem>\n", origin_.z,
                       origin_.y, origin_.x);
    out << fmt::format("<DataItem Format=\"XML\" Dimensions=\"3\">{} {} {}</DataItem>\n", dx_, dx_,
                       dx_);
    out << "</Geometry>\n";
    for (const auto& [name, a] : arrays_) {
      out << xdmf_attribute(name, a.ncomp > 1, "Cell",
                            fmt::format("{} {} {}{}", g.z, g.y, g.x, a.ncomp > 1 ? " 3" : ""),
                            h5name + ":/fields/" + name);
    }
    out << "</Grid>\n</Domain>\n</Xdmf>\n";
  }
}

}  // namespace biota::io
