#include "surfcap/synth/capture.hpp"

#include "surfcap/synth/capture.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/parallel.hpp"
#include "surfcap/core/version.hpp"
#include "surfcap/render/contact_sheet.hpp"
#include "surfcap/render/png.hpp"
#include "surfcap/synth/deformation.hpp"
#include "surfcap/synth/studio.hpp"
#include "surfcap/synth/texture_atlas.hpp"

namespace surfcap::synth {
namespace {

std::string frame_name(int frame) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d", frame);
  return name;
}

BodyOptions body_options(const Scene& scene) {
  BodyOptions options = scene.body;
  options.seed = scene.seed;
  return options;
}

/// One frame's outputs kept for the ground-truth database and the report.
struct FrameSlot {
  Eigen::MatrixXd V;
  core::RootMotion root;
  std::vector<Eigen::Vector3d> joints;
  GarmentState garment;
  long reconstruction_vertices = 0;
  long reconstruction_faces = 0;
  double noise_rms = 0;
  double target_edge = 0;
  FrameArtefacts artefacts;  ///< studio models only (per-vertex vectors dropped)
  long charts = 0, conflicting_corners = 0;
};

/// Per template vertex: the body part of its dominant bone, or the skirt.
std::vector<int> body_parts(const Body& body) {
  std::vector<int> parts(static_cast<std::size_t>(body.rest.vertex_count()));
  for (long v = 0; v < body.rest.vertex_count(); ++v) {
    Eigen::Index joint = 0;
    body.skin_weights.row(v).maxCoeff(&joint);
    BodyPart part = BodyPart::torso;
    if (joint >= shoulder_l && joint <= wrist_l) part = BodyPart::arm_l;
    if (joint >= shoulder_r && joint <= wrist_r) part = BodyPart::arm_r;
    if (joint >= hip_l && joint <= toe_l) part = BodyPart::leg_l;
    if (joint >= hip_r && joint <= toe_r) part = BodyPart::leg_r;
    if (body.garment_weight(v) > 0.5) part = BodyPart::garment;
    parts[static_cast<std::size_t>(v)] = static_cast<int>(part);
  }
  return parts;
}

/// Rest-pose true points and body parts of reconstruction vertices (for
/// merged-limb detection).
void rest_labels(const Body& body, const std::vector<int>& template_parts, const std::vector<int>& face,
                 const Eigen::MatrixXd& barycentric, Eigen::MatrixXd& rest_points, std::vector<int>& parts) {
  rest_points = surface_points(body.rest.V, body.rest.F, face, barycentric);
  parts.resize(face.size());
  for (std::size_t i = 0; i < face.size(); ++i) {
    Eigen::Index corner = 0;
    barycentric.row(static_cast<long>(i)).maxCoeff(&corner);
    parts[i] = template_parts[static_cast<std::size_t>(body.rest.F(face[i], corner))];
  }
}

/// Colours of the artefact preview: hole borders blue, merged-limb edges
/// orange, outliers and blobs magenta, phantom volume red, rough unseen patches
/// green, the rest light grey.
Eigen::MatrixXd artefact_colors(const FrameArtefacts& artefacts, const std::vector<std::uint8_t>& status) {
  Eigen::MatrixXd colors(static_cast<long>(status.size()), 3);
  for (std::size_t v = 0; v < status.size(); ++v) {
    Eigen::Vector3d c(0.82, 0.82, 0.80);
    const auto s = static_cast<VertexStatus>(status[v]);
    if (s == VertexStatus::rough) c << 0.25, 0.75, 0.30;
    if (s == VertexStatus::phantom) c << 0.90, 0.22, 0.15;
    if (s == VertexStatus::outlier || s == VertexStatus::blob) c << 0.85, 0.10, 0.85;
    if (artefacts.merged_vertex[v]) c << 1.00, 0.62, 0.05;
    if (artefacts.boundary_vertex[v]) c << 0.10, 0.30, 1.00;
    colors.row(static_cast<long>(v)) = c.transpose();
  }
  return colors;
}

struct Job {
  int sequence, frame;
};

/// A frame with the studio models: reconstruction from the cameras' views,
/// status per vertex, textured form, artefact measures.
void write_studio_frame(const Scene& scene, const Actor& actor, const std::vector<int>& template_parts,
                        const std::vector<render::Camera>& cameras, const std::filesystem::path& directory,
                        const Job& job, const core::Mesh& truth, FrameSlot& slot) {
  const MotionSpec& motion = scene.sequences[static_cast<std::size_t>(job.sequence)];
  const ReconstructionOptions& options = scene.reconstruction;
  const std::string name = frame_name(job.frame);
  const auto sequence_dir = directory / motion.name;
  std::vector<render::Image> images;
  std::vector<Silhouette> silhouettes;
  if (scene.images || options.visual_hull || options.textures) {
    const render::RenderOptions render_options = actor.render_options();
    for (const auto& camera : cameras) {
      render::Rendering rendering = render::render_mesh(truth, camera, render_options);
      if (scene.images) render::write_png(sequence_dir / "images" / camera.name / (name + ".png"), rendering.image);
      silhouettes.push_back(silhouette_from_faces(camera, rendering.face));
      images.push_back(std::move(rendering.image));
    }
  }
  const Reconstruction reconstruction =
      reconstruct_studio(truth, cameras, options.visual_hull ? silhouettes : std::vector<Silhouette>{},
                         mean_edge_length(actor.body.rest), frame_seed(scene.seed, job.sequence, job.frame), options);
  core::Mesh mesh = reconstruction.mesh;
  if (options.textures) {
    const FaceVisibility visibility = face_visibility(mesh, cameras);
    TexturedMesh textured = bake_texture(mesh, cameras, images, visibility.best_camera, options.texture_scale);
    write_textured_obj(sequence_dir / "textured" / (name + ".obj"), textured);
    mesh.colors = textured.mesh.colors;
    slot.charts = textured.charts;
    slot.conflicting_corners = textured.conflicting_corners;
  } else {
    mesh.colors.resize(mesh.vertex_count(), 3);
    for (long v = 0; v < mesh.vertex_count(); ++v)
      mesh.colors.row(v) = surface_albedo(actor.body, actor.texture, reconstruction.face[static_cast<std::size_t>(v)],
                                          reconstruction.barycentric.row(v).transpose())
                               .transpose();
  }
  core::write_mesh(sequence_dir / "mesh" / (name + ".ply"), mesh);
  const auto truth_dir = directory / "ground_truth" / motion.name / "correspondence";
  std::vector<std::int32_t> faces(reconstruction.face.begin(), reconstruction.face.end());
  core::write_npy(truth_dir / (name + ".face.npy"), faces.data(), {faces.size()});
  core::write_npy_matrix<float>(truth_dir / (name + ".barycentric.npy"), reconstruction.barycentric);
  core::write_npy(truth_dir / (name + ".status.npy"), reconstruction.status.data(), {reconstruction.status.size()});

  Eigen::MatrixXd rest_points;
  std::vector<int> parts;
  rest_labels(actor.body, template_parts, reconstruction.face, reconstruction.barycentric, rest_points, parts);
  slot.artefacts = measure_artefacts(mesh, reconstruction.status, rest_points, parts);
  slot.artefacts.merged_vertex.clear();
  slot.artefacts.boundary_vertex.clear();
  const Eigen::MatrixXd exact = surface_points(truth.V, truth.F, reconstruction.face, reconstruction.barycentric);
  double sum = 0;
  long count = 0;
  for (long v = 0; v < mesh.vertex_count(); ++v)
    if (reconstruction.status[static_cast<std::size_t>(v)] == static_cast<std::uint8_t>(VertexStatus::on_surface)) {
      sum += (mesh.V.row(v) - exact.row(v)).squaredNorm();
      ++count;
    }
  slot.noise_rms = count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
  slot.reconstruction_vertices = mesh.vertex_count();
  slot.reconstruction_faces = mesh.face_count();
  slot.target_edge = reconstruction.target_edge;
}

void write_frame(const Scene& scene, const Actor& actor, const std::vector<int>& template_parts,
                 const std::vector<render::Camera>& cameras, const std::filesystem::path& directory, const Job& job,
                 FrameSlot& slot) {
  const MotionSpec& motion = scene.sequences[static_cast<std::size_t>(job.sequence)];
  const PerformedFrame performed = actor.perform(scene, motion, job.frame);
  core::Mesh truth;
  truth.V = performed.V;
  truth.F = actor.body.rest.F;
  slot.V = performed.V;
  slot.root = {performed.pose.root.x(), performed.pose.root.y(), performed.pose.root.z(), performed.pose.heading};
  slot.joints = performed.joints;
  slot.garment = performed.garment;
  if (scene.reconstruction.studio()) {
    write_studio_frame(scene, actor, template_parts, cameras, directory, job, truth, slot);
    return;
  }
  const double edge = mean_edge_length(actor.body.rest);
  const Reconstruction reconstruction =
      reconstruct(truth, edge, frame_seed(scene.seed, job.sequence, job.frame), scene.reconstruction);
  core::Mesh mesh = reconstruction.mesh;
  mesh.colors.resize(mesh.vertex_count(), 3);
  for (long v = 0; v < mesh.vertex_count(); ++v)
    mesh.colors.row(v) = surface_albedo(actor.body, actor.texture, reconstruction.face[static_cast<std::size_t>(v)],
                                        reconstruction.barycentric.row(v).transpose())
                             .transpose();
  const std::string name = frame_name(job.frame);
  const auto sequence_dir = directory / motion.name;
  core::write_mesh(sequence_dir / "mesh" / (name + ".ply"), mesh);
  const auto truth_dir = directory / "ground_truth" / motion.name / "correspondence";
  std::vector<std::int32_t> faces(reconstruction.face.begin(), reconstruction.face.end());
  core::write_npy(truth_dir / (name + ".face.npy"), faces.data(), {faces.size()});
  core::write_npy_matrix<float>(truth_dir / (name + ".barycentric.npy"), reconstruction.barycentric);
  if (scene.images) {
    const render::RenderOptions options = actor.render_options();
    for (const auto& camera : cameras)
      render::write_png(sequence_dir / "images" / camera.name / (name + ".png"),
                        render::render_mesh(truth, camera, options).image);
  }
  const Eigen::MatrixXd exact = surface_points(truth.V, truth.F, reconstruction.face, reconstruction.barycentric);
  slot.noise_rms = std::sqrt((mesh.V - exact).rowwise().squaredNorm().mean());
  slot.reconstruction_vertices = mesh.vertex_count();
  slot.reconstruction_faces = mesh.face_count();
  slot.target_edge = reconstruction.target_edge;
}

/// What the sequence's high-level parameter came out as, measured on the performed motion.
core::Json measure_parameters(const MotionSpec& motion, const std::vector<FrameSlot>& slots, double fps) {
  const FrameSlot& first = slots.front();
  const FrameSlot& last = slots.back();
  const double duration = (static_cast<double>(slots.size()) - 1) / fps;
  core::Json measured = core::Json::object();
  switch (motion.family) {
    case MotionFamily::gait: {
      double path = 0;
      for (std::size_t t = 1; t < slots.size(); ++t)
        path += std::hypot(slots[t].root.x - slots[t - 1].root.x, slots[t].root.z - slots[t - 1].root.z);
      measured["speed"] = path / duration;
      measured["turn_rate"] = (last.root.heading - first.root.heading) / duration * 180 / M_PI;
      break;
    }
    case MotionFamily::jump: {
      double top = first.root.y;
      for (const auto& s : slots) top = std::max(top, s.root.y);
      measured["jump_height"] = top - first.root.y;
      measured["jump_distance"] = std::hypot(last.root.x - first.root.x, last.root.z - first.root.z);
      break;
    }
    case MotionFamily::reach: {
      double top = -1e9;
      for (const auto& s : slots) top = std::max(top, s.joints[wrist_r].y());
      measured["reach_height"] = top;
      break;
    }
  }
  return measured;
}

void write_database(const Scene& scene, const Actor& actor, const std::vector<std::vector<FrameSlot>>& slots,
                    const std::filesystem::path& directory) {
  core::AlignedDatabase database;
  database.fps = scene.fps;
  database.root_sequence = scene.sequences.front().name;
  database.root_frame = 0;
  database.template_mesh.F = actor.body.rest.F;
  database.template_mesh.V = core::to_centred(slots[0][0].V, slots[0][0].root);
  database.template_mesh.colors = vertex_albedo(actor.body, actor.texture);
  for (std::size_t s = 0; s < scene.sequences.size(); ++s) {
    core::AlignedSequence sequence;
    sequence.name = scene.sequences[s].name;
    for (const auto& slot : slots[s]) {
      sequence.frames.push_back(core::to_centred(slot.V, slot.root));
      sequence.root_motion.push_back(slot.root);
    }
    database.sequences.push_back(std::move(sequence));
  }
  database.provenance = {{"tool", "surfcap-synth"}, {"version", std::string(core::version())},
                         {"scene", scene_to_json(scene)}, {"kind", "ground truth"}};
  core::write_database(directory, database);
}

void write_ground_truth(const Scene& scene, const Actor& actor, const std::vector<std::vector<FrameSlot>>& slots,
                        const std::filesystem::path& directory) {
  const auto& body = actor.body;
  const auto& sk = body.skeleton;
  core::Mesh rest = body.rest;
  rest.colors = vertex_albedo(body, actor.texture);
  core::write_mesh(directory / "template_rest.ply", rest);
  core::write_npy_matrix<float>(directory / "skin_weights.npy", body.skin_weights);
  core::write_npy_matrix<float>(directory / "garment_weights.npy", body.garment_weight);
  std::vector<std::int32_t> regions;
  for (const auto r : body.regions) regions.push_back(static_cast<std::int32_t>(r));
  core::write_npy(directory / "regions.npy", regions.data(), {regions.size()});
  write_database(scene, actor, slots, directory / "database");

  core::Json joints = core::Json::array();
  for (int j = 0; j < sk.size(); ++j)
    joints.push_back({{"name", sk.names[j]}, {"parent", sk.parents[j]},
                      {"rest", {sk.rest[j].x(), sk.rest[j].y(), sk.rest[j].z()}}});
  core::Json sequences = core::Json::array();
  for (std::size_t s = 0; s < scene.sequences.size(); ++s) {
    const auto& motion = scene.sequences[s];
    const auto& frames = slots[s];
    std::vector<float> joint_positions, garment;
    for (const auto& slot : frames) {
      for (const auto& p : slot.joints) joint_positions.insert(joint_positions.end(), {float(p.x()), float(p.y()), float(p.z())});
      garment.insert(garment.end(), {float(slot.garment.swing_back), float(slot.garment.swing_side),
                                     float(slot.garment.flare), float(slot.garment.twist)});
    }
    const std::size_t T = frames.size();
    core::write_npy(directory / motion.name / "joints.npy", joint_positions.data(), {T, static_cast<std::size_t>(sk.size()), 3});
    core::write_npy(directory / motion.name / "garment.npy", garment.data(), {T, 4});
    core::Json entry = motion_to_json(motion);
    entry.update({{"cyclic", motion.cyclic()},
                  {"measured", measure_parameters(motion, frames, scene.fps)},
                  {"joints", motion.name + "/joints.npy"},
                  {"garment", motion.name + "/garment.npy"},
                  {"correspondence_face", motion.name + "/correspondence/{frame:06d}.face.npy"},
                  {"correspondence_barycentric", motion.name + "/correspondence/{frame:06d}.barycentric.npy"}});
    if (scene.reconstruction.studio())
      entry["correspondence_status"] = motion.name + "/correspondence/{frame:06d}.status.npy";
    sequences.push_back(entry);
  }
  const core::Json truth = {{"format", core::format_tag("synth_truth", 1)},
                            {"scene", scene_to_json(scene)},
                            {"version", std::string(core::version())},
                            {"database", "database/database.json"},
                            {"template_rest", "template_rest.ply"},
                            {"skin_weights", "skin_weights.npy"},
                            {"garment_weights", "garment_weights.npy"},
                            {"regions", "regions.npy"},
                            {"region_names", {"skin", "hair", "shirt", "skirt", "trousers", "shoes"}},
                            {"skeleton", joints},
                            {"noise_sigma", scene.reconstruction.noise_sigma},
                            {"sequences", sequences}};
  core::Json document = truth;
  if (scene.reconstruction.studio()) {
    document["surface_tolerance"] = scene.reconstruction.visual_hull ? scene.reconstruction.surface_tolerance : 0.0;
    document["status_codes"] = {{"on_surface", 0}, {"phantom", 1}, {"outlier", 2}, {"blob", 3}, {"rough", 4}};
  }
  core::write_json_file(directory / "truth.json", document);
}

void write_contact_sheet(const Scene& scene, const Actor& actor, const std::vector<render::Camera>& cameras,
                         const std::vector<std::vector<FrameSlot>>& slots, const std::filesystem::path& path) {
  std::vector<Job> picks;
  const long total = scene.total_frames();
  const int count = static_cast<int>(std::min<long>(std::max(1, scene.contact_sheet_frames), total));
  for (int i = 0; i < count; ++i) {
    long global = count == 1 ? 0 : (total - 1) * i / (count - 1);
    int s = 0;
    while (global >= scene.written_frames(scene.sequences[static_cast<std::size_t>(s)]))
      global -= scene.written_frames(scene.sequences[static_cast<std::size_t>(s++)]);
    picks.push_back({s, static_cast<int>(global)});
  }
  std::vector<int> views = {0};
  if (cameras.size() > 1) views.push_back(static_cast<int>(cameras.size() / 4 > 0 ? cameras.size() / 4 : 1));
  std::vector<render::Image> images;
  render::ContactSheetOptions options;
  options.columns = count;
  options.scale = scene.studio.width > 400 ? 0.5 : 1.0;
  const render::RenderOptions render_options = actor.render_options();
  for (int view : views)
    for (const auto& pick : picks) {
      core::Mesh truth;
      truth.V = slots[static_cast<std::size_t>(pick.sequence)][static_cast<std::size_t>(pick.frame)].V;
      truth.F = actor.body.rest.F;
      images.push_back(render::render_mesh(truth, cameras[static_cast<std::size_t>(view)], render_options).image);
      options.labels.push_back(scene.sequences[static_cast<std::size_t>(pick.sequence)].name + " " +
                               frame_name(pick.frame) + " " + cameras[static_cast<std::size_t>(view)].name);
    }
  render::write_png(path, render::contact_sheet(images, options));
}

/// The reconstructions of the frames that show the most artefacts (most
/// merged-limb edges, genus ≠ 0, most holes, most blobs and outliers, then
/// evenly spaced), coloured by artefact_colors, from the same two cameras as
/// the contact sheet.
void write_artefact_sheet(const Scene& scene, const Actor& actor, const std::vector<int>& template_parts,
                          const std::vector<render::Camera>& cameras, const std::vector<std::vector<FrameSlot>>& slots,
                          const std::filesystem::path& directory) {
  std::vector<Job> all;
  for (int s = 0; s < static_cast<int>(slots.size()); ++s)
    for (int t = 0; t < static_cast<int>(slots[static_cast<std::size_t>(s)].size()); ++t) all.push_back({s, t});
  auto artefacts = [&](const Job& j) -> const FrameArtefacts & {
    return slots[static_cast<std::size_t>(j.sequence)][static_cast<std::size_t>(j.frame)].artefacts;
  };
  const std::vector<std::function<double(const FrameArtefacts &)>> measures = {
      [](const FrameArtefacts& a) { return static_cast<double>(a.merged_edges); },
      [](const FrameArtefacts& a) { return static_cast<double>(std::abs(a.genus)); },
      [](const FrameArtefacts& a) { return static_cast<double>(a.holes); },
      [](const FrameArtefacts& a) { return static_cast<double>(a.blob_components * 1000 + a.outliers); }};
  const std::size_t count = static_cast<std::size_t>(std::max(1, scene.contact_sheet_frames));
  std::vector<Job> picks;
  auto picked = [&](const Job& j) {
    for (const auto& p : picks)
      if (p.sequence == j.sequence && p.frame == j.frame) return true;
    return false;
  };
  for (const auto& measure : measures) {
    if (picks.size() >= count) break;
    const Job *best = nullptr;
    for (const auto& j : all)
      if (!picked(j) && measure(artefacts(j)) > 0 && (!best || measure(artefacts(j)) > measure(artefacts(*best))))
        best = &j;
    if (best) picks.push_back(*best);
  }
  for (std::size_t i = 0; picks.size() < std::min(count, all.size()) && i < all.size(); ++i) {
    const Job& j = all[i * all.size() / std::min(count, all.size()) % all.size()];
    if (!picked(j))
      picks.push_back(j);
    else if (i + 1 == all.size())
      break;
  }
  std::vector<int> views = {0};
  if (cameras.size() > 1) views.push_back(static_cast<int>(cameras.size() / 4 > 0 ? cameras.size() / 4 : 1));
  std::vector<render::Image> images;
  render::ContactSheetOptions options;
  options.columns = static_cast<int>(picks.size());
  options.scale = scene.studio.width > 400 ? 0.5 : 1.0;
  render::RenderOptions render_options;
  render_options.background = Eigen::Vector3d(0.55, 0.57, 0.60);
  std::vector<core::Mesh> meshes;
  for (const auto& pick : picks) {
    const std::string sequence = scene.sequences[static_cast<std::size_t>(pick.sequence)].name;
    const std::string name = frame_name(pick.frame);
    core::Mesh mesh = core::read_mesh(directory / sequence / "mesh" / (name + ".ply"));
    const auto truth_dir = directory / "ground_truth" / sequence / "correspondence";
    const core::NpyArray face_array = core::read_npy(truth_dir / (name + ".face.npy"));
    const core::NpyArray status_array = core::read_npy(truth_dir / (name + ".status.npy"));
    const std::vector<int> face(face_array.data<std::int32_t>(), face_array.data<std::int32_t>() + mesh.vertex_count());
    const std::vector<std::uint8_t> status(status_array.data<std::uint8_t>(),
                                           status_array.data<std::uint8_t>() + mesh.vertex_count());
    const Eigen::MatrixXd barycentric =
        core::read_npy_matrix(truth_dir / (name + ".barycentric.npy"), mesh.vertex_count(), 3);
    Eigen::MatrixXd rest_points;
    std::vector<int> parts;
    rest_labels(actor.body, template_parts, face, barycentric, rest_points, parts);
    mesh.colors = artefact_colors(measure_artefacts(mesh, status, rest_points, parts), status);
    meshes.push_back(std::move(mesh));
  }
  for (int view : views)
    for (std::size_t p = 0; p < picks.size(); ++p) {
      const core::Mesh& mesh = meshes[p];
      // From the camera's position, zoomed on the actor.
      const render::Camera& camera = cameras[static_cast<std::size_t>(view)];
      const Eigen::Vector3d lower = mesh.V.colwise().minCoeff().transpose(),
                            upper = mesh.V.colwise().maxCoeff().transpose();
      const Eigen::Vector3d middle = (lower + upper) / 2;
      const double distance = (camera.centre() - middle).norm();
      const double fov = 2 * std::atan(0.6 * (upper - lower).norm() / distance) * 180 / M_PI;
      const render::Camera zoomed = render::look_at(camera.name, camera.centre(), middle, Eigen::Vector3d::UnitY(), fov,
                                                    camera.width, camera.height);
      images.push_back(render::render_mesh(mesh, zoomed, render_options).image);
      options.labels.push_back(scene.sequences[static_cast<std::size_t>(picks[p].sequence)].name + " " +
                               frame_name(picks[p].frame) + " " + camera.name);
    }
  render::write_png(directory / "ground_truth" / "artefacts.png", render::contact_sheet(images, options));
}

/// Counts over the frames for the report: frames with each artefact and mean
/// sizes.
core::Json artefact_figures(const Scene& scene, const std::vector<std::vector<FrameSlot>>& slots) {
  long frames = 0, merged = 0, holes = 0, genus = 0, blobs = 0, outliers = 0, several = 0, conflicts = 0;
  double vertices = 0, phantom = 0, charts = 0;
  core::Json per_frame = core::Json::array();
  for (std::size_t s = 0; s < slots.size(); ++s)
    for (std::size_t t = 0; t < slots[s].size(); ++t) {
      const FrameArtefacts& a = slots[s][t].artefacts;
      ++frames;
      merged += a.merged_edges > 0;
      holes += a.holes > 0;
      genus += a.genus != 0;
      blobs += a.blob_components > 0;
      outliers += a.outliers > 0;
      several += a.components > 1;
      vertices += static_cast<double>(a.vertices);
      phantom += a.vertices > 0 ? static_cast<double>(a.phantom) / static_cast<double>(a.vertices) : 0.0;
      charts += static_cast<double>(slots[s][t].charts);
      conflicts += slots[s][t].conflicting_corners;
      per_frame.push_back({{"sequence", scene.sequences[s].name},
                           {"frame", static_cast<long>(t)},
                           {"vertices", a.vertices},
                           {"components", a.components},
                           {"holes", a.holes},
                           {"genus", a.genus},
                           {"merged_edges", a.merged_edges},
                           {"phantom", a.phantom},
                           {"outliers", a.outliers},
                           {"blobs", a.blob_components},
                           {"rough", a.rough}});
    }
  const double n = std::max<long>(frames, 1);
  core::Json figures = {{"frames_with_merged_limbs", merged},
                        {"frames_with_holes", holes},
                        {"frames_with_genus_not_0", genus},
                        {"frames_with_blobs", blobs},
                        {"frames_with_outliers", outliers},
                        {"frames_with_several_components", several},
                        {"mean_vertices", vertices / n},
                        {"mean_phantom_share", phantom / n},
                        {"frames", per_frame}};
  if (scene.reconstruction.textures)
    figures["texture"] = {{"mean_charts", charts / n}, {"conflicting_corners", conflicts}};
  return figures;
}

/// capture.json and cameras.json through core::write_capture (the one writer of the format);
/// capture.json is written last, so its presence means the folder is complete.
void write_capture_files(const Scene& scene, const std::vector<render::Camera>& cameras,
                         const std::filesystem::path& directory) {
  core::Capture capture;
  capture.folder = directory;
  capture.name = scene.name;
  capture.fps = scene.fps;
  for (const auto& camera : cameras) capture.cameras.push_back(render::to_capture_camera(camera));
  for (const auto& motion : scene.sequences)
    capture.sequences.push_back({motion.name, motion.name + "/mesh/{frame:06d}.ply",
                                 scene.images ? motion.name + "/images/{camera}/{frame:06d}.png" : "", 0,
                                 scene.written_frames(motion)});
  core::write_capture(capture);
}

}  // namespace

