// Poisson solver: DMDA ownership equals the Decomposition, manufactured solutions converge at
// second order, the pure-Neumann null space is handled, unknown options are errors.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "grid/decomposition.hpp"
#include "linalg/petsc_environment.hpp"
#include "linalg/poisson_solver.hpp"

using namespace biota;
using linalg::PressureBC;

namespace {
class PetscEnv : public ::testing::Environment {
 public:
  void TearDown() override { linalg::finalize(); }
};
const auto* env = ::testing::AddGlobalTestEnvironment(new PetscEnv);

linalg::PressureBCs all(PressureBC b) {
  return {{{b, b}, {b, b}, {b, b}}};
}

double global_max(double v) {
  double g = 0;
  MPI_Allreduce(&v, &g, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return g;
}

struct Result {
  double error;
  int iterations;
};

/// Solve L p = f for p = prod cos(pi x) (Neumann) or prod sin(pi x) (Dirichlet) on [0,1]^3.
Result manufactured(int N, PressureBC bc, const std::string& options = "") {
  grid::Decomposition d(MPI_COMM_WORLD, {N, N, N}, {false, false, false});
  const double dx = 1.0 / N, pi = std::numbers::pi;
  linalg::PoissonSolver solver(d, dx, all(bc), nullptr, options);
  EXPECT_EQ(solver.singular(), bc == PressureBC::kNeumann);
  const auto n = d.local_cells();
  grid::Field<double> rhs(n, 1, 1), p(n, 1, 1);
  auto exact = [&](int i, int j, int k) {
    const auto& lo = d.local_box().lo;
    const double x = (lo.x + i + 0.5) * dx, y = (lo.y + j + 0.5) * dx, z = (lo.z + k + 0.5) * dx;
    return bc == PressureBC::kNeumann ? std::cos(pi * x) * std::cos(pi * y) * std::cos(pi * z)
                                      : std::sin(pi * x) * std::sin(pi * y) * std::sin(pi * z);
  };
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) rhs(i, j, k) = -3 * pi * pi * exact(i, j, k);
  auto st = solver.solve(rhs, p);
  double err = 0;
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) err = std::max(err, std::fabs(p(i, j, k) - exact(i, j, k)));
  return {global_max(err), st.iterations};
}
}  // namespace

TEST(Poisson, DmdaOwnershipMatchesDecomposition) {
  // Uneven splits on every axis the rank count allows; the Cart grid is z-fastest, PETSc x-fastest.
  grid::Decomposition d(MPI_COMM_WORLD, {17, 13, 11}, {false, true, false});
  linalg::PoissonSolver solver(d, 0.1,
                               {{{PressureBC::kNeumann, PressureBC::kDirichlet},
                                 {PressureBC::kPeriodic, PressureBC::kPeriodic},
                                 {PressureBC::kNeumann, PressureBC::kNeumann}}});
  EXPECT_EQ(solver.petsc_owned_box().lo, d.local_box().lo);
  EXPECT_EQ(solver.petsc_owned_box().hi, d.local_box().hi);
  const auto c = d.coords(), P = d.dims();
  EXPECT_EQ(solver.petsc_rank(), c.x + P.x * (c.y + P.y * c.z));
  EXPECT_FALSE(solver.singular());
}

TEST(Poisson, ManufacturedNeumannSecondOrder) {
  auto r16 = manufactured(16, PressureBC::kNeumann);
  auto r32 = manufactured(32, PressureBC::kNeumann);
  const double order = std::log2(r16.error / r32.error);
  if (::testing::UnitTest::GetInstance()->current_test_info()) {
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0)
      std::printf("Neumann: err16 %.3e err32 %.3e order %.3f its %d %d\n", r16.error, r32.error,
                  order, r16.iterations, r32.iterations);
  }
  EXPECT_GT(order, 1.9);
  EXPECT_LT(r32.error, 2e-3);
}

