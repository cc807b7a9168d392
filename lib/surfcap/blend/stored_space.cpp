#include "surfcap/blend/stored_space.hpp"

#include <algorithm>
#include <cstring>

#include "surfcap/blend/parameter_map_json.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_integer.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::blend {
namespace {

template <class T>
std::vector<T> copy_array(const core::NpyArray& array) {
  std::vector<T> values(array.size());
  if (!values.empty()) std::memcpy(values.data(), array.bytes.data(), values.size() * sizeof(T));
  return values;
}

std::vector<std::vector<double>> matrix_field(const core::Json& entry, const char* key, const std::filesystem::path& file) {
  return core::get_field<std::vector<std::vector<double>>>(entry, key, file);
}

}  // namespace

long StoredSpace::vertex_count() const {
  const long per_vertex = static_cast<long>(source_count()) * frames * 3;
  return per_vertex > 0 ? static_cast<long>(references.size()) / per_vertex : 0;
}

ParameterMap parameter_map_from_json(const core::Json& json, const std::filesystem::path& file) {
  return read_parameter_map(json, file, ParameterMapKeys::space_json);
}

StoredSpace stored_space_from_entry(const core::Json& entry, const std::filesystem::path& output,
                                    const std::filesystem::path& file, long vertices) {
  StoredSpace space;
  space.name = core::name_field(entry, "name", file);
  space.cyclic = entry.value("cyclic", false);
  space.frames = core::get_field<int>(entry, "frames", file);
  space.dimensions = core::get_field<int>(entry, "dimensions", file);
  if (space.dimensions < 1 || space.dimensions > 3 || space.frames < 2)
    throw core::bad_input(file, "space '" + space.name + "': needs 1–3 dimensions and at least 2 frames");
  for (const core::Json& source : core::get_field<core::Json>(entry, "sequences", file))
    space.sources.push_back({core::name_field(source, "name", file),
                             static_cast<int>(core::integer_field_or(source, "first", file, 0, core::kMaxFrames, 0)),
                             static_cast<int>(core::integer_field(source, "frames", file, 1, core::kMaxFrames)),
                             core::number_field(source, "duration_s", file, 0, core::kMaxDurationS, 0.0)});
  for (const core::Json& parameter : entry.value("parameters", core::Json::array())) {
    space.parameter_names.push_back(core::get_field<std::string>(parameter, "name", file));
    space.parameter_measures.push_back(parameter.value("measure", std::string()));
  }
  space.breakpoints = matrix_field(entry, "breakpoints", file);
  space.node_coordinates = matrix_field(entry, "coordinates", file);
  const core::Json& map = core::get_field<core::Json>(entry, "parameter_map", file);
  if (!map.is_null()) space.parameter_map = parameter_map_from_json(map, file);
  space.tolerance_mm = entry.value("tolerance_mm", 0.0);
  space.max_error_mm = entry.value("max_error_mm", 0.0);

  const auto N = static_cast<long>(space.source_count()), T = static_cast<long>(space.frames);
  if (space.frames > core::kMaxFrames) throw core::bad_input(file, "space '" + space.name + "': too many frames");
  core::check_memory(file, "space '" + space.name + "' (" + std::to_string(N) + " sequences of " + std::to_string(T) +
                               " frames)",
                     4.0 * static_cast<double>(N) * static_cast<double>(T) * static_cast<double>(std::max(vertices, 1L)) * 3);
  // Paths are relative to the output folder (where graph.json is), and must stay inside it.
  const auto path = [&](const core::Json& object, const char* key) { return core::path_field(object, key, file, output); };
  space.references = copy_array<float>(core::read_npy(path(entry, "references"), core::DType::float32, {N, T, vertices > 0 ? vertices : -1, 3}));
  space.root_motion = copy_array<float>(core::read_npy(path(entry, "root_motion"), core::DType::float32, {N, T, 4}));
  space.time_warp = copy_array<float>(core::read_npy(path(entry, "time_warp"), core::DType::float32, {N, T}));
  const core::Json& fields = core::get_field<core::Json>(entry, "displacements", file);
  space.displacement_threshold_m = fields.value("threshold_m", 0.0);
  space.displacement_offsets =
      copy_array<std::int64_t>(core::read_npy(path(fields, "offsets"), core::DType::int64, {space.node_count() * T + 1}));
  space.displacement_vertices = copy_array<std::int32_t>(core::read_npy(path(fields, "vertices"), core::DType::int32, {-1}));
  const auto K = static_cast<long>(space.displacement_vertices.size());
  const core::NpyArray values = core::read_npy(path(fields, "values"));
  if (values.shape != std::vector<std::size_t>{static_cast<std::size_t>(K), 3})
    throw core::bad_input(path(fields, "values"), "expected shape [" + std::to_string(K) + ", 3], found " +
                                                      core::shape_string(values.shape));
  if (values.dtype == core::DType::float16) {
    space.displacement_values = copy_array<std::uint16_t>(values);
  } else if (values.dtype == core::DType::float32) {
    for (float value : copy_array<float>(values)) space.displacement_values.push_back(core::float_to_half(value));
  } else {
    throw core::bad_input(path(fields, "values"), "expected float16 or float32 displacements");
  }
  check_stored_space(space, file);
  return space;
}

