#include "surfcap/core/database.hpp"

#include <algorithm>
#include <cmath>

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_integer.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::core {
namespace {

Eigen::Matrix3d rotation_y(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix3d R;
  // Counter-clockwise seen from +y: x → -z... right-handed rotation about +y.
  R << c, 0, s, 0, 1, 0, -s, 0, c;
  return R;
}

AlignedSequence read_sequence(const Json& entry, const std::filesystem::path& json_path, long vertex_count,
                              double& bytes_so_far) {
  AlignedSequence sequence;
  sequence.name = name_field(entry, "name", json_path);
  const long frames = integer_field(entry, "frames", json_path, 1, kMaxFrames);
  bytes_so_far += static_cast<double>(frames) * static_cast<double>(vertex_count) * 3 * (sizeof(double) + sizeof(float));
  check_memory(json_path, "sequence '" + sequence.name + "' (" + std::to_string(frames) + " frames of " +
                              std::to_string(vertex_count) + " vertices, with the sequences before it)",
               bytes_so_far);
  const auto positions_path = path_field(entry, "positions", json_path);
  const auto root_path = path_field(entry, "root_motion", json_path);
  const NpyArray positions = read_npy(positions_path, DType::float32, {frames, vertex_count, 3});
  const NpyArray root = read_npy(root_path, DType::float32, {frames, 4});
  const float* p = positions.data<float>();
  sequence.frames.resize(static_cast<std::size_t>(frames));
  for (long t = 0; t < frames; ++t) {
    Eigen::MatrixXd frame(vertex_count, 3);
    for (long v = 0; v < vertex_count; ++v)
      for (int k = 0; k < 3; ++k) frame(v, k) = p[(t * vertex_count + v) * 3 + k];
    if (!frame.allFinite()) throw bad_input(positions_path, "NaN/Inf vertex positions", t);
    if (frame.size() > 0 && frame.cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw bad_input(positions_path, "vertex positions beyond the plausible magnitude (" + std::to_string(kMaxCoordinate) + " m)", t);
    sequence.frames[static_cast<std::size_t>(t)] = std::move(frame);
  }
  const float* r = root.data<float>();
  for (long t = 0; t < frames; ++t) {
    RootMotion motion{r[t * 4 + 0], r[t * 4 + 1], r[t * 4 + 2], r[t * 4 + 3]};
    if (!std::isfinite(motion.x + motion.y + motion.z + motion.heading))
      throw bad_input(root_path, "NaN/Inf root motion", t);
    if (std::max({std::abs(motion.x), std::abs(motion.y), std::abs(motion.z)}) > kMaxCoordinate ||
        std::abs(motion.heading) > 1e6)
      throw bad_input(root_path, "root motion beyond the plausible magnitude (" + std::to_string(kMaxCoordinate) + " m)", t);
    sequence.root_motion.push_back(motion);
  }
  return sequence;
}

}  // namespace

int AlignedDatabase::sequence_index(const std::string& name) const {
  for (std::size_t i = 0; i < sequences.size(); ++i)
    if (sequences[i].name == name) return static_cast<int>(i);
  return -1;
}

long AlignedDatabase::total_frames() const {
  long total = 0;
  for (const auto& sequence : sequences) total += sequence.frame_count();
  return total;
}

Eigen::MatrixXd to_world(const Eigen::MatrixXd& centred, const RootMotion& root) {
  Eigen::MatrixXd world = centred * rotation_y(root.heading).transpose();
  world.rowwise() += Eigen::RowVector3d(root.x, root.y, root.z);
  return world;
}

Eigen::MatrixXd to_centred(const Eigen::MatrixXd& world, const RootMotion& root) {
  Eigen::MatrixXd shifted = world.rowwise() - Eigen::RowVector3d(root.x, root.y, root.z);
  return shifted * rotation_y(root.heading);
}

static AlignedDatabase read_database_document(const std::filesystem::path& database_json);

AlignedDatabase read_database(const std::filesystem::path& database_json) {
  try {
    return read_database_document(database_json);
  } catch (const nlohmann::json::exception& e) {
    throw bad_input(database_json, "a field has the wrong type: " + json_error_text(e));
  }
}

static AlignedDatabase read_database_document(const std::filesystem::path& database_json) {
  const Json document = read_json_document(database_json, "database", 1);
  AlignedDatabase database;
  database.template_mesh = read_mesh(path_field(document, "template", database_json));
  database.fps = number_field(document, "fps", database_json, 0, kMaxFps, 25.0);
  if (!(database.fps > 0)) throw bad_input(database_json, "field \"fps\" must be positive");
  database.units = document.value("units", std::string("m"));
  database.provenance = document.value("provenance", Json::object());
  if (const auto root = document.find("root"); root != document.end()) {
    database.root_sequence = name_field(*root, "sequence", database_json);
    database.root_frame = static_cast<int>(integer_field(*root, "frame", database_json, 0, kMaxFrames));
  }
  const Json sequences = get_field<Json>(document, "sequences", database_json);
  if (!sequences.is_array() || sequences.empty()) throw bad_input(database_json, "\"sequences\" must be a non-empty array");
  double bytes = 0;
  for (const auto& entry : sequences) {
    database.sequences.push_back(read_sequence(entry, database_json, database.template_mesh.vertex_count(), bytes));
    if (database.sequence_index(database.sequences.back().name) != static_cast<int>(database.sequences.size()) - 1)
      throw bad_input(database_json, "sequence '" + database.sequences.back().name + "' appears twice");
  }
  if (!database.root_sequence.empty()) {
    const int root = database.sequence_index(database.root_sequence);
    if (root < 0)
      throw bad_input(database_json, "root sequence '" + database.root_sequence + "' is not among the sequences");
    const int count = database.sequences[static_cast<std::size_t>(root)].frame_count();
    if (database.root_frame >= count)
      throw bad_input(database_json, "root frame " + std::to_string(database.root_frame) + " is beyond sequence '" +
                                         database.root_sequence + "' (" + std::to_string(count) + " frames)");
  }
  return database;
}

void write_database(const std::filesystem::path& directory, const AlignedDatabase& database) {
  const long vertex_count = database.template_mesh.vertex_count();
  write_mesh(directory / "template.ply", database.template_mesh);
  Json sequences = Json::array();
  for (const auto& sequence : database.sequences) {
    if (sequence.root_motion.size() != sequence.frames.size())
      throw internal_error("sequence " + sequence.name + ": root motion and frames differ in length");
    const long frames = sequence.frame_count();
    std::vector<float> positions(static_cast<std::size_t>(frames * vertex_count * 3));
    for (long t = 0; t < frames; ++t) {
      const auto& frame = sequence.frames[static_cast<std::size_t>(t)];
      if (frame.rows() != vertex_count || frame.cols() != 3)
        throw internal_error("sequence " + sequence.name + " frame " + std::to_string(t) + " has the wrong shape");
      for (long v = 0; v < vertex_count; ++v)
        for (int k = 0; k < 3; ++k)
          positions[static_cast<std::size_t>((t * vertex_count + v) * 3 + k)] = static_cast<float>(frame(v, k));
    }
    std::vector<float> root;
    for (const auto& r : sequence.root_motion)
      root.insert(root.end(), {static_cast<float>(r.x), static_cast<float>(r.y), static_cast<float>(r.z),
                               static_cast<float>(r.heading)});
    const std::string positions_name = "sequences/" + sequence.name + ".npy";
    const std::string root_name = "sequences/" + sequence.name + ".root.npy";
    write_npy(directory / positions_name, positions.data(),
              {static_cast<std::size_t>(frames), static_cast<std::size_t>(vertex_count), 3});
    write_npy(directory / root_name, root.data(), {static_cast<std::size_t>(frames), 4});
    sequences.push_back({{"name", sequence.name}, {"frames", frames}, {"positions", positions_name},
                         {"root_motion", root_name}});
  }
  Json document = {{"format", format_tag("database", 1)},
                   {"template", "template.ply"},
                   {"sequences", sequences},
                   {"fps", database.fps},
                   {"units", database.units},
                   {"provenance", database.provenance}};
  if (!database.root_sequence.empty())
    document["root"] = {{"sequence", database.root_sequence}, {"frame", database.root_frame}};
  write_json_file(directory / "database.json", document);
}

}  // namespace surfcap::core
