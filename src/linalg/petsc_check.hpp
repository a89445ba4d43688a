#pragma once
/// \file petsc_check.hpp
/// \brief BIOTA_PETSC(call): throw std::runtime_error naming the call and PETSc's message when
/// PETSc returns an error.
/// Private to src/linalg (the only layer that includes petsc.h).
#include <stdexcept>
#include <string>

#include "linalg/petsc_environment.hpp"

#define BIOTA_PETSC(call)                                                                  \
  do {                                                                                     \
    PetscErrorCode biota_ierr_ = (call);                                                   \
    if (biota_ierr_)                                                                       \
      throw std::runtime_error(std::string("PETSc error ") + std::to_string(biota_ierr_) + \
                               " in " #call ": " + biota::linalg::last_error_message());   \
  } while (0)
