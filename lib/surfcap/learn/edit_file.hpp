#pragma once
// Edit files (format surfcap.edit/1, docs/learn.md): handles (vertex sets with targets) and
// anchors (vertex sets held where they are) → soft constraints for PartEditor.
#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "surfcap/core/json_document.hpp"
#include "surfcap/learn/part_editor.hpp"
#include "surfcap/learn/part_set.hpp"

namespace surfcap::learn {

/// Vertices named by a selector object: {"vertices": [...]}, {"region": name}, {"part": name}
/// (all its vertices) or {"part_core": name} (its vertices shared with no other part).
std::vector<int> select_vertices(const core::Json& selector, const PartSet& parts, long vertex_count,
                                 const std::filesystem::path& source);

/// Constraints of an edit document, targets relative to `reference` (n×3).
std::vector<Constraint> edit_constraints(const core::Json& edit, const PartSet& parts, const Eigen::MatrixXd& reference,
                                         const std::filesystem::path& source);

}  // namespace surfcap::learn
