#include "surfcap/evaluation/ground_truth_error.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/render/camera.hpp"
#include "surfcap/render/rasterizer.hpp"

namespace surfcap::evaluation {

std::optional<std::filesystem::path> ground_truth_file(const core::Capture& capture) {
  const auto path = capture.folder / "ground_truth" / "truth.json";
  if (std::filesystem::exists(path)) return path;
  return std::nullopt;
}

TruthReference::TruthReference(const core::Capture& capture, const core::AlignedDatabase& aligned,
                               long observed_vertices, const std::vector<long>& dropped_vertices)
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
  const long n = observed_vertices < 0 ? aligned.template_mesh.vertex_count()
                                       : std::min(observed_vertices, aligned.template_mesh.vertex_count());
  // Template vertex v is the root reconstruction's vertex source[v].
  const long root_count = n + static_cast<long>(dropped_vertices.size());
  std::vector<long> source;
  std::size_t next_dropped = 0;
  for (long r = 0; r < root_count; ++r) {
    if (next_dropped < dropped_vertices.size() && dropped_vertices[next_dropped] == r) ++next_dropped;
    else source.push_back(r);
  }
  if (static_cast<long>(source.size()) != n)
    throw core::internal_error("TruthReference: the template's dropped vertices are not ascending root vertices");
  const core::NpyArray faces = core::read_npy(face_path, core::DType::int32, {root_count});
  const Eigen::MatrixXd root_barycentric = core::read_npy_matrix(bary_path, root_count, 3);
  barycentric_.resize(n, 3);
  faces_.resize(static_cast<std::size_t>(n));
  for (long v = 0; v < n; ++v) {
    const long r = source[static_cast<std::size_t>(v)];
    barycentric_.row(v) = root_barycentric.row(r);
    faces_[static_cast<std::size_t>(v)] = faces.data<std::int32_t>()[r];
  }
  const Eigen::MatrixXi& true_F = truth_.template_mesh.F;
  for (long v = 0; v < n; ++v)
    if (faces_[static_cast<std::size_t>(v)] < 0 || faces_[static_cast<std::size_t>(v)] >= true_F.rows())
      throw core::bad_input(face_path, "face index out of range at vertex " + std::to_string(v));

  // Status (studio models): phantom volume, outliers and blobs have no true location on the surface.
  evaluated_.assign(static_cast<std::size_t>(n), 1);
  if (root_entry.contains("correspondence_status") && truth.contains("status_codes")) {
    const auto status_path = truth_dir / core::expand_pattern(root_entry.at("correspondence_status").get<std::string>(),
                                                              aligned.root_frame);
    const core::NpyArray status = core::read_npy(status_path, core::DType::uint8, {root_count});
    const auto& codes = truth.at("status_codes");
    const int on_surface = codes.at("on_surface").get<int>(), rough = codes.value("rough", on_surface);
    for (long v = 0; v < n; ++v) {
      const int code = status.data<std::uint8_t>()[source[static_cast<std::size_t>(v)]];
      evaluated_[static_cast<std::size_t>(v)] = code == on_surface || code == rough ? 1 : 0;
    }
  }
  evaluated_fraction_ = static_cast<double>(std::count(evaluated_.begin(), evaluated_.end(), 1)) /
                        static_cast<double>(std::max<long>(1, aligned.template_mesh.vertex_count()));

  // Regions (optional: the dance capture has none), split by side of the rest pose (x sign).
  regions_ = Eigen::VectorXi::Constant(n, -1);
  downward_.assign(static_cast<std::size_t>(n), false);
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
      const auto rest_corner = [&](int k) -> Eigen::Vector3d { return rest.V.row(true_F(f, k)).transpose(); };
      const Eigen::Vector3d normal = (rest_corner(1) - rest_corner(0)).cross(rest_corner(2) - rest_corner(0));
      downward_[static_cast<std::size_t>(v)] = normal.y() < -0.5 * normal.norm();
    }
  }
  const Eigen::MatrixXd root = positions(aligned.root_sequence, aligned.root_frame);
  height_ = root.col(1).maxCoeff() - root.col(1).minCoeff();
}

