// The tiny synthetic capture, generated once, checked against its own ground truth.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "surfcap/core/database.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/render/png.hpp"
#include "surfcap/synth/capture.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

namespace fs = std::filesystem;

std::string frame_file(int frame) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d", frame);
  return name;
}

// One capture per process (ctest runs each test in its own process): every check is a step of
// one test so the tiny preset is generated once for them all.
testing::TemporaryDirectory* directory_ = nullptr;
synth::Scene* scene_ = nullptr;
core::AlignedDatabase* database_ = nullptr;

fs::path capture() { return directory_->path() / "a"; }
/// World positions of the template in frame t of sequence s, from the ground-truth database.
Eigen::MatrixXd truth(int s, int t) {
  const auto& sequence = database_->sequences[static_cast<std::size_t>(s)];
  return core::to_world(sequence.frames[static_cast<std::size_t>(t)], sequence.root_motion[static_cast<std::size_t>(t)]);
}

void CaptureJsonDescribesEveryFile() {
  const auto capture_json = core::read_json_document(capture() / "capture.json", "capture", 1);
  EXPECT_EQ(capture_json["units"], "m");
  ASSERT_EQ(capture_json["sequences"].size(), scene_->sequences.size());
  const auto cameras = render::read_cameras(capture() / "cameras.json");
  EXPECT_EQ(static_cast<int>(cameras.size()), scene_->studio.cameras);
  for (const auto& entry : capture_json["sequences"]) {
    const std::string name = entry["name"];
    const int count = entry["count"];
    for (int t = 0; t < count; ++t) {
      EXPECT_TRUE(fs::exists(capture() / name / "mesh" / (frame_file(t) + ".ply"))) << name << " " << t;
      for (const auto& camera : cameras)
        EXPECT_TRUE(fs::exists(capture() / name / "images" / camera.name / (frame_file(t) + ".png")));
    }
    EXPECT_FALSE(fs::exists(capture() / name / "mesh" / (frame_file(count) + ".ply")));
  }
  EXPECT_EQ(testing::count_hidden_files(capture()), 0);
}

void EveryReconstructionIsAClosedManifoldSphereWithItsOwnConnectivity() {
  std::set<long> vertex_counts;
  for (std::size_t s = 0; s < scene_->sequences.size(); ++s)
    for (int t = 0; t < scene_->sequences[s].frames; ++t) {
      const auto path = capture() / scene_->sequences[s].name / "mesh" / (frame_file(t) + ".ply");
      const core::Mesh mesh = core::read_mesh(path);
      const core::MeshCheck check = core::check_mesh(mesh);
      EXPECT_TRUE(check.closed() && check.manifold()) << path << ": " << check.summary();
      EXPECT_EQ(check.unreferenced_vertices, 0) << path;
      EXPECT_EQ(mesh.vertex_count() - mesh.face_count() * 3 / 2 + mesh.face_count(), 2) << path << " is not genus 0";
      EXPECT_TRUE(mesh.has_colors()) << path;
      vertex_counts.insert(mesh.vertex_count());
      EXPECT_NE(mesh.vertex_count(), database_->template_mesh.vertex_count());
    }
  // Independent remeshing: the vertex count itself differs between most frames.
  EXPECT_GT(vertex_counts.size(), static_cast<std::size_t>(scene_->total_frames() / 2));
}

void GroundTruthPutsEveryVertexWithinNoiseOfItsTrueSurfacePoint() {
  const double sigma = scene_->reconstruction.noise_sigma;
  double sum_squares = 0;
  long count = 0;
  for (std::size_t s = 0; s < scene_->sequences.size(); ++s)
    for (int t = 0; t < scene_->sequences[s].frames; t += 3) {
      const std::string name = scene_->sequences[s].name;
      const core::Mesh mesh = core::read_mesh(capture() / name / "mesh" / (frame_file(t) + ".ply"));
      const auto truth_dir = capture() / "ground_truth" / name / "correspondence";
      const auto faces = core::read_npy(truth_dir / (frame_file(t) + ".face.npy"), core::DType::int32, {mesh.vertex_count()});
      const Eigen::MatrixXd barycentric = core::read_npy_matrix(truth_dir / (frame_file(t) + ".barycentric.npy"), mesh.vertex_count(), 3);
      const std::vector<int> face(faces.data<std::int32_t>(), faces.data<std::int32_t>() + faces.size());
      const Eigen::MatrixXd points = synth::surface_points(truth(static_cast<int>(s), t), database_->template_mesh.F, face, barycentric);
      const Eigen::VectorXd distance = (mesh.V - points).rowwise().norm();
      EXPECT_LT(distance.maxCoeff(), 5 * sigma + 1e-4) << name << " frame " << t;
      EXPECT_TRUE(((barycentric.array() >= 0) && (barycentric.array() <= 1)).all());
      sum_squares += distance.squaredNorm();
      count += distance.size();
    }
  // The noise is N(0, σ) along the normal: the RMS offset is σ.
  EXPECT_NEAR(std::sqrt(sum_squares / count), sigma, 0.15 * sigma);
}

