#pragma once
// Learnt deformation spaces of parts (tejera2013 §IV-A, eqs. 5–6): per part, the differential
// coordinates δ = L_j x of every example, mean-centred SVD, leading basis vectors holding a
// given share of the energy. Read and written as parts.json + parts/*.npy (docs/learn.md).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <map>
#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/core/database.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/learn/example_selection.hpp"
#include "surfcap/learn/part_set.hpp"

namespace surfcap::learn {

/// A part's learnt space. δ vectors stack coordinates as [x₁..x_n, y₁..y_n, z₁..z_n] (eq. 5),
/// local vertex order = Part::vertices; L_j is the cotangent Laplacian of the template submesh.
struct PartModel {
  Part part;
  Eigen::VectorXd mean;   ///< δ̄_j, 3 n_j
  Eigen::MatrixXd basis;  ///< E_j, 3 n_j × l_j, orthonormal columns
  Eigen::VectorXd singular_values;  ///< all of them, descending (for reports)
  double energy = 0;      ///< share of the energy the kept vectors hold
};

struct LearntModel {
  core::Mesh template_mesh;  ///< rest pose and connectivity
  std::vector<PartModel> parts;  ///< hierarchy order, parts[0] is the root
  std::map<std::string, std::vector<int>> regions;
  std::vector<std::pair<std::string, int>> examples;  ///< (sequence, frame)
  PartSet part_set() const;
};

struct LearnOptions {
  double energy = 0.95;  ///< keep the leading vectors holding this share of Σσ²
  int max_vectors = 0;   ///< 0: no limit
  int threads = 0;
  void validate() const;
};

/// Stacked differential coordinates of `positions` (n×3 full mesh) restricted to the part.
Eigen::VectorXd part_differential_coordinates(const Eigen::SparseMatrix<double>& L, const std::vector<int>& vertices,
                                              const Eigen::MatrixXd& positions);

/// Learns every part of `parts` from the example frames (centred positions).
LearntModel learn_part_models(const core::AlignedDatabase& database, const PartSet& parts,
                              const std::vector<ExampleFrame>& examples, const LearnOptions& options,
                              const core::ProgressCallback& progress = {});

/// A one-part set holding every vertex (the global basis of tejera2013 Fig. 2, for comparison).
PartSet whole_mesh_part(long vertex_count);

/// Writes parts.json, parts/<name>.{vertices,frontier,mean,basis}.npy, regions/<name>.npy and
/// template.ply into `directory` (each atomically, parts.json last).
void write_learnt_model(const std::filesystem::path& directory, const LearntModel& model,
                        const core::Json& provenance = core::Json::object());
LearntModel read_learnt_model(const std::filesystem::path& parts_json);

}  // namespace surfcap::learn