Eigen::MatrixXd TruthReference::true_vertices(const std::string& sequence, int frame) const {
  const int s = truth_.sequence_index(sequence);
  const int c = capture_.sequence_index(sequence);
  const int offset = c < 0 ? -1 : frame - capture_.sequences[static_cast<std::size_t>(c)].first;
  if (s < 0 || offset < 0 || offset >= truth_.sequences[static_cast<std::size_t>(s)].frame_count())
    throw core::bad_input(truth_path_, "has no true frame " + std::to_string(frame) + " of '" + sequence + "'");
  const auto& seq = truth_.sequences[static_cast<std::size_t>(s)];
  return core::to_world(seq.frames[static_cast<std::size_t>(offset)], seq.root_motion[static_cast<std::size_t>(offset)]);
}

Eigen::MatrixXd TruthReference::positions(const std::string& sequence, int frame) const {
  const Eigen::MatrixXd X = true_vertices(sequence, frame);
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

std::vector<bool> TruthReference::observed(const std::string& sequence, int frame) const {
  const long n = barycentric_.rows();
  std::vector<bool> seen(static_cast<std::size_t>(n), false);
  if (capture_.cameras.empty()) return seen;
  core::Mesh surface;
  surface.V = true_vertices(sequence, frame);
  surface.F = truth_.template_mesh.F;
  const Eigen::MatrixXd points = positions(sequence, frame);
  const double tolerance = 0.005 * height_;
  render::RenderOptions options;
  options.smooth_normals = false;
  for (const auto& stored : capture_.cameras) {
    const render::Camera camera = render::from_capture_camera(stored);
    const std::vector<float> depth = render::render_mesh(surface, camera, options).depth;
    for (long v = 0; v < n; ++v) {
      if (seen[static_cast<std::size_t>(v)]) continue;
      const Eigen::Vector3d x = points.row(v).transpose();
      const auto corner = [&](int k) -> Eigen::Vector3d {
        return surface.V.row(surface.F(faces_[static_cast<std::size_t>(v)], k)).transpose();
      };
      const Eigen::Vector3d normal = (corner(1) - corner(0)).cross(corner(2) - corner(0));
      const Eigen::Vector3d towards = camera.centre() - x;
      if (!(normal.dot(towards) > 0.1 * normal.norm() * towards.norm())) continue;
      const double z = camera.to_camera(x).z();
      if (z <= 0) continue;
      const Eigen::Vector2d u = camera.project(x);
      const long px = std::lround(u.x()), py = std::lround(u.y());
      if (px < 0 || py < 0 || px >= camera.width || py >= camera.height) continue;
      const float visible =
          depth[static_cast<std::size_t>(py) * static_cast<std::size_t>(camera.width) + static_cast<std::size_t>(px)];
      if (z <= visible + tolerance) seen[static_cast<std::size_t>(v)] = true;
    }
  }
  return seen;
}

namespace {

/// Σ squared errors and counts as the frames are added: overall, seen or not, by depth and region.
struct ErrorSums {
  double total = 0, total_normal = 0, observed = 0, unobserved = 0;
  long count = 0, observed_count = 0;
  std::map<int, std::pair<double, long>> by_depth, by_region, by_region_down;
  std::vector<float> distances;  ///< every vertex-frame's error (m), for the percentiles
};

/// One frame's error against the truth (positions `world`), added to `sums`.
FrameTruthError frame_error(const TruthReference& truth, const align::FrameRecord& record,
                            const Eigen::MatrixXd& world, const Eigen::MatrixXi& F, ErrorSums& sums) {
  const Eigen::MatrixXd expected = truth.positions(record.sequence, record.frame);
  const Eigen::MatrixXd normals = core::vertex_normals(expected, F);
  const Eigen::MatrixXd error = world.topRows(expected.rows()) - expected;
  Eigen::VectorXd squared = error.rowwise().squaredNorm();
  Eigen::VectorXd along = (error.array() * normals.array()).rowwise().sum();
  long n = 0;
  for (long v = 0; v < squared.size(); ++v) {
    if (truth.evaluated(v)) ++n;
    else squared(v) = along(v) = 0;  // not on the true surface: no error
  }
  FrameTruthError frame;
  frame.rms = std::sqrt(squared.sum() / static_cast<double>(std::max<long>(1, n)));
  frame.max = std::sqrt(squared.maxCoeff());
  frame.normal_rms = std::sqrt(along.squaredNorm() / static_cast<double>(std::max<long>(1, n)));
  frame.tangential_rms = std::sqrt(std::max(0.0, frame.rms * frame.rms - frame.normal_rms * frame.normal_rms));
  frame.observed = truth.observed(record.sequence, record.frame);
  long seen = 0;
  for (long v = 0; v < squared.size(); ++v) {
    if (!truth.evaluated(v)) continue;
    if (frame.observed[static_cast<std::size_t>(v)]) {
      sums.observed += squared(v);
      ++seen;
    } else {
      sums.unobserved += squared(v);
    }
  }
  sums.observed_count += seen;
  frame.observed_fraction = static_cast<double>(seen) / static_cast<double>(std::max<long>(1, n));
  for (long v = 0; v < squared.size(); ++v)
    if (truth.evaluated(v)) sums.distances.push_back(static_cast<float>(std::sqrt(squared(v))));
  sums.total += squared.sum();
  sums.total_normal += along.squaredNorm();
  sums.count += n;
  auto& depth = sums.by_depth[record.depth];
  depth.first += squared.sum();
  depth.second += n;
  for (long v = 0; v < squared.size(); ++v) {
    if (truth.regions()(v) < 0 || !truth.evaluated(v)) continue;
    auto& region = sums.by_region[truth.regions()(v)];
    region.first += squared(v);
    ++region.second;
    if (!truth.downward()[static_cast<std::size_t>(v)]) continue;
    auto& down = sums.by_region_down[truth.regions()(v)];
    down.first += squared(v);
    ++down.second;
  }
  return frame;
}

/// The faces of F on vertices below n (the reconstruction's part of a closed template).
Eigen::MatrixXi faces_within(const Eigen::MatrixXi& F, long n) {
  std::vector<long> kept;
  for (long f = 0; f < F.rows(); ++f)
    if (F.row(f).maxCoeff() < n) kept.push_back(f);
  if (static_cast<long>(kept.size()) == F.rows()) return F;
  Eigen::MatrixXi within(static_cast<long>(kept.size()), 3);
  for (std::size_t k = 0; k < kept.size(); ++k) within.row(static_cast<long>(k)) = F.row(kept[k]);
  return within;
}

/// The overall figures from the sums.
void summarise(const TruthReference& truth, ErrorSums& sums, TruthEvaluation& evaluation) {
  const double count = static_cast<double>(std::max<long>(1, sums.count));
  if (!sums.distances.empty()) {  // the 99th percentile, nearest rank
    const auto rank = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(sums.distances.size()))) - 1;
    std::nth_element(sums.distances.begin(), sums.distances.begin() + static_cast<long>(rank), sums.distances.end());
    evaluation.p99_vertex_error = sums.distances[rank];
  }
  evaluation.rms = std::sqrt(sums.total / count);
  evaluation.normal_rms = std::sqrt(sums.total_normal / count);
  evaluation.tangential_rms =
      std::sqrt(std::max(0.0, evaluation.rms * evaluation.rms - evaluation.normal_rms * evaluation.normal_rms));
  evaluation.observed_fraction = static_cast<double>(sums.observed_count) / count;
  evaluation.observed_rms = std::sqrt(sums.observed / static_cast<double>(std::max<long>(1, sums.observed_count)));
  evaluation.unobserved_rms =
      std::sqrt(sums.unobserved / static_cast<double>(std::max<long>(1, sums.count - sums.observed_count)));
  for (const auto& [depth, sum] : sums.by_depth)
    evaluation.rms_by_depth[depth] = std::sqrt(sum.first / static_cast<double>(sum.second));
  std::map<int, long> region_vertices, region_down_vertices;
  for (long v = 0; v < truth.regions().size(); ++v) {
    if (truth.regions()(v) < 0 || !truth.evaluated(v)) continue;
    ++region_vertices[truth.regions()(v)];
    if (truth.downward()[static_cast<std::size_t>(v)]) ++region_down_vertices[truth.regions()(v)];
  }
  const double all_squared = std::max(sums.total, 1e-300);
  for (const auto& [region, sum] : sums.by_region) {
    const std::string& name = truth.region_names()[static_cast<std::size_t>(region)];
    evaluation.rms_by_region[name] = std::sqrt(sum.first / static_cast<double>(sum.second));
    evaluation.squared_share_by_region[name] = sum.first / all_squared;
  }
  for (const auto& [region, sum] : sums.by_region_down) {
    const std::string& name = truth.region_names()[static_cast<std::size_t>(region)];
    evaluation.downward_rms_by_region[name] = std::sqrt(sum.first / static_cast<double>(sum.second));
    evaluation.downward_squared_share_by_region[name] = sum.first / all_squared;
    evaluation.downward_fraction_by_region[name] =
        static_cast<double>(region_down_vertices[region]) / static_cast<double>(region_vertices[region]);
  }
}

}  // namespace

