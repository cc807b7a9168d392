#pragma once
// The triangle mesh every module passes around, and its validation.

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>

namespace surfcap::core {

/// V n×3 vertex positions (metres, y up), F m×3 vertex indices (counter-clockwise seen from
/// outside); optional per-vertex colours (n×3, 0..1) and texture coordinates (n×2).
struct Mesh {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  Eigen::MatrixXd colors;
  Eigen::MatrixXd uvs;

  long vertex_count() const { return V.rows(); }
  long face_count() const { return F.rows(); }
  bool has_colors() const { return colors.rows() > 0; }
  bool has_uvs() const { return uvs.rows() > 0; }
};

/// What check_mesh found; the counts are of offending elements, the first_* fields name one.
struct MeshCheck {
  long vertices = 0;
  long faces = 0;
  long non_finite_vertices = 0;   ///< NaN or Inf coordinates
  long out_of_range_faces = 0;    ///< an index < 0 or ≥ vertex count
  long repeated_index_faces = 0;  ///< a face using one vertex twice
  long zero_area_faces = 0;       ///< area below area_tolerance
  long non_manifold_edges = 0;    ///< edges with more than two faces, or two faces in the same direction
  long boundary_edges = 0;        ///< edges with one face (the surface is open)
  long unreferenced_vertices = 0;
  long first_non_finite_vertex = -1;
  long first_bad_face = -1;        ///< first out-of-range or repeated-index face
  long first_zero_area_face = -1;
  long first_non_manifold_edge_face = -1;

  bool closed() const { return boundary_edges == 0; }
  bool manifold() const { return non_manifold_edges == 0; }
  /// One line for logs and errors, e.g. "3 non-manifold edges (first at face 17)".
  std::string summary() const;
};

/// Counts the problems of `mesh`. A face is zero-area when its area is below area_tolerance
/// (square metres; default ~ a 1 µm triangle).
MeshCheck check_mesh(const Mesh& mesh, double area_tolerance = 1e-12);

/// Which problems are errors. Empty meshes, non-finite coordinates, out-of-range and
/// repeated-index faces always are.
struct MeshRequirements {
  bool allow_non_manifold = false;
  bool allow_zero_area_faces = false;
  bool allow_open = true;
  bool require_colors = false;
};

/// Throws bad_input (exit 3) naming `source` (and `frame`) for each violated requirement;
/// logs a warning for the problems that are allowed. Returns the check.
MeshCheck validate_mesh(const Mesh& mesh, const MeshRequirements& requirements,
                        const std::filesystem::path& source, std::optional<long> frame = std::nullopt);

/// Area-weighted vertex normals (n×3, unit).
Eigen::MatrixXd vertex_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
/// Per-face areas (m).
Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
/// Axis-aligned bounding box diagonal length.
double bounding_box_diagonal(const Eigen::MatrixXd& V);

}  // namespace surfcap::core
