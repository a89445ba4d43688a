/// \file test_sandpile.cpp
/// \brief Sandpile invariants, abelian property, Dhar's exact mean and the size exponent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/rng.hpp"
#include "models/flock/dhar.hpp"
#include "models/flock/power_law_fit.hpp"
#include "models/flock/sandpile.hpp"

using biota::models::flock::Avalanche;
using biota::models::flock::dhar_mean_avalanche_size;
using biota::models::flock::fit_power_law_log_binned;
using biota::models::flock::fit_power_law_mle;
using biota::models::flock::Sandpile;
using biota::models::flock::ToppleOrder;
using biota::models::flock::zipf_rank_size_slope;

namespace {

bool all_stable(const Sandpile& s) {
  for (auto h : s.heights())
    if (h < 0 || h > s.threshold()) return false;
  return true;
}

// Brute-force synchronous update, the definition of Avalanche::duration: every wave topples all
// sites unstable at its start once.
Avalanche reference_parallel_relax(std::vector<int>& h, int lx, int ly, int lz, int zc) {
  Avalanche a;
  const int q = zc + 1;
  for (;;) {
    std::vector<int> unstable;
    for (int i = 0; i < static_cast<int>(h.size()); ++i)
      if (h[i] > zc) unstable.push_back(i);
    if (unstable.empty()) return a;
    ++a.duration;
    for (int i : unstable) {
      h[i] -= q;
      ++a.size;
      a.lost += q - 6;
      const int x = i % lx, y = (i / lx) % ly, z = i / (lx * ly);
      const int nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z},
                            {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
      for (const auto& c : nb) {
        if (c[0] < 0 || c[0] >= lx || c[1] < 0 || c[1] >= ly || c[2] < 0 || c[2] >= lz)
          ++a.lost;
        else
          ++h[c[0] + lx * (c[1] + ly * c[2])];
      }
    }
  }
}

}  // namespace

TEST(Sandpile, InitialHeightsAreUniformIntegersZeroToThreshold) {
  Sandpile s(20, 20, 20, 7);
  std::vector<long> count(6, 0);
  for (auto h : s.heights()) {
    ASSERT_GE(h, 0);
    ASSERT_LE(h, 5);
    ++count[h];
  }
  // 8000 draws, expected 1333.3 each, sd sqrt(8000 * 1/6 * 5/6) = 33.3; allow 5 sd.
  for (long c : count) EXPECT_NEAR(c, 8000.0 / 6, 5 * 33.4);
  EXPECT_EQ(s.initial_grains(), s.sum_heights());
}

TEST(Sandpile, GrainsAreConservedAfterEveryAddition) {
  // Non-cubic lattice, and z_c = 7 where each toppling also dissipates 2 grains in the bulk.
  for (int zc : {5, 7}) {
    Sandpile s(5, 7, 6, 11, zc);
    for (std::uint64_t k = 0; k < 40000; ++k) {
      const Avalanche a =
          s.add_grain(s.random_site(k), k % 2 ? ToppleOrder::kStack : ToppleOrder::kWaves);
      ASSERT_EQ(s.initial_grains() + s.grains_added(), s.sum_heights() + s.grains_lost())
          << "after drive " << k << " zc " << zc;
      ASSERT_EQ(a.area, static_cast<std::int64_t>(s.last_toppled_sites().size()));
      ASSERT_LE(a.area, a.size);
      if (k % 1000 == 0) {
        ASSERT_TRUE(all_stable(s));
      }
    }
    EXPECT_EQ(s.grains_added(), 40000);
    EXPECT_EQ(s.relaxations(), 40000);
    EXPECT_GT(s.grains_lost(), 0);
    EXPECT_TRUE(all_stable(s));
  }
}

TEST(Sandpile, AbelianFinalStateIndependentOfToppleOrder) {
  Sandpile waves(9, 8, 7, 3);
  biota::core::Rng rng(3, 0, 0, biota::core::RngPurpose::kTest);
  for (int k = 0; k < 3000; ++k)
    waves.deposit(rng.uniform_int(0, waves.num_sites() - 1), 1 + static_cast<int>(k % 3));
  waves.deposit(waves.site(4, 4, 3), 500);  // one very unstable site
  Sandpile stack = waves;
  ASSERT_EQ(waves.heights(), stack.heights());
  const Avalanche a = waves.relax(ToppleOrder::kWaves);
  std::vector<std::int64_t> sites_a(waves.last_toppled_sites().begin(),
                                    waves.last_toppled_sites().end());
  const Avalanche b = stack.relax(ToppleOrder::kStack);
  std::vector<std::int64_t> sites_b(stack.last_toppled_sites().begin(),
                                    stack.last_toppled_sites().end());
  EXPECT_GT(a.size, 10000);  // a real test: many topplings in both orders
  EXPECT_EQ(waves.heights(), stack.heights());
  EXPECT_EQ(a.size, b.size);
  EXPECT_EQ(a.area, b.area);
  EXPECT_EQ(a.lost, b.lost);
  std::sort(sites_a.begin(), sites_a.end());
  std::sort(sites_b.begin(), sites_b.end());
  EXPECT_EQ(sites_a, sites_b);
  EXPECT_TRUE(all_stable(waves));
}