void ImagesShowTheTexturedSurfaceWhereTheCalibrationProjectsIt() {
  const auto cameras = render::read_cameras(capture() / "cameras.json");
  const synth::Actor actor(*scene_);
  const Eigen::MatrixXd albedo = synth::vertex_albedo(actor.body, actor.texture);
  auto agreement = [&](int s, int t, const render::Camera& camera, const render::Image& image) {
    core::Mesh truth_mesh;
    truth_mesh.V = truth(s, t);
    truth_mesh.F = database_->template_mesh.F;
    const auto visible = render::render_mesh(truth_mesh, camera, actor.render_options());
    const Eigen::MatrixXd normals = core::vertex_normals(truth_mesh.V, truth_mesh.F);
    long checked = 0, agreeing = 0;
    for (long v = 0; v < truth_mesh.vertex_count(); ++v) {
      const Eigen::Vector3d X = truth_mesh.V.row(v).transpose();
      const Eigen::Vector2d p = camera.project(X);
      const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
      if (x < 0 || y < 0 || x >= camera.width || y >= camera.height) continue;
      const double depth = camera.to_camera(X).z();
      if (std::abs(visible.depth[static_cast<std::size_t>(y) * camera.width + x] - depth) > 0.004) continue;  // occluded
      ++checked;
      const Eigen::Vector3d expected = visible.shade(albedo.row(v).transpose(), normals.row(v).transpose(), camera);
      agreeing += (image.get(x, y) - expected).cwiseAbs().maxCoeff() < 0.1;
    }
    return std::pair<long, double>(checked, checked ? static_cast<double>(agreeing) / checked : 0.0);
  };
  for (int s = 0; s < 2; ++s)
    for (const auto& camera : cameras) {
      const int t = 5;
      const auto image = render::read_png(capture() / scene_->sequences[static_cast<std::size_t>(s)].name / "images" /
                                          camera.name / (frame_file(t) + ".png"));
      const auto [checked, fraction] = agreement(s, t, camera, image);
      EXPECT_GT(checked, 100) << camera.name;
      EXPECT_GT(fraction, 0.85) << camera.name << ": " << checked << " visible vertices checked";
      // A camera 3 cm off its calibration sees other texture at the projected points.
      render::Camera moved = camera;
      moved.t += Eigen::Vector3d(0.03, 0.0, 0.0);
      EXPECT_LT(agreement(s, t, moved, image).second, fraction - 0.2) << camera.name;
    }
}

void GroundTruthDatabaseMatchesTheActor() {
  const synth::Actor actor(*scene_);
  EXPECT_EQ(database_->template_mesh.vertex_count(), actor.body.rest.vertex_count());
  EXPECT_TRUE(database_->template_mesh.has_colors());
  ASSERT_EQ(database_->sequences.size(), scene_->sequences.size());
  const auto& walk = scene_->sequences[0];
  for (int t : {0, 7}) {
    const auto performed = actor.perform(*scene_, walk, t);
    EXPECT_LT((truth(0, t) - performed.V).cwiseAbs().maxCoeff(), 1e-5);  // float32 storage
  }
  const auto truth_json = core::read_json_document(capture() / "ground_truth/truth.json", "synth_truth", 1);
  EXPECT_GE(truth_json["skeleton"].size(), 15u);
  EXPECT_NEAR(truth_json["sequences"][0]["measured"]["speed"].get<double>(), 1.3, 0.05);
  EXPECT_NEAR(truth_json["sequences"][1]["measured"]["speed"].get<double>(), 3.0, 0.1);
  EXPECT_TRUE(fs::exists(capture() / "ground_truth/contact_sheet.png"));
}