StoredSpace read_stored_space(const std::filesystem::path& output, const std::string& name, long vertices) {
  const std::filesystem::path file = output / "spaces" / name / "space.json";
  const core::Json document = core::read_json_document(file, "space", 1);
  StoredSpace space = stored_space_from_entry(core::get_field<core::Json>(document, "space", file), output, file, vertices);
  if (space.name != name) throw core::bad_input(file, "holds space '" + space.name + "', expected '" + name + "'");
  return space;
}

void check_stored_space(const StoredSpace& space, const std::filesystem::path& file) {
  const std::string what = "space '" + space.name + "': ";
  const auto N = static_cast<std::size_t>(space.source_count()), T = static_cast<std::size_t>(space.frames);
  const long V = space.vertex_count();
  if (space.sources.size() != N) throw core::bad_input(file, what + "expected " + std::to_string(N) + " sequences");
  if (!space.parameter_names.empty() && static_cast<int>(space.parameter_names.size()) != space.dimensions)
    throw core::bad_input(file, what + "needs one parameter per dimension or none");
  if (space.parameter_map && static_cast<int>(space.parameter_map->parameters.size()) != space.dimensions)
    throw core::bad_input(file, what + "the parameter map has the wrong number of parameters");
  if (V <= 0 || space.references.size() != N * T * static_cast<std::size_t>(V) * 3)
    throw core::bad_input(file, what + "references do not hold [N, T, V, 3] floats");
  if (space.root_motion.size() != N * T * 4 || space.time_warp.size() != N * T)
    throw core::bad_input(file, what + "root motion or time warp has the wrong size");
  if (static_cast<int>(space.breakpoints.size()) != space.dimensions)
    throw core::bad_input(file, what + "needs breakpoints per axis");
  std::size_t nodes = 1;
  for (const auto& axis : space.breakpoints) {
    if (axis.size() < 2 || axis.front() != 0.0 || axis.back() != 1.0 || !std::is_sorted(axis.begin(), axis.end()) ||
        std::adjacent_find(axis.begin(), axis.end()) != axis.end())
      throw core::bad_input(file, what + "breakpoints must rise strictly from 0 to 1");
    nodes *= axis.size();
  }
  if (space.node_coordinates.size() != nodes) throw core::bad_input(file, what + "coordinates must list every grid node");
  for (const auto& u : space.node_coordinates)
    if (static_cast<int>(u.size()) != space.dimensions) throw core::bad_input(file, what + "a node has the wrong dimension");
  const auto& offsets = space.displacement_offsets;
  if (offsets.size() != nodes * T + 1 || offsets.front() != 0 ||
      offsets.back() != static_cast<std::int64_t>(space.displacement_vertices.size()) ||
      !std::is_sorted(offsets.begin(), offsets.end()))
    throw core::bad_input(file, what + "displacement offsets must rise from 0 to the stored count");
  if (space.displacement_values.size() != space.displacement_vertices.size() * 3)
    throw core::bad_input(file, what + "displacement values need 3 per stored vertex");
  for (std::int32_t v : space.displacement_vertices)
    if (v < 0 || v >= V) throw core::bad_input(file, what + "displacement vertex " + std::to_string(v) + " out of range");
}

}  // namespace surfcap::blend
