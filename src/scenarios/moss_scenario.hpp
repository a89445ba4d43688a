#pragma once
/// \file moss_scenario.hpp
/// \brief The moss paper's experiment (spec moss.md, docs/moss.md): three moss species spreading
/// over a polygon terrain for `run.steps` days. One step is one day in the order of 3.7: photon
/// map (the terrain and today's mosses as occluders and reflectors), soil state per terrain face,
/// then the mosses: germination, growth and death, gemmae and spores (falling along -y), and one
/// spore from outside every `moss.outside_spore_interval` days.
///
/// Parallel layout: the live mosses are a particles::ParticleSet partitioned over the ranks on a
/// Cartesian decomposition of the scene box, with ghosts within the surface-of-patch radius; the
/// owner of a moss grows it and casts its gemmae and spores. The terrain, its soil state and the
/// dormant seeds (landed gemmae and spores) are small and replicated: every rank computes them the
/// same way from the same data, and every decision that creates or removes a moss depends only on
/// (seed, moss/seed id, day) and on data sorted by id, so the population is the same on any rank
/// count, bitwise (docs/moss.md, "Decomposition invariance").
#include <memory>
#include <vector>

#include "grid/decomposition.hpp"
#include "io/csv_series.hpp"
#include "io/obj_terrain.hpp"
#include "models/moss/fitness.hpp"
#include "models/moss/photon_map.hpp"
#include "models/moss/seed_fall.hpp"
#include "models/moss/soil.hpp"
#include "particles/particle_comm.hpp"
#include "scenarios/scenario.hpp"

namespace biota::scenarios {

/// \brief One live moss as gathered for tests, output and the daily scene.
struct MossRecord {
  core::GlobalId id = 0;
  core::Vec3 x{};
  int species = 0, face = 0;
  double g_moss = 0, g_max = 0, age = 0, insolation = 0;
  int layer = 0;  ///< 0 on the soil, k + 1 on a moss of layer k
};

/// \brief A landed gemma or spore that has not germinated (replicated on every rank).
struct MossSeed {
  core::GlobalId id = 0;
  int kind = 0;  ///< 0 gemma, 1 spore
  int species = 0, face = 0;
  core::Vec3 x{};
  long long born = 0;  ///< day it was created
  int layer = 0;
};

/// \brief Counters of one day (identical on every rank).
struct MossDayCounts {
  long long germinated = 0, died = 0, landed = 0, lost = 0, refused = 0, occupied = 0, expired = 0,
            dropped = 0, outside = 0;
};

/// \brief Terrain + soil + photon map + moss population; see file comment.
class MossScenario : public Scenario {
 public:
  static void declare_config(core::ConfigSchema& schema);
  /// \brief The deck keys switching the species of Table 4.2 on and off, in species order.
  static constexpr const char* kSpeciesKeys[3] = {"moss.species.bryum", "moss.species.hypnum",
                                                  "moss.species.polytrichum"};
  explicit MossScenario(const RunContext& ctx);
  ~MossScenario() override;

  void step() override;
  long long step_index() const override { return day_; }
  double time() const override { return static_cast<double>(day_) * 86400.0; }
  double dt() const override { return 86400.0; }
  void write_output() override;
  void write_checkpoint(const std::string& path) override;
  void read_checkpoint(const std::string& path) override;
  void check_health() override;
  void poison_for_test() override;
  std::string progress() override;
  std::vector<std::string> timer_sections() const override;
  core::CommCounter comm_sent() const override { return pcomm_->sent(); }

  /// \brief Every live moss sorted by id, on every rank. Collective.
  std::vector<MossRecord> gather_mosses() const;
  const std::vector<MossSeed>& seeds() const { return seeds_; }
  /// \brief Per terrain face of the last day: S (W/m²), T_s (K), rh_s, θ, bucket (mm).
  const std::vector<double>& face_insolation() const { return face_s_; }
  const std::vector<double>& face_temperature() const { return face_ts_; }
  const std::vector<double>& face_humidity() const { return face_rhs_; }
  const std::vector<double>& face_bucket() const { return bucket_; }
  const MossDayCounts& last_counts() const { return counts_; }
  /// \brief Live mosses per region (0 back: under the roof and the back floor, 1 open ground,
  /// 2 roof top), global. Collective.
  std::array<long long, 3> region_counts() const;
  /// \brief Live mosses per species, global. Collective.
  std::array<long long, 3> species_counts() const;