std::uint64_t frame_seed(int scene_seed, int sequence, int frame) {
  return (static_cast<std::uint64_t>(scene_seed) * 0x9e3779b97f4a7c15ULL) ^
         (static_cast<std::uint64_t>(sequence + 1) << 32) ^ static_cast<std::uint64_t>(frame + 1);
}

Actor::Actor(const Scene& scene)
    : body(make_body(body_options(scene))),
      texture(static_cast<std::uint64_t>(scene.seed), 0.05 * scene.body.height / 1.75),
      rest_normals(core::vertex_normals(body.rest.V, body.rest.F)) {}

PerformedFrame Actor::perform(const Scene& scene, const MotionSpec& motion, int frame) const {
  PerformedFrame result;
  const double time = frame / scene.fps;
  result.pose = pose_at(body.skeleton, motion, scene.fps, time);
  result.garment = garment_at(body.skeleton, motion, scene.fps, time, scene.garment);
  result.V = deform_body(body, rest_normals, result.pose, result.garment);
  result.joints = forward_kinematics(body.skeleton, result.pose).position;
  return result;
}

render::RenderOptions Actor::render_options() const {
  render::RenderOptions options;
  options.background = Eigen::Vector3d(0.55, 0.57, 0.60);
  options.ambient = 0.45;
  options.diffuse = 0.55;
  options.surface_color = [this](long face, const Eigen::Vector3d& b) {
    return surface_albedo(body, texture, face, b);
  };
  return options;
}

