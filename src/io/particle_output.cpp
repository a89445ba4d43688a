#include "io/particle_output.hpp"

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkTypeUInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataWriter.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "io/hdf5_util.hpp"
#include "io/pvd_series.hpp"
#include "io/write_file.hpp"
#include "io/xdmf_attribute.hpp"

namespace biota::io {

namespace {

// Exclusive prefix sum and total of a per-rank count (fixes the offsets of rank blocks).
std::pair<hsize_t, hsize_t> offset_and_total(MPI_Comm comm, std::size_t n) {
  unsigned long long mine = n, before = 0, total = 0;
  MPI_Exscan(&mine, &before, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) before = 0;  // MPI_Exscan leaves rank 0's result undefined
  MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
  return {before, total};
}

void check_sizes(const ParticleData& d) {
  const std::size_t n = d.ids.size();
  if (d.positions.size() != 3 * n) throw std::logic_error("ParticleOutput: positions != 3 * ids");
  if (d.owned > n) throw std::logic_error("ParticleOutput: owned > points");
  for (const auto& [name, v] : d.scalars)
    if (v.size() != n) throw std::logic_error("ParticleOutput: scalar " + name + " has wrong size");
  for (const auto& [name, v] : d.vectors)
    if (v.size() != 3 * n)
      throw std::logic_error("ParticleOutput: vector " + name + " has wrong size");
  for (const auto& l : d.lines)
    if (l[0] >= n || l[1] >= n) throw std::logic_error("ParticleOutput: line index out of range");
  for (const auto& [name, v] : d.line_scalars)
    if (v.size() != d.lines.size())
      throw std::logic_error("ParticleOutput: line scalar " + name + " has wrong size");
  const auto& t = d.surface;
  if (t.positions.size() % 3 != 0 || t.triangles.size() % 3 != 0)
    throw std::logic_error("ParticleOutput: surface arrays are not triples");
  for (const auto v : t.triangles)
    if (v >= t.positions.size() / 3)
      throw std::logic_error("ParticleOutput: surface vertex index out of range");
  for (const auto& [name, v] : t.cell_scalars)
    if (!v.empty() && v.size() != t.triangles.size() / 3)
      throw std::logic_error("ParticleOutput: surface scalar " + name + " has wrong size");
}

// The surface as VTK PolyData (triangles, cell scalars); rank 0.
void write_surface_vtp(const SurfaceData& t, const std::string& path, int compression) {
  vtkNew<vtkPolyData> poly;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  const std::size_t nv = t.positions.size() / 3, nt = t.triangles.size() / 3;
  pts->SetNumberOfPoints(static_cast<vtkIdType>(nv));
  for (std::size_t i = 0; i < nv; ++i)
    pts->SetPoint(static_cast<vtkIdType>(i), t.positions[3 * i], t.positions[3 * i + 1],
                  t.positions[3 * i + 2]);
  poly->SetPoints(pts);
  vtkNew<vtkCellArray> polys;
  for (std::size_t k = 0; k < nt; ++k) {
    const vtkIdType abc[3] = {static_cast<vtkIdType>(t.triangles[3 * k]),
                              static_cast<vtkIdType>(t.triangles[3 * k + 1]),
                              static_cast<vtkIdType>(t.triangles[3 * k + 2])};
    polys->InsertNextCell(3, abc);
  }
  poly->SetPolys(polys);
  for (const auto& [name, v] : t.cell_scalars) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->SetNumberOfTuples(static_cast<vtkIdType>(nt));
    std::copy(v.begin(), v.end(), a->GetPointer(0));
    poly->GetCellData()->AddArray(a);
  }
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(poly);
  write_vtk_checked(*writer, path, compression);
}

}  // namespace

ParticleOutput::ParticleOutput(MPI_Comm comm, std::string dir, std::string prefix, long long step,
                               double time, std::string effective_config, int vtk_compression)
    : comm_(comm),
      dir_(std::move(dir)),
      prefix_(std::move(prefix)),
      step_(step),
      time_(time),
      config_(std::move(effective_config)),
      vtk_compression_(vtk_compression) {}

void ParticleOutput::write(const ParticleData& d) {
  check_sizes(d);
  namespace fs = std::filesystem;
  int rank = 0, size = 1;
  MPI_Comm_rank(comm_, &rank);
  MPI_Comm_size(comm_, &size);
  const std::string stem = fmt::format("{}_{:06d}", prefix_, step_);
  const fs::path vtk_dir = fs::path(dir_) / "vtk";
  if (rank == 0) fs::create_directories(vtk_dir);
  MPI_Barrier(comm_);

  // ---------------- HDF5: owned points in rank order at Exscan offsets; each line with its own
  // two end points (a line may end on a ghost copy whose row lives on another rank, so lines
  // carry their geometry instead of indices into the point rows).
  const std::size_t no = d.owned, nl = d.lines.size();
  const auto [p_off, p_tot] = offset_and_total(comm_, no);
  const auto [l_off, l_tot] = offset_and_total(comm_, nl);
  WriteFile h5_file((fs::path(dir_) / (stem + ".h5")).string(), comm_, "output");
  const hid_t file = h5_file.id();
  h5::write_string_attribute(file, "config", config_);
  h5::write_double_attribute(file, "time", time_);
  h5::write_int_attribute(file, "step", step_);
  h5::write_int_attribute(file, "points", static_cast<long long>(p_tot));
  h5::write_int_attribute(file, "lines", static_cast<long long>(l_tot));
  auto write_rows = [&](const std::string& name, const void* data, int ncomp, hsize_t off,
                        hsize_t total, std::size_t count, hid_t type = H5T_NATIVE_DOUBLE) {
    std::vector<hsize_t> g = {total}, o = {off}, c = {count};
    if (ncomp > 1) g.push_back(ncomp), o.push_back(0), c.push_back(ncomp);
    h5_file.write_block(name, g, o, c, static_cast<const double*>(data), type);
  };
  if (p_tot > 0) {  // none at all (a moss population that died out): no /points datasets
    // The owned points are the first `no` rows of each array (the ghost copies follow).
    write_rows("/points/position", d.positions.data(), 3, p_off, p_tot, no);
    write_rows("/points/id", d.ids.data(), 1, p_off, p_tot, no, H5T_NATIVE_UINT64);
    for (const auto& [name, v] : d.scalars)
      write_rows("/points/" + name, v.data(), 1, p_off, p_tot, no);
    for (const auto& [name, v] : d.vectors)
      write_rows("/points/" + name, v.data(), 3, p_off, p_tot, no);
  }
  if (l_tot > 0) {  // a zero-size global dataset cannot be written (point clouds have no lines)
    std::vector<double> lpos(6 * nl);
    std::vector<std::uint64_t> lids(2 * nl), conn(2 * nl);
    for (std::size_t k = 0; k < nl; ++k)
      for (int e = 0; e < 2; ++e) {
        const std::size_t p = d.lines[k][e];
        for (int c = 0; c < 3; ++c) lpos[6 * k + 3 * e + c] = d.positions[3 * p + c];
        lids[2 * k + e] = d.ids[p];
        conn[2 * k + e] = 2 * (l_off + k) + e;
      }
    write_rows("/lines/position", lpos.data(), 3, 2 * l_off, 2 * l_tot, 2 * nl);
    write_rows("/lines/connectivity", conn.data(), 2, l_off, l_tot, nl, H5T_NATIVE_UINT64);
    write_rows("/lines/id", lids.data(), 2, l_off, l_tot, nl, H5T_NATIVE_UINT64);
    for (const auto& [name, v] : d.line_scalars)
      write_rows("/lines/" + name, v.data(), 1, l_off, l_tot, nl);
  }
  // Surface: replicated, rank 0's copy (the others write empty blocks).
  const auto& surf = d.surface;
  const std::size_t sv = rank == 0 ? surf.positions.size() / 3 : 0;
  const std::size_t st = rank == 0 ? surf.triangles.size() / 3 : 0;
  const auto [sv_off, sv_tot] = offset_and_total(comm_, sv);
  const auto [st_off, st_tot] = offset_and_total(comm_, st);
  if (st_tot > 0) {
    write_rows("/surface/position", surf.positions.data(), 3, sv_off, sv_tot, sv);
    write_rows("/surface/triangles", surf.triangles.data(), 3, st_off, st_tot, st,
               H5T_NATIVE_UINT64);
    for (const auto& [name, v] : surf.cell_scalars)
      write_rows("/surface/" + name, v.data(), 1, st_off, st_tot, st);
  }
  const double h5_bytes = h5_file.close();

  // ---------------- VTK piece of this rank: all points (ghost copies flagged), owned points as
  // vertices, segments as lines.
  const std::size_t np = d.ids.size();
  const std::string piece = fmt::format("{}_{:04d}.vtp", stem, rank);
  // The pieces hold the HDF5 file's values and the ghost copies (a fifth more, at most).
  require_free_space(comm_, (vtk_dir / piece).string(), 1.2 * h5_bytes, "output",
                     "the VTK pieces of " + stem);
  run_agreed(comm_, true, [&] {
    vtkNew<vtkPolyData> poly;
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    pts->SetNumberOfPoints(static_cast<vtkIdType>(np));
    for (std::size_t i = 0; i < np; ++i)
      pts->SetPoint(static_cast<vtkIdType>(i), d.positions[3 * i], d.positions[3 * i + 1],
                    d.positions[3 * i + 2]);
    poly->SetPoints(pts);
    vtkNew<vtkCellArray> verts, lines;
    for (std::size_t i = 0; i < no; ++i) {
      const vtkIdType v = static_cast<vtkIdType>(i);
      verts->InsertNextCell(1, &v);
    }
    for (const auto& l : d.lines) {
      const vtkIdType ab[2] = {static_cast<vtkIdType>(l[0]), static_cast<vtkIdType>(l[1])};
      lines->InsertNextCell(2, ab);
    }
    poly->SetVerts(verts);
    poly->SetLines(lines);
    vtkNew<vtkTypeUInt64Array> ids;
    ids->SetName("id");
    ids->SetNumberOfTuples(static_cast<vtkIdType>(np));
    std::copy(d.ids.begin(), d.ids.end(), ids->GetPointer(0));
    poly->GetPointData()->AddArray(ids);
    vtkNew<vtkUnsignedCharArray> ghost;
    ghost->SetName("ghost");
    ghost->SetNumberOfTuples(static_cast<vtkIdType>(np));
    for (std::size_t i = 0; i < np; ++i) ghost->SetValue(static_cast<vtkIdType>(i), i >= no);
    poly->GetPointData()->AddArray(ghost);
    auto add_point_array = [&](const std::string& name, const std::vector<double>& v, int nc) {
      vtkNew<vtkDoubleArray> a;
      a->SetName(name.c_str());
      a->SetNumberOfComponents(nc);
      a->SetNumberOfTuples(static_cast<vtkIdType>(np));
      std::copy(v.begin(), v.end(), a->GetPointer(0));
      poly->GetPointData()->AddArray(a);
    };
    for (const auto& [name, v] : d.scalars) add_point_array(name, v, 1);
    for (const auto& [name, v] : d.vectors) add_point_array(name, v, 3);
    // Cell data covers verts first, then lines (VTK's cell order); verts get NaN.
    for (const auto& [name, v] : d.line_scalars) {
      vtkNew<vtkDoubleArray> a;
      a->SetName(name.c_str());
      a->SetNumberOfTuples(static_cast<vtkIdType>(no + nl));
      for (std::size_t i = 0; i < no; ++i) a->SetValue(static_cast<vtkIdType>(i), std::nan(""));
      for (std::size_t k = 0; k < nl; ++k) a->SetValue(static_cast<vtkIdType>(no + k), v[k]);
      poly->GetCellData()->AddArray(a);
    }
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetInputData(poly);
    write_vtk_checked(*writer, (vtk_dir / piece).string(), vtk_compression_);
  });

  // ---------------- .pvtp index, .pvd series, XDMF (rank 0).
  run_agreed(comm_, rank == 0, [&] { write_indexes(d, stem, {p_tot, l_tot, sv_tot, st_tot}); });
}

