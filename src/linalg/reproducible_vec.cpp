#include "linalg/reproducible_vec.hpp"

#include <petsc/private/vecimpl.h>

#include <cmath>
#include <exception>

#include "core/reproducible_sum.hpp"

namespace biota::linalg {

namespace {

/// Runs f, turning an exception into a PETSc error (nothing may unwind through PETSc's C code).
template <class F>
PetscErrorCode guarded(F&& f) {
  try {
    return f();
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
}

MPI_Comm comm_of(Vec v) {
  MPI_Comm c = MPI_COMM_NULL;
  PetscObjectGetComm(reinterpret_cast<PetscObject>(v), &c);
  return c;
}

PetscErrorCode dot(Vec x, Vec y, PetscScalar* value) {
  return guarded([&]() -> PetscErrorCode {
    const PetscScalar *a, *b;
    PetscInt n;
    PetscCall(VecGetLocalSize(x, &n));
    PetscCall(VecGetArrayRead(x, &a));
    PetscCall(VecGetArrayRead(y, &b));
    *value = core::reproducible_dot(a, b, static_cast<std::size_t>(n), comm_of(x));
    PetscCall(VecRestoreArrayRead(x, &a));
    PetscCall(VecRestoreArrayRead(y, &b));
    return 0;
  });
}

PetscErrorCode mdot(Vec x, PetscInt nv, const Vec y[], PetscScalar* values) {
  for (PetscInt k = 0; k < nv; ++k) PetscCall(dot(x, y[k], values + k));
  return 0;
}

PetscErrorCode norm(Vec x, NormType type, PetscReal* value) {
  return guarded([&]() -> PetscErrorCode {
    const PetscScalar* a;
    PetscInt n;
    PetscCall(VecGetLocalSize(x, &n));
    PetscCall(VecGetArrayRead(x, &a));
    const auto len = static_cast<std::size_t>(n);
    const MPI_Comm c = comm_of(x);
    PetscErrorCode err = 0;
    switch (type) {
      case NORM_1:
        *value = core::reproducible_abs_sum(a, len, c);
        break;
      case NORM_2:
      case NORM_FROBENIUS:
        *value = std::sqrt(core::reproducible_dot(a, a, len, c));
        break;
      case NORM_INFINITY: {  // a maximum: exact in any order; a NaN wins, as in PETSc
        double m = 0;
        for (std::size_t i = 0; i < len; ++i) {
          const double v = std::fabs(a[i]);
          if (!(v <= m)) m = v;
          if (std::isnan(v)) break;
        }
        MPI_Allreduce(MPI_IN_PLACE, &m, 1, MPI_DOUBLE, MPI_MAX, c);
        *value = m;
        break;
      }
      case NORM_1_AND_2:
        value[0] = core::reproducible_abs_sum(a, len, c);
        value[1] = std::sqrt(core::reproducible_dot(a, a, len, c));
        break;
      default:
        err = PETSC_ERR_SUP;
    }
    PetscCall(VecRestoreArrayRead(x, &a));
    return err;
  });
}

}  // namespace

PetscErrorCode make_reproducible(Vec v) {
  // The public VecOperation enum of PETSc 3.18 names only a few operations; VecSetOperation
  // indexes the table of the private header, so the entries are set there by name.
  v->ops->dot = dot;
  v->ops->tdot = dot;
  v->ops->mdot = mdot;
  v->ops->mtdot = mdot;
  v->ops->norm = norm;
  return 0;
}

PetscErrorCode reproducible_create_vecs(Mat A, Vec* right, Vec* left) {
  PetscInt m, n, M, N;
  PetscCall(MatGetLocalSize(A, &m, &n));
  PetscCall(MatGetSize(A, &M, &N));
  MPI_Comm c;
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &c));
  if (right) {
    PetscCall(VecCreateMPI(c, n, N, right));
    PetscCall(make_reproducible(*right));
  }
  if (left) {
    PetscCall(VecCreateMPI(c, m, M, left));
    PetscCall(make_reproducible(*left));
  }
  return 0;
}

}  // namespace biota::linalg
