/// \file test_legacy_checkpoint_rows.cpp
/// \brief Seaweed checkpoints written before the parent anchor and the rest orientation left the
/// particle layout (issue 11, session 31) still restart: to_current_seaweed_rows() maps their
/// rows onto the current layout column by column, and refuses, on every rank alike, rows whose
/// dropped values are not the ones the model implies (0 - anchor_child, the identity).
#include <gtest/gtest.h>
#include <mpi.h>

#include <functional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "models/plants/seaweed_mechanics.hpp"

using namespace biota;
using namespace biota::models::plants;

namespace {

/// The layout as it was: seaweed_layout() with anchor_parent and q_rest after anchor_child.
/// Written out, not derived from seaweed_layout(): it is the format on users' disks, so a column
/// added to the current layout later must make this test fail, not move the old format along.
particles::ParticleLayout legacy_layout() {
  particles::ParticleLayout l;
  l.add_real("v", 3, true, true);
  l.add_real("q", 4, true, true);
  l.add_real("omega", 3, true, true);
  l.add_real("force", 3, false, false);
  l.add_real("torque", 3, false, false);
  l.add_real("u_fluid", 3, true, false);
  l.add_real("drag_impulse", 3, true, true);
  l.add_real("anchor_child", 3, true, true);
  l.add_real("anchor_parent", 3, true, true);
  l.add_real("q_rest", 4, true, true);
  l.add_position("x_sample", true, true);
  l.add_real("joint_force", 1, true, false);
  l.add_real("joint_torque", 1, true, false);
  l.add_real("radius", 1, true, true);
  l.add_u64("plant", 1, true, true);
  l.add_u64("parent", 1, true, true);
  return l;
}

/// A distinct value for every column of every sphere, by attribute name (the same in both
/// layouts), and what the old code stored in the two dropped attributes.
void fill(particles::ParticleSet& s, std::size_t n, int rank) {
  const auto& L = s.layout();
  for (std::size_t i = 0; i < n; ++i) {
    const GlobalId id = static_cast<GlobalId>(1000 * rank + i);
    s.add_owned(id, {0.1 + 0.01 * double(i), 0.2, 0.3 + rank});
  }
  for (std::size_t a = 0; a < L.reals().size(); ++a) {
    const auto& spec = L.reals()[a];
    if (spec.name == "x") continue;  // the position, set above
    for (int c = 0; c < spec.ncomp; ++c)
      for (std::size_t i = 0; i < n; ++i) {
        double v = std::hash<std::string>{}(spec.name) % 1000 + 0.125 * c + 1e-3 * double(i);
        if (spec.name == "anchor_child") v = c == 2 ? -0.005 : 0.0;  // a vertical stem's anchor
        if (spec.name == "anchor_parent") v = c == 2 ? 0.005 : 0.0;  // (x - parent_x) / 2
        if (spec.name == "q_rest") v = c == 0 ? 1.0 : 0.0;
        s.real(static_cast<int>(a), c)[i] = v;
      }
  }
  for (std::size_t a = 0; a < L.u64s().size(); ++a) {
    if (L.u64s()[a].name == "id") continue;
    for (std::size_t i = 0; i < n; ++i) s.u64(static_cast<int>(a))[i] = 7 * i + a;
  }
}

std::vector<double> rows_of(const particles::ParticleSet& s) {
  std::vector<double> rows;
  for (std::size_t i = 0; i < s.n_owned(); ++i) s.pack(i, false, rows);
  return rows;
}

}  // namespace

TEST(LegacySeaweedRows, MapOntoTheCurrentLayoutColumnByColumn) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const std::size_t n = 5 + static_cast<std::size_t>(rank);
  particles::ParticleSet old_set(legacy_layout()), new_set(seaweed_layout());
  fill(old_set, n, rank);
  fill(new_set, n, rank);
  std::vector<double> rows = rows_of(old_set);
  int width = old_set.pack_width(false);
  ASSERT_EQ(width, new_set.pack_width(false) + 7);
  to_current_seaweed_rows(rows, width, "old.h5", MPI_COMM_WORLD);
  EXPECT_EQ(width, new_set.pack_width(false));
  const std::vector<double> expected = rows_of(new_set);
  ASSERT_EQ(rows.size(), expected.size());
  for (std::size_t k = 0; k < rows.size(); ++k) EXPECT_EQ(rows[k], expected[k]) << k;
  // Rows of the current layout are left alone.
  std::vector<double> current = expected;
  to_current_seaweed_rows(current, width, "new.h5", MPI_COMM_WORLD);
  EXPECT_EQ(current, expected);
}

TEST(LegacySeaweedRows, RefuseAnotherRestOrientationOnEveryRank) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  particles::ParticleSet old_set(legacy_layout());
  fill(old_set, 4, rank);
  if (rank == 0) old_set.real(old_set.layout().find_real("q_rest"), 0)[2] = 0.5;  // rank 0 only
  std::vector<double> rows = rows_of(old_set);
  int width = old_set.pack_width(false);
  try {
    to_current_seaweed_rows(rows, width, "old.h5", MPI_COMM_WORLD);
    FAIL() << "no error on rank " << rank;
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("old.h5: 1 seaweed_particles rows"), std::string::npos)
        << e.what();
  }
}

TEST(LegacySeaweedRows, RefuseAnyOtherWidthNamingTheFile) {
  const int current = particles::ParticleSet(seaweed_layout()).pack_width(false);
  int width = current + 3;
  std::vector<double> rows(2 * static_cast<std::size_t>(width), 0.0);
  try {
    to_current_seaweed_rows(rows, width, "other.h5", MPI_COMM_WORLD);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "other.h5: seaweed_particles rows have " + std::to_string(current + 3) +
                  " values; this version reads " + std::to_string(current) + " (another layout)");
  }
}
