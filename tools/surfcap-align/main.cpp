// surfcap-align: capture folder → aligned database (docs/align.md). Each command is one library
// stage (similarity/similarity_stages.hpp, evaluation/register_stage.hpp); `run` chains them.
#include <cstdio>

#include "surfcap/align/image_features.hpp"
#include "surfcap/core/cli.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/evaluation/register_stage.hpp"
#include "surfcap/similarity/similarity_stages.hpp"
#include "import_command.hpp"

namespace {

using namespace surfcap;

/// --root and --root-candidates (the tree's root frame), shared by "tree" and "run".
void add_root_options(CLI::App* command, similarity::SimilarityStageOptions& options) {
  command->add_option("--root", options.root,
                      "Root frame as <sequence>:<frame> (default: minimal weighted depth among the widest-stance frames)");
  command->add_option("--root-candidates", options.root_candidates,
                      "Automatic root: among this fraction of the frames with the widest stance (1: every frame)")
      ->check(CLI::PositiveNumber & CLI::Range(0.0, 1.0));
}

/// The alignment options (their tables) and the report options of "register" and "run".
void add_register_options(CLI::App* command, evaluation::RegisterStageOptions& options) {
  core::add_options(command, options.alignment);
  core::add_options(command, options.report);
}

/// --trunk, --shard k/K or --merge K as a job; bad_arguments (2) for a malformed k/K.
evaluation::RegisterJob register_job(bool trunk, const std::string& shard, int merge) {
  using Kind = evaluation::RegisterJob::Kind;
  if (trunk) return {Kind::trunk, 0, 0};
  if (merge > 0) return {Kind::merge, 0, merge};
  if (shard.empty()) return {};
  int k = 0, count = 0;
  char tail = 0;
  if (std::sscanf(shard.c_str(), "%d/%d%c", &k, &count, &tail) != 2 || count < 1 || k < 1 || k > count)
    throw core::bad_arguments("--shard " + shard + ": expected k/K with 1 <= k <= K, e.g. 2/4");
  return {Kind::shard, k, count};
}

}  // namespace

int main(int argc, char** argv) {
  // The alignment allocates and frees image-sized buffers (renderings, flow fields, pyramids) many
  // times per frame.
  core::retain_freed_memory();
  align::serial_image_processing();
  core::ToolApp app("surfcap-align", "surfcap-align: capture folder → aligned database (shape similarity tree, "
                                     "non-rigid alignment)");
  std::string capture, out;
  similarity::SimilarityStageOptions similarity;
  evaluation::RegisterStageOptions registration;
  auto& cli = app.cli();
  cli.require_subcommand(1);

  auto* histograms = cli.add_subcommand("histograms", "Volumetric shape histogram of every captured frame");
  histograms->add_option("--capture", capture, "Capture folder (or its capture.json)")->required();
  histograms->add_option("--out", out, "Database folder to write into")->required();
  histograms->add_option("--voxel-size", similarity.histogram.voxel_size, "Volume sampling grid spacing (m)");
  histograms->add_option("--max-radius", similarity.histogram.max_radius, "Outer radius of the last shell (m)");
  histograms->add_option("--shells", similarity.histogram.shells, "Radial shells");
  histograms->add_option("--elevation-bins", similarity.histogram.elevation_bins, "Elevation sectors");
  histograms->add_option("--azimuth-order", similarity.histogram.azimuth_order, "Highest azimuth harmonic");

  auto* similarity_cmd = cli.add_subcommand("similarity", "Temporally filtered similarity matrix (or one row block)");
  similarity_cmd->add_option("--out", out, "Database folder holding similarity/histograms.npy")->required();
  similarity_cmd->add_option("--rows", similarity.rows, "Compute only rows a:b into similarity/rows/ (for farms)");
  similarity_cmd->add_option("--window", similarity.similarity.temporal_window, "Temporal filter half-width k (frames)")
      ->check(CLI::Range(0, 50));
  similarity_cmd->add_option("--search", similarity.search, "Rotation search: fft or exhaustive")
      ->check(CLI::IsMember({"fft", "exhaustive"}));

  auto* merge = cli.add_subcommand("merge", "Join similarity/rows/*.npy into similarity/matrix.npy");
  merge->add_option("--out", out, "Database folder")->required();

  auto* tree = cli.add_subcommand("tree", "Shape similarity tree (pruned minimum spanning tree)");
  tree->add_option("--out", out, "Database folder holding similarity/matrix.npy")->required();
  add_root_options(tree, similarity);
  tree->add_option("--ground-truth", similarity.ground_truth,
                   "Ground-truth aligned database.json: report the tree's quality ratio");

  auto* register_cmd = cli.add_subcommand("register", "Non-rigid alignment along similarity/tree.json → database.json");
  register_cmd->add_option("--out", out, "Database folder holding similarity/ (written into)")->required();
  register_cmd->add_option("--capture", registration.capture, "Capture folder (default: the one histograms.json names)");
  add_register_options(register_cmd, registration);
  // Registration jobs (docs/pipelines.md "Registration jobs"): none of them changes an output.
  bool trunk_job = false;
  std::string shard_job;
  int merge_shards = 0;
  auto* trunk_option = register_cmd->add_flag(
      "--trunk", trunk_job, "Registration job: align the tree's trunk only, into DB/register/trunk.{json,npy}");
  auto* shard_option = register_cmd->add_option(
      "--shard", shard_job, "Registration job k/K (after --trunk): align the units of shard k of K into "
                            "DB/register/shard-k-of-K.{json,npy}");
  auto* merge_option = register_cmd->add_option(
      "--merge", merge_shards, "Join DB/register/trunk and shards 1..K into what the single job writes")
      ->check(CLI::Range(1, 100000));
  trunk_option->excludes(shard_option)->excludes(merge_option);
  shard_option->excludes(merge_option);

  auto* run = cli.add_subcommand("run", "histograms → similarity → tree → register in one go");
  run->add_option("--capture", capture, "Capture folder (or its capture.json)")->required();
  run->add_option("--out", out, "Database folder to write")->required();
  add_root_options(run, similarity);
  run->add_option("--voxel-size", similarity.histogram.voxel_size, "Volume sampling grid spacing (m)");
  run->add_option("--window", similarity.similarity.temporal_window, "Temporal filter half-width k (frames)")
      ->check(CLI::Range(0, 50));
  add_register_options(run, registration);

  const tools::ImportCommands imports(app);  // import-cameras, import-capture

  return app.run(argc, argv, [&] {
    similarity.threads = registration.alignment.threads = app.common().threads;
    similarity.options_json = registration.options_json = app.options_json();
    registration.provenance_json = app.provenance_json();
    if (registration.provenance_json.contains("register"))
      for (const char* job_option : {"trunk", "shard", "merge"}) registration.provenance_json["register"].erase(job_option);
    registration.job = register_job(trunk_job, shard_job, merge_shards);
    if (*histograms) similarity::run_histograms_stage(capture, out, similarity);
    if (*similarity_cmd) similarity::run_similarity_stage(out, similarity);
    if (*merge) similarity::run_merge_stage(out);
    if (*tree) similarity::run_tree_stage(out, similarity);
    if (*register_cmd) evaluation::run_register_stage(out, registration);
    if (*run) {
      registration.capture = capture;
      registration.stage = "align.run";
      similarity::run_similarity_chain(capture, out, similarity);
      evaluation::run_register_stage(out, registration);
    }
    imports.run();
  });
}
