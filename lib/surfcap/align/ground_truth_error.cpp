#include "surfcap/align/ground_truth_error.hpp"

#include <cmath>

#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::align {

std::optional<std::filesystem::path> ground_truth_file(const core::Capture& capture) {
  const auto path = capture.folder / "ground_truth" / "truth.json";
  if (std::filesystem::exists(path)) return path;
  return std::nullopt;
}

TruthEvaluation evaluate_against_truth(const core::Capture& capture, const Registration& registration) {
  const auto truth_path = ground_truth_file(capture);
  if (!truth_path) throw core::bad_input(capture.folder, "has no ground_truth/truth.json");
  const auto truth_dir = truth_path->parent_path();
  const core::Json truth = core::read_json_file(*truth_path);
  const core::AlignedDatabase database =
      core::read_database(truth_dir / truth.at("database").get<std::string>());
  const auto& aligned = registration.database;

  // The root reconstruction's true correspondence.
  core::Json root_entry;
  for (const auto& entry : truth.at("sequences"))
    if (entry.at("name").get<std::string>() == aligned.root_sequence) root_entry = entry;
  if (root_entry.is_null()) throw core::bad_input(*truth_path, "has no sequence '" + aligned.root_sequence + "'");
  const auto face_path =
      truth_dir / core::expand_pattern(root_entry.at("correspondence_face").get<std::string>(), aligned.root_frame);
  const auto bary_path = truth_dir / core::expand_pattern(root_entry.at("correspondence_barycentric").get<std::string>(),
                                                          aligned.root_frame);
  const long n = aligned.template_mesh.vertex_count();
  const core::NpyArray faces = core::read_npy(face_path, core::DType::int32, {n});
  const Eigen::MatrixXd barycentric = core::read_npy_matrix(bary_path, n, 3);
  const Eigen::MatrixXi& true_F = database.template_mesh.F;
  for (long v = 0; v < n; ++v)
    if (faces.data<std::int32_t>()[v] < 0 || faces.data<std::int32_t>()[v] >= true_F.rows())
      throw core::bad_input(face_path, "face index out of range at vertex " + std::to_string(v));

  auto true_positions = [&](const std::string& sequence, int frame, const std::filesystem::path& where) {
    const int s = database.sequence_index(sequence);
    const int c = capture.sequence_index(sequence);
    const int offset = frame - capture.sequences[static_cast<std::size_t>(c)].first;
    if (s < 0 || offset < 0 || offset >= database.sequences[static_cast<std::size_t>(s)].frame_count())
      throw core::bad_input(where, "has no true frame " + std::to_string(frame) + " of '" + sequence + "'");
    const auto& seq = database.sequences[static_cast<std::size_t>(s)];
    const Eigen::MatrixXd X = core::to_world(seq.frames[static_cast<std::size_t>(offset)],
                                             seq.root_motion[static_cast<std::size_t>(offset)]);
    Eigen::MatrixXd points(n, 3);
    for (long v = 0; v < n; ++v) {
      const int f = faces.data<std::int32_t>()[v];
      points.row(v) = barycentric(v, 0) * X.row(true_F(f, 0)) + barycentric(v, 1) * X.row(true_F(f, 1)) +
                      barycentric(v, 2) * X.row(true_F(f, 2));
    }
    return points;
  };

  TruthEvaluation evaluation;
  {
    const Eigen::MatrixXd root = true_positions(aligned.root_sequence, aligned.root_frame, *truth_path);
    evaluation.height = root.col(1).maxCoeff() - root.col(1).minCoeff();
  }
  const long nodes = static_cast<long>(registration.frames.size());
  evaluation.frames.resize(static_cast<std::size_t>(nodes));
  double total = 0;
  std::map<int, std::pair<double, long>> by_depth;
  for (long node = 0; node < nodes; ++node) {
    const auto& record = registration.frames[static_cast<std::size_t>(node)];
    const Eigen::MatrixXd expected = true_positions(record.sequence, record.frame, *truth_path);
    const Eigen::VectorXd squared = (registration.world_positions[static_cast<std::size_t>(node)] - expected)
                                        .rowwise()
                                        .squaredNorm();
    auto& frame = evaluation.frames[static_cast<std::size_t>(node)];
    frame.rms = std::sqrt(squared.mean());
    frame.max = std::sqrt(squared.maxCoeff());
    total += squared.sum();
    auto& depth = by_depth[record.depth];
    depth.first += squared.sum();
    depth.second += n;
    if (frame.rms > evaluation.worst_frame_rms) {
      evaluation.worst_frame_rms = frame.rms;
      evaluation.worst_node = node;
    }
  }
  evaluation.rms = std::sqrt(total / static_cast<double>(n * nodes));
  for (const auto& [depth, sums] : by_depth)
    evaluation.rms_by_depth[depth] = std::sqrt(sums.first / static_cast<double>(sums.second));
  return evaluation;
}

core::Json TruthEvaluation::to_json(const Registration& registration) const {
  const double percent = 100.0 / height;
  core::Json depth = core::Json::array();
  for (const auto& [d, rms_at] : rms_by_depth)
    depth.push_back({{"depth", d}, {"rms_m", rms_at}, {"rms_percent_height", rms_at * percent}});
  const auto& worst = registration.frames[static_cast<std::size_t>(worst_node)];
  return {{"height_m", height},
          {"rms_m", rms},
          {"rms_percent_height", rms * percent},
          {"worst_frame", worst.sequence + ":" + std::to_string(worst.frame)},
          {"worst_frame_rms_m", worst_frame_rms},
          {"worst_frame_rms_percent_height", worst_frame_rms * percent},
          {"by_depth", depth}};
}

}  // namespace surfcap::align
