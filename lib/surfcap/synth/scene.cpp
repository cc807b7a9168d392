#include "surfcap/synth/scene.hpp"

#include <algorithm>
#include <set>

#include "surfcap/core/error.hpp"

namespace surfcap::synth {
namespace {

MotionSpec gait(const std::string& name, int frames, int cycles, double speed, double turn_rate = 0) {
  MotionSpec m;
  m.name = name;
  m.family = MotionFamily::gait;
  m.frames = frames;
  m.cycles = cycles;
  m.speed = speed;
  m.turn_rate = turn_rate;
  return m;
}

MotionSpec jump(const std::string& name, int frames, double height, double distance) {
  MotionSpec m;
  m.name = name;
  m.family = MotionFamily::jump;
  m.frames = frames;
  m.jump_height = height;
  m.jump_distance = distance;
  return m;
}

MotionSpec reach(const std::string& name, int frames, double height) {
  MotionSpec m;
  m.name = name;
  m.family = MotionFamily::reach;
  m.frames = frames;
  m.reach_height = height;
  return m;
}

template <class T>
void read(const core::Json& object, const char* key, T& value, const std::string& source) {
  if (!object.contains(key)) return;
  try {
    value = object.at(key).get<T>();
  } catch (const core::Json::exception& e) {
    throw core::bad_arguments(source + ": field \"" + key + "\" has the wrong type: " + e.what());
  }
}

const char* unseen_name(UnseenMode mode) {
  switch (mode) {
    case UnseenMode::remove: return "remove";
    case UnseenMode::rough: return "rough";
    default: return "keep";
  }
}

/// All the studio models on, at `vertices` per reconstruction and `voxel` metres of carving.
ReconstructionOptions studio_reconstruction(int vertices, double voxel) {
  ReconstructionOptions r;
  r.visual_hull = true;
  r.voxel = voxel;
  r.surface_tolerance = voxel;
  r.vertices = vertices;
  r.noise_sigma = 0.002;
  r.floor_cut = true;
  r.unseen = UnseenMode::remove;
  r.outlier_fraction = 0.002;
  r.blobs = 1.0;
  r.textures = true;
  return r;
}

}  // namespace

UnseenMode unseen_mode(const std::string& name) {
  if (name == "keep") return UnseenMode::keep;
  if (name == "remove") return UnseenMode::remove;
  if (name == "rough") return UnseenMode::rough;
  throw core::bad_arguments("unseen must be keep, remove or rough, not '" + name + "'");
}

std::vector<std::string> preset_names() { return {"tiny", "demo", "full", "studio", "studio_tiny", "long"}; }

Scene preset_scene(const std::string& name) {
  Scene scene;
  scene.name = name;
  if (name == "tiny") {
    scene.body.target_vertices = 1000;
    scene.studio.cameras = 4;
    scene.studio.width = 320;
    scene.studio.height = 240;
    scene.sequences = {gait("walk", 24, 1, 1.3), gait("run", 20, 1, 3.0), jump("jump_low", 24, 0.15, 0.3),
                       jump("jump_high", 24, 0.35, 0.3)};
  } else if (name == "demo") {
    scene.body.target_vertices = 3000;
    scene.sequences = {gait("walk", 28, 1, 1.3), gait("run", 36, 2, 3.0), jump("jump_low", 40, 0.15, 0.3),
                       jump("jump_high", 40, 0.45, 0.3)};
  } else if (name == "full") {
    scene.body.target_vertices = 3000;
    scene.sequences = {gait("walk", 28, 1, 1.3),           gait("run", 36, 2, 3.0),
                       gait("walk_left", 56, 2, 1.3, 40),   gait("walk_right", 56, 2, 1.3, -40),
                       jump("jump_low", 40, 0.15, 0.3),     jump("jump_high", 40, 0.45, 0.3),
                       jump("jump_short", 40, 0.25, 0.2),   jump("jump_long", 44, 0.25, 1.0),
                       reach("reach_low", 50, 0.85),        reach("reach_high", 50, 1.85)};
  } else if (name == "studio") {
    scene.body.target_vertices = 6000;
    scene.studio.cameras = 12;
    scene.studio.width = 800;
    scene.studio.height = 600;
    // CGAL's remeshing lands below the target edge: 37,000 gives about 50,000 vertices.
    scene.reconstruction = studio_reconstruction(37000, 0.006);
    scene.reconstruction.unseen = UnseenMode::rough;
    scene.sequences = {gait("walk", 16, 1, 1.3), gait("run", 12, 1, 3.0), jump("jump_high", 20, 0.45, 0.3),
                       reach("reach_low", 20, 0.85)};
  } else if (name == "studio_tiny") {
    scene.body.target_vertices = 1000;
    scene.studio.cameras = 6;
    scene.studio.width = 320;
    scene.studio.height = 240;
    scene.reconstruction = studio_reconstruction(3000, 0.02);
    scene.sequences = {gait("walk", 4, 1, 1.3), jump("jump_high", 6, 0.35, 0.3), reach("reach_low", 6, 0.85)};
  } else if (name == "long") {
    // A studio day's worth of takes: 2,006 frames in 28 sequences, each family performed at many
    // speeds, turn rates, heights and distances. No images unless asked (--images): the
    // histograms, similarity and tree do not read them (docs/synth.md gives their cost).
    scene.body.target_vertices = 8000;
    scene.images = false;
    scene.contact_sheet_frames = 8;
    scene.sequences = {gait("walk", 112, 4, 1.3),           gait("walk_slow", 120, 4, 0.9),
                       gait("walk_fast", 104, 4, 1.7),      gait("walk_left", 112, 4, 1.3, 40),
                       gait("walk_right", 112, 4, 1.3, -40), gait("circle_left", 140, 5, 1.1, 90),
                       gait("circle_right", 140, 5, 1.1, -90), gait("jog", 88, 4, 2.2),
                       gait("jog_left", 88, 4, 2.2, 60),    gait("run", 72, 4, 3.0),
                       gait("run_left", 72, 4, 3.0, 60),    gait("run_right", 72, 4, 3.0, -60),
                       gait("sprint", 64, 4, 4.0),          jump("hop", 32, 0.08, 0.1),
                       jump("jump_low", 40, 0.15, 0.3),     jump("jump_mid", 40, 0.3, 0.3),
                       jump("jump_high", 44, 0.45, 0.3),    jump("jump_top", 48, 0.6, 0.2),
                       jump("jump_short", 40, 0.25, 0.2),   jump("jump_long", 48, 0.3, 1.0),
                       jump("jump_far", 52, 0.4, 1.5),      reach("reach_floor", 60, 0.7),
                       reach("reach_low", 50, 0.85),        reach("reach_waist", 50, 1.1),
                       reach("reach_mid", 50, 1.3),         reach("reach_head", 50, 1.6),
                       reach("reach_high", 50, 1.85),       reach("reach_top", 56, 2.1)};
  } else {
    throw core::bad_arguments("unknown preset '" + name + "' (tiny, demo, full, studio, studio_tiny or long)");
  }
  return scene;
}

void Scene::validate() const {
  auto fail = [&](const std::string& what) { return core::bad_arguments("scene '" + name + "': " + what); };
  if (!(fps > 0 && fps <= 240)) throw fail("fps must be in (0, 240]");
  if (body.target_vertices < 200 || body.target_vertices > 200000) throw fail("actor vertices must be in [200, 200000]");
  if (!(body.height > 0.5 && body.height < 2.5)) throw fail("actor height must be in (0.5, 2.5) m");
  if (studio.cameras < 1 || studio.cameras > 64) throw fail("cameras must be in [1, 64]");
  if (studio.width < 16 || studio.height < 16 || studio.width > 8192 || studio.height > 8192)
    throw fail("image size must be in [16, 8192] pixels");
  if (!(studio.fov > 1 && studio.fov < 170)) throw fail("fov must be in (1, 170) degrees");
  if (!(studio.radius > 0.5)) throw fail("camera radius must exceed 0.5 m");
  if (!(reconstruction.noise_sigma >= 0 && reconstruction.noise_sigma < 0.05)) throw fail("noise must be in [0, 50) mm");
  if (!(reconstruction.edge_jitter >= 0 && reconstruction.edge_jitter < 0.5)) throw fail("edge_jitter must be in [0, 0.5)");
  if (reconstruction.iterations < 1 || reconstruction.iterations > 20) throw fail("iterations must be in [1, 20]");
  const auto& r = reconstruction;
  if (!(r.voxel >= 0.002 && r.voxel <= 0.1)) throw fail("voxel_mm must be in [2, 100]");
  if (!(r.surface_tolerance >= 0 && r.surface_tolerance <= 0.05)) throw fail("surface_tolerance_mm must be in [0, 50]");
  if (r.vertices < 0 || r.vertices > 500000) throw fail("reconstruction vertices must be in [0, 500000]");
  if (!(r.floor_height > -1 && r.floor_height < 1)) throw fail("floor_height must be in (-1, 1) m");
  if (r.min_views < 1 || r.min_views > 64) throw fail("min_views must be in [1, 64]");
  if (!(r.rough_sigma >= 0 && r.rough_sigma < 0.05)) throw fail("rough_mm must be in [0, 50)");
  if (!(r.outlier_fraction >= 0 && r.outlier_fraction <= 0.2)) throw fail("outliers must be in [0, 0.2]");
  if (!(r.outlier_distance >= 0 && r.outlier_distance <= 0.5)) throw fail("outlier_mm must be in [0, 500]");
  if (!(r.blobs >= 0 && r.blobs <= 20)) throw fail("blobs must be in [0, 20]");
  if (!(r.blob_radius >= 0.001 && r.blob_radius <= 0.2)) throw fail("blob_radius_mm must be in [1, 200]");
  if (!(r.texture_scale >= 0.25 && r.texture_scale <= 8)) throw fail("texture_scale must be in [0.25, 8]");
  if (frames_per_sequence < 0 || frames_per_sequence == 1) throw fail("frames_per_sequence must be 0 (all) or ≥ 2");
  if (sequences.empty()) throw fail("no sequences");
  std::set<std::string> names;
  for (const auto& s : sequences)
    if (!names.insert(s.name).second) throw fail("two sequences are named '" + s.name + "'");
}

int Scene::written_frames(const MotionSpec& motion) const {
  return frames_per_sequence > 0 ? std::min(motion.frames, frames_per_sequence) : motion.frames;
}

long Scene::total_frames() const {
  long total = 0;
  for (const auto& s : sequences) total += written_frames(s);
  return total;
}

core::Json scene_to_json(const Scene& s) {
  core::Json sequences = core::Json::array();
  for (const auto& m : s.sequences) sequences.push_back(motion_to_json(m));
  core::Json document = {{"format", core::format_tag("synth_scene", 1)},
          {"name", s.name},
          {"fps", s.fps},
          {"seed", s.seed},
          {"images", s.images},
          {"contact_sheet_frames", s.contact_sheet_frames},
          {"actor", {{"height", s.body.height}, {"vertices", s.body.target_vertices}}},
          {"studio",
           {{"cameras", s.studio.cameras},
            {"width", s.studio.width},
            {"height", s.studio.height},
            {"radius", s.studio.radius},
            {"elevation", s.studio.elevation},
            {"fov", s.studio.fov},
            {"target", {s.studio.target.x(), s.studio.target.y(), s.studio.target.z()}}}},
          {"reconstruction",
           {{"edge_jitter", s.reconstruction.edge_jitter},
            {"noise_mm", s.reconstruction.noise_sigma * 1000},
            {"iterations", s.reconstruction.iterations}}},
          {"garment",
           {{"natural_frequency", s.garment.natural_frequency},
            {"damping", s.garment.damping},
            {"drag", s.garment.drag}}},
          {"sequences", sequences}};
  if (s.frames_per_sequence > 0) document["frames_per_sequence"] = s.frames_per_sequence;
  // The studio models appear only when one is on: scenes without them read and write as before.
  const auto& r = s.reconstruction;
  if (r.studio())
    document["reconstruction"].update({{"model", r.visual_hull ? "visual_hull" : "remesh"},
                                       {"voxel_mm", r.voxel * 1000},
                                       {"surface_tolerance_mm", r.surface_tolerance * 1000},
                                       {"vertices", r.vertices},
                                       {"floor_cut", r.floor_cut},
                                       {"floor_height", r.floor_height},
                                       {"unseen", unseen_name(r.unseen)},
                                       {"min_views", r.min_views},
                                       {"rough_mm", r.rough_sigma * 1000},
                                       {"outliers", r.outlier_fraction},
                                       {"outlier_mm", r.outlier_distance * 1000},
                                       {"blobs", r.blobs},
                                       {"blob_radius_mm", r.blob_radius * 1000},
                                       {"textures", r.textures},
                                       {"texture_scale", r.texture_scale}});
  return document;
}

Scene scene_from_json(const core::Json& d, const std::string& source) {
  if (!d.is_object()) throw core::bad_arguments(source + ": a scene must be a JSON object");
  if (d.contains("format") && d.at("format") != core::format_tag("synth_scene", 1))
    throw core::bad_arguments(source + ": format must be \"" + core::format_tag("synth_scene", 1) + "\"");
  Scene s;
  read(d, "name", s.name, source);
  read(d, "fps", s.fps, source);
  read(d, "seed", s.seed, source);
  read(d, "images", s.images, source);
  read(d, "contact_sheet_frames", s.contact_sheet_frames, source);
  read(d, "frames_per_sequence", s.frames_per_sequence, source);
  if (d.contains("actor")) {
    read(d["actor"], "height", s.body.height, source);
    read(d["actor"], "vertices", s.body.target_vertices, source);
  }
  if (d.contains("studio")) {
    const auto& c = d["studio"];
    read(c, "cameras", s.studio.cameras, source);
    read(c, "width", s.studio.width, source);
    read(c, "height", s.studio.height, source);
    read(c, "radius", s.studio.radius, source);
    read(c, "elevation", s.studio.elevation, source);
    read(c, "fov", s.studio.fov, source);
    std::vector<double> target;
    read(c, "target", target, source);
    if (!target.empty()) {
      if (target.size() != 3) throw core::bad_arguments(source + ": studio.target must hold 3 numbers");
      s.studio.target = Eigen::Vector3d(target[0], target[1], target[2]);
    }
  }
  if (d.contains("reconstruction")) {
    const auto& r = d["reconstruction"];
    read(r, "edge_jitter", s.reconstruction.edge_jitter, source);
    double noise_mm = s.reconstruction.noise_sigma * 1000;
    read(r, "noise_mm", noise_mm, source);
    s.reconstruction.noise_sigma = noise_mm / 1000;
    read(r, "iterations", s.reconstruction.iterations, source);
    auto& o = s.reconstruction;
    std::string model = "remesh", unseen = unseen_name(o.unseen);
    read(r, "model", model, source);
    if (model != "remesh" && model != "visual_hull")
      throw core::bad_arguments(source + ": reconstruction.model must be \"remesh\" or \"visual_hull\"");
    o.visual_hull = model == "visual_hull";
    auto millimetres = [&](const char* key, double& metres) {
      double mm = metres * 1000;
      read(r, key, mm, source);
      metres = mm / 1000;
    };
    millimetres("voxel_mm", o.voxel);
    millimetres("surface_tolerance_mm", o.surface_tolerance);
    read(r, "vertices", o.vertices, source);
    read(r, "floor_cut", o.floor_cut, source);
    read(r, "floor_height", o.floor_height, source);
    read(r, "unseen", unseen, source);
    try {
      o.unseen = unseen_mode(unseen);
    } catch (const core::Error& e) {
      throw core::bad_arguments(source + ": reconstruction." + e.what());
    }
    read(r, "min_views", o.min_views, source);
    millimetres("rough_mm", o.rough_sigma);
    read(r, "outliers", o.outlier_fraction, source);
    millimetres("outlier_mm", o.outlier_distance);
    read(r, "blobs", o.blobs, source);
    millimetres("blob_radius_mm", o.blob_radius);
    read(r, "textures", o.textures, source);
    read(r, "texture_scale", o.texture_scale, source);
  }
  if (d.contains("garment")) {
    read(d["garment"], "natural_frequency", s.garment.natural_frequency, source);
    read(d["garment"], "damping", s.garment.damping, source);
    read(d["garment"], "drag", s.garment.drag, source);
  }
  if (d.contains("sequences")) {
    if (!d["sequences"].is_array()) throw core::bad_arguments(source + ": \"sequences\" must be an array");
    for (const auto& entry : d["sequences"]) s.sequences.push_back(motion_from_json(entry, source));
  }
  s.validate();
  return s;
}

Scene read_scene(const std::filesystem::path& path) {
  core::Json document;
  try {
    document = core::read_json_file(path);
  } catch (const core::Error& e) {
    throw core::bad_arguments(std::string("--scene: ") + e.what());
  }
  return scene_from_json(document, path.string());
}

}  // namespace surfcap::synth
