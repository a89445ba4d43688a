#pragma once
/// \file reproducible_vec.hpp
/// \brief PETSc vectors whose inner products and norms are the same bits on any decomposition
/// (core::reproducible_dot), so a Krylov solve on them takes the same steps on 1, 2 or 3 ranks.
/// Private to src/linalg (the only layer that includes petsc.h).
#include <petscmat.h>
#include <petscvec.h>

namespace biota::linalg {

/// \brief Route v's dot, transpose dot, multiple dots and norms through the reproducible sums.
/// Vectors duplicated from v (VecDuplicate of a plain MPI vector, e.g. a KSP's work vectors)
/// inherit the routing; those of a DMDA (DMCreateGlobalVector) do not, so use a plain vector.
PetscErrorCode make_reproducible(Vec v);

/// \brief A MATOP_CREATE_VECS for shell matrices (MatShellSetOperation): plain MPI vectors of A's
/// layout, made reproducible, so the work vectors a KSP creates from A are too.
PetscErrorCode reproducible_create_vecs(Mat A, Vec* right, Vec* left);

}  // namespace biota::linalg
