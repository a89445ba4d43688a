#pragma once
/// \file sandpile.hpp
/// \brief 3D Bak–Tang–Wiesenfeld sandpile with open boundaries (spec boids.md section 2.3).
#include <cstdint>
#include <span>
#include <vector>

namespace biota::models::flock {

/// \brief Order in which unstable sites are toppled during a relaxation.
///
/// The model is abelian (spec 2.3): the final stable heights, the number of topplings and the set
/// of toppled sites do not depend on the order. Two orders exist so that this can be tested and so
/// that the cheaper one can be chosen when the duration is not needed.
enum class ToppleOrder {
  /// \brief Synchronous (parallel-update) waves: every site unstable at the start of a wave topples
  /// once in that wave. FIFO by wave; the only order that measures Avalanche::duration.
  kWaves,
  /// \brief LIFO stack; a popped site topples as many times as needed at once (h / (z_c + 1)).
  /// Fastest; Avalanche::duration is reported as 0 (not measured).
  kStack,
};

/// \brief Statistics of one relaxation (one avalanche).
struct Avalanche {
  /// \brief Avalanche size s: number of topplings (spec table in 2.3, [reading]).
  std::int64_t size = 0;
  /// \brief Number of distinct sites that toppled at least once.
  std::int64_t area = 0;
  /// \brief Number of parallel-update waves with at least one toppling (ToppleOrder::kWaves only).
  ///
  /// Wave 1 topples the sites unstable after the drive, wave t + 1 topples every site that is
  /// unstable after all topplings of wave t, each once. 0 if nothing toppled or if the order was
  /// ToppleOrder::kStack.
  std::int64_t duration = 0;
  /// \brief Grains that left the lattice during this relaxation (open boundary, plus any bulk
  /// dissipation when z_c > 5).
  std::int64_t lost = 0;
};

/// \brief Everything needed to restart a Sandpile exactly (checkpoint payload).
struct SandpileState {
  /// \brief Heights of the interior sites, site id = x + Lx * (y + Ly * z).
  std::vector<std::int32_t> heights;
  /// \brief Grains on the lattice right after initialisation (the random 0..z_c fill).
  std::int64_t initial_grains = 0;
  /// \brief Grains added by drives and deposits since initialisation.
  std::int64_t grains_added = 0;
  /// \brief Grains lost through the boundary (and bulk dissipation) since initialisation.
  std::int64_t grains_lost = 0;
  /// \brief Topplings since initialisation.
  std::int64_t topplings = 0;
  /// \brief Relaxations (avalanches, including empty ones) since initialisation.
  std::int64_t relaxations = 0;
};

/// \brief 3D BTW sandpile on an Lx × Ly × Lz lattice with open boundaries (spec 2.3, eqs. 3.1–3.2).
///
/// A site topples when h > z_c (ambiguity 2 of the spec: stable values are 0..z_c). A toppling
/// removes z_c + 1 grains and gives one to each of the 6 face neighbours; grains sent outside the
/// lattice are lost. With the paper's z_c = 5 the bulk is conservative; z_c > 5 is allowed and
/// dissipates z_c - 5 grains per toppling (a standard way to cut the avalanche size off).
///
/// Invariant, checked by the tests: initial_grains + grains_added == grains_on_lattice +
/// grains_lost.
///
/// Storage is a flat array with one ghost layer so that the 6 neighbours are fixed offsets; ghosts
/// hold a large negative height so they never topple, and the grains they receive are counted as
/// lost through a precomputed per-site sink count. Relaxation is O(topplings) and allocates nothing
/// after construction (all work lists are reserved to the lattice size).
class Sandpile {
 public:
  /// \brief Fill every site with an integer uniform in 0..threshold, drawn from core::Rng keyed by
  /// (seed, site id, step 0, RngPurpose::kSandpile) so the fill does not depend on ranks or order.
  /// \throws std::invalid_argument if a size is < 1, the lattice is too large for 32-bit indices,
  /// or threshold < 5.
  Sandpile(int lx, int ly, int lz, std::uint64_t seed, int threshold = 5);

  /// \brief Drive (eq. 3.1): add one grain at `site` and relax fully (eq. 3.2).
  /// The toppled sites are then available from last_toppled_sites(). Precondition (unchecked, this
  /// is the hot path): 0 <= site < num_sites().
  Avalanche add_grain(std::int64_t site, ToppleOrder order = ToppleOrder::kWaves);

