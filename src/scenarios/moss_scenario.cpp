#include "scenarios/moss_scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <limits>
#include <unordered_map>

#include "core/allgather.hpp"
#include "core/error.hpp"
#include "core/memory.hpp"
#include "io/output_layout.hpp"
#include "models/moss/life_cycle.hpp"
#include "models/moss/soil_depth.hpp"

namespace biota::scenarios {

namespace mm = models::moss;
using core::Vec3;

namespace {

// Rng stream ids of the replicated draws (moss and seed ids stay far below 2^60).
constexpr std::uint64_t kInitialStream = std::uint64_t{1} << 60;
constexpr std::uint64_t kOutsideStream = std::uint64_t{2} << 60;

// Uniform hash grid over points (integer counts only: decomposition-invariant).
struct PointGrid {
  double h;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells;
  static std::uint64_t key(long long i, long long j, long long k) {
    return (static_cast<std::uint64_t>(i + (1 << 20)) << 42) ^
           (static_cast<std::uint64_t>(j + (1 << 20)) << 21) ^
           static_cast<std::uint64_t>(k + (1 << 20));
  }
  long long c(double v) const { return static_cast<long long>(std::floor(v / h)); }
  void add(const Vec3& p, std::size_t i) { cells[key(c(p.x), c(p.y), c(p.z))].push_back(i); }
  template <class F>
  void near(const Vec3& p, F&& f) const {
    const long long ci = c(p.x), cj = c(p.y), ck = c(p.z);
    for (long long i = ci - 1; i <= ci + 1; ++i)
      for (long long j = cj - 1; j <= cj + 1; ++j)
        for (long long k = ck - 1; k <= ck + 1; ++k) {
          auto it = cells.find(key(i, j, k));
          if (it == cells.end()) continue;
          for (std::size_t q : it->second) f(q);
        }
  }
};

}  // namespace

MossScenario::~MossScenario() = default;

MossScenario::MossScenario(const RunContext& ctx) : ctx_(ctx) {
  const auto& c = ctx.config;
  seed_ = static_cast<std::uint64_t>(c.get_int("seed"));
  vtk_compression_ =
      io::output_layout_whole(
          c, "applies to grid fields (tank, seaweed, wind); the moss writes no grid fields")
          .compression;
  load_terrain();
  weather_.temperature = c.get_real("moss.weather.temperature");
  weather_.humidity = c.get_real("moss.weather.humidity");
  weather_.wind = c.get_real("moss.weather.wind");
  const double n0 = c.get_real("moss.weather.possible_sunshine");
  if (c.get_real("moss.weather.sunshine") > n0)
    c.fail("moss.weather.sunshine", fmt::format("must not exceed moss.weather.possible_sunshine "
                                                "= {} h (allowed: 0 to {})",
                                                n0, n0));
  weather_.sunshine_ratio = c.get_real("moss.weather.sunshine") / n0;
  rain_days_ = static_cast<int>(c.get_int("moss.weather.rain_days"));
  rain_mm_ = c.get_real("moss.weather.precipitation");
  if (rain_mm_ > 0 && rain_days_ == 0)
    c.fail("moss.weather.rain_days", "is 0 but moss.weather.precipitation > 0 (allowed: 1 to 365)");
  delta_form_ = c.get_string("moss.soil.delta_form") == "printed" ? mm::DeltaForm::kPrinted
                                                                  : mm::DeltaForm::kCorrected;
  ch_radius_ = c.get_real("moss.soil.ch_radius");
  size_ = c.get_real("moss.size");
  ch_max_count_ = std::floor(M_PI * ch_radius_ * ch_radius_ / (size_ * size_));
  moss_reflectance_ = c.get_real("moss.reflectance");
  gemma_distance_ = c.get_real("moss.gemma_distance");
  spore_distance_ = c.get_real("moss.spore_distance");
  patch_radius_ = c.get_real("moss.patch.radius");
  patch_inside_ = static_cast<int>(c.get_int("moss.patch.inside"));
  max_layers_ = static_cast<int>(c.get_int("moss.max_layers"));
  max_mosses_ = c.get_int("moss.max_mosses");
  max_seeds_ = c.get_int("moss.max_seeds");
  outside_interval_ = c.get_int("moss.outside_spore_interval");
  back_z_ = c.get_real("moss.region.back_z");
  roof_y_ = c.get_real("moss.region.roof_y");
  {
    // Replicated: seeds (~80 B), the day's moss list and scene (~400 B per moss: record, 8
    // vertices + 6 quads in Embree, BVH), photon-map queries (~40 B per point); per rank: the
    // stored hits (<= 1 / (1 - ρ_max) per photon, ~150 B each with ghosts and kd-tree).
    int ranks = 1;
    MPI_Comm_size(ctx.comm, &ranks);
    const double photons = static_cast<double>(c.get_int("moss.light.photons"));
    double rmax = c.get_real("moss.reflectance");
    for (double r : c.get_real_list("moss.soil.reflectance")) rmax = std::max(rmax, r);
    core::check_memory(
        ctx.comm, c,
        {{"seeds", 120.0 * double(max_seeds_)},
         {"mosses and scene", 440.0 * double(max_mosses_)},
         {"photon hits", 150.0 * photons / std::max(0.02, 1 - rmax) / ranks}},
        fmt::format("moss.max_mosses = {}, moss.max_seeds = {}, moss.light.photons = {}",
                    max_mosses_, max_seeds_, photons));
  }
  species_ = mm::paper_species();
  for (int k = 0; k < 3; ++k)
    if (c.get_bool(MossScenario::kSpeciesKeys[k])) species_enabled_.push_back(k);
  if (species_enabled_.empty())
    c.fail("moss.species.bryum", "and the other two species are all false; enable at least one");

  // Light.
  map_settings_.photons = c.get_int("moss.light.photons");
  map_settings_.radius = c.get_real("moss.light.radius");
  map_settings_.open_insolation = c.get_real("moss.light.open_insolation");
  map_settings_.indirect = c.get_bool("moss.light.indirect");
  map_settings_.distance_factor = c.get_real("moss.light.distance_factor");
  Vec3 to_sun{0, 1, 0};
  const std::string mode = c.get_string("moss.sun.mode");
  if (mode == "angles")
    to_sun = mm::sun_direction_from_angles(c.get_real("moss.sun.elevation"),
                                           c.get_real("moss.sun.azimuth"));
  if (mode == "date") {
    try {
      to_sun =
          mm::sun_direction_from_date(static_cast<int>(c.get_int("moss.sun.day_of_year")),
                                      c.get_real("moss.sun.hour"), c.get_real("moss.sun.latitude"));
    } catch (const std::invalid_argument& e) {
      c.fail("moss.sun.hour", e.what());
    }
  }
  sphere_ = tracer_->bounding_sphere();
  light_ = mm::sun_light(to_sun, sphere_, map_settings_.distance_factor);
  photon_map_ = std::make_unique<mm::PhotonMap>(ctx.comm, lo_, hi_, map_settings_.radius);

  // Soil: bucket full at day 0 (erratum 10).
  const std::size_t nf = mesh_.triangles.size();
  bucket_.resize(nf);
  for (std::size_t f = 0; f < nf; ++f)
    bucket_[f] = std::clamp(depth_mm_[f], 1.0, 1000.0) *
                 mm::soil_params(static_cast<mm::SoilType>(mesh_.palette_index[f])).theta_sat;
  face_s_.assign(nf, 0.0), face_ts_.assign(nf, 0.0), face_rhs_.assign(nf, 0.0);
  face_theta_.assign(nf, 0.0);

  noise_ = mm::GrowthNoise(c.get_real("moss.noise.amplitude"), c.get_real("moss.noise.hurst"),
                           static_cast<int>(c.get_int("moss.noise.levels")), seed_, lo_, hi_);

  // Mosses: partitioned on cells of at least the patch radius (<= 64 per axis).
  const Vec3 ext = hi_ - lo_ + Vec3{2 * patch_radius_, 2 * patch_radius_, 2 * patch_radius_};
  const double dx = std::max(patch_radius_, std::max({ext.x, ext.y, ext.z}) / 64.0);
  core::Index3 cells;
  for (int d = 0; d < 3; ++d) cells[d] = std::max(1, static_cast<int>(std::ceil(ext[d] / dx)));
  decomp_ = std::make_unique<grid::Decomposition>(ctx.comm, cells,
                                                  std::array<bool, 3>{false, false, false});
  pcomm_ = std::make_unique<particles::ParticleComm>(
      *decomp_, dx, lo_ - Vec3{patch_radius_, patch_radius_, patch_radius_});
  particles::ParticleLayout layout;
  a_gmoss_ = layout.add_real("g_moss", 1, true, false);
  a_gmax_ = layout.add_real("g_max", 1, true, false);
  a_age_ = layout.add_real("age", 1, true, false);
  a_s_ = layout.add_real("insolation", 1, true, false);
  u_species_ = layout.add_u64("species", 1, true, false);
  u_face_ = layout.add_u64("face", 1, true, false);
  u_layer_ = layout.add_u64("layer", 1, true, false);
  set_ = std::make_unique<particles::ParticleSet>(layout);
  {
    auto scope = ctx_.timers.scope("setup");
    place_initial();
  }
  if (decomp_->rank() == 0)
    fmt::print(
        "moss: terrain {} triangles, box [{:.3g}, {:.3g}] x [{:.3g}, {:.3g}] x [{:.3g}, {:.3g}] "
        "m; {} photons/day ({}), S_open {} W/m^2; T = {} K; {} initial mosses; ranks {} x {} x "
        "{}\n",
        nf, lo_.x, hi_.x, lo_.y, hi_.y, lo_.z, hi_.z, map_settings_.photons,
        map_settings_.indirect ? "indirect light on" : "indirect light off",
        map_settings_.open_insolation, weather_.temperature, next_moss_id_, decomp_->dims()[0],
        decomp_->dims()[1], decomp_->dims()[2]);
}

void MossScenario::load_terrain() {
  const auto& c = ctx_.config;
  namespace fs = std::filesystem;
  fs::path file = c.get_string("moss.terrain.file");
  if (file.is_relative()) file = fs::path(c.source()).parent_path() / file;
  const std::vector<io::PaletteColour> pal{{"humus", {0x5c / 255.0, 0x33 / 255.0, 0x17 / 255.0}},
                                           {"sand", {0xcc / 255.0, 0x99 / 255.0, 0x33 / 255.0}},
                                           {"asphalt", {0x80 / 255.0, 0x80 / 255.0, 0x80 / 255.0}}};
  try {
    mesh_ = io::read_obj_terrain(file.string(), pal, c.get_real("moss.terrain.colour_tolerance"),
                                 c.get_string("moss.terrain.up"));
  } catch (const core::InputError& e) {
    c.fail("moss.terrain.file", std::string("cannot be used: ") + e.what());
  }
  const auto& refl = c.get_real_list("moss.soil.reflectance");
  for (int k = 0; k < 3; ++k)
    if (!(refl[k] >= 0 && refl[k] <= 1))
      c.fail("moss.soil.reflectance", fmt::format("[{}] = {} is outside [0, 1]", k, refl[k]));
  const std::size_t nf = mesh_.triangles.size();
  reflect_.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) reflect_[f] = refl[mesh_.palette_index[f]];
  normal_ = mm::face_normals(mesh_.vertices, mesh_.triangles);
  centroid_.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& t = mesh_.triangles[f];
    centroid_[f] = (mesh_.vertices[t[0]] + mesh_.vertices[t[1]] + mesh_.vertices[t[2]]) / 3.0;
  }
  lo_ = {1e300, 1e300, 1e300}, hi_ = {-1e300, -1e300, -1e300};
  for (const auto& v : mesh_.vertices)
    for (int d = 0; d < 3; ++d) lo_[d] = std::min(lo_[d], v[d]), hi_[d] = std::max(hi_[d], v[d]);
  tracer_ = std::make_unique<mm::PhotonTracer>(mesh_.vertices, mesh_.triangles, reflect_);
  depth_mm_ = mm::soil_depth_mm(*tracer_, mesh_.vertices, mesh_.triangles);
  sampler_ = std::make_unique<mm::SurfaceSampler>(mesh_.vertices, mesh_.triangles, normal_);
  if (!(sampler_->area() > 0))
    c.fail("moss.terrain.file",
           "has no upward face (outward normal with y > 0; is `moss.terrain.up` right?): no place "
           "for a moss to stand");
}