 private:
  void load_terrain();
  void place_initial();
  int region_of(const core::Vec3& x) const;
  void add_moss(core::GlobalId id, const core::Vec3& x, int species, int face, int layer);
  void photon_and_soil(const std::vector<MossRecord>& all);
  void germinate(const std::vector<MossRecord>& all);
  void grow_and_reproduce(const std::vector<MossRecord>& all);
  void settle_new_seeds(std::vector<double>& mine);
  void record_csv();
  void open_csv(bool resume);
  void write_terrain_and_mosses();
  double fitness_at(int species, double insolation, int face) const;
  bool may_germinate(const MossSeed& s) const;

  RunContext ctx_;
  std::uint64_t seed_ = 0;
  long long day_ = 0;
  int vtk_compression_ = 0;  ///< output.compression of the VTK pieces
  // Terrain, replicated.
  io::TerrainMesh mesh_;
  std::vector<models::moss::Vec3> centroid_, normal_;
  std::vector<double> reflect_, depth_mm_;
  std::unique_ptr<models::moss::PhotonTracer> tracer_;
  std::unique_ptr<models::moss::SurfaceSampler> sampler_;  // upward faces, by area
  std::unique_ptr<models::moss::PhotonMap> photon_map_;
  models::moss::BoundingSphere sphere_;
  models::moss::SquareLight light_;
  models::moss::PhotonMapSettings map_settings_;
  core::Vec3 lo_{}, hi_{};
  // Weather and soil.
  models::moss::Weather weather_;
  models::moss::SoilConstants soil_k_;
  models::moss::DeltaForm delta_form_ = models::moss::DeltaForm::kCorrected;
  double rain_mm_ = 0;
  int rain_days_ = 180;
  double ch_radius_ = 0.1, ch_max_count_ = 0;
  std::vector<double> bucket_, face_s_, face_ts_, face_rhs_, face_theta_;
  // Mosses and seeds.
  std::array<models::moss::Species, 3> species_;
  std::vector<int> species_enabled_;
  double size_ = 0.01, moss_reflectance_ = 0.2;
  double gemma_distance_ = 0.02, spore_distance_ = 0.05;
  double patch_radius_ = 0.015;
  int patch_inside_ = 8, max_layers_ = 3;
  long long max_mosses_ = 16384, max_seeds_ = 65536;
  long long outside_interval_ = 10;
  core::GlobalId next_moss_id_ = 0, next_seed_id_ = 0;
  double back_z_ = 0.7, roof_y_ = 1.0;
  models::moss::GrowthNoise noise_;
  std::unique_ptr<grid::Decomposition> decomp_;
  std::unique_ptr<particles::ParticleComm> pcomm_;
  std::unique_ptr<particles::ParticleSet> set_;
  int a_gmoss_ = 0, a_gmax_ = 0, a_age_ = 0, a_s_ = 0, u_species_ = 0, u_face_ = 0, u_layer_ = 0;
  std::vector<MossSeed> seeds_;
  std::vector<double> seed_s_;         // today's S at the seeds that may germinate
  std::vector<long long> seed_query_;  // per seed: index into seed_s_, -1 if it cannot germinate
  std::vector<double> moss_s_;         // today's S at each moss of the day's gathered list
  MossDayCounts counts_;
  long long total_seeds_lost_ = 0;
  io::CsvSeries csv_;
  bool csv_open_ = false;
  models::moss::PhotonMapStats last_map_{};
  std::vector<core::Vec3> scene_mosses_;  // the mosses in the tracer's scene
  bool scene_built_ = false;
};

}  // namespace biota::scenarios
