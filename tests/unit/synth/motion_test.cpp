// The actor, its motions and the garment, against truths that cannot drift.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/synth/capture.hpp"
#include "surfcap/synth/deformation.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

const synth::Actor& tiny_actor() {
  static const synth::Scene scene = synth::preset_scene("tiny");
  static const synth::Actor actor(scene);
  return actor;
}

Eigen::MatrixXd centred(const synth::PerformedFrame& frame) {
  return core::to_centred(frame.V, {frame.pose.root.x(), frame.pose.root.y(), frame.pose.root.z(), frame.pose.heading});
}

TEST(Body, TemplateIsAClosedManifoldSphereOfTheRequestedSize) {
  const auto& body = tiny_actor().body;
  const core::MeshCheck check = core::check_mesh(body.rest);
  EXPECT_TRUE(check.closed() && check.manifold()) << check.summary();
  EXPECT_EQ(check.zero_area_faces, 0);
  EXPECT_EQ(body.rest.vertex_count() - body.rest.face_count() * 3 / 2 + body.rest.face_count(), 2);
  EXPECT_NEAR(body.rest.vertex_count(), 1000, 50);
  EXPECT_GE(body.skeleton.size(), 15);
  const Eigen::VectorXd sums = body.skin_weights.rowwise().sum();
  EXPECT_LT((sums.array() - 1).abs().maxCoeff(), 1e-9);
  EXPECT_GT((body.garment_weight.array() > 0.5).count(), body.rest.vertex_count() / 20);
  // Height and extent of a person.
  EXPECT_NEAR(body.rest.V.col(1).maxCoeff(), 1.75, 0.03);
  EXPECT_NEAR(body.rest.V.col(1).minCoeff(), 0.0, 0.03);
}

// CGAL's surface mesher orders its refinement by handle; without time stamps a handle compares
// by address, so the mesh depended on the heap's state (and differed under ASan). Mesh twice with
// the heap in other states in between: the meshes must be identical, bit for bit.
TEST(Body, MeshingDoesNotDependOnTheHeap) {
  const synth::Skeleton skeleton = synth::make_skeleton(1.75);
  const synth::BodyField field(skeleton, synth::SkirtShape{});
  const core::Mesh first = synth::mesh_implicit_surface(field, 400, 1);
  std::vector<std::unique_ptr<char[]>> clutter;  // shifts where the next blocks are allocated
  for (int i = 0; i < 64; ++i) clutter.emplace_back(new char[static_cast<std::size_t>(4096 + 977 * i)]);
  for (std::size_t i = 0; i < clutter.size(); i += 2) clutter[i].reset();
  const core::Mesh second = synth::mesh_implicit_surface(field, 400, 1);
  ASSERT_EQ(first.vertex_count(), second.vertex_count());
  ASSERT_EQ(first.face_count(), second.face_count());
  EXPECT_TRUE(first.V == second.V);
  EXPECT_TRUE(first.F == second.F);
  const core::Mesh other_seed = synth::mesh_implicit_surface(field, 400, 2);
  EXPECT_FALSE(other_seed.V.rows() == first.V.rows() && other_seed.V == first.V) << "the seed is ignored";
}

TEST(Motion, CyclicMotionsAreCyclic) {
  const auto& actor = tiny_actor();
  const synth::Scene scene = synth::preset_scene("tiny");
  int cyclic = 0;
  for (const auto& motion : scene.sequences) {
    if (!motion.cyclic()) continue;  // the jumps
    ++cyclic;
    const Eigen::MatrixXd first = centred(actor.perform(scene, motion, 0));
    const Eigen::MatrixXd wrapped = centred(actor.perform(scene, motion, motion.frames));
    const Eigen::MatrixXd middle = centred(actor.perform(scene, motion, motion.frames / 2));
    EXPECT_LT((first - wrapped).rowwise().norm().maxCoeff(), 1e-6) << motion.name;
    EXPECT_GT((first - middle).rowwise().norm().maxCoeff(), 0.05) << motion.name << " does not move";
  }
  EXPECT_EQ(cyclic, 2);  // walk and run
}