void MossScenario::add_moss(core::GlobalId id, const Vec3& x, int species, int face, int layer) {
  if (pcomm_->owner_of(x) != decomp_->rank()) return;
  const std::size_t i = set_->add_owned(id, x);
  set_->u64(u_species_)[i] = static_cast<std::uint64_t>(species);
  set_->u64(u_face_)[i] = static_cast<std::uint64_t>(face);
  set_->u64(u_layer_)[i] = static_cast<std::uint64_t>(layer);
}

void MossScenario::place_initial() {
  // Replicated: every rank draws every placement and keeps the ones it owns.
  const mm::SurfaceSampler& sampler = *sampler_;
  const long long n = ctx_.config.get_int("moss.initial");
  PointGrid grid{size_, {}};
  std::vector<Vec3> placed;
  for (long long k = 0; k < n && static_cast<long long>(placed.size()) < max_mosses_; ++k) {
    core::Rng rng(seed_, kInitialStream + static_cast<std::uint64_t>(k), 0,
                  core::RngPurpose::kMoss);
    const int sp = species_enabled_[rng.uniform_int(0, std::ssize(species_enabled_) - 1)];
    const mm::Landing l = sampler.sample(rng, size_);
    bool taken = false;
    grid.near(l.centre, [&](std::size_t q) {
      const Vec3 d = placed[q] - l.centre;
      taken = taken || core::dot(d, d) < 0.81 * size_ * size_;
    });
    if (taken) continue;
    grid.add(l.centre, placed.size());
    placed.push_back(l.centre);
    add_moss(next_moss_id_++, l.centre, sp, l.face, 0);
  }
}

