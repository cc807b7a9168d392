// Pairwise non-rigid alignment at ~3k and ~10k template vertices on one core, with
// the split reported as counters: tetrahedralisation (once per template), factorisation,
// matching (closest points, ICP) and solves (rotation fits + back-substitution).
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <cmath>

#include "../unit/align/deformable_shape.hpp"
#include "../unit/align/textured_capture.hpp"
#include "surfcap/align/appearance_flow.hpp"
#include "surfcap/align/feature_constraints.hpp"
#include "surfcap/align/image_features.hpp"
#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/render/camera.hpp"

namespace {

using namespace surfcap;

// Template: an asymmetric body of 39·76 + 2 = 2,966 vertices; target: another tessellation of it,
// bent and twisted.
/// Part colours by height at rest (dark feet, grey legs, red skirt, blue shirt), as the synth
/// actor's materials: what the colour-aware patch matching works on.
Eigen::MatrixXd part_colours(const Eigen::MatrixXd& rest) {
  Eigen::MatrixXd colours(rest.rows(), 3);
  for (long v = 0; v < rest.rows(); ++v) {
    const double y = rest(v, 1);
    if (y < -0.7) colours.row(v) << 0.05, 0.05, 0.05;
    else if (y < -0.2) colours.row(v) << 0.35, 0.35, 0.4;
    else if (y < 0.1) colours.row(v) << 0.7, 0.15, 0.15;
    else colours.row(v) << 0.15, 0.25, 0.7;
  }
  return colours;
}

/// `rings`×`segments` template tessellation; the target's has about 1.09 times the vertices.
void pairwise_alignment(benchmark::State& state, bool colours, int rings, int segments) {
  omp_set_num_threads(1);
  core::retain_freed_memory();  // as surfcap-align runs
  core::Mesh template_mesh = align::testing::ellipsoid(rings, segments);
  const core::Mesh target_rest = align::testing::ellipsoid(rings * 47 / 40, segments * 70 / 76);
  const Eigen::MatrixXd target_V = align::testing::deform_points(target_rest.V, 0.6, 0.5, {0.05, 0.02, -0.04});
  Eigen::MatrixXd target_colours;
  if (colours) {
    template_mesh.colors = part_colours(template_mesh.V);
    target_colours = part_colours(target_rest.V);
  }
  const align::PairwiseOptions options;
  // The calibration every capture has: eight cameras around the body (silhouette evidence of the
  // coverage pulls and the uncovered check).
  const std::vector<render::Camera> cameras =
      render::ring_cameras(8, 4.0, 0.0, Eigen::Vector3d::Zero(), 40.0, 640, 480);
  align::FeaturePair views;
  views.cameras = &cameras;
  const Eigen::MatrixXd truth = align::testing::deform_points(template_mesh.V, 0.6, 0.5, {0.05, 0.02, -0.04});
  double tetrahedralisation = 0, matching = 0, factorisation = 0, solves = 0, total = 0, rms = 0;
  long iterations = 0, colour_patches = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const align::AlignmentTemplate model(template_mesh, options);  // tetrahedralisation + patches
    const geometry::SurfaceQuery target(target_V, target_rest.F);
    const align::PairwiseResult result =
        align::align_pair(model, model.deformer().rest(), target, options, colours ? &target_colours : nullptr, views);
    benchmark::DoNotOptimize(result.positions.data());
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    tetrahedralisation += model.seconds_tetrahedralisation();
    matching += result.timings.matching;
    factorisation += result.timings.factorisation;
    solves += result.timings.solves;
    colour_patches = result.color_patches;
    const Eigen::VectorXd errors = (result.positions.topRows(truth.rows()) - truth).rowwise().norm();
    rms = std::sqrt(errors.squaredNorm() / static_cast<double>(errors.size()));
    ++iterations;
  }
  const double n = static_cast<double>(iterations);
  state.counters["vertices"] = static_cast<double>(template_mesh.vertex_count());
  state.counters["total_s"] = total / n;
  state.counters["tetrahedralisation_s"] = tetrahedralisation / n;
  state.counters["matching_s"] = matching / n;
  state.counters["factorisation_s"] = factorisation / n;
  state.counters["solves_s"] = solves / n;
  // The accuracy the time buys: RMS distance of the aligned template vertices from where the bend
  // and twist take them, in % of the template's height.
  state.counters["rms_percent_height"] = 100 * rms / (template_mesh.V.col(1).maxCoeff() - template_mesh.V.col(1).minCoeff());
  if (colours) state.counters["colour_patches"] = static_cast<double>(colour_patches);
}

