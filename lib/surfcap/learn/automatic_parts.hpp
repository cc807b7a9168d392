#pragma once
// Automatic part decomposition for characters without a parts config: vertices clustered by the
// similarity of their motion over the examples (near-rigid groups), each cluster grown into its
// neighbours for the overlap, the tree built by vertex sharing.
#include <string>
#include <vector>

#include "surfcap/core/database.hpp"
#include "surfcap/learn/example_selection.hpp"
#include "surfcap/learn/part_set.hpp"

namespace surfcap::learn {

struct AutomaticPartsOptions {
  int parts = 6;              ///< clusters
  double overlap = 0.05;      ///< metres of geodesic growth into the neighbours
  int iterations = 20;        ///< k-means iterations
  int threads = 0;
  void validate() const;
};

/// Parts named part0, part1, ... (part0 the root: the largest cluster). Deterministic.
PartSet automatic_parts(const core::AlignedDatabase& database, const std::vector<ExampleFrame>& examples,
                        const AutomaticPartsOptions& options);

}  // namespace surfcap::learn