void ParticleOutput::write_indexes(const ParticleData& d, const std::string& stem,
                                   const Totals& totals) const {
  namespace fs = std::filesystem;
  int size = 1;
  MPI_Comm_size(comm_, &size);
  const fs::path vtk_dir = fs::path(dir_) / "vtk";
  const auto& surf = d.surface;
  const unsigned long long p_tot = totals.points, l_tot = totals.lines,
                           sv_tot = totals.surface_vertices, st_tot = totals.surface_triangles;
  {
    std::ostringstream out;
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PPolyData\" version=\"1.0\" "
           "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<PPolyData GhostLevel=\"0\">\n"
           "<PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/></PPoints>\n";
    out << "<PPointData>\n<PDataArray type=\"UInt64\" Name=\"id\"/>\n"
           "<PDataArray type=\"UInt8\" Name=\"ghost\"/>\n";
    for (const auto& [name, v] : d.scalars)
      out << fmt::format("<PDataArray type=\"Float64\" Name=\"{}\"/>\n", name);
    for (const auto& [name, v] : d.vectors)
      out << fmt::format("<PDataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"3\"/>\n",
                         name);
    out << "</PPointData>\n<PCellData>\n";
    for (const auto& [name, v] : d.line_scalars)
      out << fmt::format("<PDataArray type=\"Float64\" Name=\"{}\"/>\n", name);
    out << "</PCellData>\n";
    for (int r = 0; r < size; ++r)
      out << fmt::format("<Piece Source=\"{}_{:04d}.vtp\"/>\n", stem, r);
    out << "</PPolyData>\n</VTKFile>\n";
    write_text_file((vtk_dir / (stem + ".pvtp")).string(), out.str());
  }
  update_pvd((fs::path(dir_) / (prefix_ + ".pvd")).string(), step_, time_, "vtk/" + stem + ".pvtp");
  if (st_tot > 0) {
    write_surface_vtp(surf, (vtk_dir / (stem + "_surface.vtp")).string(), vtk_compression_);
    update_pvd((fs::path(dir_) / (prefix_ + "_surface.pvd")).string(), step_, time_,
               "vtk/" + stem + "_surface.vtp");
  }
  {
    std::ostringstream out;
    const std::string h5 = stem + ".h5";
    out << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n";
    out << fmt::format(
        "<Grid Name=\"{}\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
        "<Time Value=\"{:.17g}\"/>\n",
        prefix_, time_);
    if (p_tot > 0) {
      out << fmt::format(
          "<Grid Name=\"points\" GridType=\"Uniform\">\n"
          "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{0}\" "
          "NodesPerElement=\"1\"/>\n"
          "<Geometry GeometryType=\"XYZ\"><DataItem Format=\"HDF\" NumberType=\"Float\" "
          "Precision=\"8\" Dimensions=\"{0} 3\">{1}:/points/position</DataItem></Geometry>\n"
          "<Attribute Name=\"id\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
          "Format=\"HDF\" "
          "NumberType=\"UInt\" Precision=\"8\" Dimensions=\"{0}\">{1}:/points/id</DataItem>"
          "</Attribute>\n",
          p_tot, h5);
      for (const auto& [name, v] : d.scalars)
        out << xdmf_attribute(name, false, "Node", std::to_string(p_tot), h5 + ":/points/" + name);
      for (const auto& [name, v] : d.vectors)
        out << xdmf_attribute(name, true, "Node", std::to_string(p_tot) + " 3",
                              h5 + ":/points/" + name);
      out << "</Grid>\n";
    }
    if (l_tot > 0) {
      out << fmt::format(
          "<Grid Name=\"lines\" GridType=\"Uniform\">\n"
          "<Topology TopologyType=\"Polyline\" NumberOfElements=\"{0}\" NodesPerElement=\"2\">"
          "<DataItem Format=\"HDF\" NumberType=\"UInt\" Precision=\"8\" Dimensions=\"{0} 2\">"
          "{1}:/lines/connectivity</DataItem></Topology>\n"
          "<Geometry GeometryType=\"XYZ\"><DataItem Format=\"HDF\" NumberType=\"Float\" "
          "Precision=\"8\" Dimensions=\"{2} 3\">{1}:/lines/position</DataItem></Geometry>\n",
          l_tot, h5, 2 * l_tot);
      for (const auto& [name, v] : d.line_scalars)
        out << xdmf_attribute(name, false, "Cell", std::to_string(l_tot), h5 + ":/lines/" + name);
      out << "</Grid>\n";
    }
    if (st_tot > 0) {
      out << fmt::format(
          "<Grid Name=\"surface\" GridType=\"Uniform\">\n"
          "<Topology TopologyType=\"Triangle\" NumberOfElements=\"{0}\">"
          "<DataItem Format=\"HDF\" NumberType=\"UInt\" Precision=\"8\" Dimensions=\"{0} 3\">"
          "{1}:/surface/triangles</DataItem></Topology>\n"
          "<Geometry GeometryType=\"XYZ\"><DataItem Format=\"HDF\" NumberType=\"Float\" "
          "Precision=\"8\" Dimensions=\"{2} 3\">{1}:/surface/position</DataItem></Geometry>\n",
          st_tot, h5, sv_tot);
      for (const auto& [name, v] : surf.cell_scalars)
        out << xdmf_attribute(name, false, "Cell", std::to_string(st_tot),
                              h5 + ":/surface/" + name);
      out << "</Grid>\n";
    }
    out << "</Grid>\n</Domain>\n</Xdmf>\n";
    write_text_file((fs::path(dir_) / (stem + ".xmf")).string(), out.str());
  }
}

}  // namespace biota::io