int MossScenario::region_of(const Vec3& x) const {
  if (x.y > roof_y_) return 2;
  return x.z < back_z_ ? 0 : 1;
}

bool MossScenario::may_germinate(const MossSeed& s) const {
  // (3.17) is at most the product of the factors' largest values 1/2 + 2^-n (erratum 17: the
  // smallest, 1/2 - 2^-n, is never larger in magnitude), so G g(L) <= bound g(L); a seed with
  // bound g(L) <= τ_b fails (3.24) today for any S, T_s and rh_s.
  const auto& sp = species_[s.species];
  const double bound = (0.5 + std::pow(2.0, -sp.n_t)) * (0.5 + std::pow(2.0, -sp.n_rh)) *
                       (0.5 + std::pow(2.0, -sp.n_s));
  const auto w = s.kind == 0 ? mm::kGemmaWindow : mm::kSporeWindow;
  const double L = static_cast<double>(day_ - s.born);
  return L <= w.l1 && bound * mm::factor_fitness(L, w.l0, w.l1, 1.0) > sp.tau_b;
}

double MossScenario::fitness_at(int species, double insolation, int face) const {
  return mm::fitness(species_[species], face_ts_[face], face_rhs_[face], insolation);
}

std::vector<MossRecord> MossScenario::gather_mosses() const {
  constexpr int kW = 11;
  std::vector<double> mine;
  mine.reserve(kW * set_->n_owned());
  for (std::size_t i = 0; i < set_->n_owned(); ++i) {
    const Vec3 x = set_->pos(i);
    mine.insert(mine.end(), {std::bit_cast<double>(set_->id(i)), x.x, x.y, x.z,
                             double(set_->u64(u_species_)[i]), double(set_->u64(u_face_)[i]),
                             set_->real(a_gmoss_)[i], set_->real(a_gmax_)[i], set_->real(a_age_)[i],
                             set_->real(a_s_)[i], double(set_->u64(u_layer_)[i])});
  }
  const std::vector<double> all = core::allgather_concat(ctx_.comm, mine);
  const int total = static_cast<int>(all.size());
  std::vector<MossRecord> out;
  out.reserve(total / kW);
  for (int k = 0; k + kW <= total; k += kW)
    out.push_back({std::bit_cast<core::GlobalId>(all[k]),
                   {all[k + 1], all[k + 2], all[k + 3]},
                   static_cast<int>(all[k + 4]),
                   static_cast<int>(all[k + 5]),
                   all[k + 6],
                   all[k + 7],
                   all[k + 8],
                   all[k + 9],
                   static_cast<int>(all[k + 10])});
  std::sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.id < b.id; });
  return out;
}