TEST(Motion, FamiliesRealiseTheirParameter) {
  const synth::Scene scene = synth::preset_scene("full");
  const auto skeleton = synth::make_skeleton();
  auto motion = [&](const std::string& name) {
    for (const auto& m : scene.sequences)
      if (m.name == name) return m;
    throw std::runtime_error("no " + name);
  };
  auto apex = [&](const synth::MotionSpec& m) {
    double top = -1e9;
    for (int t = 0; t < m.frames; ++t) top = std::max(top, synth::root_at(skeleton, m, scene.fps, t / scene.fps).position.y());
    return top - synth::root_at(skeleton, m, scene.fps, 0).position.y();
  };
  EXPECT_NEAR(apex(motion("jump_low")), 0.15, 0.03);
  EXPECT_NEAR(apex(motion("jump_high")), 0.45, 0.03);
  auto travel = [&](const synth::MotionSpec& m) {
    return (synth::root_at(skeleton, m, scene.fps, m.duration(scene.fps)).position -
            synth::root_at(skeleton, m, scene.fps, 0).position).norm();
  };
  EXPECT_NEAR(travel(motion("jump_short")), 0.2, 0.02);
  EXPECT_NEAR(travel(motion("jump_long")), 1.0, 0.02);
  auto hand = [&](const synth::MotionSpec& m) {
    double top = -1e9;
    for (int t = 0; t < m.frames; ++t)
      top = std::max(top, synth::forward_kinematics(skeleton, synth::pose_at(skeleton, m, scene.fps, t / scene.fps)).position[synth::wrist_r].y());
    return top;
  };
  EXPECT_NEAR(hand(motion("reach_low")), 0.85, 0.15);
  EXPECT_NEAR(hand(motion("reach_high")), 1.85, 0.15);
  auto heading_change = [&](const synth::MotionSpec& m) {
    return synth::root_at(skeleton, m, scene.fps, m.duration(scene.fps)).heading - synth::root_at(skeleton, m, scene.fps, 0).heading;
  };
  EXPECT_GT(heading_change(motion("walk_left")), 0.5);
  EXPECT_LT(heading_change(motion("walk_right")), -0.5);
}

TEST(Garment, SkirtLagsAndTrailsWithSpeed) {
  const synth::Scene scene = synth::preset_scene("tiny");
  const auto skeleton = synth::make_skeleton();
  double walk = 0, run = 0;
  for (int t = 0; t < 20; ++t) {
    walk += synth::garment_at(skeleton, scene.sequences[0], scene.fps, t / scene.fps).swing_back / 20;
    run += synth::garment_at(skeleton, scene.sequences[1], scene.fps, t / scene.fps).swing_back / 20;
  }
  EXPECT_GT(walk, 0.05);      // trails behind when moving forward
  EXPECT_GT(run, 2 * walk);   // more at speed
  // A jump: still before take-off, flared in flight.
  const synth::MotionSpec jump = synth::preset_scene("demo").sequences[3];
  EXPECT_NEAR(synth::garment_at(skeleton, jump, scene.fps, 0.0).flare, 0.0, 1e-6);
  EXPECT_GT(synth::garment_at(skeleton, jump, scene.fps, 0.5 * jump.duration(scene.fps) + 0.2).flare, 0.1);
}

