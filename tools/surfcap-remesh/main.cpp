// surfcap-remesh: a mesh sequence with one connectivity (template + positions.npy) → an
// unstructured capture folder (every frame remeshed independently, noise along the normals) with
// ground truth in the layout of docs/synth.md (database + per-vertex correspondence), so that
// surfcap-align register can be checked on real motion (docs/align.md, scripts/make_dance_capture.sh).
#include <spdlog/spdlog.h>

#include "surfcap/align/remesh.hpp"
#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/core/cli.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/parallel.hpp"
#include "surfcap/core/progress.hpp"

namespace {

using namespace surfcap;

struct Arguments {
  std::string template_path, positions_path, out;
  std::string sequence = "dance";
  int first = 0, count = -1, step = 1;
  double edge_scale = 1.0, noise_mm = 1.0, fps = 25;
  std::uint64_t seed = 1;
};

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
  const double edge = align::mean_edge(source) * args.edge_scale;
  core::ProgressReporter progress("remesh", static_cast<std::size_t>(count));
  std::vector<long> vertex_counts(static_cast<std::size_t>(count));
  core::parallel_for(count, app.common().threads, [&](long k) {
    core::Mesh frame = source;
    frame.V = frame_positions(static_cast<int>(k));
    align::RemeshOptions options;
    options.edge = edge;
    options.noise_sigma = args.noise_mm / 1000;
    options.seed = args.seed * 1000003ULL + static_cast<std::uint64_t>(k);
    const align::RemeshResult result = align::remesh(frame, options);
    const std::string name = frame_name(static_cast<int>(k));
    core::write_mesh(out / args.sequence / "mesh" / (name + ".ply"), result.mesh);
    const auto truth_dir = out / "ground_truth" / args.sequence / "correspondence";
    std::vector<std::int32_t> faces(result.face.begin(), result.face.end());
    core::write_npy(truth_dir / (name + ".face.npy"), faces.data(), {faces.size()});
    core::write_npy_matrix<float>(truth_dir / (name + ".barycentric.npy"), result.barycentric);
    vertex_counts[static_cast<std::size_t>(k)] = result.mesh.vertex_count();
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
  truth.provenance = {{"kind", "ground truth"}, {"tool", "surfcap-remesh"}, {"options", app.provenance_options()}};
  core::write_database(out / "ground_truth" / "database", truth);
  core::write_json_file(out / "ground_truth" / "truth.json",
                        {{"format", core::format_tag("remesh_truth", 1)},
                         {"database", "database/database.json"},
                         {"source", {{"template", args.template_path}, {"positions", args.positions_path},
                                     {"first", args.first}, {"step", args.step}}},
                         {"noise_sigma", args.noise_mm / 1000},
                         {"sequences", {{{"name", args.sequence},
                                         {"correspondence_face", args.sequence + "/correspondence/{frame:06d}.face.npy"},
                                         {"correspondence_barycentric",
                                          args.sequence + "/correspondence/{frame:06d}.barycentric.npy"}}}}});
  core::Capture capture;
  capture.folder = out;
  capture.name = args.sequence;
  capture.fps = args.fps;
  capture.sequences.push_back({args.sequence, args.sequence + "/mesh/{frame:06d}.ply", "", 0, count});
  core::write_capture(capture);  // last: its presence means complete
  const auto [low, high] = std::minmax_element(vertex_counts.begin(), vertex_counts.end());
  spdlog::info("{} frames remeshed ({}–{} vertices, source {}) → {}/capture.json", count, *low, *high,
               source.vertex_count(), out.string());
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
  return app.run(argc, argv, [&] { run(args, app); });
}