TEST(Sandpile, WavesMatchBruteForceParallelUpdate) {
  for (int zc : {5, 6}) {
    Sandpile s(6, 5, 7, 5, zc);
    for (std::uint64_t k = 0; k < 3000; ++k) s.add_grain(s.random_site(k));  // reach criticality
    long nontrivial = 0;
    for (std::uint64_t k = 3000; k < 4000; ++k) {
      const auto h0 = s.heights();
      std::vector<int> h(h0.begin(), h0.end());
      const std::int64_t site = s.random_site(k);
      ++h[site];
      const Avalanche ref = reference_parallel_relax(h, 6, 5, 7, zc);
      const Avalanche a = s.add_grain(site, ToppleOrder::kWaves);
      ASSERT_EQ(a.size, ref.size) << "drive " << k;
      ASSERT_EQ(a.duration, ref.duration) << "drive " << k;
      ASSERT_EQ(a.lost, ref.lost) << "drive " << k;
      const auto h1 = s.heights();
      ASSERT_EQ(std::vector<int>(h1.begin(), h1.end()), h);
      nontrivial += a.duration > 3;
    }
    EXPECT_GT(nontrivial, 20);  // enough multi-wave avalanches for the comparison to bite
  }
}

TEST(Sandpile, StackAndWavesGiveSameAvalancheSequence) {
  Sandpile a(10, 10, 10, 9), b(10, 10, 10, 9);
  for (std::uint64_t k = 0; k < 30000; ++k) {
    const Avalanche x = a.add_grain(a.random_site(k), ToppleOrder::kWaves);
    const Avalanche y = b.add_grain(b.random_site(k), ToppleOrder::kStack);
    ASSERT_EQ(x.size, y.size);
    ASSERT_EQ(x.area, y.area);
    ASSERT_EQ(x.lost, y.lost);
    EXPECT_EQ(y.duration, 0);
  }
  EXPECT_EQ(a.heights(), b.heights());
}

TEST(Sandpile, SameSeedSameHistoryAndCheckpointRestartIsExact) {
  Sandpile a(8, 8, 8, 42), b(8, 8, 8, 42), c(8, 8, 8, 43);
  EXPECT_EQ(a.heights(), b.heights());
  EXPECT_NE(a.heights(), c.heights());
  for (std::uint64_t k = 0; k < 5000; ++k) a.add_grain(a.random_site(k));
  const auto saved = a.state();
  std::vector<std::int64_t> sizes_a;
  for (std::uint64_t k = 5000; k < 10000; ++k)
    sizes_a.push_back(a.add_grain(a.random_site(k)).size);
  for (std::uint64_t k = 0; k < 5000; ++k) b.add_grain(b.random_site(k));
  EXPECT_EQ(b.heights(), saved.heights);
  Sandpile r(8, 8, 8, 42);
  r.restore(saved);
  std::vector<std::int64_t> sizes_r;
  for (std::uint64_t k = 5000; k < 10000; ++k)
    sizes_r.push_back(r.add_grain(r.random_site(k)).size);
  EXPECT_EQ(sizes_a, sizes_r);
  EXPECT_EQ(a.heights(), r.heights());
  EXPECT_EQ(a.grains_lost(), r.grains_lost());
  EXPECT_EQ(a.topplings(), r.topplings());
  Sandpile wrong(8, 8, 7, 42);
  EXPECT_THROW(wrong.restore(saved), std::invalid_argument);
}

TEST(Dhar, SmallCasesByHand) {
  // One site: Δ = 6, so <s> = 1/6 (it topples once iff h = 5, one of the 6 recurrent states).
  EXPECT_NEAR(dhar_mean_avalanche_size(1, 1, 1), 1.0 / 6, 1e-14);
  // Two sites: Δ = [[6,-1],[-1,6]], Σ Δ⁻¹ = 2 / 5, <s> = 1/5.
  EXPECT_NEAR(dhar_mean_avalanche_size(2, 1, 1), 0.2, 1e-14);
  // z_c = 7: Δ = 8 on one site.
  EXPECT_NEAR(dhar_mean_avalanche_size(1, 1, 1, 7), 0.125, 1e-14);
}