TEST(Poisson, ManufacturedDirichletSecondOrder) {
  auto r16 = manufactured(16, PressureBC::kDirichlet);
  auto r32 = manufactured(32, PressureBC::kDirichlet);
  const double order = std::log2(r16.error / r32.error);
  int rank;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf("Dirichlet: err16 %.3e err32 %.3e order %.3f its %d %d\n", r16.error, r32.error,
                order, r16.iterations, r32.iterations);
  EXPECT_GT(order, 1.9);
}

// Multigrid: iterations per solve (cold start, rtol 1e-10) stay flat as the grid is refined, for
// every preconditioner of the comparison, on sizes that do not halve evenly down to the coarsest
// level (30 -> 15 -> 8 -> 4), with the right answer (second-order error).
TEST(Poisson, MultigridIterationsFlatInGridSize) {
  int rank;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  for (const std::string opts :
       {"", "-poisson_pc_type gmg", "-poisson_pc_type pfmg", "-poisson_pc_type mg",
        "-poisson_pc_type gamg", "-poisson_pc_type hypre"})
    for (PressureBC bc : {PressureBC::kNeumann, PressureBC::kDirichlet}) {
      int lo = 1 << 30, hi = 0;
      std::vector<double> err;
      for (int N : {10, 20, 30}) {
        const auto r = manufactured(N, bc, opts);
        lo = std::min(lo, r.iterations);
        hi = std::max(hi, r.iterations);
        err.push_back(r.error);
        if (rank == 0)
          std::printf("[%s] %s N=%d: %d its, error %.3e\n", opts.empty() ? "default" : opts.c_str(),
                      bc == PressureBC::kNeumann ? "Neumann" : "Dirichlet", N, r.iterations,
                      r.error);
      }
      linalg::clear_options(opts);
      EXPECT_LE(hi, 20) << opts;
      EXPECT_LE(hi - lo, 3) << opts;          // flat: no growth with the number of levels
      EXPECT_LT(err[2], err[0] / 7) << opts;  // (30/10)^2 = 9 for second order
    }
}

TEST(Poisson, UnknownOptionIsAnError) {
  grid::Decomposition d(MPI_COMM_WORLD, {8, 8, 8}, {false, false, false});
  std::string msg;
  try {
    linalg::PoissonSolver s(d, 0.1, all(PressureBC::kNeumann), nullptr, "-poisson_ksp_rtoll 1e-8",
                            "wind.poisson_options");
  } catch (const core::InputError& e) {
    msg = e.what();
  }
  EXPECT_NE(msg.find("-poisson_ksp_rtoll"), std::string::npos) << msg;
  EXPECT_NE(msg.find("wind.poisson_options"), std::string::npos) << msg;
  // A valid option is accepted, and an option outside the prefix is refused by name.
  EXPECT_NO_THROW(linalg::PoissonSolver(d, 0.1, all(PressureBC::kNeumann), nullptr,
                                        "-poisson_ksp_rtol 1e-9", "wind.poisson_options"));
  EXPECT_THROW(linalg::PoissonSolver(d, 0.1, all(PressureBC::kNeumann), nullptr, "-ksp_rtol 1e-9",
                                     "wind.poisson_options"),
               core::InputError);
}

TEST(Poisson, DescriptionSaysWhenThinBlocksChangeTheHierarchy) {
  // 5 cells along x split over the ranks: 1 rank and 2 (3 + 2 cells) halve x like one rank does;
  // 3 ranks (2 + 2 + 1) cannot (a block thinner than two cells), so the hierarchy, and the
  // bits, differ from one rank's, and the description says so.
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  grid::Decomposition d(MPI_COMM_WORLD, {5, 12, 12}, {false, false, false}, {size, 1, 1});
  linalg::PoissonSolver solver(d, 0.1,
                               {{{PressureBC::kNeumann, PressureBC::kDirichlet},
                                 {PressureBC::kNeumann, PressureBC::kNeumann},
                                 {PressureBC::kNeumann, PressureBC::kNeumann}}});
  const std::string text = solver.description();
  EXPECT_EQ(text.find("not bit for bit") != std::string::npos, size == 3) << text;
}