void MossScenario::step() {
  if (!csv_open_) open_csv(false);
  counts_ = {};
  const auto all = gather_mosses();
  photon_and_soil(all);
  {
    auto scope = ctx_.timers.scope("moss");
    germinate(all);
    grow_and_reproduce(all);
  }
  ++day_;
  {
    auto scope = ctx_.timers.scope("stats");
    record_csv();
  }
}

void MossScenario::photon_and_soil(const std::vector<MossRecord>& all) {
  // 1. Photon map over today's scene: terrain + every live moss (sorted by id on every rank, so
  // every rank builds the same BVH).
  std::vector<Vec3> pos(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) pos[i] = all[i].x;
  {
    auto scope = ctx_.timers.scope("scene");
    if (!scene_built_ || pos != scene_mosses_) {  // unchanged at the cap in a constant climate
      tracer_->set_mosses(pos, size_, moss_reflectance_);
      scene_mosses_ = pos;
      scene_built_ = true;
    }
  }
  std::vector<Vec3> q = centroid_;
  q.insert(q.end(), pos.begin(), pos.end());
  // Seeds that cannot germinate today whatever their S (the bound of may_germinate) need no S.
  seed_query_.assign(seeds_.size(), -1);
  for (std::size_t j = 0; j < seeds_.size(); ++j)
    if (may_germinate(seeds_[j])) {
      seed_query_[j] = static_cast<long long>(q.size() - centroid_.size() - pos.size());
      q.push_back(seeds_[j].x);
    }
  const auto S =
      photon_map_->insolation(*tracer_, light_, sphere_, seed_, static_cast<std::uint64_t>(day_),
                              map_settings_, q, &last_map_);
  const std::size_t nf = centroid_.size(), nm = all.size();
  std::copy(S.begin(), S.begin() + nf, face_s_.begin());
  moss_s_.assign(S.begin() + nf, S.begin() + nf + nm);
  seed_s_.assign(S.begin() + nf + nm, S.end());
  ctx_.timers.add("photon_trace", last_map_.trace_seconds);
  ctx_.timers.add("photon_map", last_map_.map_seconds);
  auto scope = ctx_.timers.scope("soil");
  // 2. Soil state per face (replicated): (3.5) with m = mosses within ch_radius of the centroid.
  PointGrid grid{ch_radius_, {}};
  for (std::size_t i = 0; i < nm; ++i) grid.add(pos[i], i);
  const double r2 = ch_radius_ * ch_radius_;
  const double rain = mm::is_rain_day(day_, rain_days_) ? rain_mm_ / rain_days_ : 0.0;
  for (std::size_t f = 0; f < nf; ++f) {
    long long m = 0;
    grid.near(centroid_[f], [&](std::size_t i) {
      const Vec3 d = pos[i] - centroid_[f];
      m += core::dot(d, d) < r2 ? 1 : 0;
    });
    mm::SoilDayInput in;
    in.insolation = face_s_[f];
    in.ch = mm::bulk_transfer(static_cast<double>(m), ch_max_count_, soil_k_);
    in.bucket = bucket_[f];
    in.rain = rain;
    in.depth_mm = depth_mm_[f];
    in.soil = static_cast<mm::SoilType>(mesh_.palette_index[f]);
    const auto st = mm::soil_day(in, weather_, soil_k_, delta_form_);
    bucket_[f] = st.bucket;
    face_ts_[f] = st.surface_temperature;
    face_rhs_[f] = st.surface_humidity;
    face_theta_[f] = st.theta;
  }
}