// The ground truth must stay a surface something could follow. At the synth's largest flare the
// skirt's underside (the cap of the solid cone between the hem and the thighs) used to tear
// between the legs, where the outward direction turns round the skirt's axis, and at the step of
// the garment weight from skirt to trousers: at rest pose tiny's worst face grew 12.3× (7.0× with
// the membrane fraction alone; demo's jump_low:29 183×). Now it opens like a membrane: 4.3×. A few
// pairs at the hem's rounded rim still fold (5 on tiny, as before): reported, not bounded.
TEST(Garment, FullyFlaredSkirtStretchesWithoutTearing) {
  const auto& actor = tiny_actor();
  const auto& body = actor.body;
  synth::GarmentState flared;
  flared.flare = 0.45;  // garment_at's clamp
  const Eigen::MatrixXd V = synth::deform_body(body, actor.rest_normals, synth::Pose(), flared);
  const Eigen::MatrixXi& F = body.rest.F;
  auto normals = [&](const Eigen::MatrixXd& X) {
    Eigen::MatrixXd N(F.rows(), 3);
    for (long f = 0; f < F.rows(); ++f) {
      const Eigen::Vector3d a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
      N.row(f) = (b - a).cross(c - a).normalized().transpose();
    }
    return N;
  };
  const Eigen::MatrixXd N0 = normals(body.rest.V), N = normals(V);
  const double stretch = (core::face_areas(V, F).array() / core::face_areas(body.rest.V, F).array()).maxCoeff();
  std::map<std::pair<int, int>, long> first_face;
  long folded = 0;
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto edge = std::minmax(F(f, k), F(f, (k + 1) % 3));
      const auto [it, inserted] = first_face.emplace(edge, f);
      if (inserted) continue;
      const long g = it->second;
      if (N0.row(f).dot(N0.row(g)) > 0.5 && N.row(f).dot(N.row(g)) < 0) ++folded;
    }
  RecordProperty("max_face_stretch", std::to_string(stretch));
  RecordProperty("folded_pairs", std::to_string(folded));
  std::printf("fully flared skirt: worst face area x %.1f, folded adjacent pairs %ld\n", stretch, folded);
  EXPECT_LT(stretch, 6.0);
}

// The blending issue relies on this: halfway between walk and run, averaging vertex positions
// misplaces the swinging skirt far more than the rigidly carried head.
TEST(Garment, LinearBlendOfWalkAndRunIsWrongNearTheGarment) {
  const auto& actor = tiny_actor();
  synth::Scene scene = synth::preset_scene("tiny");
  const synth::MotionSpec walk = scene.sequences[0], run = scene.sequences[1];
  synth::MotionSpec middle = walk;
  middle.speed = 0.5 * (walk.speed + run.speed);
  middle.frames = 22;  // period halfway between walk (24) and run (20)
  double garment_error = 0, head_error = 0;
  long garment_count = 0, head_count = 0;
  const auto& body = actor.body;
  for (int k = 0; k < 4; ++k) {
    const double phase = k / 4.0;
    auto at_phase = [&](const synth::MotionSpec& m) {
      synth::PerformedFrame f;
      const double time = phase * m.frames / scene.fps;
      f.pose = synth::pose_at(body.skeleton, m, scene.fps, time);
      f.garment = synth::garment_at(body.skeleton, m, scene.fps, time);
      f.V = synth::deform_body(body, actor.rest_normals, f.pose, f.garment);
      return centred(f);
    };
    const Eigen::MatrixXd blend = 0.5 * (at_phase(walk) + at_phase(run));
    const Eigen::VectorXd error = (blend - at_phase(middle)).rowwise().norm();
    for (long v = 0; v < error.size(); ++v) {
      if (body.garment_weight[v] > 0.9 && body.garment_depth[v] > 0.7) {
        garment_error = std::max(garment_error, error[v]);
        ++garment_count;
      }
      if (body.skin_weights(v, synth::head) > 0.9) {
        head_error = std::max(head_error, error[v]);
        ++head_count;
      }
    }
  }
  ASSERT_GT(garment_count, 0);
  ASSERT_GT(head_count, 0);
  RecordProperty("garment_error_mm", std::to_string(1000 * garment_error));
  RecordProperty("head_error_mm", std::to_string(1000 * head_error));
  std::printf("linear blend walk/run vs true middle: garment max %.1f mm, head max %.1f mm\n", 1000 * garment_error,
              1000 * head_error);
  EXPECT_GT(garment_error, 0.010);
  EXPECT_GT(garment_error, 2 * head_error);
}

TEST(Scene, ConfigFilesAreThePresets) {
  for (const auto& name : synth::preset_names()) {
    const auto path = std::filesystem::path(SURFCAP_SOURCE_DIR) / "configs/synth" / (name + ".json");
    const synth::Scene from_file = synth::read_scene(path);
    EXPECT_EQ(synth::scene_to_json(from_file), synth::scene_to_json(synth::preset_scene(name))) << path;
  }
}

