// surfcap-remesh: a mesh sequence with one connectivity (template + positions.npy) → an
// unstructured capture folder (every frame remeshed independently, noise along the normals) with
// ground truth in the layout of docs/synth.md (database + per-vertex correspondence), so that
// surfcap-align register can be checked on real motion (docs/align.md, scripts/make_dance_capture.sh).
#include <spdlog/spdlog.h>

#include <algorithm>

#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/core/cli.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/parallel.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/geometry/mean_edge_length.hpp"
#include "surfcap/render/camera.hpp"
#include "surfcap/synth/remesh.hpp"
#include "surfcap/synth/scene.hpp"
#include "surfcap/synth/studio.hpp"

namespace {

using namespace surfcap;

struct Arguments {
  std::string template_path, positions_path, out;
  std::string sequence = "dance";
  int first = 0, count = -1, step = 1;
  double edge_scale = 1.0, noise_mm = 1.0, fps = 25;
  std::uint64_t seed = 1;
  // Studio artefacts (docs/synth.md): off unless asked for.
  bool visual_hull = false;
  int cameras = 12;
  double voxel_mm = 10, floor_cut_mm = -1, outliers = 0, blobs = 0;
  std::string unseen = "keep";
  bool studio() const { return visual_hull || floor_cut_mm >= 0 || outliers > 0 || blobs > 0 || unseen != "keep"; }
};

/// The studio models as asked for; the floor is `floor` (the sequence's lowest point).
synth::ReconstructionOptions studio_options(const Arguments& args, double floor) {
  synth::ReconstructionOptions options;
  options.noise_sigma = args.noise_mm / 1000;
  options.visual_hull = args.visual_hull;
  options.voxel = args.voxel_mm / 1000;
  options.surface_tolerance = options.voxel;  // the hull is as precise as its grid
  options.floor_cut = args.floor_cut_mm >= 0;
  options.floor_height = floor + args.floor_cut_mm / 1000;
  options.unseen = synth::unseen_mode(args.unseen);
  options.outlier_fraction = args.outliers;
  options.blobs = args.blobs;
  return options;
}

std::string frame_name(int frame) { return core::expand_pattern("{frame:06d}", frame); }

void run(const Arguments& args, const core::ToolApp& app) {
  const core::Mesh source = core::read_mesh(args.template_path);
  std::vector<std::size_t> shape;
  const std::vector<double> positions = core::read_npy_as_double(args.positions_path, {-1, source.vertex_count(), 3}, &shape);
  const int available = static_cast<int>(shape[0]);
  if (args.first < 0 || args.first >= available || args.step < 1) throw core::bad_arguments("--first/--step out of range");
  const int count = args.count < 0 ? (available - args.first + args.step - 1) / args.step : args.count;
  if (count < 1 || args.first + (count - 1) * args.step >= available)
    throw core::bad_arguments("--count exceeds the " + std::to_string(available) + " frames of " + args.positions_path);
  auto frame_positions = [&](int k) {
    const std::size_t base = static_cast<std::size_t>(args.first + k * args.step) * source.vertex_count() * 3;
    Eigen::MatrixXd V(source.vertex_count(), 3);
    for (long v = 0; v < V.rows(); ++v)
      for (int c = 0; c < 3; ++c) V(v, c) = positions[base + static_cast<std::size_t>(v) * 3 + c];
    return V;
  };
  const std::filesystem::path out = args.out;
  const double edge = geometry::mean_edge_length(source.V, source.F) * args.edge_scale;
  core::ProgressReporter progress("remesh", static_cast<std::size_t>(count));
  std::vector<long> vertex_counts(static_cast<std::size_t>(count)), holes(static_cast<std::size_t>(count)),
      genus(static_cast<std::size_t>(count)), phantom(static_cast<std::size_t>(count));
  // With the studio models: a ring of cameras around the whole performance, the floor at its lowest point.
  std::vector<render::Camera> cameras;
  double floor = 0;
  if (args.studio()) {
    Eigen::Vector3d lower = Eigen::Vector3d::Constant(1e300), upper = -lower;
    for (int k = 0; k < count; ++k) {
      const Eigen::MatrixXd V = frame_positions(k);
      lower = lower.cwiseMin(V.colwise().minCoeff().transpose());
      upper = upper.cwiseMax(V.colwise().maxCoeff().transpose());
    }
    floor = lower.y();
    const Eigen::Vector3d target = (lower + upper) / 2;
    const double reach = std::max({upper.x() - lower.x(), upper.z() - lower.z(), upper.y() - lower.y()});
    cameras = render::ring_cameras(args.cameras, 2.5 * reach + 1.0, upper.y(), target, 40, 640, 480);
  }
  core::parallel_for(count, app.common().threads, [&](long k) {
    core::Mesh frame = source;
    frame.V = frame_positions(static_cast<int>(k));
    const std::uint64_t seed = args.seed * 1000003ULL + static_cast<std::uint64_t>(k);
    core::Mesh mesh;
    std::vector<int> face;
    Eigen::MatrixXd barycentric;
    std::vector<std::uint8_t> status;
    if (args.studio()) {
      synth::Reconstruction result = synth::reconstruct_studio(frame, cameras, {}, edge, seed, studio_options(args, floor));
      const synth::FrameArtefacts artefacts = synth::measure_artefacts(result.mesh, result.status, Eigen::MatrixXd(), {});
      holes[static_cast<std::size_t>(k)] = artefacts.holes;
      genus[static_cast<std::size_t>(k)] = artefacts.genus;
      phantom[static_cast<std::size_t>(k)] = artefacts.phantom;
      mesh = std::move(result.mesh);
      face = std::move(result.face);
      barycentric = std::move(result.barycentric);
      status = std::move(result.status);
    } else {
      synth::RemeshOptions options;
      options.edge = edge;
      options.noise_sigma = args.noise_mm / 1000;
      options.seed = seed;
      synth::RemeshResult result = synth::remesh(frame, options);
      mesh = std::move(result.mesh);
      face = std::move(result.face);
      barycentric = std::move(result.barycentric);
    }
    const std::string name = frame_name(static_cast<int>(k));
    core::write_mesh(out / args.sequence / "mesh" / (name + ".ply"), mesh);
    const auto truth_dir = out / "ground_truth" / args.sequence / "correspondence";
    std::vector<std::int32_t> faces(face.begin(), face.end());
    core::write_npy(truth_dir / (name + ".face.npy"), faces.data(), {faces.size()});
    core::write_npy_matrix<float>(truth_dir / (name + ".barycentric.npy"), barycentric);
    if (args.studio()) core::write_npy(truth_dir / (name + ".status.npy"), status.data(), {status.size()});
    vertex_counts[static_cast<std::size_t>(k)] = mesh.vertex_count();
    progress.advance();
  });
  progress.finish();

  // Ground truth: the source connectivity is the true template.
  core::AlignedDatabase truth;
  truth.template_mesh = source;
  truth.template_mesh.V = frame_positions(0);
  truth.root_sequence = args.sequence;
  truth.root_frame = 0;
  truth.fps = args.fps;
  core::AlignedSequence sequence;
  sequence.name = args.sequence;
  for (int k = 0; k < count; ++k) {
    const Eigen::MatrixXd world = frame_positions(k);
    const core::RootMotion motion = align::root_motion(truth.template_mesh.V, world);
    sequence.frames.push_back(core::to_centred(world, motion));
    sequence.root_motion.push_back(motion);
  }
  truth.sequences.push_back(std::move(sequence));
  truth.provenance = {{"kind", "ground truth"}, {"tool", "surfcap-remesh"}, {"options", app.provenance_json()}};
  core::write_database(out / "ground_truth" / "database", truth);
  core::Json truth_json = {{"format", core::format_tag("remesh_truth", 1)},
                            {"database", "database/database.json"},
                            {"source", {{"template", args.template_path}, {"positions", args.positions_path},
                                        {"first", args.first}, {"step", args.step}}},
                            {"noise_sigma", args.noise_mm / 1000},
                            {"sequences", {{{"name", args.sequence},
                                            {"correspondence_face", args.sequence + "/correspondence/{frame:06d}.face.npy"},
                                            {"correspondence_barycentric",
                                             args.sequence + "/correspondence/{frame:06d}.barycentric.npy"}}}}};
  if (args.studio()) {
    truth_json["sequences"][0]["correspondence_status"] = args.sequence + "/correspondence/{frame:06d}.status.npy";
    truth_json["surface_tolerance"] = args.visual_hull ? studio_options(args, floor).surface_tolerance : 0.0;
    truth_json["status_codes"] = {{"on_surface", 0}, {"phantom", 1}, {"outlier", 2}, {"blob", 3}, {"rough", 4}};
  }
  core::write_json_file(out / "ground_truth" / "truth.json", truth_json);
  core::Capture capture;
  capture.folder = out;
  capture.name = args.sequence;
  capture.fps = args.fps;
  capture.sequences.push_back({args.sequence, args.sequence + "/mesh/{frame:06d}.ply", "", 0, count});
  // A studio's reconstructions come with the calibration that made them (no images).
  for (const render::Camera& camera : cameras) capture.cameras.push_back(render::to_capture_camera(camera));
  core::write_capture(capture);  // last: its presence means complete
  const auto [low, high] = std::minmax_element(vertex_counts.begin(), vertex_counts.end());
  spdlog::info("{} frames remeshed ({}–{} vertices, source {}) → {}/capture.json", count, *low, *high,
               source.vertex_count(), out.string());
  if (args.studio()) {
    long open = 0, handles = 0, phantom_total = 0;
    for (int k = 0; k < count; ++k) {
      open += holes[static_cast<std::size_t>(k)] > 0;
      handles += genus[static_cast<std::size_t>(k)] != 0;
      phantom_total += phantom[static_cast<std::size_t>(k)];
    }
    spdlog::info("studio artefacts: {} of {} frames open, {} with genus ≠ 0, {} phantom vertices", open, count,
                 handles, phantom_total);
  }
}

}  // namespace

