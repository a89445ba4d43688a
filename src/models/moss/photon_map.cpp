#include "models/moss/photon_map.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace biota::models::moss {

namespace {

// nanoflann adaptor over the position columns of a ParticleSet (owned + ghosts).
struct HitCloud {
  const particles::ParticleSet& set;
  std::size_t kdtree_get_point_count() const { return set.n_total(); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const {
    return set.real(particles::ParticleSet::kPos, static_cast<int>(d))[i];
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using HitTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, HitCloud>,
                                                    HitCloud, 3>;

// Counts the points of a radius search without storing them.
struct CountResult {
  double radius2;
  std::size_t count = 0;
  void init() {}
  void clear() { count = 0; }
  std::size_t size() const { return count; }
  bool empty() const { return count == 0; }
  bool full() const { return true; }
  bool addPoint(double dist, std::size_t) {
    if (dist < radius2) ++count;
    return true;
  }
  double worstDist() const { return radius2; }
};

}  // namespace

PhotonMap::PhotonMap(MPI_Comm comm, const Vec3& lo, const Vec3& hi, double radius)
    : comm_(comm), radius_(radius) {
  // Cells of edge >= r (ghost cutoff), at most 64 per axis; the box is widened by r on each side.
  const Vec3 origin = lo - Vec3{radius, radius, radius};
  const Vec3 ext = hi - lo + Vec3{2 * radius, 2 * radius, 2 * radius};
  const double dx = std::max(radius, std::max({ext.x, ext.y, ext.z}) / 64.0);
  core::Index3 cells;
  for (int d = 0; d < 3; ++d) cells[d] = std::max(1, static_cast<int>(std::ceil(ext[d] / dx)));
  decomp_ =
      std::make_unique<grid::Decomposition>(comm, cells, std::array<bool, 3>{false, false, false});
  pcomm_ = std::make_unique<particles::ParticleComm>(*decomp_, dx, origin);
  set_ = std::make_unique<particles::ParticleSet>(particles::ParticleLayout{});
}

PhotonMap::~PhotonMap() = default;

std::vector<double> PhotonMap::insolation(const PhotonTracer& tracer, const SquareLight& light,
                                          const BoundingSphere& sphere, std::uint64_t seed,
                                          std::uint64_t day, const PhotonMapSettings& s,
                                          const std::vector<Vec3>& queries, PhotonMapStats* stats) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm_, &rank);
  MPI_Comm_size(comm_, &size);
  const auto n = static_cast<std::uint64_t>(s.photons);
  const std::uint64_t first = n * rank / size, last = n * (rank + 1) / size;
  const double t0 = MPI_Wtime();
  std::vector<PhotonHit> hits;
  const TraceStats ts =
      tracer.trace(light, sphere, seed, day, first, last, s.indirect, s.max_bounces, hits);

  const double t1 = MPI_Wtime();
  set_->resize(0, 0);
  for (const auto& h : hits)
    set_->add_owned(h.photon * 128 + static_cast<std::uint64_t>(std::min(h.bounce, 127)), h.x);
  pcomm_->redistribute(*set_);
  pcomm_->build_ghosts(*set_, radius_);

  HitCloud cloud{*set_};
  HitTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  std::vector<long long> local(queries.size(), 0);
  const double r2 = radius_ * radius_;
  for (std::size_t q = 0; q < queries.size(); ++q) {
    if (pcomm_->owner_of(queries[q]) != rank) continue;
    CountResult res{r2};
    const double pt[3] = {queries[q].x, queries[q].y, queries[q].z};
    if (set_->n_total() > 0) tree.findNeighbors(res, pt, nanoflann::SearchParams());
    local[q] = static_cast<long long>(res.count);
  }
  const double t2 = MPI_Wtime();
  counts_.assign(queries.size(), 0);
  MPI_Allreduce(local.data(), counts_.data(), static_cast<int>(queries.size()), MPI_LONG_LONG,
                MPI_SUM, comm_);

  long long mine[3] = {ts.draws, ts.photons, ts.stored}, all[3] = {0, 0, 0};
  MPI_Allreduce(mine, all, 3, MPI_LONG_LONG, MPI_SUM, comm_);
  const double rho_ref =
      photon_density_per_draw(light, s.reference.value_or(sphere.centre), Vec3{0, 1, 0});
  const double plain_draws =
      static_cast<double>(all[0]) / (1.0 - emission_cone_cos2(light, sphere));
  const double phi = s.open_insolation / (plain_draws * rho_ref);
  if (stats) *stats = {all[0], all[1], all[2], phi, t1 - t0, t2 - t1};
  std::vector<double> out(queries.size());
  const double area = std::numbers::pi * r2;
  for (std::size_t q = 0; q < queries.size(); ++q)
    out[q] = phi * static_cast<double>(counts_[q]) / area;
  return out;
}

}  // namespace biota::models::moss