TEST(SynthCapture, TinyPresetMatchesItsGroundTruth) {
  testing::TemporaryDirectory directory("synth-capture");
  synth::Scene scene = synth::preset_scene("tiny");
  core::StageReport report("synth");
  synth::generate_capture(scene, directory / "a", 2, report);
  core::AlignedDatabase database = core::read_database(directory / "a/ground_truth/database/database.json");
  directory_ = &directory;
  scene_ = &scene;
  database_ = &database;
  {
    SCOPED_TRACE("CaptureJsonDescribesEveryFile");
    CaptureJsonDescribesEveryFile();
  }
  {
    SCOPED_TRACE("EveryReconstructionIsAClosedManifoldSphereWithItsOwnConnectivity");
    EveryReconstructionIsAClosedManifoldSphereWithItsOwnConnectivity();
  }
  {
    SCOPED_TRACE("GroundTruthPutsEveryVertexWithinNoiseOfItsTrueSurfacePoint");
    GroundTruthPutsEveryVertexWithinNoiseOfItsTrueSurfacePoint();
  }
  {
    SCOPED_TRACE("ImagesShowTheTexturedSurfaceWhereTheCalibrationProjectsIt");
    ImagesShowTheTexturedSurfaceWhereTheCalibrationProjectsIt();
  }
  {
    SCOPED_TRACE("GroundTruthDatabaseMatchesTheActor");
    GroundTruthDatabaseMatchesTheActor();
  }
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

TEST(SynthCapture, SameSeedGivesByteIdenticalOutputOnAnyThreadCount) {
  testing::TemporaryDirectory directory("synth-determinism");
  synth::Scene scene = synth::preset_scene("tiny");
  scene.images = false;  // tests/e2e/synth_tiny.sh compares the images across processes
  core::StageReport first("synth");
  synth::generate_capture(scene, directory / "a", 2, first);
  core::StageReport second("synth");
  synth::generate_capture(scene, directory / "b", 1, second);
  long compared = 0;
  for (const auto& entry : fs::recursive_directory_iterator(directory / "a")) {
    if (!entry.is_regular_file()) continue;
    const auto relative = fs::relative(entry.path(), directory / "a");
    const auto other = directory / "b" / relative;
    ASSERT_TRUE(fs::exists(other)) << relative;
    EXPECT_EQ(file_bytes(entry.path()), file_bytes(other)) << relative;
    ++compared;
  }
  EXPECT_GT(compared, scene.total_frames() * 3);
}

TEST(SynthCapture, ACutWritesTheWholeCapturesFirstFramesByteForByte) {
  testing::TemporaryDirectory directory("synth-cut");
  synth::Scene scene = synth::preset_scene("tiny");
  scene.images = false;
  scene.sequences = {scene.sequences[0], scene.sequences[3]};  // walk, jump_high
  scene.sequences[0].frames = 10;
  scene.sequences[1].frames = 12;
  core::StageReport whole_report("synth");
  synth::generate_capture(scene, directory / "whole", 2, whole_report);
  synth::Scene cut = scene;
  cut.frames_per_sequence = 4;
  core::StageReport cut_report("synth");
  synth::generate_capture(cut, directory / "cut", 2, cut_report);

  const auto capture_json = core::read_json_document(directory / "cut/capture.json", "capture", 1);
  ASSERT_EQ(capture_json["sequences"].size(), 2u);
  const core::AlignedDatabase whole_truth = core::read_database(directory / "whole/ground_truth/database/database.json");
  const core::AlignedDatabase cut_truth = core::read_database(directory / "cut/ground_truth/database/database.json");
  for (std::size_t s = 0; s < 2; ++s) {
    const std::string name = scene.sequences[s].name;
    EXPECT_EQ(capture_json["sequences"][s]["count"], 4);
    for (int t = 0; t < 4; ++t) {
      for (const std::string file : {name + "/mesh/" + frame_file(t) + ".ply",
                                     "ground_truth/" + name + "/correspondence/" + frame_file(t) + ".face.npy",
                                     "ground_truth/" + name + "/correspondence/" + frame_file(t) + ".barycentric.npy"})
        EXPECT_EQ(file_bytes(directory / "cut" / file), file_bytes(directory / "whole" / file)) << file;
      EXPECT_TRUE(cut_truth.sequences[s].frames[static_cast<std::size_t>(t)] ==
                  whole_truth.sequences[s].frames[static_cast<std::size_t>(t)]);
      EXPECT_EQ(cut_truth.sequences[s].root_motion[static_cast<std::size_t>(t)].heading,
                whole_truth.sequences[s].root_motion[static_cast<std::size_t>(t)].heading);
    }
    EXPECT_EQ(cut_truth.sequences[s].frame_count(), 4);
    EXPECT_TRUE(fs::exists(directory / "whole" / name / "mesh" / (frame_file(4) + ".ply")));
    EXPECT_FALSE(fs::exists(directory / "cut" / name / "mesh" / (frame_file(4) + ".ply")));
  }
  EXPECT_EQ(cut_report.to_json()["frames"], 8);
}

}  // namespace
}  // namespace surfcap
