#pragma once
// Files of the transition stage (docs/formats.md §transitions): OUT/transitions/FROM__TO.npy
// (float32 [R_from·T_from, R_to·T_to] similarity), FROM__TO.json (surfcap.transition/1 metadata)
// and FROM__TO.png (heat map of 1 − s, node borders in white).
#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/blend/stored_space.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/graph/transition_similarity.hpp"

namespace surfcap::graph {

/// "FROM__TO" (the stem of the three files).
std::string transition_stem(const std::string& from, const std::string& to);

/// Writes the .npy, the .png and last the .json into <output>/transitions/ (each atomically).
void write_transition(const std::filesystem::path& output, const blend::StoredSpace& from,
                      const blend::StoredSpace& to, const TransitionSimilarity& similarity,
                      const core::Json& provenance);

/// Reads <output>/transitions/FROM__TO.npy, checking it is float32 [rows, cols] with values in [0, 1];
/// bad_input naming the file when it is missing or wrong.
std::vector<float> read_transition_similarity(const std::filesystem::path& output, const std::string& from,
                                              const std::string& to, long rows, long cols);

}  // namespace surfcap::graph
