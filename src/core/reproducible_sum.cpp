#include "core/reproducible_sum.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace biota::core {

namespace {

constexpr int kLanes = 8;  // independent accumulators, so the passes vectorise
// A slice is below 2^32 in magnitude, so a double accumulator stays an exact integer (< 2^53)
// for 2^21 slices; lanes are flushed to 64-bit integers well before.
constexpr std::size_t kFlushTerms = std::size_t{1} << 20;
// The integer sums of all ranks stay below 2^62 (the top slice's total, shifted by 2^64, in a
// signed 128-bit integer) while there are fewer terms than this.
constexpr double kMaxTerms = 1073741824.0;  // 2^30

/// The sum of term(i), i < n, over all ranks (see the header).
template <class Term>
double sum_terms(std::size_t n, MPI_Comm comm, Term term) {
  // Pass 1: the largest magnitude and whether every term is finite (t - t is NaN otherwise).
  double lane_max[kLanes] = {}, lane_nan[kLanes] = {};
  std::size_t i = 0;
  for (; i + kLanes <= n; i += kLanes)
    for (int l = 0; l < kLanes; ++l) {
      const double t = term(i + l), a = std::fabs(t);
      lane_max[l] = a > lane_max[l] ? a : lane_max[l];
      lane_nan[l] += t - t;
    }
  for (; i < n; ++i) {
    const double t = term(i), a = std::fabs(t);
    lane_max[0] = a > lane_max[0] ? a : lane_max[0];
    lane_nan[0] += t - t;
  }
  double local[3] = {0, 0, static_cast<double>(n) >= kMaxTerms ? 1.0 : 0.0}, global[3];
  for (int l = 0; l < kLanes; ++l) {
    local[0] = lane_max[l] > local[0] ? lane_max[l] : local[0];
    local[1] += lane_nan[l];
  }
  local[1] = local[1] == 0 ? 0.0 : 1.0;  // NaN != 0
  MPI_Allreduce(local, global, 3, MPI_DOUBLE, MPI_MAX, comm);
  if (global[2] > 0)
    throw std::runtime_error("reproducible sum: 2^30 terms or more on one rank");
  if (global[1] > 0) {  // an infinity or a NaN: the plain sum carries it
    double plain = 0, all = 0;
    for (std::size_t k = 0; k < n; ++k) plain += term(k);
    MPI_Allreduce(&plain, &all, 1, MPI_DOUBLE, MPI_SUM, comm);
    return all;
  }
  if (global[0] == 0) return 0.0;
  int e = 0;
  std::frexp(global[0], &e);  // max |t| < 2^e
  // u = t 2^(32 - e) in two exact power-of-two factors (one could leave the double range).
  const int shift = 32 - e;
  const double f1 = std::ldexp(1.0, shift / 2), f2 = std::ldexp(1.0, shift - shift / 2);
  const double two32 = 4294967296.0;
  // Pass 2: each term's three slices, summed per lane in doubles (exact integers), flushed to
  // 64-bit integers.
  std::int64_t sums[4] = {0, 0, 0, static_cast<std::int64_t>(n)};
  double acc[3][kLanes] = {};
  const auto flush = [&] {
    for (int s = 0; s < 3; ++s)
      for (int l = 0; l < kLanes; ++l) {
        sums[s] += static_cast<std::int64_t>(acc[s][l]);
        acc[s][l] = 0;
      }
  };
  const auto slices = [&](double t, int l) {
    double u = (t * f1) * f2;  // |u| < 2^32
    const double s1 = std::trunc(u);
    u = (u - s1) * two32;  // the remainder, exact
    const double s2 = std::trunc(u);
    u = (u - s2) * two32;
    acc[0][l] += s1, acc[1][l] += s2, acc[2][l] += std::trunc(u);
  };
  i = 0;
  while (i < n) {
    const std::size_t end = n - i > kFlushTerms ? i + kFlushTerms : n;
    for (; i + kLanes <= end; i += kLanes)
      for (int l = 0; l < kLanes; ++l) slices(term(i + l), l);
    for (; i < end; ++i) slices(term(i), 0);
    flush();
  }
  std::int64_t total[4];
  MPI_Allreduce(sums, total, 4, MPI_INT64_T, MPI_SUM, comm);
  if (static_cast<double>(total[3]) >= kMaxTerms)
    throw std::runtime_error("reproducible sum: 2^30 terms or more over all ranks");
  const __int128 two64 = static_cast<__int128>(1) << 64;
  const __int128 v = static_cast<__int128>(total[0]) * two64 +
                     static_cast<__int128>(total[1]) * static_cast<__int128>(two32) +
                     static_cast<__int128>(total[2]);
  // One rounding of the exact total, then an exact scaling (rounded again only below the
  // normal range): the same integers give the same bits everywhere.
  return std::ldexp(static_cast<double>(v), e - 96);
}

}  // namespace

double reproducible_dot(const double* x, const double* y, std::size_t n, MPI_Comm comm) {
  return sum_terms(n, comm, [x, y](std::size_t i) { return x[i] * y[i]; });
}

double reproducible_sum(const double* x, std::size_t n, MPI_Comm comm) {
  return sum_terms(n, comm, [x](std::size_t i) { return x[i]; });
}

double reproducible_abs_sum(const double* x, std::size_t n, MPI_Comm comm) {
  return sum_terms(n, comm, [x](std::size_t i) { return std::fabs(x[i]); });
}

}  // namespace biota::core
