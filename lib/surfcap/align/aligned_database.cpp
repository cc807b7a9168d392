#include "surfcap/align/aligned_database.hpp"

#include <cmath>

namespace surfcap::align {

core::RootMotion root_motion(const Eigen::MatrixXd& template_rest, const Eigen::MatrixXd& world) {
  const Eigen::RowVector3d rest_centre = template_rest.colwise().mean();
  const Eigen::RowVector3d centre = world.colwise().mean();
  double cosine = 0, sine = 0;
  for (long i = 0; i < world.rows(); ++i) {
    const Eigen::RowVector3d a = template_rest.row(i) - rest_centre, b = world.row(i) - centre;
    cosine += b.x() * a.x() + b.z() * a.z();
    sine += b.x() * a.z() - b.z() * a.x();
  }
  core::RootMotion root;
  root.x = centre.x();
  root.y = centre.y();
  root.z = centre.z();
  root.heading = std::atan2(sine, cosine);
  return root;
}

core::AlignedDatabase aligned_database(const core::Capture& capture, const similarity::FrameList& frames,
                                       const core::Mesh& template_mesh, int root_sequence, int root_frame,
                                       const std::vector<Eigen::MatrixXd>& world) {
  core::AlignedDatabase database;
  database.template_mesh = template_mesh;
  database.root_sequence = capture.sequences[static_cast<std::size_t>(root_sequence)].name;
  database.root_frame = root_frame;
  database.fps = capture.fps;
  database.units = capture.units;
  std::size_t node = 0;
  for (const auto& sequence : frames.sequences) {
    core::AlignedSequence aligned;
    aligned.name = sequence.name;
    for (int k = 0; k < sequence.count; ++k, ++node) {
      const core::RootMotion motion = root_motion(template_mesh.V, world[node]);
      aligned.frames.push_back(core::to_centred(world[node], motion));
      aligned.root_motion.push_back(motion);
    }
    database.sequences.push_back(std::move(aligned));
  }
  return database;
}

}  // namespace surfcap::align
