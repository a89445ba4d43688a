// MossScenario: statistics, CSV, output, checkpoints, health (the daily loop is in
// moss_scenario.cpp).
#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "io/checkpoint.hpp"
#include "io/particle_output.hpp"
#include "scenarios/moss_scenario.hpp"

namespace biota::scenarios {

namespace mm = models::moss;
using core::Vec3;

std::array<long long, 3> MossScenario::region_counts() const {
  std::array<long long, 3> c{0, 0, 0};
  for (std::size_t i = 0; i < set_->n_owned(); ++i) ++c[region_of(set_->pos(i))];
  MPI_Allreduce(MPI_IN_PLACE, c.data(), 3, MPI_LONG_LONG, MPI_SUM, ctx_.comm);
  return c;
}

std::array<long long, 3> MossScenario::species_counts() const {
  std::array<long long, 3> c{0, 0, 0};
  for (std::size_t i = 0; i < set_->n_owned(); ++i) ++c[set_->u64(u_species_)[i]];
  MPI_Allreduce(MPI_IN_PLACE, c.data(), 3, MPI_LONG_LONG, MPI_SUM, ctx_.comm);
  return c;
}

namespace {
const char* kCsvHeader =
    "day,live,bryum,hypnum,polytrichum,back,open,roof,seeds,germinated,died,landed,lost,refused,"
    "occupied,expired,dropped,outside";
}

void MossScenario::open_csv(bool resume) {
  csv_open_ = true;
  if (decomp_->rank() == 0) {
    const std::string path = ctx_.output_dir + "/moss_counts.csv";
    if (resume)
      csv_.resume(path, kCsvHeader, static_cast<double>(day_) + 0.5);
    else
      csv_.start(path, kCsvHeader);
  }
  if (!resume) record_csv();  // the day-0 row
}

void MossScenario::record_csv() {
  const auto sp = species_counts();
  const auto rg = region_counts();
  if (decomp_->rank() != 0 || !csv_.is_open()) return;
  const auto& k = counts_;
  csv_.row(fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", day_,
                       sp[0] + sp[1] + sp[2], sp[0], sp[1], sp[2], rg[0], rg[1], rg[2],
                       seeds_.size(), k.germinated, k.died, k.landed, k.lost, k.refused, k.occupied,
                       k.expired, k.dropped, k.outside));
}

void MossScenario::write_output() {
  auto scope = ctx_.timers.scope("output");
  io::ParticleData d;
  const std::size_t no = set_->n_owned();
  d.owned = no;
  std::vector<double> species(no), gm(no), age(no), s(no), rot(no), region(no), layer(no);
  for (std::size_t i = 0; i < no; ++i) {
    const Vec3 x = set_->pos(i);
    d.positions.insert(d.positions.end(), {x.x, x.y, x.z});
    d.ids.push_back(set_->id(i));
    species[i] = static_cast<double>(set_->u64(u_species_)[i]);
    gm[i] = set_->real(a_gmoss_)[i];
    age[i] = set_->real(a_age_)[i];
    s[i] = set_->real(a_s_)[i];
    region[i] = region_of(x);
    layer[i] = static_cast<double>(set_->u64(u_layer_)[i]);
    // The paper turns each moss model at random (2.9): a fixed angle per moss, by its id.
    core::Rng r(seed_, set_->id(i), 0, core::RngPurpose::kMoss);
    rot[i] = r.uniform(0, 360);
  }
  d.scalars = {{"species", std::move(species)}, {"G_moss", std::move(gm)},
               {"age", std::move(age)},         {"S", std::move(s)},
               {"rotation", std::move(rot)},    {"region", std::move(region)},
               {"layer", std::move(layer)}};
  // The terrain with the day's soil state per face (replicated; written by rank 0).
  auto& t = d.surface;
  if (decomp_->rank() == 0) {
    for (const auto& v : mesh_.vertices) t.positions.insert(t.positions.end(), {v.x, v.y, v.z});
    for (const auto& tri : mesh_.triangles)
      for (int k = 0; k < 3; ++k) t.triangles.push_back(static_cast<std::uint64_t>(tri[k]));
    std::vector<double> soil(mesh_.palette_index.begin(), mesh_.palette_index.end());
    t.cell_scalars = {{"S", face_s_},         {"T_s", face_ts_},   {"rh_s", face_rhs_},
                      {"theta", face_theta_}, {"bucket", bucket_}, {"soil", std::move(soil)},
                      {"depth", depth_mm_}};
  } else {
    for (const char* name : {"S", "T_s", "rh_s", "theta", "bucket", "soil", "depth"})
      t.cell_scalars.push_back({name, {}});
  }
  io::ParticleOutput out(ctx_.comm, ctx_.output_dir, "moss", day_, time(),
                         ctx_.config.effective_toml(), vtk_compression_);
  out.write(d);
}