void generate_capture(const Scene& scene, const std::filesystem::path& directory, int threads,
                      core::StageReport& report, const core::ProgressCallback& progress) {
  scene.validate();
  auto actor_timer = report.time("actor");
  const Actor actor(scene);
  actor_timer.stop();
  const core::MeshCheck check = core::check_mesh(actor.body.rest);
  if (!check.closed() || !check.manifold())
    throw core::internal_error("the actor's template is not a closed manifold: " + check.summary());
  spdlog::info("actor: {} vertices, {} faces", actor.body.rest.vertex_count(), actor.body.rest.face_count());

  const auto& studio = scene.studio;
  const auto cameras = render::ring_cameras(studio.cameras, studio.radius, studio.elevation, studio.target, studio.fov,
                                            studio.width, studio.height);
  const std::vector<int> template_parts = body_parts(actor.body);
  std::vector<Job> jobs;
  std::vector<std::vector<FrameSlot>> slots;
  for (int s = 0; s < static_cast<int>(scene.sequences.size()); ++s) {
    const int frames = scene.written_frames(scene.sequences[static_cast<std::size_t>(s)]);
    slots.emplace_back(static_cast<std::size_t>(frames));
    for (int t = 0; t < frames; ++t) jobs.push_back({s, t});
  }
  {
    auto timer = report.time("frames");
    std::atomic<std::size_t> done{0};
    core::parallel_for(static_cast<long>(jobs.size()), threads, [&](long i) {
      const Job& job = jobs[static_cast<std::size_t>(i)];
      write_frame(scene, actor, template_parts, cameras, directory, job,
                  slots[static_cast<std::size_t>(job.sequence)][static_cast<std::size_t>(job.frame)]);
      if (progress) progress(++done, jobs.size());
    });
  }
  {
    auto timer = report.time("ground_truth");
    write_ground_truth(scene, actor, slots, directory / "ground_truth");
    write_contact_sheet(scene, actor, cameras, slots, directory / "ground_truth" / "contact_sheet.png");
    if (scene.reconstruction.studio()) write_artefact_sheet(scene, actor, template_parts, cameras, slots, directory);
  }
  write_capture_files(scene, cameras, directory);

  long min_vertices = std::numeric_limits<long>::max(), max_vertices = 0;
  double noise_sum = 0;
  for (const auto& sequence : slots)
    for (const auto& slot : sequence) {
      min_vertices = std::min(min_vertices, slot.reconstruction_vertices);
      max_vertices = std::max(max_vertices, slot.reconstruction_vertices);
      noise_sum += slot.noise_rms * slot.noise_rms;
    }
  auto& figures = report.figures();
  figures["scene"] = scene.name;
  figures["seed"] = scene.seed;
  figures["frames"] = static_cast<long>(jobs.size());
  figures["sequences"] = static_cast<long>(scene.sequences.size());
  figures["cameras"] = studio.cameras;
  figures["images"] = scene.images ? static_cast<long>(jobs.size()) * studio.cameras : 0L;
  figures["template"] = {{"vertices", actor.body.rest.vertex_count()}, {"faces", actor.body.rest.face_count()},
                         {"mean_edge_m", mean_edge_length(actor.body.rest)}};
  figures["reconstructions"] = {{"min_vertices", min_vertices}, {"max_vertices", max_vertices},
                                {"noise_rms_mm", 1000 * std::sqrt(noise_sum / static_cast<double>(jobs.size()))}};
  if (scene.reconstruction.studio()) figures["artefacts"] = artefact_figures(scene, slots);
  core::Json parameters = core::Json::object();
  for (std::size_t s = 0; s < scene.sequences.size(); ++s)
    parameters[scene.sequences[s].name] = measure_parameters(scene.sequences[s], slots[s], scene.fps);
  figures["measured_parameters"] = parameters;
}

}  // namespace surfcap::synth
