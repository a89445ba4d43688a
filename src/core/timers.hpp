#pragma once
/// \file timers.hpp
/// \brief Named wall-clock timers and a PETSc -log_view / LAMMPS-style summary over ranks.
#include <mpi.h>

#include <map>
#include <string>

namespace biota::core {

/// \brief Accumulates wall time per named section; `report` prints min/avg/max over ranks.
class Timers {
 public:
  /// \brief RAII scope that adds its lifetime to a section.
  class Scope {
   public:
    Scope(Timers& t, const std::string& name) : t_(t), name_(name), start_(MPI_Wtime()) {}
    ~Scope() { t_.add(name_, MPI_Wtime() - start_); }

   private:
    Timers& t_;
    std::string name_;
    double start_;
  };
  Scope scope(const std::string& name) { return Scope(*this, name); }
  void add(const std::string& name, double seconds) { sections_[name] += seconds; }
  double total(const std::string& name) const {
    auto it = sections_.find(name);
    return it == sections_.end() ? 0.0 : it->second;
  }
  /// \brief Table of every section (collective): the ranks first agree on the union of their
  /// section names (one missing on a rank counts as 0). Returns the text on rank 0, empty
  /// elsewhere.
  std::string report(MPI_Comm comm, double wall_total) const;
  const std::map<std::string, double>& sections() const { return sections_; }

 private:
  std::map<std::string, double> sections_;
};

}  // namespace biota::core
