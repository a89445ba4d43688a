#pragma once
/// \file particle_set.hpp
/// \brief Structure-of-arrays particle storage with owned and ghost ranges and 64-bit global ids.
///
/// A kind of particle (plant sphere, boid, moss patch) is described by a `ParticleLayout`: a list
/// of real and 64-bit integer attributes, each saying whether it travels on migration and whether
/// it is refreshed on ghosts (LAMMPS atom_vec / Cabana AoSoA member lists). Communication packs
/// exactly those columns, so no kind needs hand-written pack/unpack code.
///
/// Storage: one column per attribute component. Indices [0, n_owned) are owned particles,
/// [n_owned, n_owned + n_ghost) ghosts (copies of particles owned elsewhere or periodic images).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace biota::particles {

using core::GlobalId;
using core::Real;
using core::Vec3;

/// \brief Id value meaning "no particle" (e.g. a broken or absent bond partner).
inline constexpr GlobalId kNoId = ~GlobalId{0};

/// \brief Declaration of one attribute.
struct AttributeSpec {
  std::string name;
  int ncomp = 1;
  bool migrate = true;  ///< travels with the particle when it changes owner
  bool ghost = false;   ///< copied to ghosts on every ghost refresh
  /// A point in space (3 components, m): shifted with the position for periodic ghost images
  /// and periodic wraps, so e.g. a sampling point stays next to the image's position.
  bool position = false;
};

/// \brief The attribute list of a particle kind. Position "x" (real, 3) and "id" (u64, 1) always
/// exist as attribute 0 of their type and always travel both on migration and on ghost refresh.
class ParticleLayout {
 public:
  ParticleLayout();
  /// \brief Declare a real attribute; returns its handle.
  int add_real(const std::string& name, int ncomp, bool migrate, bool ghost);
  /// \brief Declare a position-valued real attribute (3 components, m; see
  /// AttributeSpec::position); returns its handle.
  int add_position(const std::string& name, bool migrate, bool ghost);
  /// \brief Declare a 64-bit integer attribute (ids of partners, plant ids, flags); returns handle.
  int add_u64(const std::string& name, int ncomp, bool migrate, bool ghost);
  const std::vector<AttributeSpec>& reals() const { return reals_; }
  const std::vector<AttributeSpec>& u64s() const { return u64s_; }
  int find_real(const std::string& name) const;
  int find_u64(const std::string& name) const;

 private:
  std::vector<AttributeSpec> reals_, u64s_;
};

/// \brief SoA particle set; see file comment.
class ParticleSet {
 public:
  static constexpr int kPos = 0;  ///< handle of the position attribute
  static constexpr int kId = 0;   ///< handle of the id attribute

  explicit ParticleSet(ParticleLayout layout);

  const ParticleLayout& layout() const { return layout_; }
  std::size_t n_owned() const { return n_owned_; }
  std::size_t n_ghost() const { return n_total_ - n_owned_; }
  std::size_t n_total() const { return n_total_; }

  /// \brief Column of component `c` of real attribute `a` (valid for owned and ghost indices).
  Real* real(int a, int c = 0) { return rcol_[rfirst_[a] + c].data(); }
  const Real* real(int a, int c = 0) const { return rcol_[rfirst_[a] + c].data(); }
  std::uint64_t* u64(int a, int c = 0) { return ucol_[ufirst_[a] + c].data(); }
  const std::uint64_t* u64(int a, int c = 0) const { return ucol_[ufirst_[a] + c].data(); }
  GlobalId id(std::size_t i) const { return ucol_[0][i]; }
  Vec3 pos(std::size_t i) const { return {rcol_[0][i], rcol_[1][i], rcol_[2][i]}; }
  void set_pos(std::size_t i, const Vec3& p) {
    rcol_[0][i] = p.x;
    rcol_[1][i] = p.y;
    rcol_[2][i] = p.z;
  }
  Vec3 vec3(int a, std::size_t i) const {
    const std::size_t f = rfirst_[a];
    return {rcol_[f][i], rcol_[f + 1][i], rcol_[f + 2][i]};
  }
  void set_vec3(int a, std::size_t i, const Vec3& v) {
    const std::size_t f = rfirst_[a];
    rcol_[f][i] = v.x;
    rcol_[f + 1][i] = v.y;
    rcol_[f + 2][i] = v.z;
  }
  void add_vec3(int a, std::size_t i, const Vec3& v) {
    const std::size_t f = rfirst_[a];
    rcol_[f][i] += v.x;
    rcol_[f + 1][i] += v.y;
    rcol_[f + 2][i] += v.z;
  }

