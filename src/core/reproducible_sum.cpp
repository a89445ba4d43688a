#include "core/reproducible_sum.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

// The lane vectors below are returned by value between functions of this file only; GCC notes
// on builds without AVX-512 that such returns have another ABI there (-Wpsabi), which does not
// matter for internal functions. Passed by reference instead, they went through the stack
// (perf annotate: vector stores and reloads in the inner loop).
#pragma GCC diagnostic ignored "-Wpsabi"

namespace biota::core {

namespace {

// Eight terms at a time in GCC vector registers (AVX-512, two AVX or four SSE registers, as the
// build allows); lanes are independent, so every operation is the same on any build.
constexpr int kLanes = 8;
using Lanes = double __attribute__((vector_size(kLanes * sizeof(double))));
// A slice is at most 2^32 in magnitude, so a lane's double accumulator stays an exact integer
// (< 2^53) for 2^20 slices; lanes are flushed to 64-bit integers then.
constexpr std::size_t kFlushTerms = std::size_t{1} << 20;
// The integer sums of all ranks stay below 2^62 (the top slice's total, shifted by 2^64, in a
// signed 128-bit integer) while there are fewer terms than this.
constexpr double kMaxTerms = 1073741824.0;  // 2^30

Lanes load(const double* p, std::size_t count) {  // count < kLanes: the rest zero
  Lanes v = {};
  std::memcpy(&v, p, count * sizeof(double));
  return v;
}

/// The sum of the terms over all ranks (see the header); `terms(i, count)` gives the terms i ..
/// i + count - 1 (count <= kLanes) in lanes, zero beyond count.
template <class Terms>
double sum_terms(std::size_t n, MPI_Comm comm, Terms terms) {
  // Pass 1: the largest magnitude, and whether every term is finite (t - t is NaN otherwise).
  const Lanes zero = {};
  Lanes largest = zero, not_finite = zero;
  for (std::size_t i = 0; i < n; i += kLanes) {
    const Lanes t = terms(i, std::min<std::size_t>(kLanes, n - i));
    const Lanes a = t < zero ? -t : t;
    largest = a > largest ? a : largest;
    not_finite += t - t;
  }
  double local[3] = {0, 0, static_cast<double>(n) >= kMaxTerms ? 1.0 : 0.0}, global[3];
  for (int l = 0; l < kLanes; ++l) {
    local[0] = largest[l] > local[0] ? largest[l] : local[0];
    local[1] += not_finite[l];
  }
  local[1] = local[1] == 0 ? 0.0 : 1.0;  // NaN != 0
  MPI_Allreduce(local, global, 3, MPI_DOUBLE, MPI_MAX, comm);
  if (global[2] > 0) throw std::runtime_error("reproducible sum: 2^30 terms or more on one rank");
  if (global[1] > 0) {  // an infinity or a NaN: the plain sum carries it
    double plain = 0, all = 0;
    for (std::size_t i = 0; i < n; i += kLanes) {
      const std::size_t count = std::min<std::size_t>(kLanes, n - i);
      const Lanes t = terms(i, count);
      for (std::size_t l = 0; l < count; ++l) plain += t[l];
    }
    MPI_Allreduce(&plain, &all, 1, MPI_DOUBLE, MPI_SUM, comm);
    return all;
  }
  if (global[0] == 0) return 0.0;
  int e = 0;
  std::frexp(global[0], &e);  // max |t| < 2^e
  // u = t 2^(32 - e) in two exact power-of-two factors (one could leave the double range).
  const int shift = 32 - e;
  const double f1 = std::ldexp(1.0, shift / 2), f2 = std::ldexp(1.0, shift - shift / 2);
  // Pass 2: each term's three slices: u = s1 + s2 2^-32 + s3 2^-64 (+ a remainder below 2^-65,
  // dropped), each slice the integer nearest to what is left, by adding and subtracting
  // 1.5 2^52 (exact for |u| < 2^51; round to nearest). Summed per lane in doubles, flushed to
  // 64-bit integers.
  const double two32 = 4294967296.0, magic = 6755399441055744.0;  // 2^32, 1.5 2^52
  std::int64_t sums[4] = {0, 0, 0, static_cast<std::int64_t>(n)};
  Lanes acc1 = zero, acc2 = zero, acc3 = zero;
  const auto flush = [&] {
    for (int l = 0; l < kLanes; ++l) {
      sums[0] += static_cast<std::int64_t>(acc1[l]);
      sums[1] += static_cast<std::int64_t>(acc2[l]);
      sums[2] += static_cast<std::int64_t>(acc3[l]);
    }
    acc1 = acc2 = acc3 = zero;
  };
  for (std::size_t i = 0; i < n;) {
    const std::size_t end = n - i > kFlushTerms ? i + kFlushTerms : n;
    for (; i < end; i += kLanes) {
      Lanes u = (terms(i, std::min<std::size_t>(kLanes, end - i)) * f1) * f2;  // |u| < 2^32
      const Lanes s1 = (u + magic) - magic;
      u = (u - s1) * two32;  // what is left, exact: |u| <= 2^31
      const Lanes s2 = (u + magic) - magic;
      u = (u - s2) * two32;
      acc1 += s1, acc2 += s2, acc3 += (u + magic) - magic;
    }
    flush();
  }
  std::int64_t total[4];
  MPI_Allreduce(sums, total, 4, MPI_INT64_T, MPI_SUM, comm);
  if (static_cast<double>(total[3]) >= kMaxTerms)
    throw std::runtime_error("reproducible sum: 2^30 terms or more over all ranks");
  const __int128 v = static_cast<__int128>(total[0]) * (static_cast<__int128>(1) << 64) +
                     static_cast<__int128>(total[1]) * (static_cast<__int128>(1) << 32) +
                     static_cast<__int128>(total[2]);
  // One rounding of the exact total, then an exact scaling (rounded again only below the
  // normal range): the same integers give the same bits everywhere.
  return std::ldexp(static_cast<double>(v), e - 96);
}

}  // namespace

double reproducible_dot(const double* x, const double* y, std::size_t n, MPI_Comm comm) {
  return sum_terms(n, comm, [x, y](std::size_t i, std::size_t count) {
    return count == kLanes ? load(x + i, kLanes) * load(y + i, kLanes)
                           : load(x + i, count) * load(y + i, count);
  });
}

double reproducible_sum(const double* x, std::size_t n, MPI_Comm comm) {
  return sum_terms(n, comm, [x](std::size_t i, std::size_t count) { return load(x + i, count); });
}

double reproducible_abs_sum(const double* x, std::size_t n, MPI_Comm comm) {
  return sum_terms(n, comm, [x](std::size_t i, std::size_t count) {
    const Lanes t = load(x + i, count), zero = {};
    return t < zero ? -t : t;
  });
}

}  // namespace biota::core
