#pragma once
/// \file revision.hpp
/// \brief The git revision this binary was built from, for `biota --version`, the run's first
/// lines and every HDF5 file it writes (attribute `biota_revision`), so a result names its code.

namespace biota::core {

/// \brief `git describe --always --dirty` of the source tree at build time (a "-dirty" suffix:
/// uncommitted changes), or "unknown" when built without git or outside a clone.
const char* revision();

}  // namespace biota::core