  /// \brief Add `count` grains at `site` without relaxing (to prepare unstable states).
  void deposit(std::int64_t site, std::int32_t count);

  /// \brief Relax every unstable site until all are stable; returns the merged avalanche.
  /// O(N) scan for unstable sites plus O(topplings).
  Avalanche relax(ToppleOrder order = ToppleOrder::kWaves);

  /// \brief Site of drive number `drive` for a uniformly random drive: core::Rng keyed by
  /// (seed, id 2^64 - 1, step = drive, kSandpile), so it never shares a stream with the fill.
  std::int64_t random_site(std::uint64_t drive) const;

  /// \brief Distinct sites toppled by the last add_grain() or relax(), in order of first toppling.
  /// Valid until the next mutating call.
  std::span<const std::int64_t> last_toppled_sites() const { return toppled_ids_; }

  /// \brief Height of one site.
  std::int32_t height(std::int64_t site) const { return h_[padded_[site]]; }
  /// \brief Site id of coordinates (x, y, z): x + Lx * (y + Ly * z).
  std::int64_t site(int x, int y, int z) const { return x + 1LL * lx_ * (y + 1LL * ly_ * z); }
  /// \brief Number of sites Lx * Ly * Lz.
  std::int64_t num_sites() const { return n_; }
  /// \brief Lattice extents.
  int lx() const { return lx_; }
  int ly() const { return ly_; }  ///< \brief Lattice extent in y.
  int lz() const { return lz_; }  ///< \brief Lattice extent in z.
  /// \brief Toppling threshold z_c (topple iff h > z_c).
  int threshold() const { return zc_; }
  /// \brief Seed of the fill and of random_site().
  std::uint64_t seed() const { return seed_; }

  /// \brief Grains put on the lattice by the initial fill.
  std::int64_t initial_grains() const { return initial_grains_; }
  /// \brief Grains added by add_grain() and deposit().
  std::int64_t grains_added() const { return grains_added_; }
  /// \brief Grains lost since initialisation.
  std::int64_t grains_lost() const { return grains_lost_; }
  /// \brief Grains on the lattice, kept as a running count (O(1)).
  std::int64_t grains_on_lattice() const { return initial_grains_ + grains_added_ - grains_lost_; }
  /// \brief Topplings since initialisation.
  std::int64_t topplings() const { return topplings_; }
  /// \brief Relaxations since initialisation.
  std::int64_t relaxations() const { return relaxations_; }

  /// \brief Interior heights, site id order (for checkpoints and output).
  std::vector<std::int32_t> heights() const;
  /// \brief Sum of the interior heights, recomputed in O(N) (to check the running counts).
  std::int64_t sum_heights() const;
  /// \brief Copy of the full state for a checkpoint.
  SandpileState state() const;
  /// \brief Restore a state written by state(); the lattice size must match.
  /// \throws std::invalid_argument on a size mismatch.
  void restore(const SandpileState& s);

 private:
  Avalanche relax_waves(Avalanche a);
  Avalanche relax_stack(Avalanche a);
  void note_toppled(std::int32_t p);
  void finish(Avalanche& a);
  void rearm_ghosts();

  int lx_, ly_, lz_, zc_;
  std::uint64_t seed_;
  std::int64_t n_;
  int px_, py_, pz_;                      // padded extents
  std::int32_t off_[6];                   // neighbour offsets in the padded array
  std::vector<std::int32_t> h_;           // padded heights; ghosts hold kGhost + received grains
  std::vector<std::uint8_t> sink_;        // grains lost per toppling of each interior site
  std::vector<std::int32_t> padded_;      // site id -> padded index
  std::vector<std::int32_t> site_of_;     // padded index -> site id (-1 for ghosts)
  std::vector<std::uint32_t> avl_mark_;   // == avl_serial_ if toppled in the current avalanche
  std::vector<std::uint32_t> wave_mark_;  // == wave_serial_ if queued for the wave being built
  std::uint32_t avl_serial_ = 0, wave_serial_ = 0;
  std::vector<std::int32_t> work_a_, work_b_;  // stack, or current/next wave lists
  std::vector<std::int32_t> toppled_;          // padded indices of distinct toppled sites
  std::vector<std::int64_t> toppled_ids_;      // the same as site ids
  std::int64_t initial_grains_ = 0, grains_added_ = 0, grains_lost_ = 0, topplings_ = 0,
               relaxations_ = 0, lost_since_rearm_ = 0;
};

}  // namespace biota::models::flock