void BM_PairwiseAlignment3k(benchmark::State& state) { pairwise_alignment(state, false, 40, 76); }
BENCHMARK(BM_PairwiseAlignment3k)->Unit(benchmark::kMillisecond)->Iterations(3);

// The same with vertex colours on both meshes: the colour-aware patch fits at the two coarsest
// levels (one more ICP per patch there, a k-d tree over the target) and the photometric dense fit.
void BM_PairwiseAlignment3kColour(benchmark::State& state) { pairwise_alignment(state, true, 40, 76); }
BENCHMARK(BM_PairwiseAlignment3kColour)->Unit(benchmark::kMillisecond)->Iterations(3);

// The same body at 69·144 + 2 = 9,938 template vertices (a studio reconstruction's resolution).
void BM_PairwiseAlignment10k(benchmark::State& state) { pairwise_alignment(state, false, 70, 144); }
BENCHMARK(BM_PairwiseAlignment10k)->Unit(benchmark::kMillisecond)->Iterations(2);

// Image features of one frame seen by 8 cameras at 640×640 (detection + back-projection), and the
// matching of two such frames (FLANN both ways, ratio, mutual, neighbour check), one core.
void BM_FeatureDetectionAndMatching(benchmark::State& state) {
  omp_set_num_threads(1);
  const align::testing::TexturedCapture scene("features_bench", 8, 640);
  const geometry::SurfaceQuery parent_surface(scene.frames[0], scene.rest.F), child_surface(scene.frames[1], scene.rest.F);
  const align::FeatureOptions options;
  double detection = 0, matching = 0;
  long iterations = 0, matches = 0, features = 0;
  for (auto _ : state) {
    auto start = std::chrono::steady_clock::now();
    const align::FrameFeatures parent = align::detect_frame_features(scene.capture, 0, 0, parent_surface, options);
    const align::FrameFeatures child = align::detect_frame_features(scene.capture, 0, 1, child_surface, options);
    detection += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 2;
    start = std::chrono::steady_clock::now();
    const align::FeatureMatching found = align::feature_constraints(
        scene.frames[0], scene.rest.F, parent, child, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 0.01, 1.8, options);
    matching += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    matches = static_cast<long>(found.constraints.size());
    features = parent.size();
    ++iterations;
  }
  const double n = static_cast<double>(iterations);
  state.counters["features_per_frame"] = static_cast<double>(features);
  state.counters["matches"] = static_cast<double>(matches);
  state.counters["detection_per_frame_s"] = detection / n;
  state.counters["matching_per_pair_s"] = matching / n;
}
BENCHMARK(BM_FeatureDetectionAndMatching)->Unit(benchmark::kMillisecond)->Iterations(2);

// One appearance-flow iteration's correspondences (render the estimate with the root appearance,
// DIS flow forward and backward, ray casts) for 8 cameras at 640×640, and the root appearance
// (8 visibility renderings), one core. An alignment runs 3 flow iterations per edge.
void BM_AppearanceFlow(benchmark::State& state) {
  omp_set_num_threads(1);
  const align::testing::TexturedCapture scene("flow_bench", 8, 640);
  const geometry::SurfaceQuery child(scene.frames[1], scene.rest.F);
  const align::FlowOptions options;
  const double edge = 0.02;
  const std::vector<align::GreyImage> child_images = align::read_grey_images(scene.capture, 0, 1);
  const Eigen::MatrixXd estimate = scene.frames[1].rowwise() + Eigen::RowVector3d(0.006, 0.004, 0.0);
  double appearance = 0, flow = 0;
  long iterations = 0, pixels = 0;
  for (auto _ : state) {
    auto start = std::chrono::steady_clock::now();
    const align::TemplateAppearance root(scene.rest, align::capture_cameras(scene.capture),
                                         align::read_grey_images(scene.capture, 0, 0), edge, options);
    appearance += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const align::ChildViews views(child, child_images);  // rendered in the timed call, as an edge's first iteration
    start = std::chrono::steady_clock::now();
    const align::FlowTargets targets = align::flow_targets(root, estimate, scene.rest.F, views, edge, options);
    flow += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    pixels = targets.pixels;
    ++iterations;
  }
  const double n = static_cast<double>(iterations);
  state.counters["pixels"] = static_cast<double>(pixels);
  state.counters["appearance_s"] = appearance / n;
  state.counters["flow_iteration_s"] = flow / n;
}
BENCHMARK(BM_AppearanceFlow)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace
