#include "app/restart_check.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>

#include "core/error.hpp"
#include "io/checkpoint.hpp"

namespace biota::app {
namespace {

bool may_change(const std::string& key) {
  for (const auto& p : restart_may_change()) {
    if (p.size() > 2 && p.compare(p.size() - 2, 2, ".*") == 0) {
      if (key.rfind(p.substr(0, p.size() - 1), 0) == 0) return true;
    } else if (key == p) {
      return true;
    }
  }
  return false;
}

// One value as text: reals in their shortest round-trip form (0.55, not 0.55000000000000004).
std::string value_text(const toml::node& node) {
  if (auto d = node.value_exact<double>()) return fmt::format("{}", *d);
  if (const auto* arr = node.as_array()) {
    std::string out = "[";
    for (const auto& e : *arr) out += (out.size() > 1 ? ", " : "") + value_text(e);
    return out + "]";
  }
  std::ostringstream s;
  node.visit([&](const auto& v) { s << toml::toml_formatter{v}; });
  return s.str();
}

// Flatten effective-config TOML text to dotted key -> value text (same printer for both sides).
void flatten(const toml::table& t, const std::string& prefix,
             std::map<std::string, std::string>& out) {
  for (const auto& [k, node] : t) {
    const std::string key =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = node.as_table())
      flatten(*sub, key, out);
    else
      out[key] = value_text(node);
  }
}

std::map<std::string, std::string> flat_config(const std::string& text, const std::string& name) {
  std::map<std::string, std::string> out;
  try {
    flatten(toml::parse(text, name), "", out);
  } catch (const toml::parse_error&) {
    throw core::InputError(name + ": the checkpoint's stored configuration is not valid TOML");
  }
  return out;
}

}  // namespace

const std::vector<std::string>& restart_may_change() {
  static const std::vector<std::string> keys = {
      "run.*",
      "output.*",
      "checkpoint.*",
      "seaweed.metrics_interval",
      "seaweed.balance.sphere_cost",
      "seaweed.balance.rank_speed",
      "seaweed.sub_step_block",
      "flock.stats_interval",
      "tree.csv_interval",
      "wind.poisson_options",
  };
  return keys;
}

void check_restart(MPI_Comm comm, const core::Config& cfg, const std::string& path) {
  if (!std::filesystem::exists(path))
    throw core::InputError(path + ": --restart checkpoint does not exist");
  const auto h = io::read_checkpoint_header(comm, path);
  if (!h.opened)
    throw core::InputError(path +
                           ": --restart file is not a readable HDF5 file (truncated, "
                           "still being written, or not HDF5)");
  if (h.format < 0)
    throw core::InputError(path +
                           ": --restart file is an HDF5 file but not a biota checkpoint "
                           "(no biota_checkpoint_format attribute)");
  if (h.format > io::kCheckpointFormat)
    throw core::InputError(fmt::format(
        "{}: checkpoint format {} is newer than this biota reads (up to {}); use the biota that "
        "wrote it",
        path, h.format, io::kCheckpointFormat));
  if (!h.complete)
    throw core::InputError(path + ": checkpoint is incomplete (its write did not finish)");
  const std::string scenario = cfg.get_string("scenario");
  if (h.scenario != scenario)
    throw core::InputError(fmt::format("{}: checkpoint of scenario '{}', but {} runs scenario '{}'",
                                       path, h.scenario, cfg.source(), scenario));
  const auto stored = flat_config(h.config, path);
  const auto deck = flat_config(cfg.effective_toml(), cfg.source());
  std::map<std::string, std::string> keys = stored;
  keys.insert(deck.begin(), deck.end());
  for (const auto& [key, unused] : keys) {
    if (may_change(key)) continue;
    auto a = stored.find(key), b = deck.find(key);
    const std::string in_ckpt = a == stored.end() ? "(not set)" : a->second;
    const std::string in_deck = b == deck.end() ? "(not set)" : b->second;
    if (in_ckpt != in_deck)
      throw core::InputError(fmt::format(
          "{}: {} = {} in the checkpoint {} but {} in the deck; a restart may change only "
          "run.*, output.*, checkpoint.* and the intervals and options listed in "
          "docs/robustness.md",
          cfg.source(), key, in_ckpt, path, in_deck));
  }
}

std::string checkpoint_dir(const core::Config& cfg) {
  const std::string dir = cfg.get_string("checkpoint.dir");
  return dir.empty()
             ? (std::filesystem::path(cfg.get_string("output.dir")) / "checkpoints").string()
             : dir;
}

std::string latest_checkpoint(MPI_Comm comm, const core::Config& cfg) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const std::string dir = checkpoint_dir(cfg), scenario = cfg.get_string("scenario");
  std::string best;
  if (rank == 0) {
    const std::regex name(scenario + "_([0-9]+)\\.h5");
    std::map<long long, std::string, std::greater<>> found;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
      std::smatch m;
      const std::string f = e.path().filename().string();
      if (std::regex_match(f, m, name)) found[std::stoll(m[1])] = e.path().string();
    }
    for (const auto& [step, path] : found) {
      const auto h = io::read_checkpoint_header(MPI_COMM_SELF, path);
      if (h.opened && h.complete && h.format >= 0 && h.format <= io::kCheckpointFormat &&
          h.scenario == scenario) {
        best = path;
        break;
      }
    }
  }
  int len = static_cast<int>(best.size());
  MPI_Bcast(&len, 1, MPI_INT, 0, comm);
  best.resize(len);
  MPI_Bcast(best.data(), len, MPI_CHAR, 0, comm);
  if (best.empty())
    cfg.fail("checkpoint.dir", "(" + dir + ") holds no complete checkpoint '" + scenario +
                                   "_<step>.h5' for --restart latest");
  return best;
}

}  // namespace biota::app
