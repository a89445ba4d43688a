// core::reproducible_sum / _dot on 1, 2 and 3 ranks: the same bits however the terms are spread
// over the ranks and ordered on each, the exact result where a plain sum cancels it away, and
// infinities and NaNs carried as a plain sum carries them.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "core/reproducible_sum.hpp"

using biota::core::reproducible_abs_sum;
using biota::core::reproducible_dot;
using biota::core::reproducible_sum;

namespace {

int rank_of(MPI_Comm c) {
  int r;
  MPI_Comm_rank(c, &r);
  return r;
}
int size_of(MPI_Comm c) {
  int s;
  MPI_Comm_size(c, &s);
  return s;
}

/// Term i of a global series over 2^-40 .. 2^40 in magnitude, both signs (a hash of i: the same
/// values on every rank count).
double term(std::uint64_t i) {
  std::uint64_t h = (i + 1) * 0x9E3779B97F4A7C15ull;
  h ^= h >> 29, h *= 0xBF58476D1CE4E5B9ull, h ^= h >> 32;
  const double mantissa = 1.0 + double(h & 0xFFFFF) / double(1 << 20);
  const int exponent = int((h >> 20) % 81) - 40;
  return ((h >> 40) & 1 ? -1.0 : 1.0) * std::ldexp(mantissa, exponent);
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

constexpr std::uint64_t kTerms = 10007;

/// This rank's terms: a contiguous, uneven block (`strided` false) or every size-th term from the
/// last backwards (`strided` true).
std::vector<std::uint64_t> my_indices(MPI_Comm c, bool strided) {
  const int r = rank_of(c), p = size_of(c);
  std::vector<std::uint64_t> idx;
  if (strided) {
    for (std::uint64_t i = kTerms; i-- > 0;)
      if (int(i % p) == r) idx.push_back(i);
  } else {  // block r ends at (r + 1)^2 / p^2 of the terms
    const auto end = [&](int b) { return kTerms * std::uint64_t(b) * b / std::uint64_t(p * p); };
    for (std::uint64_t i = r == 0 ? 0 : end(r); i < end(r + 1); ++i) idx.push_back(i);
  }
  return idx;
}

}  // namespace

TEST(ReproducibleSum, SameBitsOnAnySplitAndOrder) {
  // Reference: all terms on this rank alone, in order.
  std::vector<double> all(kTerms), all_y(kTerms);
  for (std::uint64_t i = 0; i < kTerms; ++i) all[i] = term(i), all_y[i] = term(i + kTerms);
  const double sum_ref = reproducible_sum(all.data(), all.size(), MPI_COMM_SELF);
  const double dot_ref = reproducible_dot(all.data(), all_y.data(), all.size(), MPI_COMM_SELF);
  const double abs_ref = reproducible_abs_sum(all.data(), all.size(), MPI_COMM_SELF);
  // A plain sum in another order differs in its last bits: the test would see an order effect.
  double forward = 0, backward = 0;
  for (std::uint64_t i = 0; i < kTerms; ++i) forward += all[i], backward += all[kTerms - 1 - i];
  EXPECT_NE(forward, backward);
  for (bool strided : {false, true}) {
    std::vector<double> x, y;
    for (auto i : my_indices(MPI_COMM_WORLD, strided)) x.push_back(all[i]), y.push_back(all_y[i]);
    EXPECT_TRUE(same_bits(reproducible_sum(x.data(), x.size(), MPI_COMM_WORLD), sum_ref));
    EXPECT_TRUE(same_bits(reproducible_dot(x.data(), y.data(), x.size(), MPI_COMM_WORLD), dot_ref));
    EXPECT_TRUE(same_bits(reproducible_abs_sum(x.data(), x.size(), MPI_COMM_WORLD), abs_ref));
  }
  // And close to the exact value: long double sums of the positive and negative parts.
  long double pos = 0, neg = 0;
  for (double t : all) (t > 0 ? pos : neg) += t;
  EXPECT_NEAR(sum_ref, double(pos + neg), 1e-12 * double(pos));
}

TEST(ReproducibleSum, ExactWhereAPlainSumCancels) {
  // 2^60 and -2^60 on different ranks with 1 and 2^-30 in between: the plain sum in this order
  // loses the small terms; the exact sum is 1 + 2^-30 (the slices reach down to 2^(61-96)).
  const int r = rank_of(MPI_COMM_WORLD), p = size_of(MPI_COMM_WORLD);
  std::vector<double> x;
  if (r == 0) x = {std::ldexp(1.0, 60), 1.0};
  if (r == p - 1) x.insert(x.end(), {std::ldexp(1.0, -30), -std::ldexp(1.0, 60)});
  double plain = 0;
  for (double t : {std::ldexp(1.0, 60), 1.0, std::ldexp(1.0, -30), -std::ldexp(1.0, 60)})
    plain += t;
  EXPECT_EQ(plain, 0.0);
  EXPECT_EQ(reproducible_sum(x.data(), x.size(), MPI_COMM_WORLD), 1.0 + std::ldexp(1.0, -30));
}

TEST(ReproducibleSum, EmptyZeroAndNonFinite) {
  const int r = rank_of(MPI_COMM_WORLD), p = size_of(MPI_COMM_WORLD);
  EXPECT_EQ(reproducible_sum(nullptr, 0, MPI_COMM_WORLD), 0.0);
  std::vector<double> zeros(7, 0.0);
  EXPECT_EQ(reproducible_dot(zeros.data(), zeros.data(), zeros.size(), MPI_COMM_WORLD), 0.0);
  // An infinity or a NaN on one rank reaches every rank.
  std::vector<double> x = {1.0, 2.0};
  if (r == p - 1) x.push_back(std::numeric_limits<double>::infinity());
  EXPECT_EQ(reproducible_sum(x.data(), x.size(), MPI_COMM_WORLD),
            std::numeric_limits<double>::infinity());
  if (r == 0) x.push_back(std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(std::isnan(reproducible_sum(x.data(), x.size(), MPI_COMM_WORLD)));
  // The largest magnitudes stay finite: max |t| just below 2^1024.
  std::vector<double> big = {std::numeric_limits<double>::max(),
                             -std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::denorm_min()};
  EXPECT_EQ(reproducible_sum(big.data(), big.size(), MPI_COMM_SELF), 0.0);
  std::vector<double> tiny = {std::numeric_limits<double>::denorm_min(),
                              std::numeric_limits<double>::denorm_min()};
  EXPECT_EQ(reproducible_sum(tiny.data(), tiny.size(), MPI_COMM_SELF),
            2 * std::numeric_limits<double>::denorm_min());
}

TEST(ReproducibleSum, CorrectlyRoundedOverManyFlushes) {
  // 3 * 2^20 + 7 terms t = 1 + 2^-40 + 2^-52 (several flushes of the lanes on one rank), split
  // unevenly over the ranks. The exact sum n + n (2^-40 + 2^-52) needs 74 bits; its correctly
  // rounded value is one rounding of n plus the exactly representable n (2^-40 + 2^-52).
  const std::uint64_t n = 3 * (std::uint64_t{1} << 20) + 7;
  const int r = rank_of(MPI_COMM_WORLD), p = size_of(MPI_COMM_WORLD);
  const std::uint64_t lo = n * std::uint64_t(r) * r / std::uint64_t(p * p),
                      hi = n * std::uint64_t(r + 1) * (r + 1) / std::uint64_t(p * p);
  const double t = 1.0 + std::ldexp(1.0, -40) + std::ldexp(1.0, -52);
  const std::vector<double> x(hi - lo, t);
  const double small = double(n) * std::ldexp(1.0, -40) + double(n) * std::ldexp(1.0, -52);
  EXPECT_EQ(reproducible_sum(x.data(), x.size(), MPI_COMM_WORLD), double(n) + small);
  double plain = 0;  // the plain sum on one rank drifts from it
  for (std::uint64_t i = 0; i < n; ++i) plain += t;
  EXPECT_NE(plain, double(n) + small);
}
