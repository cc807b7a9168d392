#pragma once
// An aligned database built in memory from a template mesh and a [T, V, 3] positions array
// (e.g. ../shared/data/dance) — for benchmarks and the tools' --positions. With `centre`, each
// frame's root motion (ground-plane centroid and the heading best aligning it to the first frame)
// is estimated and removed, as an aligned database stores it (DESIGN §3.2); otherwise it is zero.
#include <filesystem>
#include <string>

#include "surfcap/core/database.hpp"

namespace surfcap::learn {

core::AlignedDatabase database_from_positions(const std::filesystem::path& template_mesh,
                                              const std::filesystem::path& positions_npy,
                                              const std::string& sequence_name = "sequence", bool centre = true);

}  // namespace surfcap::learn
