#include "scenarios/tree_scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "core/allgather.hpp"
#include "core/error.hpp"
#include "io/particle_output.hpp"

namespace biota::scenarios {

namespace mp = models::plants;
using core::Vec3;

namespace {
constexpr int kMaxSpecies = 3;
std::string sp_key(int s, const char* what) {
  return fmt::format("tree.species{}.{}", s + 1, what);
}
}  // namespace

void TreeScenario::declare_config(core::ConfigSchema& s) {
  WindScenario::declare_config(s);
  s.add_int("tree.count", 1, 1, 1'000'000, "number of trees");
  s.add_string("tree.placement", "explicit", {"explicit", "random"},
               "explicit: tree.positions; random: in tree.region_lo..region_hi with "
               "tree.min_spacing (Philox keyed by seed and tree id)");
  s.add_real_list("tree.positions", std::vector<double>{}, -1, "m",
                  "explicit placement: x y z of every tree's root, 3 per tree");
  s.add_real_list("tree.species_of", std::vector<double>{}, -1, "-",
                  "explicit placement: species (1..tree.species) of every tree; empty: tree t is "
                  "species (t mod tree.species) + 1");
  s.add_real_list("tree.heights", std::vector<double>{}, -1, "m",
                  "height of every tree; empty: its species' height");
  s.add_real_list("tree.region_lo", std::vector<double>{8, 4}, 2, "m",
                  "random placement: lower x y corner of the region");
  s.add_real_list("tree.region_hi", std::vector<double>{24, 12}, 2, "m",
                  "random placement: upper x y corner of the region");
  s.add_real("tree.ground", 0.0, 0.0, std::nullopt, "m", "random placement: root height z");
  s.add_real("tree.min_spacing", 2.0, 0.0, std::nullopt, "m",
             "random placement: least distance between roots");
  s.add_int("tree.species", 1, 1, kMaxSpecies, "number of species (tree.species1 .. 3)");
  for (int k = 0; k < kMaxSpecies; ++k) {
    s.add_string(
        sp_key(k, "lsystem"), "lsystems/paper_fig1.lsys", {},
        fmt::format("L-system file of species {} (relative: to the deck's directory)", k + 1));
    s.add_real(sp_key(k, "height"), 6.67, 0.0, std::nullopt, "m",
               fmt::format("height of species {} (the turtle geometry is scaled to it)", k + 1),
               true);
    s.add_int(sp_key(k, "seed"), 1, 0, 1'000'000'000'000, "L-system seed (stochastic rules)");
    s.add_int(sp_key(k, "derivations"), -1, -1, 1000, "derivations (-1: the file's)");
  }
  s.add_int("tree.max_modules", 10'000'000, 1, 1'000'000'000, "module cap of one derivation");
  s.add_real("tree.density", 230, 0.0, std::nullopt, "kg/m^3", "wood density delta, eq. 1", true);
  s.add_real("tree.k_restore", 1e4, 0.0, std::nullopt, "N/m^2", "K_r of eq. 5", true);
  s.add_real("tree.k_wind", 0.08, 0.0, std::nullopt, "N s/m^3", "K_w of eq. 3");
  s.add_real("tree.k_branch", 0.1, 0.0, std::nullopt, "-",
             "K_b: the wind receives -K_b F_w (paper 5.2)");
  s.add_real("tree.k_react", 0.8, 0.0, std::nullopt, "-", "K_d of eq. 6 (reaction)");
  s.add_real("tree.k_damp", 0.83, 0.0, 1.0, "-", "K_d of eq. 9, velocity factor per tree.damp_dt");
  s.add_real("tree.damp_dt", 1.0 / 30, 0.0, std::nullopt, "s",
             "step the per-step damping k_damp is calibrated for (k_damp^(dt/damp_dt))", true);
  s.add_real_list("tree.gravity", std::vector<double>{0, 0, -9.8}, 3, "m/s^2",
                  "gravity on the nodes, eq. 4 (world frame, z up)");
  s.add_real("tree.radius_min", 0.02, 0.0, std::nullopt, "m", "radius of the tips", true);
  s.add_real("tree.radius_max", 0.05, 0.0, std::nullopt, "m", "radius of the trunk base", true);
  s.add_bool("tree.pipe_radii", true,
             "radii by the pipe model (false: the turtle widths scaled to radius_max)");
  s.add_bool("tree.two_way", true, "the trees push back on the wind (false: one-way coupling)");
  s.add_int("tree.substeps", 1, 1, 100000, "tree steps per wind.step_time");
  s.add_bool("tree.contacts", false,
             "branch collisions: links as capsules, penalty + friction (between trees and "
             "between links of one tree that share no node)");
  s.add_real("tree.contact_stiffness", 100.0, 0.0, std::nullopt, "N/m",
             "penalty k_c per metre of capsule overlap", true);
  s.add_real("tree.contact_friction", 0.5, 0.0, std::nullopt, "-", "Coulomb coefficient mu");
  s.add_real("tree.contact_viscous", 10.0, 0.0, std::nullopt, "N s/m",
             "tangential friction c_t |v_t| below the Coulomb limit");
  s.add_int("tree.csv_interval", 1, 1, 1'000'000'000, "scenario steps between trees.csv rows");
}

TreeScenario::TreeScenario(const RunContext& ctx) : WindScenario(ctx) {
  const auto& cfg = ctx.config;
  const double dx = mac_->params().dx;
  pcomm_ = std::make_unique<particles::ParticleComm>(*decomp_, dx);
  transfer_ = std::make_unique<coupling::MacCoupling>(*decomp_, dx);
  samples_ = std::make_unique<coupling::RemoteSamples>(*pcomm_);
  k_branch_ = cfg.get_real("tree.k_branch");
  substeps_ = static_cast<int>(cfg.get_int("tree.substeps"));
  two_way_ = cfg.get_bool("tree.two_way");
  csv_every_ = static_cast<int>(cfg.get_int("tree.csv_interval"));

  mp::NodeLinkParams p;
  p.density = cfg.get_real("tree.density");
  p.k_restore = cfg.get_real("tree.k_restore");
  p.k_wind = cfg.get_real("tree.k_wind");
  p.k_react = cfg.get_real("tree.k_react");
  p.k_damp = cfg.get_real("tree.k_damp");
  p.damp_dt = cfg.get_real("tree.damp_dt");
  const auto& g = cfg.get_real_list("tree.gravity");
  p.gravity = {g[0], g[1], g[2]};
  p.r_min = cfg.get_real("tree.radius_min");
  p.r_max = cfg.get_real("tree.radius_max");
  if (p.r_min > p.r_max)
    cfg.fail("tree.radius_min", fmt::format("must not exceed tree.radius_max = {}", p.r_max));
  p.pipe_radii = cfg.get_bool("tree.pipe_radii");

  // Species: L-system files relative to the deck's directory.
  const int nspecies = static_cast<int>(cfg.get_int("tree.species"));
  std::vector<mp::TreeSpecies> species(nspecies);
  const std::filesystem::path deck_dir = std::filesystem::path(cfg.source()).parent_path();
  for (int k = 0; k < nspecies; ++k) {
    std::filesystem::path f = cfg.get_string(sp_key(k, "lsystem"));
    if (f.is_relative() && std::filesystem::is_regular_file(deck_dir / f)) f = deck_dir / f;
    if (!std::filesystem::is_regular_file(f))
      cfg.fail(sp_key(k, "lsystem"), fmt::format("cannot read the L-system file (looked for {} "
                                                 "relative to the deck's directory and to the "
                                                 "working directory)",
                                                 cfg.get_string(sp_key(k, "lsystem"))));
    try {
      species[k].lsystem = mp::read_lsystem(f.string());
    } catch (const core::InputError& e) {  // file:line:col: what, under the key that named it
      cfg.fail(sp_key(k, "lsystem"), fmt::format("is not a valid L-system: {}", e.what()));
    }
    species[k].seed = static_cast<std::uint64_t>(cfg.get_int(sp_key(k, "seed")));
    species[k].derivations = static_cast<int>(cfg.get_int(sp_key(k, "derivations")));
    species[k].height = cfg.get_real(sp_key(k, "height"));
  }

  // Sites: identical on every rank.
  const int n = static_cast<int>(cfg.get_int("tree.count"));
  const Vec3 L = pcomm_->domain_hi();
  if (cfg.get_string("tree.placement") == "random") {
    const auto& lo = cfg.get_real_list("tree.region_lo");
    const auto& hi = cfg.get_real_list("tree.region_hi");
    if (!(0 <= lo[0] && lo[0] <= hi[0] && hi[0] <= L.x && 0 <= lo[1] && lo[1] <= hi[1] &&
          hi[1] <= L.y))
      cfg.fail("tree.region_lo",
               fmt::format("and tree.region_hi = [{}, {}] must give lo <= hi inside the wind box "
                           "[0, {}] x [0, {}] m",
                           hi[0], hi[1], L.x, L.y));
    sites_ = mp::random_sites(static_cast<std::uint64_t>(cfg.get_int("seed")), n, lo[0], lo[1],
                              hi[0], hi[1], cfg.get_real("tree.ground"),
                              cfg.get_real("tree.min_spacing"), species);
  } else {
    const auto& pos = cfg.get_real_list("tree.positions");
    if (pos.size() != 3 * static_cast<std::size_t>(n))
      cfg.fail("tree.positions",
               fmt::format("has {} numbers; explicit placement needs 3 per tree (tree.count = {}: "
                           "{} numbers)",
                           pos.size(), n, 3 * n));
    sites_.resize(n);
    for (int t = 0; t < n; ++t) {
      sites_[t].id = static_cast<std::uint64_t>(t);
      sites_[t].species = t % nspecies;
      sites_[t].base = {pos[3 * t], pos[3 * t + 1], pos[3 * t + 2]};
      for (int d = 0; d < 3; ++d)
        if (!(sites_[t].base[d] >= 0 && sites_[t].base[d] <= L[d]))
          cfg.fail(
              "tree.positions",
              fmt::format("tree {} stands at ({}, {}, {}), outside the wind box [0, {}] x "
                          "[0, {}] x [0, {}] m",
                          t, sites_[t].base.x, sites_[t].base.y, sites_[t].base.z, L.x, L.y, L.z));
    }
  }
  const auto& sof = cfg.get_real_list("tree.species_of");
  if (!sof.empty() && sof.size() != static_cast<std::size_t>(n))
    cfg.fail(
        "tree.species_of",
        fmt::format("has {} entries; give one per tree (tree.count = {}) or none", sof.size(), n));
  const auto& hts = cfg.get_real_list("tree.heights");
  if (!hts.empty() && hts.size() != static_cast<std::size_t>(n))
    cfg.fail("tree.heights", fmt::format("has {} entries; give one per tree (tree.count = {}) or "
                                         "none",
                                         hts.size(), n));
  for (int t = 0; t < n; ++t) {
    if (!sof.empty()) {
      if (!(sof[t] >= 1 && sof[t] <= nspecies && sof[t] == std::floor(sof[t])))
        cfg.fail("tree.species_of",
                 fmt::format("entry {} = {} is not a species number in 1..{} (tree.species)", t,
                             sof[t], nspecies));
      sites_[t].species = static_cast<int>(sof[t]) - 1;
    }
    sites_[t].height = hts.empty() ? species[sites_[t].species].height : hts[t];
    if (!(sites_[t].height > 0 && sites_[t].base.z + sites_[t].height < L.z))
      cfg.fail(hts.empty() ? sp_key(sites_[t].species, "height") : "tree.heights",
               fmt::format("tree {}: height {} m from z = {} m must be > 0 and stay below the "
                           "top of the wind box ({} m)",
                           t, sites_[t].height, sites_[t].base.z, L.z));
  }

  // Owned trees: the rank whose box holds the root.
  const std::size_t max_modules = static_cast<std::size_t>(cfg.get_int("tree.max_modules"));
  long long nodes = 0;
  for (const auto& s : sites_) {
    if (pcomm_->owner_of(s.base) != decomp_->rank()) continue;
    try {
      trees_.push_back(mp::build_tree(species[s.species], s, p, max_modules));
    } catch (const mp::ModuleCapError& e) {
      const std::string key = sp_key(s.species, "derivations");
      throw core::InputError(fmt::format(
          "{}: {} = {}: {} (tree.max_modules); allowed: at most {} derivations with this cap, or "
          "raise tree.max_modules (at most 1000000000)",
          cfg.source(), key, cfg.get_int(key), e.what(), e.derivation() - 1));
    } catch (const std::invalid_argument& e) {
      throw core::InputError(
          fmt::format("{}: {} ({})", cfg.source(), e.what(), sp_key(s.species, "lsystem")));
    }
    owned_.push_back(s);
    const auto& t = trees_.back();
    std::size_t top = 0;
    for (std::size_t k = 0; k < t.size(); ++k)
      if (t.positions()[k].z > t.positions()[top].z) top = k;
    tip_.push_back(top);
    fw_.emplace_back(t.size());
    nodes += static_cast<long long>(t.size());
  }
  MPI_Allreduce(MPI_IN_PLACE, &nodes, 1, MPI_LONG_LONG, MPI_SUM, ctx.comm);
  contacts_ = cfg.get_bool("tree.contacts");
  contact_.stiffness = cfg.get_real("tree.contact_stiffness");
  contact_.friction = cfg.get_real("tree.contact_friction");
  contact_.viscous = cfg.get_real("tree.contact_viscous");
  if (contacts_) {
    // Explicit penalty: omega dt = sqrt(k_c / m_min) dt must stay well inside the stable range.
    double m_min = 1e300;
    for (const auto& t : trees_)
      for (std::size_t k = 0; k < t.size(); ++k)
        if (t.parents()[k] >= 0) m_min = std::min(m_min, t.masses()[k]);
    MPI_Allreduce(MPI_IN_PLACE, &m_min, 1, MPI_DOUBLE, MPI_MIN, ctx.comm);
    const double wdt = std::sqrt(contact_.stiffness / m_min) * step_time_ / substeps_;
    if (wdt > 1.5)
      cfg.fail("tree.contact_stiffness",
               fmt::format("gives sqrt(k_c / m_min) dt = {:.3g} > 1.5 with the lightest node of "
                           "{:.3g} kg and dt = wind.step_time / tree.substeps = {:.3g} s: the "
                           "explicit contact is unstable (lower it or raise tree.substeps)",
                           wdt, m_min, step_time_ / substeps_));
    for (std::size_t t = 0; t < trees_.size(); ++t) {
      const auto& tr = trees_[t];
      std::vector<mp::Capsule> caps;
      for (std::size_t k = 0; k < tr.size(); ++k)
        if (const std::int64_t j = tr.parents()[k]; j >= 0)
          caps.push_back({tr.positions()[j],
                          tr.positions()[k],
                          {},
                          {},
                          tr.radii()[k],
                          owned_[t].id,
                          j,
                          static_cast<std::int64_t>(k)});
      const auto pairs = mp::overlapping_pairs(caps);
      grown_together_.emplace_back(pairs.begin(), pairs.end());
    }
  }
  if (decomp_->rank() == 0)
    fmt::print(
        "tree: {} trees of {} species, {} nodes, {} tree steps of {:.6g} s per wind step, "
        "coupling {}\n",
        sites_.size(), nspecies, nodes, substeps_, step_time_ / substeps_,
        two_way_ ? "two-way" : "one-way");
}

void TreeScenario::step() {
  if (!csv_started_) open_csv();
  std::vector<core::GlobalId> ids;
  std::vector<Vec3> at;
  {
    auto scope = ctx_.timers.scope("coupling");
    for (std::size_t t = 0; t < trees_.size(); ++t)
      for (std::size_t k = 0; k < trees_[t].size(); ++k) {
        if (trees_[t].parents()[k] < 0) continue;  // roots: fixed, no wind force
        ids.push_back(mp::tree_node_id(owned_[t].id, k));
        at.push_back(trees_[t].positions()[k]);
      }
    mac_->refresh();  // current ghost faces for the interpolation
  }
  std::vector<Vec3> wind;
  {
    auto scope = ctx_.timers.scope("coupling");
    wind = samples_->interpolate(*transfer_, mac_->velocity(), ids, at);
  }
  std::vector<Vec3> force(ids.size());
  std::vector<std::vector<Vec3>> extra;
  if (contacts_) {
    auto scope = ctx_.timers.scope("contacts");
    contact_forces(extra);
  }
  {
    auto scope = ctx_.timers.scope("trees");
    const double dt = step_time_ / substeps_;
    std::size_t m = 0;
    std::vector<Vec3> w, f;
    for (std::size_t t = 0; t < trees_.size(); ++t) {
      auto& tree = trees_[t];
      const std::size_t m0 = m;
      w.assign(tree.size(), {});
      for (std::size_t k = 0; k < tree.size(); ++k)
        if (tree.parents()[k] >= 0) w[k] = wind[m++];
      auto& acc = fw_[t];
      std::fill(acc.begin(), acc.end(), Vec3{});
      for (int s = 0; s < substeps_; ++s) {
        tree.step(dt, w, &f, contacts_ ? &extra[t] : nullptr);
        for (std::size_t k = 0; k < tree.size(); ++k) acc[k] += f[k];
      }
      m = m0;
      for (std::size_t k = 0; k < tree.size(); ++k) {
        acc[k] = acc[k] * (1.0 / substeps_);
        if (tree.parents()[k] >= 0) force[m++] = acc[k];
      }
    }
  }
  {
    auto scope = ctx_.timers.scope("coupling");
    auto& f = mac_->force();
    f.fill(0.0);
    if (two_way_) {  // -K_b F_w as force per unit mass of the cell's air (paper 5.2)
      const double dx = mac_->params().dx;
      samples_->spread(*transfer_, f, ids, at, force, -k_branch_ / (air_density_ * dx * dx * dx));
    }
  }
  WindScenario::step();
  if (step_ % csv_every_ == 0) record_csv();
}

void TreeScenario::contact_forces(std::vector<std::vector<Vec3>>& extra) {
  constexpr int kw = 16;  // tree, node, parent, a, b, va, vb, radius
  std::vector<double> mine;
  for (std::size_t t = 0; t < trees_.size(); ++t) {
    const auto& tr = trees_[t];
    for (std::size_t k = 0; k < tr.size(); ++k) {
      const std::int64_t j = tr.parents()[k];
      if (j < 0) continue;
      const Vec3 a = tr.positions()[j], b = tr.positions()[k], va = tr.velocities()[j],
                 vb = tr.velocities()[k];
      mine.insert(mine.end(), {static_cast<double>(owned_[t].id), static_cast<double>(k),
                               static_cast<double>(j), a.x, a.y, a.z, b.x, b.y, b.z, va.x, va.y,
                               va.z, vb.x, vb.y, vb.z, tr.radii()[k]});
    }
  }
  const std::vector<double> buf = core::allgather_concat(ctx_.comm, mine);
  const int total = static_cast<int>(buf.size());
  // The same list, in (tree, node) order, on every rank.
  const std::size_t n = static_cast<std::size_t>(total / kw);
  std::vector<std::size_t> order(n);
  for (std::size_t q = 0; q < n; ++q) order[q] = q;
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return std::pair(buf[x * kw], buf[x * kw + 1]) < std::pair(buf[y * kw], buf[y * kw + 1]);
  });
  std::vector<mp::Capsule> all(n);
  std::map<std::uint64_t, std::size_t> index;
  for (std::size_t t = 0; t < owned_.size(); ++t) index[owned_[t].id] = t;
  std::vector<std::size_t> my;
  for (std::size_t q = 0; q < n; ++q) {
    const double* v = &buf[order[q] * kw];
    auto& c = all[q];
    c.tree = static_cast<std::uint64_t>(v[0]);
    c.node_b = static_cast<std::int64_t>(v[1]);
    c.node_a = static_cast<std::int64_t>(v[2]);
    c.a = {v[3], v[4], v[5]};
    c.b = {v[6], v[7], v[8]};
    c.va = {v[9], v[10], v[11]};
    c.vb = {v[12], v[13], v[14]};
    c.radius = v[15];
    if (index.count(c.tree)) my.push_back(q);
  }
  std::vector<Vec3> fa, fb;
  auto skip = [&](const mp::Capsule& a, const mp::Capsule& b) {
    if (a.tree != b.tree) return false;
    const auto& g = grown_together_[index.at(a.tree)];
    return g.count({std::min(a.node_b, b.node_b), std::max(a.node_b, b.node_b)}) != 0;
  };
  last_contacts_ = mp::capsule_forces(all, my, contact_, fa, fb, skip);
  extra.assign(trees_.size(), {});
  for (std::size_t t = 0; t < trees_.size(); ++t) extra[t].assign(trees_[t].size(), {});
  for (std::size_t m = 0; m < my.size(); ++m) {
    const auto& c = all[my[m]];
    auto& e = extra[index[c.tree]];
    e[c.node_a] += fa[m];  // a fixed root ignores it
    e[c.node_b] += fb[m];
  }
  MPI_Allreduce(MPI_IN_PLACE, &last_contacts_, 1, MPI_LONG_LONG, MPI_SUM, ctx_.comm);
  last_contacts_ /= 2;  // each contact seen from both capsules
}

double TreeScenario::tip_displacement(std::size_t t) const {
  const auto& tr = trees_[t];
  return core::norm(tr.positions()[tip_[t]] - tr.initial_positions()[tip_[t]]);
}

Vec3 TreeScenario::total_wind_force() const {
  double s[3] = {0, 0, 0};
  for (const auto& acc : fw_)
    for (const Vec3& f : acc) s[0] += f.x, s[1] += f.y, s[2] += f.z;
  MPI_Allreduce(MPI_IN_PLACE, s, 3, MPI_DOUBLE, MPI_SUM, ctx_.comm);
  return {s[0], s[1], s[2]};
}

void TreeScenario::open_csv() {
  // Fresh run: new file with the t = 0 rows; restart: keep the rows up to the restart time.
  csv_started_ = true;
  if (decomp_->rank() == 0) {
    const std::string path = ctx_.output_dir + "/trees.csv";
    const std::string header =
        "time,tree,species,tip_displacement,max_displacement,max_bending_angle,wind_force_x,"
        "wind_force_y,wind_force_z";
    if (step_ > 0)
      csv_.resume(path, header, time() + 0.5 * step_time_);
    else
      csv_.start(path, header);
  }
  if (step_ == 0) record_csv();
}

void TreeScenario::record_csv() {
  // One row per tree, gathered to rank 0 and written in tree id order.
  constexpr int kw = 8;
  std::vector<double> mine;
  for (std::size_t t = 0; t < trees_.size(); ++t) {
    Vec3 fw;
    for (const Vec3& f : fw_[t]) fw += f;
    mine.insert(mine.end(),
                {static_cast<double>(owned_[t].id), static_cast<double>(owned_[t].species + 1),
                 tip_displacement(t), trees_[t].max_displacement(), trees_[t].max_bending_angle(),
                 fw.x, fw.y, fw.z});
  }
  int count = static_cast<int>(mine.size()), size = decomp_->size();
  std::vector<int> counts(size), displs(size);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, ctx_.comm);
  int total = 0;
  for (int r = 0; r < size; ++r) displs[r] = total, total += counts[r];
  std::vector<double> all(decomp_->rank() == 0 ? total : 0);
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE,
              0, ctx_.comm);
  if (decomp_->rank() != 0) return;
  std::map<long long, const double*> rows;
  for (int r = 0; r < total / kw; ++r) rows[static_cast<long long>(all[r * kw])] = &all[r * kw];
  for (const auto& [id, v] : rows)
    csv_.row(fmt::format("{:.9f},{},{},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}", time(), id,
                         static_cast<int>(v[1]), v[2], v[3], v[4], v[5], v[6], v[7]));
}

