#include "app/lsystem_command.hpp"

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <filesystem>
#include <map>

#include "core/error.hpp"
#include "models/plants/lsystem.hpp"
#include "models/plants/turtle.hpp"

namespace biota::app {

namespace {

void write_vtp(const std::string& path, const models::plants::TurtleGeometry& g) {
  vtkNew<vtkPolyData> poly;
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkDoubleArray> radius, order;
  radius->SetName("radius");
  order->SetName("branch_order");
  vtkNew<vtkDoubleArray> seg_radius;
  seg_radius->SetName("radius");
  for (const auto& s : g.segments) {
    const vtkIdType a = pts->InsertNextPoint(s.start.x, s.start.y, s.start.z);
    const vtkIdType b = pts->InsertNextPoint(s.end.x, s.end.y, s.end.z);
    radius->InsertNextValue(s.radius);
    radius->InsertNextValue(s.radius);
    const vtkIdType ab[2] = {a, b};
    lines->InsertNextCell(2, ab);
    order->InsertNextValue(s.order);
    seg_radius->InsertNextValue(s.radius);
  }
  poly->SetPoints(pts);
  poly->SetLines(lines);
  poly->GetPointData()->AddArray(radius);
  poly->GetCellData()->AddArray(seg_radius);
  poly->GetCellData()->AddArray(order);
  vtkNew<vtkXMLPolyDataWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(poly);
  // VTK logs a failed open itself, in colour over several lines, and Write() still returned 1:
  // its own messages off, the writer's error code and the file decide.
  vtkObject::GlobalWarningDisplayOff();
  const int written = w->Write();
  std::error_code ec;
  if (written != 1 || w->GetErrorCode() != 0 || !std::filesystem::is_regular_file(path, ec))
    throw core::InputError(path + ": cannot write the VTK file (--vtk)");
}

}  // namespace

int run_lsystem_command(const LSystemCommandOptions& opt, bool root) {
  namespace mp = models::plants;
  // The image file's name and folder before the derivation, which may take a while.
  if (!opt.vtk.empty()) {
    const std::filesystem::path vtk(opt.vtk);
    std::error_code ec;
    if (vtk.extension() != ".vtp")
      throw core::InputError(fmt::format(
          "--vtk {}: the file must end in .vtp (VTK XML poly data, as ParaView reads it)",
          opt.vtk));
    if (vtk.has_parent_path() && !std::filesystem::is_directory(vtk.parent_path(), ec))
      throw core::InputError(fmt::format("--vtk {}: the folder {} does not exist", opt.vtk,
                                         vtk.parent_path().string()));
  }
  const auto ls = mp::read_lsystem(opt.file);
  mp::DeriveOptions d;
  d.derivations = opt.derivations;
  d.seed = opt.seed;
  d.tree_id = opt.tree_id;
  d.max_modules = static_cast<std::size_t>(opt.max_modules);
  const auto s = [&] {
    try {
      return mp::derive(ls, d);
    } catch (const mp::ModuleCapError& e) {
      throw core::InputError(fmt::format(
          "{} (--max-modules); allowed: at most {} derivations (--derivations) with this cap, or "
          "raise --max-modules",
          e.what(), e.derivation() - 1));
    }
  }();
  const auto g = mp::interpret(ls, s);
  if (!root) return 0;
  std::map<char, long long> count;
  long long pairs = 0;
  for (char c : s.sym) ++count[c], pairs += c == '[';
  fmt::print("lsystem: {} ({} derivations, seed {}, angle {} deg)\n", opt.file,
             opt.derivations >= 0 ? opt.derivations : ls.derivations, opt.seed, ls.angle_deg);
  fmt::print("modules: {}\n", s.size());
  fmt::print("symbols:");
  for (const auto& [c, n] : count) fmt::print(" {}={}", c, n);
  fmt::print("\nbracket pairs: {}\nsegments: {}\n", pairs, g.segments.size());
  fmt::print("bbox min: {:.6f} {:.6f} {:.6f}\nbbox max: {:.6f} {:.6f} {:.6f}\n", g.lo.x, g.lo.y,
             g.lo.z, g.hi.x, g.hi.y, g.hi.z);
  fmt::print("height: {:.6f}\n", g.hi.y - g.lo.y);
  if (opt.print_string) fmt::print("string: {}\n", s.to_string());
  if (!opt.vtk.empty()) {
    write_vtp(opt.vtk, g);
    fmt::print("wrote {}\n", opt.vtk);
  }
  return 0;
}

}  // namespace biota::app
