#include "surfcap/evaluation/alignment_report.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/mesh_repair.hpp"
#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/appearance_flow.hpp"
#include "surfcap/align/observed_surface.hpp"
#include "surfcap/align/pairwise_checks.hpp"
#include "surfcap/geometry/mean_edge_length.hpp"

namespace surfcap::evaluation {

namespace {

/// Blue (0) → cyan → green → yellow → red (1), as BGR bytes.
cv::Scalar heat_bgr(double value) {
  const double t = std::clamp(value, 0.0, 1.0) * 4.0;
  const int band = std::min(3, static_cast<int>(t));
  const double u = t - band;
  double r = 0, g = 0, b = 0;
  switch (band) {
    case 0: b = 1; g = u; break;
    case 1: g = 1; b = 1 - u; break;
    case 2: g = 1; r = u; break;
    default: r = 1; g = 1 - u; break;
  }
  return cv::Scalar(std::round(255 * b), std::round(255 * g), std::round(255 * r));
}

cv::Mat render_panel(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::VectorXd& values, double scale,
                     int size, const std::string& label) {
  cv::Mat panel(size, size, CV_8UC3, cv::Scalar(255, 255, 255));
  const Eigen::RowVector3d low = V.colwise().minCoeff(), high = V.colwise().maxCoeff();
  const double extent = std::max(high.x() - low.x(), high.y() - low.y()) * 1.1;
  const double pixels = (size - 30) / std::max(extent, 1e-9);
  const Eigen::RowVector3d centre = (low + high) / 2;
  auto project = [&](long v) {
    return cv::Point(static_cast<int>(std::lround(size / 2.0 + (V(v, 0) - centre.x()) * pixels)),
                     static_cast<int>(std::lround(size / 2.0 + 10 - (V(v, 1) - centre.y()) * pixels)));
  };
  // Painter's algorithm: faces from back (−z) to front, ties by index (deterministic).
  std::vector<long> order(static_cast<std::size_t>(F.rows()));
  std::iota(order.begin(), order.end(), 0);
  Eigen::VectorXd depth(F.rows());
  for (long f = 0; f < F.rows(); ++f) depth(f) = V(F(f, 0), 2) + V(F(f, 1), 2) + V(F(f, 2), 2);
  std::stable_sort(order.begin(), order.end(), [&](long a, long b) { return depth(a) < depth(b); });
  for (const long f : order) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
    const double shade = 0.45 + 0.55 * std::abs(normal.z());
    const double value = (values(F(f, 0)) + values(F(f, 1)) + values(F(f, 2))) / (3.0 * scale);
    const cv::Scalar colour = heat_bgr(value) * shade;
    const cv::Point points[3] = {project(F(f, 0)), project(F(f, 1)), project(F(f, 2))};
    cv::fillConvexPoly(panel, points, 3, colour, cv::LINE_8);
  }
  cv::putText(panel, label, cv::Point(6, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_8);
  return panel;
}

}  // namespace

core::Json alignment_figures(const align::Registration& registration) {
  const auto template_unobserved_fraction = [](const align::Registration& r) {
    const long n = r.database.template_mesh.vertex_count();
    return n > 0 ? 1.0 - static_cast<double>(r.template_observed_vertices) / static_cast<double>(n) : 0.0;
  };
  core::Json frames = core::Json::array();
  double mean_sum = 0, worst = 0;
  long patch = 0, dense = 0, feature = 0, coverage = 0, flow = 0;
  int max_depth = 0;
  long retried = 0, unrecovered = 0, predicted_frames = 0, predicted_patches = 0, hinged_patches = 0, carried_patches = 0,
       frames_with_holes = 0, frames_with_merged = 0;
  double most_unobserved = 0, most_merged = 0;
  for (const auto& record : registration.frames) {
    const auto& a = record.alignment;
    core::Json attempts = core::Json::array();
    for (const auto& attempt : record.failed_attempts)
      attempts.push_back({{"parent", attempt.parent}, {"mean_residual_m", attempt.mean_residual},
                          {"uncovered_fraction", attempt.uncovered_fraction},
                          {"stacked_fraction", attempt.stacked_fraction},
                          {"failure", attempt.failure}});
    retried += record.failed_attempts.empty() ? 0 : 1;
    unrecovered += record.unrecovered ? 1 : 0;
    frames.push_back({{"sequence", record.sequence},
                      {"frame", record.frame},
                      {"node", record.node},
                      {"parent", record.parent},
                      {"depth", record.depth},
                      {"mean_residual_m", a.mean_residual},
                      {"max_residual_m", a.max_residual},
                      {"uncovered_fraction", a.uncovered_fraction},
                      {"stacked_fraction", a.stacked_fraction},
                      {"holes", {{"count", a.holes}, {"largest_perimeter_m", a.largest_hole_perimeter}}},
                      {"unobserved_fraction", a.unobserved_fraction},
                      {"merged", {{"regions", a.merged_regions}, {"fraction", a.merged_fraction}}},
                      {"correspondences", {{"patch", a.patch_constraints}, {"dense", a.dense_constraints},
                                           {"feature", a.feature_constraints}, {"color", a.color_constraints},
                                           {"coverage", a.coverage_constraints}, {"crease", a.crease_constraints}, {"flow_pixels", a.flow_pixels}, {"flow", a.flow_vertices}}},
                      {"accepted_patches", a.accepted_patches},
                      {"color_patches", a.color_patches},
                      {"predicted", a.predicted},
                      {"predicted_patches", a.predicted_patches},
                      {"hinged_patches", a.hinged_patches},
                      {"carried_patches", a.carried_patches},
                      {"total_patches", a.total_patches},
                      {"heading_change_rad", a.heading_change},
                      {"image_features", record.features},
                      {"failed_attempts", attempts},
                      {"unrecovered", record.unrecovered},
                      {"entry_attempts", record.entry_attempts},
                      {"seconds", record.seconds},
                      {"timings_s", {{"matching", a.timings.matching}, {"factorisation", a.timings.factorisation},
                                     {"solves", a.timings.solves}}}});
    mean_sum += a.mean_residual;
    worst = std::max(worst, a.max_residual);
    patch += a.patch_constraints;
    dense += a.dense_constraints;
    feature += a.feature_constraints;
    coverage += a.coverage_constraints;
    flow += a.flow_vertices;
    max_depth = std::max(max_depth, record.depth);
    predicted_frames += a.predicted ? 1 : 0;
    predicted_patches += a.predicted_patches;
    hinged_patches += a.hinged_patches;
    carried_patches += a.carried_patches;
    frames_with_holes += a.holes > 0 ? 1 : 0;
    most_unobserved = std::max(most_unobserved, a.unobserved_fraction);
    frames_with_merged += a.merged_regions > 0 ? 1 : 0;
    most_merged = std::max(most_merged, a.merged_fraction);
  }
  const double count = std::max<double>(1.0, static_cast<double>(registration.frames.size()));
  return {{"frames", frames},
          {"summary", {{"frames", registration.frames.size()},
                       {"mean_residual_m", mean_sum / count},
                       {"max_residual_m", worst},
                       {"max_depth", max_depth},
                       {"frames_with_failed_attempts", retried},
                       {"frames_unrecovered", unrecovered},
                       {"frames_predicted", predicted_frames},
                       {"predicted_patches", predicted_patches},
                       {"hinged_patches", hinged_patches},
                       {"carried_patches", carried_patches},
                       {"correspondences", {{"patch", patch}, {"dense", dense}, {"feature", feature},
                                           {"coverage", coverage}, {"flow", flow}}},
                       {"deformer", registration.deformer_model},
                       {"volume_vertices", registration.volume_vertices},
                       {"elements", registration.elements},
                       {"template_unseen_vertices", registration.template_unseen_vertices},
                       {"softened_elements", registration.softened_elements},
                       {"cut_elements", registration.cut_elements},
                       {"template_seconds", registration.seconds_template},
                       {"appearance_coverage", registration.appearance_coverage},
                       {"frames_with_holes", frames_with_holes},
                       {"template_unobserved_fraction", template_unobserved_fraction(registration)},
                       {"template_dropped_vertices", registration.template_dropped_vertices.size()},
                       {"max_unobserved_fraction", most_unobserved},
                       {"frames_with_merged_regions", frames_with_merged},
                       {"max_merged_fraction", most_merged}}}};
}

std::vector<long> preview_nodes(const align::Registration& registration, int count) {
  const long nodes = static_cast<long>(registration.frames.size());
  std::vector<long> chosen;
  long root = 0, deepest = 0, worst = 0;
  for (long node = 0; node < nodes; ++node) {
    const auto& record = registration.frames[static_cast<std::size_t>(node)];
    if (record.parent < 0) root = node;
    if (record.depth > registration.frames[static_cast<std::size_t>(deepest)].depth) deepest = node;
    if (record.alignment.mean_residual > registration.frames[static_cast<std::size_t>(worst)].alignment.mean_residual)
      worst = node;
  }
  for (const long node : {root, nodes / 2, deepest, worst})
    if (std::find(chosen.begin(), chosen.end(), node) == chosen.end() && static_cast<int>(chosen.size()) < count)
      chosen.push_back(node);
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

namespace {

/// The legend of a heat scale in millimetres.
std::string millimetre_legend(double scale, const std::string& what) {
  char legend[160];
  std::snprintf(legend, sizeof legend, "0 .. %.1f mm %s", 1000 * scale, what.c_str());
  return legend;
}

void write_sheet(const std::filesystem::path& path, const std::vector<cv::Mat>& panels, const std::string& legend) {
  if (panels.empty()) return;
  cv::Mat sheet;
  cv::hconcat(panels, sheet);
  cv::Mat bar(28, sheet.cols, CV_8UC3, cv::Scalar(255, 255, 255));
  for (int x = 0; x < 200 && x + 10 < bar.cols; ++x)
    cv::line(bar, cv::Point(10 + x, 4), cv::Point(10 + x, 14), heat_bgr(x / 199.0));
  cv::putText(bar, legend, cv::Point(220, 16), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_8);
  cv::vconcat(sheet, bar, sheet);
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", sheet, bytes, {cv::IMWRITE_PNG_COMPRESSION, 6}))
    throw core::io_error(path, "PNG encoding failed");
  core::write_file_atomically(path, std::span(reinterpret_cast<const std::byte*>(bytes.data()), bytes.size()));
}

/// A frame's reconstruction as the alignment read it (large holes open).
core::Mesh read_frame(const core::Capture& capture, const align::FrameRecord& record) {
  core::RepairLimits limits;
  limits.keep_large_holes_open = true;
  return core::read_reconstruction(capture.mesh_path(capture.sequence_index(record.sequence), record.frame),
                                   record.frame, limits);
}

std::string node_label(const align::FrameRecord& record, const char* what, double value) {
  char label[160];
  std::snprintf(label, sizeof label, "%s:%d depth %d %s %.1f mm", record.sequence.c_str(), record.frame, record.depth,
                what, 1000 * value);
  return label;
}

}  // namespace

namespace {

constexpr int kPanelSize = 360;

/// Calls visit(record, its reconstruction as aligned, aligned template positions) for each node.
template <class Visit>
void visit_nodes(const core::Capture& capture, const align::Registration& registration, const std::vector<long>& nodes,
                 Visit&& visit) {
  for (const long node : nodes) {
    const auto& record = registration.frames[static_cast<std::size_t>(node)];
    visit(record, read_frame(capture, record), registration.world_positions[static_cast<std::size_t>(node)]);
  }
}

/// The front panel and the side view (a quarter turn about the vertical through the centroid).
void add_front_and_side(std::vector<cv::Mat>& panels, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                        const Eigen::VectorXd& values, double scale, const std::string& label,
                        const std::string& side_label = "side") {
  panels.push_back(render_panel(V, F, values, scale, kPanelSize, label));
  Eigen::MatrixXd side = V.rowwise() - V.colwise().mean();
  side.col(0).swap(side.col(2));
  side.col(0) *= -1;
  panels.push_back(render_panel(side, F, values, scale, kPanelSize, side_label));
}

}  // namespace

void write_residual_preview(const std::filesystem::path& path, const core::Capture& capture,
                            const align::Registration& registration, const std::vector<long>& nodes, double scale) {
  std::vector<cv::Mat> panels;
  const Eigen::MatrixXi& F = registration.database.template_mesh.F;
  visit_nodes(capture, registration, nodes,
              [&](const align::FrameRecord& record, const core::Mesh& target, const Eigen::MatrixXd& V) {
                const geometry::SurfaceQuery query(target.V, target.F);
                const Eigen::VectorXd values = align::surface_distances(V, query);
                panels.push_back(render_panel(V, F, values, scale, kPanelSize, node_label(record, "mean", values.mean())));
              });
  write_sheet(path, panels, millimetre_legend(scale, "to the reconstruction"));
}

bool has_observation_figures(const align::Registration& registration) {
  if (registration.template_observed_vertices < registration.database.template_mesh.vertex_count() ||
      registration.template_unseen_vertices > 0 || !registration.template_cut_vertices.empty())
    return true;
  return std::any_of(registration.frames.begin(), registration.frames.end(),
                     [](const align::FrameRecord& record) {
                       return record.alignment.holes > 0 || record.alignment.merged_regions > 0;
                     });
}

void write_observation_preview(const std::filesystem::path& path, const core::Capture& capture,
                               const align::Registration& registration, const std::vector<long>& nodes) {
  std::vector<cv::Mat> panels;
  const Eigen::MatrixXi& F = registration.database.template_mesh.F;
  // The merged regions as the pairwise checks measured them (pairwise_alignment.cpp).
  const Eigen::MatrixXd& rest = registration.database.template_mesh.V;
  const double mean_edge = geometry::mean_edge_length(rest, F);
  const double height = rest.col(1).maxCoeff() - rest.col(1).minCoeff();
  // What no camera sees at the root, where the volume is soft (alignment_template.hpp): found as
  // the template found it, on the root's positions (the template's, in the capture's frame).
  std::vector<char> unseen;
  for (std::size_t node = 0; node < registration.frames.size(); ++node)
    if (registration.frames[node].parent < 0 && registration.world_positions[node].rows() > 0)
      unseen = align::unseen_vertices(registration.world_positions[node], F, align::capture_cameras(capture));
  const std::vector<long>& cut = registration.template_cut_vertices;
  visit_nodes(capture, registration, nodes,
              [&](const align::FrameRecord& record, const core::Mesh& target, const Eigen::MatrixXd& V) {
                const geometry::SurfaceQuery query(target.V, target.F);
                const align::ObservedSurface observed(target.V, target.F);
                const align::MergedRegions merged =
                    align::merged_regions(rest, V, F, query, mean_edge, height);
                Eigen::VectorXd values = Eigen::VectorXd::Zero(V.rows());
                for (long v = 0; v < V.rows(); ++v)
                  if (v >= registration.template_observed_vertices) values(v) = 1;  // red
                  else if (observed.partial() && !observed.observed(query.closest_point(V.row(v).transpose())))
                    values(v) = 0.875;  // orange
                  else if (std::binary_search(cut.begin(), cut.end(), v))
                    values(v) = 0.75;  // yellow
                  else if (merged.merged[static_cast<std::size_t>(v)])
                    values(v) = 0.5;  // green
                  else if (!unseen.empty() && unseen[static_cast<std::size_t>(v)])
                    values(v) = 0.25;  // cyan
                char label[200], side_label[100];
                std::snprintf(label, sizeof label, "%s:%d %ld holes, %.0f %% unobserved", record.sequence.c_str(),
                              record.frame, record.alignment.holes, 100 * record.alignment.unobserved_fraction);
                std::snprintf(side_label, sizeof side_label, "side; %ld merged regions", record.alignment.merged_regions);
                add_front_and_side(panels, V, F, values, 1.0, label, side_label);
                if (record.parent >= 0 || unseen.empty()) return;
                // The root from below (x, z, −y: a rotation, the viewer under the feet): most of
                // what no camera sees faces the floor.
                Eigen::MatrixXd below(V.rows(), 3);
                below << V.col(0), V.col(2), -V.col(1);
                char below_label[100];
                std::snprintf(below_label, sizeof below_label, "from below; %ld seen by no camera",
                              static_cast<long>(std::count(unseen.begin(), unseen.end(), 1)));
                panels.push_back(render_panel(below, F, values, 1.0, kPanelSize, below_label));
              });
  write_sheet(path, panels,
              "observed (blue), seen by no camera at the root (cyan), fused with another part (green), where the "
              "template's volume was cut from a part it touches (yellow), over a hole's rim in this frame (orange), "
              "closing surface (red)");
}

void write_value_preview(const std::filesystem::path& path, const align::Registration& registration,
                         const std::vector<long>& nodes, const std::vector<Eigen::VectorXd>& values, double scale,
                         const std::string& what) {
  std::vector<cv::Mat> panels;
  const Eigen::MatrixXi& F = registration.database.template_mesh.F;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const auto& record = registration.frames[static_cast<std::size_t>(nodes[k])];
    const Eigen::MatrixXd& V = registration.world_positions[static_cast<std::size_t>(nodes[k])];
    const std::string label = node_label(record, "rms", std::sqrt(values[k].squaredNorm() / static_cast<double>(values[k].size())));
    add_front_and_side(panels, V, F, values[k], scale, label);
  }
  write_sheet(path, panels, millimetre_legend(scale, what));
}

}  // namespace surfcap::evaluation
