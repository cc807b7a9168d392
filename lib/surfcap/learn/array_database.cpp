#include "surfcap/learn/array_database.hpp"

#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::learn {

core::AlignedDatabase database_from_positions(const std::filesystem::path& template_mesh,
                                              const std::filesystem::path& positions_npy,
                                              const std::string& sequence_name) {
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
    sequence.frames.push_back(std::move(frame));
    sequence.root_motion.push_back({});
  }
  db.sequences.push_back(std::move(sequence));
  db.root_sequence = sequence_name;
  return db;
}

}  // namespace surfcap::learn
