#pragma once
// An aligned database built in memory from a template mesh and a [T, V, 3] positions array
// (e.g. ../shared/data/dance), zero root motion — for benchmarks and the tools' --positions.
#include <filesystem>
#include <string>

#include "surfcap/core/database.hpp"

namespace surfcap::learn {

core::AlignedDatabase database_from_positions(const std::filesystem::path& template_mesh,
                                              const std::filesystem::path& positions_npy,
                                              const std::string& sequence_name = "sequence");

}  // namespace surfcap::learn