void MossScenario::write_checkpoint(const std::string& path) {
  auto scope = ctx_.timers.scope("checkpoint");
  io::CheckpointWriter w(*decomp_, path);
  w.write_attribute("scenario", std::string("moss"));
  w.write_attribute("config", ctx_.config.effective_toml());
  w.write_attribute("moss_day", static_cast<std::int64_t>(day_));
  w.write_attribute("moss_next_moss_id", static_cast<std::int64_t>(next_moss_id_));
  w.write_attribute("moss_next_seed_id", static_cast<std::int64_t>(next_seed_id_));
  w.write_attribute("moss_seeds_lost", static_cast<std::int64_t>(total_seeds_lost_));
  const int width = set_->pack_width(false);
  std::vector<double> rows;
  for (std::size_t i = 0; i < set_->n_owned(); ++i) set_->pack(i, false, rows);
  long long live = static_cast<long long>(set_->n_owned());
  MPI_Allreduce(MPI_IN_PLACE, &live, 1, MPI_LONG_LONG, MPI_SUM, ctx_.comm);
  w.write_attribute("moss_live", static_cast<std::int64_t>(live));
  if (live > 0) w.write_rows("moss_mosses", rows, width);  // no empty datasets in HDF5
  std::vector<double> seeds;  // exact in doubles: ids, days and faces < 2^53
  for (const auto& s : seeds_)
    seeds.insert(seeds.end(), {double(s.id), double(s.kind), double(s.species), double(s.face),
                               s.x.x, s.x.y, s.x.z, double(s.born), double(s.layer)});
  w.write_replicated("moss_seeds", seeds.empty() ? std::vector<double>{-1.0} : seeds);
  w.write_replicated("moss_bucket", bucket_);
  w.write_replicated("moss_face_state", [&] {
    std::vector<double> v = face_s_;
    v.insert(v.end(), face_ts_.begin(), face_ts_.end());
    v.insert(v.end(), face_rhs_.begin(), face_rhs_.end());
    v.insert(v.end(), face_theta_.begin(), face_theta_.end());
    return v;
  }());
  const auto& k = counts_;
  w.write_replicated("moss_counts", {double(k.germinated), double(k.died), double(k.landed),
                                     double(k.lost), double(k.refused), double(k.occupied),
                                     double(k.expired), double(k.dropped), double(k.outside)});
  w.commit();
}

void MossScenario::read_checkpoint(const std::string& path) {
  io::CheckpointReader r(*decomp_, path);
  day_ = r.read_attribute_int("moss_day");
  next_moss_id_ = static_cast<core::GlobalId>(r.read_attribute_int("moss_next_moss_id"));
  next_seed_id_ = static_cast<core::GlobalId>(r.read_attribute_int("moss_next_seed_id"));
  total_seeds_lost_ = r.read_attribute_int("moss_seeds_lost");
  int width = set_->pack_width(false);
  std::vector<double> rows;
  if (r.read_attribute_int("moss_live") > 0) rows = r.read_rows_share("moss_mosses", width);
  if (width != set_->pack_width(false))
    throw core::InputError(path + ": checkpoint moss layout differs");
  const std::size_t n = rows.size() / width;
  set_->resize(n, n);
  for (std::size_t k = 0; k < n; ++k) set_->unpack(k, false, rows.data() + k * width);
  pcomm_->redistribute(*set_);
  seeds_.clear();
  const auto sv = r.read_replicated("moss_seeds");
  for (std::size_t k = 0; k + 9 <= sv.size(); k += 9)
    seeds_.push_back({static_cast<core::GlobalId>(sv[k]),
                      static_cast<int>(sv[k + 1]),
                      static_cast<int>(sv[k + 2]),
                      static_cast<int>(sv[k + 3]),
                      {sv[k + 4], sv[k + 5], sv[k + 6]},
                      std::llround(sv[k + 7]),
                      static_cast<int>(sv[k + 8])});
  const auto b = r.read_replicated("moss_bucket");
  const std::size_t nf = centroid_.size();
  const auto fs = r.read_replicated("moss_face_state");
  if (b.size() != nf || fs.size() != 4 * nf)
    throw core::InputError(path + ": checkpoint terrain has another number of faces");
  bucket_ = b;
  face_s_.assign(fs.begin(), fs.begin() + nf);
  face_ts_.assign(fs.begin() + nf, fs.begin() + 2 * nf);
  face_rhs_.assign(fs.begin() + 2 * nf, fs.begin() + 3 * nf);
  face_theta_.assign(fs.begin() + 3 * nf, fs.end());
  const auto c = r.read_replicated("moss_counts");
  counts_ = {std::llround(c.at(0)), std::llround(c.at(1)), std::llround(c.at(2)),
             std::llround(c.at(3)), std::llround(c.at(4)), std::llround(c.at(5)),
             std::llround(c.at(6)), std::llround(c.at(7)), std::llround(c.at(8))};
  open_csv(true);
}

void MossScenario::check_health() {
  for (std::size_t i = 0; i < set_->n_owned(); ++i) {
    const Vec3 p = set_->pos(i);
    if (!std::isfinite(p.x + p.y + p.z + set_->real(a_gmoss_)[i]))
      throw core::UnstableError(
          fmt::format("moss: moss {} non-finite at day {}", set_->id(i), day_));
  }
  for (std::size_t f = 0; f < bucket_.size(); ++f)
    if (!std::isfinite(bucket_[f] + face_ts_[f] + face_rhs_[f]))
      throw core::UnstableError(
          fmt::format("moss: soil state of terrain face {} non-finite at day {}", f, day_));
}

void MossScenario::poison_for_test() {
  if (set_->n_owned() == 0) return Scenario::poison_for_test();
  set_->real(a_gmoss_)[0] = std::numeric_limits<double>::quiet_NaN();
}

std::string MossScenario::progress() {
  const auto sp = species_counts();
  return fmt::format("mosses {} (bryum {} hypnum {} polytrichum {}) seeds {} germinated {} died {}",
                     sp[0] + sp[1] + sp[2], sp[0], sp[1], sp[2], seeds_.size(), counts_.germinated,
                     counts_.died);
}

std::vector<std::string> MossScenario::timer_sections() const {
  return {"setup", "scene", "photon_trace", "photon_map", "soil",
          "moss",  "stats", "output",       "checkpoint"};
}

}  // namespace biota::scenarios