void TreeScenario::write_output() {
  WindScenario::write_output();
  auto scope = ctx_.timers.scope("output");
  // Every node of the owned trees as a point, every link as a line (child, parent).
  io::ParticleData d;
  std::vector<double> radius, tree, disp, vel;
  for (std::size_t t = 0; t < trees_.size(); ++t) {
    const auto& tr = trees_[t];
    const auto first = static_cast<std::uint32_t>(d.ids.size());
    for (std::size_t k = 0; k < tr.size(); ++k) {
      const Vec3 x = tr.positions()[k], v = tr.velocities()[k];
      d.positions.insert(d.positions.end(), {x.x, x.y, x.z});
      d.ids.push_back(mp::tree_node_id(owned_[t].id, k));
      radius.push_back(tr.radii()[k]);
      tree.push_back(static_cast<double>(owned_[t].id));
      disp.push_back(core::norm(x - tr.initial_positions()[k]));
      vel.insert(vel.end(), {v.x, v.y, v.z});
      if (tr.parents()[k] >= 0)
        d.lines.push_back({first + static_cast<std::uint32_t>(k),
                           first + static_cast<std::uint32_t>(tr.parents()[k])});
    }
  }
  d.owned = d.ids.size();
  d.scalars = {
      {"radius", std::move(radius)}, {"tree", std::move(tree)}, {"displacement", std::move(disp)}};
  d.vectors = {{"velocity", std::move(vel)}};
  io::ParticleOutput out(ctx_.comm, ctx_.output_dir, "tree_nodes", step_, time(),
                         ctx_.config.effective_toml(), out_layout_.compression);
  out.write(d);
}

void TreeScenario::write_extra(io::CheckpointWriter& w) {
  // One row per node of the owned trees: tree id, node, position, velocity.
  std::vector<double> rows;
  for (std::size_t t = 0; t < trees_.size(); ++t)
    for (std::size_t k = 0; k < trees_[t].size(); ++k) {
      const Vec3 x = trees_[t].positions()[k], v = trees_[t].velocities()[k];
      rows.insert(rows.end(), {static_cast<double>(owned_[t].id), static_cast<double>(k), x.x, x.y,
                               x.z, v.x, v.y, v.z});
    }
  w.write_rows("tree_nodes", rows, 8);
}

void TreeScenario::read_extra(io::CheckpointReader& r) {
  int ncols = 0;
  const auto rows = r.read_all_rows("tree_nodes", ncols);
  if (ncols != 8) throw core::InputError("checkpoint tree_nodes layout differs");
  std::map<std::uint64_t, std::size_t> index;
  for (std::size_t t = 0; t < owned_.size(); ++t) index[owned_[t].id] = t;
  std::size_t restored = 0;
  for (std::size_t q = 0; q + 8 <= rows.size(); q += 8) {
    auto it = index.find(static_cast<std::uint64_t>(rows[q]));
    if (it == index.end()) continue;
    auto& tr = trees_[it->second];
    const auto k = static_cast<std::size_t>(rows[q + 1]);
    if (k >= tr.size()) throw core::InputError("checkpoint tree_nodes: node beyond its tree");
    tr.positions()[k] = {rows[q + 2], rows[q + 3], rows[q + 4]};
    tr.velocities()[k] = {rows[q + 5], rows[q + 6], rows[q + 7]};
    ++restored;
  }
  std::size_t mine = 0;
  for (const auto& t : trees_) mine += t.size();
  if (restored != mine)
    throw core::InputError(
        fmt::format("checkpoint tree_nodes: {} of this rank's {} nodes found (another stand?)",
                    restored, mine));
}

void TreeScenario::check_health() {
  WindScenario::check_health();
  std::uint64_t bad = ~std::uint64_t{0};
  for (std::size_t t = 0; t < trees_.size(); ++t)
    for (std::size_t k = 0; k < trees_[t].size(); ++k) {
      const Vec3 x = trees_[t].positions()[k];
      if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z))
        bad = std::min(bad, mp::tree_node_id(owned_[t].id, k));
    }
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_UINT64_T, MPI_MIN, ctx_.comm);
  if (bad != ~std::uint64_t{0})
    throw core::UnstableError(fmt::format(
        "tree: node {} of tree {} non-finite at step {} (t = {:.6g} s); lower wind.step_time or "
        "raise tree.substeps",
        bad & 0xffffffffu, bad >> 32, step_, time()));
}

std::string TreeScenario::progress() {
  double tip = 0;
  for (std::size_t t = 0; t < trees_.size(); ++t) tip = std::max(tip, tip_displacement(t));
  MPI_Allreduce(MPI_IN_PLACE, &tip, 1, MPI_DOUBLE, MPI_MAX, ctx_.comm);
  std::string c = contacts_ ? fmt::format(" contacts {}", last_contacts_) : "";
  return WindScenario::progress() + fmt::format(" tip max {:.4g} m", tip) + c;
}

std::vector<std::string> TreeScenario::timer_sections() const {
  auto s = WindScenario::timer_sections();
  s.insert(s.begin(), {"trees", "contacts", "coupling"});
  return s;
}

}  // namespace biota::scenarios
