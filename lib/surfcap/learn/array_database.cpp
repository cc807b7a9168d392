#include "surfcap/learn/array_database.hpp"

#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::learn {

core::AlignedDatabase database_from_positions(const std::filesystem::path& template_mesh,
                                              const std::filesystem::path& positions_npy,
                                              const std::string& sequence_name, bool centre) {
  core::AlignedDatabase db;
  db.template_mesh = core::read_mesh(template_mesh);
  const long n = db.template_mesh.vertex_count();
  std::vector<std::size_t> shape;
  const std::vector<double> values = core::read_npy_as_double(positions_npy, {-1, n, 3}, &shape);
  core::AlignedSequence sequence;
  sequence.name = sequence_name;
  for (std::size_t t = 0; t < shape[0]; ++t) {
    Eigen::MatrixXd frame(n, 3);
    for (long v = 0; v < n; ++v)
      for (int c = 0; c < 3; ++c) frame(v, c) = values[(t * n + v) * 3 + c];
    if (!frame.allFinite()) throw core::bad_input(positions_npy, "non-finite position", static_cast<long>(t));
    core::RootMotion root;
    if (centre) {
      const Eigen::RowVector3d c = frame.colwise().mean();
      root.x = c[0], root.z = c[2];
      if (!sequence.frames.empty()) {
        // Heading θ maximising Σ b·R_y(θ)a, a = first centred frame, b = this frame about its centroid.
        const Eigen::MatrixXd& a = sequence.frames.front();
        const Eigen::MatrixXd b = frame.rowwise() - c;
        const double s = (a.col(2).array() * b.col(0).array() - a.col(0).array() * b.col(2).array()).sum();
        const double k = (a.col(0).array() * b.col(0).array() + a.col(2).array() * b.col(2).array()).sum();
        root.heading = std::atan2(s, k);
      }
    }
    sequence.frames.push_back(core::to_centred(frame, root));
    sequence.root_motion.push_back(root);
  }
  if (centre) {  // the template moves with the first frame's ground-plane offset
    db.template_mesh.V.col(0).array() -= sequence.root_motion.front().x;
    db.template_mesh.V.col(2).array() -= sequence.root_motion.front().z;
  }
  db.sequences.push_back(std::move(sequence));
  db.root_sequence = sequence_name;
  return db;
}

}  // namespace surfcap::learn