void MossScenario::germinate(const std::vector<MossRecord>& all) {
  // Replicated, in seed-id order: (3.24); an occupied spot (a live moss, or a seed germinated
  // earlier today, within 0.9 model sizes) makes the seed disappear: an established moss always
  // has priority, and among seeds the older (lower id) one; at the cap germination is refused.
  PointGrid grid{size_, {}};
  std::vector<Vec3> taken;
  for (const auto& m : all) grid.add(m.x, taken.size()), taken.push_back(m.x);
  long long live = static_cast<long long>(all.size());
  std::vector<MossSeed> keep;
  keep.reserve(seeds_.size());
  for (std::size_t j = 0; j < seeds_.size(); ++j) {
    const MossSeed& s = seeds_[j];
    const auto w = s.kind == 0 ? mm::kGemmaWindow : mm::kSporeWindow;
    const double L = static_cast<double>(day_ - s.born);
    if (L > w.l1) {
      ++counts_.expired;
      continue;
    }
    const bool can = seed_query_[j] >= 0;
    if (!can || !mm::germinates(species_[s.species],
                                fitness_at(s.species, seed_s_[seed_query_[j]], s.face), L, w)) {
      keep.push_back(s);
      continue;
    }
    if (live >= max_mosses_) {
      ++counts_.refused;
      keep.push_back(s);
      continue;
    }
    bool occupied = false;
    grid.near(s.x, [&](std::size_t q) {
      const Vec3 d = taken[q] - s.x;
      occupied = occupied || core::dot(d, d) < 0.81 * size_ * size_;
    });
    if (occupied) {
      ++counts_.occupied;
      continue;
    }
    grid.add(s.x, taken.size());
    taken.push_back(s.x);
    ++live;
    ++counts_.germinated;
    add_moss(next_moss_id_++, s.x, s.species, s.face, s.layer);
  }
  seeds_.swap(keep);
}

