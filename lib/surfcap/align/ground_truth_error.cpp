#include "surfcap/align/ground_truth_error.hpp"

#include <cmath>

#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::align {

std::optional<std::filesystem::path> ground_truth_file(const core::Capture& capture) {
  const auto path = capture.folder / "ground_truth" / "truth.json";
  if (std::filesystem::exists(path)) return path;
  return std::nullopt;
}

TruthReference::TruthReference(const core::Capture& capture, const core::AlignedDatabase& aligned)
    : capture_(capture) {
  const auto truth_path = ground_truth_file(capture);
  if (!truth_path) throw core::bad_input(capture.folder, "has no ground_truth/truth.json");
  truth_path_ = *truth_path;
  const auto truth_dir = truth_path_.parent_path();
  const core::Json truth = core::read_json_file(truth_path_);
  truth_ = core::read_database(truth_dir / truth.at("database").get<std::string>());

  // The root reconstruction's true correspondence.
  core::Json root_entry;
  for (const auto& entry : truth.at("sequences"))
    if (entry.at("name").get<std::string>() == aligned.root_sequence) root_entry = entry;
  if (root_entry.is_null()) throw core::bad_input(truth_path_, "has no sequence '" + aligned.root_sequence + "'");
  const auto face_path =
      truth_dir / core::expand_pattern(root_entry.at("correspondence_face").get<std::string>(), aligned.root_frame);
  const auto bary_path = truth_dir / core::expand_pattern(root_entry.at("correspondence_barycentric").get<std::string>(),
                                                          aligned.root_frame);
  const long n = aligned.template_mesh.vertex_count();
  const core::NpyArray faces = core::read_npy(face_path, core::DType::int32, {n});
  barycentric_ = core::read_npy_matrix(bary_path, n, 3);
  const Eigen::MatrixXi& true_F = truth_.template_mesh.F;
  faces_.assign(faces.data<std::int32_t>(), faces.data<std::int32_t>() + n);
  for (long v = 0; v < n; ++v)
    if (faces_[static_cast<std::size_t>(v)] < 0 || faces_[static_cast<std::size_t>(v)] >= true_F.rows())
      throw core::bad_input(face_path, "face index out of range at vertex " + std::to_string(v));

  // Regions (optional: the dance capture has none), split by side of the rest pose (x sign).
  regions_ = Eigen::VectorXi::Constant(n, -1);
  if (truth.contains("regions") && truth.contains("region_names") && truth.contains("template_rest")) {
    const auto region_path = truth_dir / truth.at("regions").get<std::string>();
    const core::NpyArray regions = core::read_npy(region_path, core::DType::int32, {truth_.template_mesh.vertex_count()});
    const core::Mesh rest = core::read_mesh(truth_dir / truth.at("template_rest").get<std::string>());
    const auto names = truth.at("region_names").get<std::vector<std::string>>();
    for (const auto& name : names) {
      region_names_.push_back(name + ".-x");
      region_names_.push_back(name + ".+x");
    }
    for (long v = 0; v < n; ++v) {
      const int f = faces_[static_cast<std::size_t>(v)];
      Eigen::Index nearest = 0;
      barycentric_.row(v).maxCoeff(&nearest);
      const int corner = true_F(f, static_cast<int>(nearest));
      const int region = regions.data<std::int32_t>()[corner];
      if (region < 0 || region >= static_cast<int>(names.size()) || corner >= rest.vertex_count()) continue;
      regions_(v) = 2 * region + (rest.V(corner, 0) >= 0 ? 1 : 0);
    }
  }
  const Eigen::MatrixXd root = positions(aligned.root_sequence, aligned.root_frame);
  height_ = root.col(1).maxCoeff() - root.col(1).minCoeff();
}

Eigen::MatrixXd TruthReference::positions(const std::string& sequence, int frame) const {
  const int s = truth_.sequence_index(sequence);
  const int c = capture_.sequence_index(sequence);
  const int offset = c < 0 ? -1 : frame - capture_.sequences[static_cast<std::size_t>(c)].first;
  if (s < 0 || offset < 0 || offset >= truth_.sequences[static_cast<std::size_t>(s)].frame_count())
    throw core::bad_input(truth_path_, "has no true frame " + std::to_string(frame) + " of '" + sequence + "'");
  const auto& seq = truth_.sequences[static_cast<std::size_t>(s)];
  const Eigen::MatrixXd X =
      core::to_world(seq.frames[static_cast<std::size_t>(offset)], seq.root_motion[static_cast<std::size_t>(offset)]);
  const Eigen::MatrixXi& F = truth_.template_mesh.F;
  const long n = barycentric_.rows();
  Eigen::MatrixXd points(n, 3);
  for (long v = 0; v < n; ++v) {
    const int f = faces_[static_cast<std::size_t>(v)];
    points.row(v) = barycentric_(v, 0) * X.row(F(f, 0)) + barycentric_(v, 1) * X.row(F(f, 1)) +
                    barycentric_(v, 2) * X.row(F(f, 2));
  }
  return points;
}

