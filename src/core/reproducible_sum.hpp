#pragma once
/// \file reproducible_sum.hpp
/// \brief Global sums whose result does not depend on how the terms are spread over the ranks or
/// ordered on one: the same bits on any decomposition.
///
/// A floating-point sum depends on its order, and MPI_Allreduce adds the ranks' partial sums in
/// an order of its own. Here every term is cut, on a grid fixed by the global largest term
/// (2^e > max |t|), into three integer slices of at most 32 bits at 2^(e-32), 2^(e-64) and
/// 2^(e-96) (each the nearest integer to what is left); the slices are summed as integers
/// (exact, so in any order), and the integer total is rounded to a double once. The result is
/// the correctly rounded sum of the terms rounded to the grid 2^(e-96), i.e. within
/// 2^-96 n max |t| of the exact sum: more accurate than a plain sum, and reproducible.
/// Terms that are not finite give the plain sum (an infinity or NaN, as MPI_SUM would).
/// Cost: two passes over the terms and two small reductions (docs/decisions.md).
#include <mpi.h>

#include <cstddef>

namespace biota::core {

/// \brief Sum over all ranks of x[i] * y[i], i < n (each rank its own n), reproducibly.
/// \throws std::runtime_error if the ranks hold 2^30 terms or more together (the integer slices
/// could overflow).
double reproducible_dot(const double* x, const double* y, std::size_t n, MPI_Comm comm);

/// \brief Sum over all ranks of x[i], i < n, reproducibly.
double reproducible_sum(const double* x, std::size_t n, MPI_Comm comm);

/// \brief Sum over all ranks of |x[i]|, i < n, reproducibly.
double reproducible_abs_sum(const double* x, std::size_t n, MPI_Comm comm);

}  // namespace biota::core