void MossScenario::grow_and_reproduce(const std::vector<MossRecord>& all) {
  // Owners grow their mosses (3.17)-(3.21); a moss germinated today starts tomorrow.
  const bool spore_day = mm::is_rain_day(day_, rain_days_);
  const std::size_t no = set_->n_owned();
  std::vector<char> dead(no, 0);
  std::vector<int> gemmae(no, 0);
  std::vector<char> spore(no, 0);
  long long died = 0;
  for (std::size_t i = 0; i < no; ++i) {
    const core::GlobalId id = set_->id(i);
    auto it = std::lower_bound(all.begin(), all.end(), id,
                               [](const MossRecord& r, core::GlobalId v) { return r.id < v; });
    if (it == all.end() || it->id != id) continue;
    const double s = moss_s_[static_cast<std::size_t>(it - all.begin())];
    const int sp = static_cast<int>(set_->u64(u_species_)[i]);
    const int face = static_cast<int>(set_->u64(u_face_)[i]);
    mm::MossState st{set_->real(a_gmoss_)[i], set_->real(a_gmax_)[i],
                     static_cast<long long>(set_->real(a_age_)[i])};
    const mm::MossDay d = mm::moss_day(species_[sp], fitness_at(sp, s, face), spore_day, st);
    set_->real(a_gmoss_)[i] = st.g_moss;
    set_->real(a_gmax_)[i] = st.g_max;
    set_->real(a_age_)[i] = static_cast<double>(st.age_days);
    set_->real(a_s_)[i] = s;
    dead[i] = d.dies;
    died += d.dies ? 1 : 0;
    gemmae[i] = d.dies ? 0 : d.gemmae;
    spore[i] = !d.dies && d.spore;
  }
  // Survivors only; then ghosts within the patch radius for the surface-of-patch test.
  std::vector<int> g2;
  std::vector<char> s2;
  for (std::size_t i = 0; i < no; ++i)
    if (!dead[i]) g2.push_back(gemmae[i]), s2.push_back(spore[i]);
  set_->remove_owned(dead);
  pcomm_->migrate(*set_);  // nothing moves; sets up the ghost plan
  pcomm_->build_ghosts(*set_, patch_radius_);
  PointGrid near{patch_radius_, {}};
  for (std::size_t k = 0; k < set_->n_total(); ++k) near.add(set_->pos(k), k);
  const double pr2 = patch_radius_ * patch_radius_;
  std::vector<Vec3> centres(all.size());
  std::vector<int> faces(all.size()), layers(all.size());
  for (std::size_t k = 0; k < all.size(); ++k)
    centres[k] = all[k].x, faces[k] = all[k].face, layers[k] = all[k].layer;
  // One record per seed made: parent id, index, kind, species, face (-1: lost), centre.
  std::vector<double> mine;
  for (std::size_t i = 0; i < set_->n_owned(); ++i) {
    if (g2[i] == 0 && !s2[i]) continue;
    const Vec3 x = set_->pos(i);
    int neighbours = 0;
    near.near(x, [&](std::size_t k) {
      const Vec3 d = set_->pos(k) - x;
      neighbours += (k != i && core::dot(d, d) < pr2) ? 1 : 0;
    });
    if (neighbours >= patch_inside_) continue;  // inside a dense patch: grows, no offspring
    const core::GlobalId id = set_->id(i);
    const int sp = static_cast<int>(set_->u64(u_species_)[i]);
    const int face = static_cast<int>(set_->u64(u_face_)[i]);
    core::Rng rng(seed_, id, static_cast<std::uint64_t>(day_), core::RngPurpose::kMoss);
    const int n = g2[i] + (s2[i] ? 1 : 0);
    for (int k = 0; k < n; ++k) {
      const bool is_spore = k == g2[i];
      const Vec3 dir =
          is_spore ? mm::spore_direction(normal_[face], rng) : mm::gemma_direction(rng);
      Vec3 b = x + dir * (is_spore ? spore_distance_ : gemma_distance_);  // (3.22), (3.23)
      b += noise_.offset(b);
      const auto l =
          mm::drop_seed(*tracer_, normal_, centres, faces, layers, max_layers_, b, size_);
      mine.insert(mine.end(),
                  {std::bit_cast<double>(id), double(k), is_spore ? 1.0 : 0.0, double(sp),
                   l ? double(l->face) : -1.0, l ? l->centre.x : 0.0, l ? l->centre.y : 0.0,
                   l ? l->centre.z : 0.0, l ? double(l->layer) : 0.0});
    }
  }
  set_->clear_ghosts();
  MPI_Allreduce(MPI_IN_PLACE, &died, 1, MPI_LONG_LONG, MPI_SUM, ctx_.comm);
  counts_.died = died;
  settle_new_seeds(mine);
}