int main(int argc, char** argv) {
  core::ToolApp app("surfcap-remesh",
                    "surfcap-remesh: mesh sequence (one connectivity) → unstructured capture with ground truth");
  Arguments args;
  auto& cli = app.cli();
  cli.add_option("--template", args.template_path, "Mesh with the sequence's connectivity (OBJ/PLY/OFF)")->required();
  cli.add_option("--positions", args.positions_path, "float32 [T, V, 3] vertex positions (.npy)")->required();
  cli.add_option("--out", args.out, "Capture folder to write")->required();
  cli.add_option("--sequence", args.sequence, "Sequence name");
  cli.add_option("--first", args.first, "First source frame");
  cli.add_option("--count", args.count, "Frames to write (-1: all from --first)");
  cli.add_option("--step", args.step, "Source frame step");
  cli.add_option("--edge-scale", args.edge_scale, "Target edge length as a multiple of the source mean edge")
      ->check(CLI::Range(0.2, 10.0));
  cli.add_option("--noise-mm", args.noise_mm, "Noise along the normals (σ, mm)")->check(CLI::Range(0.0, 50.0));
  cli.add_option("--seed", args.seed, "Seed of the remeshing and noise");
  cli.add_option("--fps", args.fps, "Frame rate written into capture.json");
  cli.add_flag("--visual-hull", args.visual_hull, "Reconstruct by shape from silhouette from a ring of cameras");
  cli.add_option("--cameras", args.cameras, "Cameras of the ring (with the studio options)")->check(CLI::Range(2, 64));
  cli.add_option("--voxel-mm", args.voxel_mm, "Visual-hull carving grid spacing, mm")->check(CLI::Range(2.0, 100.0));
  cli.add_option("--floor-cut-mm", args.floor_cut_mm,
                 "Remove the surface up to this height above the sequence's lowest point (open soles)")
      ->check(CLI::Range(0.0, 500.0));
  cli.add_option("--unseen", args.unseen, "Faces seen by fewer than two cameras: keep, remove or rough")
      ->check(CLI::IsMember({"keep", "remove", "rough"}));
  cli.add_option("--outliers", args.outliers, "Share of vertices pushed off the surface")->check(CLI::Range(0.0, 0.2));
  cli.add_option("--blobs", args.blobs, "Mean spurious blobs per frame")->check(CLI::Range(0.0, 20.0));
  return app.run(argc, argv, [&] { run(args, app); });
}
