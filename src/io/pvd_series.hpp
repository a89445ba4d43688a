#pragma once
/// \file pvd_series.hpp
/// \brief ParaView .pvd time-series index, kept consistent across restarts.
#include <string>

namespace biota::io {

/// \brief Add (time, file) to the .pvd at `pvd_path`, dropping entries of the same or later steps
/// (a restarted run rewrites its future). `step` orders entries. Rank 0 only. Written atomically.
void update_pvd(const std::string& pvd_path, long long step, double time,
                const std::string& relative_file);

}  // namespace biota::io