void MossScenario::settle_new_seeds(std::vector<double>& mine) {
  constexpr int kW = 9;
  const std::vector<double> all = core::allgather_concat(ctx_.comm, mine);
  const int total = static_cast<int>(all.size());
  std::vector<std::size_t> order(static_cast<std::size_t>(total / kW));
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  auto key = [&](std::size_t k) {
    return std::pair{std::bit_cast<core::GlobalId>(all[kW * k]), all[kW * k + 1]};
  };
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return key(a) < key(b); });
  auto push = [&](int kind, int species, int face, const Vec3& x, int layer) {
    if (static_cast<long long>(seeds_.size()) >= max_seeds_) {
      ++counts_.dropped;
      return;
    }
    seeds_.push_back({next_seed_id_++, kind, species, face, x, day_, layer});
    ++counts_.landed;
  };
  for (std::size_t k : order) {
    const double* r = all.data() + kW * k;
    if (r[4] < 0) {
      ++counts_.lost;
      continue;
    }
    push(static_cast<int>(r[2]), static_cast<int>(r[3]), static_cast<int>(r[4]), {r[5], r[6], r[7]},
         static_cast<int>(r[8]));
  }
  // One spore from outside every interval days (spec 2.4), placed like the initial mosses.
  if (outside_interval_ > 0 && (day_ + 1) % outside_interval_ == 0) {
    core::Rng rng(seed_, kOutsideStream, static_cast<std::uint64_t>(day_), core::RngPurpose::kMoss);
    const int sp = species_enabled_[rng.uniform_int(0, std::ssize(species_enabled_) - 1)];
    const mm::Landing l = sampler_->sample(rng, size_);
    ++counts_.outside;
    push(1, sp, l.face, l.centre, 0);
  }
  total_seeds_lost_ += counts_.lost;
}

}  // namespace biota::scenarios
