#pragma once
// The files registration jobs hand on (docs/pipelines.md "Registration jobs"):
// DB/register/trunk.{json,npy} from the trunk job and DB/register/shard-<k>-of-<K>.{json,npy}
// from shard job k of K. The .npy holds the aligned nodes' deformer vertices (float64, nodes ×
// volume vertices × 3, exact); the JSON (surfcap.register_part/1, written last, so it marks the
// part complete) holds their records, the context the part was aligned in and the .npy's checksum.

#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::align {

std::filesystem::path trunk_part_path(const std::filesystem::path& database);
/// `shard` counts from 1.
std::filesystem::path shard_part_path(const std::filesystem::path& database, int shard, int shards);

/// What every part of one registration must share: the alignment options, the capture, the
/// checksums of similarity/tree.json and matrix.npy, and the partition.
core::Json part_context(const std::filesystem::path& database, const std::string& capture,
                        const RegisterOptions& options, const TreePartition& partition);

/// The trunk's part (with the template's figures) or shard `shard` of `shards` (its units).
struct PartLabel {
  int shard = 0;   ///< 0: the trunk
  int shards = 0;
  std::vector<long> units;
};

/// Writes the part atomically: the .npy, then the JSON. `summary` gives the template's figures.
void write_registration_part(const std::filesystem::path& path, const PartLabel& label, const core::Json& context,
                             const RegistrationPart& part, const Registration& summary);

/// Reads a part written by write_registration_part and checks it against what the reader expects:
/// a missing file is io_error (4) saying which job writes it; another context, label or node set,
/// or a .npy that is not the one the JSON was written with, is bad_input (3) naming the file.
/// The trunk's template figures go into `summary` (when not null).
RegistrationPart read_registration_part(const std::filesystem::path& path, const PartLabel& label,
                                        const core::Json& context, const std::vector<long>& nodes,
                                        long volume_vertices, Registration* summary = nullptr);

}  // namespace surfcap::align