  /// \brief Append an owned particle (drops all ghosts first); other attributes are zero.
  std::size_t add_owned(GlobalId id, const Vec3& pos);
  /// \brief Drop every ghost.
  void clear_ghosts() { resize(n_owned_, n_owned_); }
  /// \brief Remove owned particles flagged in `remove` (size n_owned); drops ghosts. With
  /// keep_order the remaining particles keep their order (every column moves down past the
  /// holes); without it the last kept particles fill the holes (work in the number removed).
  void remove_owned(const std::vector<char>& remove, bool keep_order = true);
  /// \brief Permute the owned particles: new slot m holds old owned particle order[m] (a
  /// permutation of [0, n_owned)); drops ghosts. Used to keep storage in spatial (cell) order so
  /// that neighbour loops touch memory in order; results never depend on the storage order.
  /// \throws std::invalid_argument if order.size() != n_owned().
  void reorder_owned(const std::vector<std::size_t>& order);
  /// \brief Zero one real attribute on owned and ghost particles.
  void zero_real(int a);

  // ---- packing (used by ParticleComm) ----
  /// \brief Doubles per particle for a migration / ghost message.
  int pack_width(bool ghost_only) const;
  /// \brief Append particle i's migrating (ghost_only=false) or ghost columns to `buf`.
  void pack(std::size_t i, bool ghost_only, std::vector<double>& buf) const;
  /// \brief Handles of the position-valued real attributes other than the position.
  const std::vector<int>& extra_positions() const { return extra_pos_; }
  /// \brief Write one packed particle into slot i (which must exist).
  void unpack(std::size_t i, bool ghost_only, const double* in);
  /// \brief Pack the real attributes `reals` and then the u64 attributes `u64s` of the particles
  /// `rows`, particle by particle (one row of their components each), appended to `buf`; `shift`
  /// is added to component `axis` of every position-valued attribute among them (a periodic
  /// image's offset; added even when 0). Filled column by column: one pass per column.
  /// With ghost_reals() and ghost_u64s() a row is what pack(i, true) gives.
  void pack_rows(const std::vector<std::size_t>& rows, const std::vector<int>& reals,
                 const std::vector<int>& u64s, int axis, Real shift,
                 std::vector<double>& buf) const;
  /// \brief Doubles in one row of pack_rows() for these attributes.
  std::size_t row_width(const std::vector<int>& reals, const std::vector<int>& u64s) const;
  /// \brief The inverse of pack_rows(): `count` rows into slots [first, first + count).
  void unpack_rows(std::size_t first, std::size_t count, const std::vector<int>& reals,
                   const std::vector<int>& u64s, const double* in);
  /// \brief The real / u64 attributes a ghost carries (flagged `ghost`), in layout order.
  const std::vector<int>& ghost_reals() const { return ghost_reals_; }
  const std::vector<int>& ghost_u64s() const { return ghost_u64s_; }
  /// \brief Append ghosts copying particles `from` (ghost columns; the others zero), with `shift`
  /// added to component `axis` of every position-valued ghost attribute: the values that
  /// pack(i, true), that shift and unpack() give, without a message (a periodic image held by
  /// this rank).
  void append_ghost_copies(const std::vector<std::size_t>& from, int axis, Real shift);
  /// \brief Resize to n_owned owned and n_total - n_owned ghosts (new slots zeroed).
  void resize(std::size_t n_owned, std::size_t n_total);
  /// \brief Swap particle slots i and j (all columns).
  void swap_slots(std::size_t i, std::size_t j);

 private:
  ParticleLayout layout_;
  std::vector<std::size_t> rfirst_, ufirst_;  // first column of each attribute
  std::vector<std::vector<Real>> rcol_;
  std::vector<std::vector<std::uint64_t>> ucol_;
  std::vector<Real> spare_real_;  // reorder_owned's gather target
  std::vector<std::uint64_t> spare_u64_;
  std::vector<char> rmig_, rghost_, umig_, ughost_;  // per column flags
  std::vector<int> extra_pos_, ghost_reals_, ghost_u64s_;
  std::size_t n_owned_ = 0, n_total_ = 0;
};

}  // namespace biota::particles