TruthEvaluation evaluate_against_truth(const TruthReference& truth, const Registration& registration) {
  const Eigen::MatrixXi& F = registration.database.template_mesh.F;
  TruthEvaluation evaluation;
  evaluation.height = truth.height();
  const long nodes = static_cast<long>(registration.frames.size());
  evaluation.frames.resize(static_cast<std::size_t>(nodes));
  double total = 0, total_normal = 0;
  long count = 0;
  std::map<int, std::pair<double, long>> by_depth;
  std::map<int, std::pair<double, long>> by_region;
  for (long node = 0; node < nodes; ++node) {
    const auto& record = registration.frames[static_cast<std::size_t>(node)];
    const Eigen::MatrixXd expected = truth.positions(record.sequence, record.frame);
    const Eigen::MatrixXd normals = core::vertex_normals(expected, F);
    const Eigen::MatrixXd error = registration.world_positions[static_cast<std::size_t>(node)] - expected;
    const Eigen::VectorXd squared = error.rowwise().squaredNorm();
    const Eigen::VectorXd along = (error.array() * normals.array()).rowwise().sum();
    const long n = squared.size();
    auto& frame = evaluation.frames[static_cast<std::size_t>(node)];
    frame.rms = std::sqrt(squared.mean());
    frame.max = std::sqrt(squared.maxCoeff());
    frame.normal_rms = std::sqrt(along.squaredNorm() / static_cast<double>(n));
    frame.tangential_rms = std::sqrt(std::max(0.0, frame.rms * frame.rms - frame.normal_rms * frame.normal_rms));
    total += squared.sum();
    total_normal += along.squaredNorm();
    count += n;
    auto& depth = by_depth[record.depth];
    depth.first += squared.sum();
    depth.second += n;
    for (long v = 0; v < n; ++v) {
      if (truth.regions()(v) < 0) continue;
      auto& region = by_region[truth.regions()(v)];
      region.first += squared(v);
      ++region.second;
    }
    if (frame.rms > evaluation.worst_frame_rms) {
      evaluation.worst_frame_rms = frame.rms;
      evaluation.worst_node = node;
    }
  }
  evaluation.rms = std::sqrt(total / static_cast<double>(std::max<long>(1, count)));
  evaluation.normal_rms = std::sqrt(total_normal / static_cast<double>(std::max<long>(1, count)));
  evaluation.tangential_rms = std::sqrt(std::max(0.0, evaluation.rms * evaluation.rms - evaluation.normal_rms * evaluation.normal_rms));
  for (const auto& [depth, sums] : by_depth)
    evaluation.rms_by_depth[depth] = std::sqrt(sums.first / static_cast<double>(sums.second));
  for (const auto& [region, sums] : by_region)
    evaluation.rms_by_region[truth.region_names()[static_cast<std::size_t>(region)]] =
        std::sqrt(sums.first / static_cast<double>(sums.second));
  return evaluation;
}

TruthEvaluation evaluate_against_truth(const core::Capture& capture, const Registration& registration) {
  return evaluate_against_truth(TruthReference(capture, registration.database), registration);
}

core::Json TruthEvaluation::to_json(const Registration& registration) const {
  const double percent = 100.0 / height;
  core::Json depth = core::Json::array();
  for (const auto& [d, rms_at] : rms_by_depth)
    depth.push_back({{"depth", d}, {"rms_m", rms_at}, {"rms_percent_height", rms_at * percent}});
  core::Json regions = core::Json::object();
  for (const auto& [name, rms_at] : rms_by_region) regions[name] = rms_at;
  const auto& worst = registration.frames[static_cast<std::size_t>(worst_node)];
  return {{"height_m", height},
          {"rms_m", rms},
          {"rms_percent_height", rms * percent},
          {"normal_rms_m", normal_rms},
          {"tangential_rms_m", tangential_rms},
          {"worst_frame", worst.sequence + ":" + std::to_string(worst.frame)},
          {"worst_frame_rms_m", worst_frame_rms},
          {"worst_frame_rms_percent_height", worst_frame_rms * percent},
          {"by_depth", depth},
          {"by_region_rms_m", regions}};
}

}  // namespace surfcap::align