TEST(Sandpile, StationaryMeanAvalancheSizeMatchesDhar) {
  // Stationary state: uniform drives after a burn-in. Avalanche sizes are correlated through the
  // heights, so the error of the mean comes from batch means (64 batches much longer than the
  // correlation time of a few hundred drives on 125 sites).
  const int l = 5;
  const double exact = dhar_mean_avalanche_size(l, l, l);
  Sandpile s(l, l, l, 2024);
  const std::uint64_t burn = 200000, batches = 64, per_batch = 60000;
  for (std::uint64_t k = 0; k < burn; ++k) s.add_grain(s.random_site(k), ToppleOrder::kStack);
  std::vector<double> means;
  std::uint64_t k = burn;
  for (std::uint64_t b = 0; b < batches; ++b) {
    double sum = 0;
    for (std::uint64_t i = 0; i < per_batch; ++i, ++k)
      sum += static_cast<double>(s.add_grain(s.random_site(k), ToppleOrder::kStack).size);
    means.push_back(sum / per_batch);
  }
  double m = 0, v = 0;
  for (double x : means) m += x;
  m /= batches;
  for (double x : means) v += (x - m) * (x - m);
  const double se = std::sqrt(v / (batches - 1) / batches);
  std::printf("[ dhar ] L=%d exact <s> = %.6f, measured %.6f +- %.6f (%.2f se)\n", l, exact, m, se,
              (m - exact) / se);
  EXPECT_NEAR(m, exact, 4 * se);
  EXPECT_LT(se, 0.01 * exact);  // the test must be sharp enough to mean something
}

TEST(Sandpile, SizeExponentL32) {
  const int l = 32;
  Sandpile s(l, l, l, 77);
  // Burn-in: the random 0..5 fill (mean 2.5) is far below the critical density; 4 grains per
  // site is well past the point where the mean height stops rising.
  const std::uint64_t burn = 4 * static_cast<std::uint64_t>(s.num_sites()), drives = 4000000;
  for (std::uint64_t k = 0; k < burn; ++k) s.add_grain(s.random_site(k), ToppleOrder::kStack);
  std::vector<std::int64_t> hist(1, 0);
  double sum = 0;
  for (std::uint64_t k = burn; k < burn + drives; ++k) {
    const auto size = s.add_grain(s.random_site(k), ToppleOrder::kStack).size;
    sum += static_cast<double>(size);
    if (size >= static_cast<std::int64_t>(hist.size())) hist.resize(size + 1, 0);
    ++hist[size];
  }
  // Window: above the lattice-scale head (s < 10) and well below the cutoff s_c ~ L^3.
  const auto binned = fit_power_law_log_binned(hist, 10, 2000, 5);
  const auto mle = fit_power_law_mle(hist, 10, 2000);
  // Rank-size (Zipf) slope over the ranks of the same size window [10, 2000].
  std::int64_t rank_of_10 = 0, rank_of_2000 = 0;
  for (std::size_t i = 10; i < hist.size(); ++i) rank_of_10 += hist[i];
  for (std::size_t i = 2000; i < hist.size(); ++i) rank_of_2000 += hist[i];
  const double zipf = zipf_rank_size_slope(hist, rank_of_2000, rank_of_10);
  std::printf("[ tau ] L=%d: mean size %.3f (Dhar %.3f)\n", l, sum / drives,
              dhar_mean_avalanche_size(l, l, l));
  std::printf(
      "[ tau ] L=%d: binned %.4f +- %.4f (%d bins), MLE %.4f +- %.4f, n=%lld, "
      "Zipf rank-size slope %.4f, max size %zu\n",
      l, binned.tau, binned.tau_error, binned.points, mle.tau, mle.tau_error,
      static_cast<long long>(binned.samples), zipf, hist.size() - 1);
  EXPECT_GE(binned.tau, 1.2);
  EXPECT_LE(binned.tau, 1.5);
  EXPECT_GE(mle.tau, 1.2);
  EXPECT_LE(mle.tau, 1.5);
}

TEST(PowerLawFit, RecoversKnownExponentFromExactHistogram) {
  // Expected counts of a pure discrete power law: both fits must return τ exactly-ish.
  std::vector<std::int64_t> hist(100001, 0);
  for (int s = 1; s <= 100000; ++s) hist[s] = std::llround(1e12 * std::pow(s, -1.7));
  EXPECT_NEAR(fit_power_law_mle(hist, 5, 50000).tau, 1.7, 1e-4);
  EXPECT_NEAR(fit_power_law_log_binned(hist, 5, 50000, 10).tau, 1.7, 0.01);
}
