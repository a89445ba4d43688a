// In-process A/B of CellList::for_each_pair (docs/performance-seaweed.md, session 21): the
// current header against an older one (namespace renamed to particles_old by run.sh), on the
// sphere positions of a real checkpoint, alternating the two builds-and-loops 400 times.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

#include "old_cell_list.hpp"
#include "particles/cell_list.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: cell_list_ab <positions.bin> [cutoff, m: 0.021]\n");
    return 1;
  }
  FILE* in = std::fopen(argv[1], "rb");
  unsigned long long n = 0;
  if (!in || std::fread(&n, sizeof n, 1, in) != 1) return 1;
  std::vector<double> pos(n * 3);
  if (std::fread(pos.data(), sizeof(double), pos.size(), in) != pos.size()) return 1;
  std::fclose(in);
  std::vector<double> x(n), y(n), z(n);
  for (std::size_t i = 0; i < n; ++i)
    x[i] = pos[3 * i], y[i] = pos[3 * i + 1], z[i] = pos[3 * i + 2];
  // The seaweed contact range: 2 radius + cluster margin + skin = 0.01 + 0.001 + 0.01 m.
  const double cutoff = argc > 2 ? std::atof(argv[2]) : 0.021;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  pairs.reserve(std::size_t(1) << 21);
  const auto keep = [&](std::size_t i, std::size_t j, double) { pairs.emplace_back(i, j); };
  const int reps = 400, warm = 4;
  double seconds[2] = {0, 0};
  std::size_t found[2] = {0, 0};
  for (int rep = 0; rep < reps; ++rep) {
    const int variant = rep & 1;
    pairs.clear();
    const auto t0 = std::chrono::steady_clock::now();
    if (variant == 0) {
      biota::particles_old::CellList cells(x.data(), y.data(), z.data(), n, cutoff);
      cells.for_each_pair(keep);
    } else {
      biota::particles::CellList cells(x.data(), y.data(), z.data(), n, cutoff);
      cells.for_each_pair(keep);
    }
    const auto t1 = std::chrono::steady_clock::now();
    if (rep >= warm) seconds[variant] += std::chrono::duration<double>(t1 - t0).count();
    found[variant] = pairs.size();
  }
  const double per = (reps - warm) / 2;
  std::printf(
      "%llu points, cutoff %g: pairs old %zu new %zu; ms per build + loop: old %.3f new %.3f, "
      "new/old %.3f\n",
      n, cutoff, found[0], found[1], 1e3 * seconds[0] / per, 1e3 * seconds[1] / per,
      seconds[1] / seconds[0]);
  return found[0] == found[1] ? 0 : 2;
}