TruthEvaluation evaluate_against_truth(const TruthReference& truth, const align::Registration& registration) {
  TruthEvaluation evaluation;
  evaluation.height = truth.height();
  evaluation.evaluated_fraction = truth.evaluated_fraction();
  evaluation.frames.resize(registration.frames.size());
  ErrorSums sums;
  const Eigen::MatrixXi F = faces_within(registration.database.template_mesh.F, truth.vertex_count());
  for (std::size_t node = 0; node < registration.frames.size(); ++node) {
    auto& frame = evaluation.frames[node];
    frame = frame_error(truth, registration.frames[node], registration.world_positions[node], F, sums);
    if (frame.rms > evaluation.worst_frame_rms) {
      evaluation.worst_frame_rms = frame.rms;
      evaluation.worst_node = static_cast<long>(node);
    }
  }
  summarise(truth, sums, evaluation);
  return evaluation;
}

TruthEvaluation evaluate_against_truth(const core::Capture& capture, const align::Registration& registration) {
  return evaluate_against_truth(
      TruthReference(capture, registration.database, registration.template_observed_vertices,
                     registration.template_dropped_vertices),
      registration);
}

core::Json TruthEvaluation::to_json(const align::Registration& registration) const {
  const double percent = 100.0 / height;
  core::Json depth = core::Json::array();
  for (const auto& [d, rms_at] : rms_by_depth)
    depth.push_back({{"depth", d}, {"rms_m", rms_at}, {"rms_percent_height", rms_at * percent}});
  const auto to_object = [](const std::map<std::string, double>& values) {
    core::Json object = core::Json::object();
    for (const auto& [name, value] : values) object[name] = value;
    return object;
  };
  const auto& worst = registration.frames[static_cast<std::size_t>(worst_node)];
  return {{"height_m", height},
          {"evaluated_fraction", evaluated_fraction},
          {"rms_m", rms},
          {"rms_percent_height", rms * percent},
          {"normal_rms_m", normal_rms},
          {"tangential_rms_m", tangential_rms},
          {"p99_vertex_error_m", p99_vertex_error},
          {"p99_vertex_error_percent_height", p99_vertex_error * percent},
          {"worst_frame", worst.sequence + ":" + std::to_string(worst.frame)},
          {"worst_frame_rms_m", worst_frame_rms},
          {"worst_frame_rms_percent_height", worst_frame_rms * percent},
          {"observed_fraction", observed_fraction},
          {"observed_rms_m", observed_rms},
          {"observed_rms_percent_height", observed_rms * percent},
          {"unobserved_rms_m", unobserved_rms},
          {"unobserved_rms_percent_height", unobserved_rms * percent},
          {"by_depth", depth},
          {"by_region_rms_m", to_object(rms_by_region)},
          {"by_region_squared_share", to_object(squared_share_by_region)},
          {"by_region_downward_rms_m", to_object(downward_rms_by_region)},
          {"by_region_downward_squared_share", to_object(downward_squared_share_by_region)},
          {"by_region_downward_fraction", to_object(downward_fraction_by_region)}};
}

}  // namespace surfcap::evaluation