TEST(Scene, LongPresetHoldsTwoThousandFramesOfVariedTakes) {
  const synth::Scene scene = synth::preset_scene("long");
  EXPECT_NO_THROW(scene.validate());
  EXPECT_GE(scene.total_frames(), 2000);
  EXPECT_GE(scene.sequences.size(), 20u);
  EXPECT_FALSE(scene.images);
  EXPECT_EQ(scene.body.target_vertices, 8000);
  EXPECT_FALSE(scene.reconstruction.studio());
  // Each family performed at many settings of its parameters, turning both ways.
  std::map<synth::MotionFamily, std::set<double>> settings;
  std::set<double> turns;
  for (const auto& m : scene.sequences) {
    EXPECT_GE(m.frames, 32) << m.name;
    if (m.family == synth::MotionFamily::gait) settings[m.family].insert(m.speed), turns.insert(m.turn_rate);
    if (m.family == synth::MotionFamily::jump) settings[m.family].insert(100 * m.jump_height + m.jump_distance);
    if (m.family == synth::MotionFamily::reach) settings[m.family].insert(m.reach_height);
  }
  EXPECT_GE(settings[synth::MotionFamily::gait].size(), 6u);
  EXPECT_GE(settings[synth::MotionFamily::jump].size(), 6u);
  EXPECT_GE(settings[synth::MotionFamily::reach].size(), 6u);
  EXPECT_LT(*turns.begin(), 0);
  EXPECT_GT(*turns.rbegin(), 0);
}

TEST(Scene, ACutCountsTheFirstFramesOfEachSequence) {
  synth::Scene scene = synth::preset_scene("long");
  const long whole = scene.total_frames();
  scene.frames_per_sequence = 18;
  EXPECT_EQ(scene.total_frames(), 18 * static_cast<long>(scene.sequences.size()));
  scene.frames_per_sequence = 100;
  long expected = 0;
  for (const auto& m : scene.sequences) {
    EXPECT_EQ(scene.written_frames(m), std::min(m.frames, 100)) << m.name;
    expected += std::min(m.frames, 100);
  }
  EXPECT_EQ(scene.total_frames(), expected);
  EXPECT_LT(expected, whole);
  // The cut travels with the scene file; a scene without one writes no such field.
  const core::Json document = synth::scene_to_json(scene);
  EXPECT_EQ(document.at("frames_per_sequence"), 100);
  EXPECT_EQ(synth::scene_from_json(document, "scene.json").total_frames(), expected);
  EXPECT_FALSE(synth::scene_to_json(synth::preset_scene("long")).contains("frames_per_sequence"));
  for (const int bad : {-1, 1}) {
    scene.frames_per_sequence = bad;
    try {
      scene.validate();
      ADD_FAILURE() << bad;
    } catch (const core::Error& e) {
      EXPECT_EQ(e.code(), core::ExitCode::bad_arguments) << e.what();
    }
  }
}

TEST(Scene, BadScenesAreRejectedWithExitCode2) {
  auto expect_bad = [](const core::Json& document) {
    try {
      synth::scene_from_json(document, "scene.json");
      ADD_FAILURE() << document.dump();
    } catch (const core::Error& e) {
      EXPECT_EQ(e.code(), core::ExitCode::bad_arguments) << e.what();
    }
  };
  core::Json scene = synth::scene_to_json(synth::preset_scene("tiny"));
  EXPECT_NO_THROW(synth::scene_from_json(scene, "scene.json"));
  core::Json duplicate = scene;
  duplicate["sequences"][1]["name"] = "walk";
  expect_bad(duplicate);
  core::Json no_frames = scene;
  no_frames["sequences"][0]["frames"] = 1;
  expect_bad(no_frames);
  core::Json family = scene;
  family["sequences"][0]["family"] = "cartwheel";
  expect_bad(family);
  core::Json cameras = scene;
  cameras["studio"]["cameras"] = 0;
  expect_bad(cameras);
  core::Json format = scene;
  format["format"] = "surfcap.synth_scene/9";
  expect_bad(format);
}

}  // namespace
}  // namespace surfcap
