// Reading the SURFCAP_motion_graph extension (docs/formats.md): every accessor's type and count
// is checked against the shape its metadata implies, every index against its range.
#include <algorithm>
#include <limits>

#include "surfcap/asset/glb_extension.hpp"
#include "surfcap/asset/glb_trajectory.hpp"
#include "surfcap/blend/parameter_map_json.hpp"
#include "surfcap/blend/stored_space.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::asset::detail {

namespace {

/// Accessor index under `key`, -1 when absent (an empty array).
int optional_accessor(const core::Json& object, const std::string& key, const std::filesystem::path& source) {
  return object.contains(key) ? integer_field(object, key, source) : -1;
}

template <class T>
std::vector<T> read_optional(const GlbAccessors& accessors, const core::Json& object, const std::string& key,
                             int component_type, int type, long count, const std::string& what) {
  const int index = optional_accessor(object, key, accessors.source());
  if (index < 0) {
    if (count > 0) throw core::bad_input(accessors.source(), what + ": missing " + key);
    return {};
  }
  return accessors.read<T>(index, component_type, type, count, what + " " + key);
}

/// n·m, or bad_input when the product is not a plausible element count.
long shape(long n, long m, const GlbAccessors& accessors, const std::string& what) {
  if (n < 0 || m < 0 || (m > 0 && n > std::numeric_limits<std::uint32_t>::max() / m))
    throw core::bad_input(accessors.source(), what + ": impossible array shape");
  return n * m;
}

std::vector<int> checked_indices(const std::vector<std::uint32_t>& values, long limit, const GlbAccessors& accessors,
                                 const std::string& what) {
  std::vector<int> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i] >= static_cast<std::uint64_t>(limit)) throw core::bad_input(accessors.source(), what + ": index out of range");
    out[i] = static_cast<int>(values[i]);
  }
  return out;
}

void read_displacements(const core::Json& json, const GlbAccessors& accessors, long vertices, CharacterSpace& space) {
  const auto& source = accessors.source();
  const std::string what = "space '" + space.name + "' displacements";
  space.displacement_threshold_m = core::get_field<double>(json, "thresholdM", source);
  if (json.contains("frameMasks")) {
    const int exponent = static_cast<int>(integer_field(json, "valueExponent", source, -30, -1));
    const long words = (space.frames + 31) / 32;
    DisplacementCodes codes;
    codes.masks = accessors.read<std::uint32_t>(
        integer_field(json, "frameMasks", source), u32, TINYGLTF_TYPE_SCALAR,
        shape(shape(space.node_count(), vertices, accessors, what), words, accessors, what), what + " frameMasks");
    codes.values = read_optional<std::uint32_t>(accessors, json, "valueTrajectories", u32, TINYGLTF_TYPE_VEC3, -1, what);
    decode_displacements(codes, vertices, exponent, space, source, what);
    return;
  }
  const long rows = shape(space.node_count(), space.frames, accessors, what);
  const auto offsets = accessors.read<std::uint32_t>(integer_field(json, "offsets", source), u32,
                                                     TINYGLTF_TYPE_SCALAR, rows + 1, what + " offsets");
  for (long r = 0; r < rows; ++r)
    if (offsets[r] > offsets[r + 1]) throw core::bad_input(source, what + ": offsets decrease at row " + std::to_string(r));
  if (offsets.front() != 0) throw core::bad_input(source, what + ": offsets must start at 0");
  const long stored = offsets.back();
  space.displacement_offsets.assign(offsets.begin(), offsets.end());
  const auto stored_vertices = read_optional<std::uint32_t>(accessors, json, "vertices", u32, TINYGLTF_TYPE_SCALAR, stored, what);
  const auto indices = checked_indices(stored_vertices, vertices, accessors, what);
  space.displacement_vertices.assign(indices.begin(), indices.end());
  const int values = optional_accessor(json, "values", source);
  if (values >= 0 && accessors.accessor(values, what + " values").componentType == f32) {
    // The compressed form: float32 values that are float16 values (docs/formats.md).
    for (const float value : accessors.read<float>(values, f32, TINYGLTF_TYPE_VEC3, stored, what + " values")) {
      const std::uint16_t half = core::float_to_half(value);
      if (core::half_to_float(half) != value) throw core::bad_input(source, what + ": a value is not a float16 value");
      space.displacement_values.push_back(half);
    }
  } else {
    space.displacement_values = read_optional<std::uint16_t>(accessors, json, "values", u16, TINYGLTF_TYPE_VEC3, stored, what);
  }
  for (const std::uint16_t half : space.displacement_values)
    if ((half & 0x7C00) == 0x7C00) throw core::bad_input(source, what + ": NaN or infinite float16 value");
}

CharacterSpace read_space(const core::Json& json, const GlbAccessors& accessors, const Character& character) {
  const auto& source = accessors.source();
  CharacterSpace space;
  space.name = core::get_field<std::string>(json, "name", source);
  const std::string what = "space '" + space.name + "'";
  space.cyclic = core::get_field<bool>(json, "cyclic", source);
  space.frames = integer_field(json, "frames", source);
  space.dimensions = integer_field(json, "dimensions", source);
  if (space.dimensions < 1 || space.dimensions > 3 || space.frames < 1)
    throw core::bad_input(source, what + ": dimensions must be 1..3 and frames positive");
  for (const core::Json& s : core::get_field<core::Json>(json, "sources", source))
    space.sources.push_back({core::get_field<std::string>(s, "sequence", source),
                             static_cast<int>(integer_field(s, "first", source, 0)),
                             static_cast<int>(integer_field(s, "frames", source, 0)),
                             core::get_field<double>(s, "durationS", source)});
  if (static_cast<int>(space.sources.size()) != space.source_count())
    throw core::bad_input(source, what + ": 2^dimensions sources expected");
  space.parameter_names = json.value("parameterNames", std::vector<std::string>{});
  space.parameter_measures = json.value("parameterMeasures", std::vector<std::string>{});
  space.breakpoints = core::get_field<std::vector<std::vector<double>>>(json, "breakpoints", source);
  space.node_coordinates = core::get_field<std::vector<std::vector<double>>>(json, "nodeCoordinates", source);
  if (space.node_count() < space.source_count()) throw core::bad_input(source, what + ": fewer nodes than corners");
  for (const auto& u : space.node_coordinates)
    if (static_cast<int>(u.size()) != space.dimensions) throw core::bad_input(source, what + ": node of the wrong dimension");
  const long n = space.source_count(), nt = shape(n, space.frames, accessors, what);
  if (const int weights = optional_accessor(json, "nodeWeights", source); weights >= 0)
    accessors.read<float>(weights, f32, TINYGLTF_TYPE_SCALAR, shape(space.node_count(), n, accessors, what), what + " nodeWeights");
  const long vertices = character.vertex_count();
  if (json.contains("referenceTrajectories")) {  // the compressed form's trajectory coding (glb_trajectory.hpp)
    const int exponent = static_cast<int>(integer_field(json, "referenceExponent", source, -30, -1));
    space.references = decode_references(
        accessors.read<std::uint32_t>(integer_field(json, "referenceTrajectories", source), u32, TINYGLTF_TYPE_VEC3,
                                      shape(nt, vertices, accessors, what), what + " referenceTrajectories"),
        n, space.frames, vertices, exponent, source, what + " referenceTrajectories");
  } else {
    space.references = accessors.read<float>(integer_field(json, "references", source), f32, TINYGLTF_TYPE_VEC3,
                                             shape(nt, vertices, accessors, what), what + " references");
  }
  space.root_motion = accessors.read<float>(integer_field(json, "rootMotion", source), f32, TINYGLTF_TYPE_VEC4, nt,
                                            what + " rootMotion");
  space.time_warp = accessors.read<float>(integer_field(json, "timeWarp", source), f32, TINYGLTF_TYPE_SCALAR, nt,
                                          what + " timeWarp");
  read_displacements(core::get_field<core::Json>(json, "displacements", source), accessors, vertices, space);
  if (json.contains("parameterMap")) space.parameter_map =
        blend::read_parameter_map(json["parameterMap"], source, blend::ParameterMapKeys::gltf, space.dimensions);
  space.tolerance_mm = core::get_field<double>(json, "toleranceMm", source);
  space.max_error_mm = core::get_field<double>(json, "maxErrorMm", source);
  blend::check_stored_space(space, source);  // the invariants space.json readers check too
  return space;
}

int space_named(const Character& character, const std::string& name) {
  for (std::size_t i = 0; i < character.spaces.size(); ++i)
    if (character.spaces[i].name == name) return static_cast<int>(i);
  return -1;
}

}  // namespace

void read_spaces(const core::Json& extension, const GlbAccessors& accessors, Character& character) {
  if (!extension.contains("spaces")) return;
  for (const core::Json& json : extension["spaces"]) character.spaces.push_back(read_space(json, accessors, character));
}

void read_transitions(const core::Json& extension, const GlbAccessors& accessors, Character& character) {
  if (!extension.contains("transitions")) return;
  const auto& source = accessors.source();
  for (const core::Json& json : extension["transitions"]) {
    CharacterTransition t;
    t.from = core::get_field<std::string>(json, "from", source);
    t.to = core::get_field<std::string>(json, "to", source);
    t.rows = integer_field(json, "rows", source);
    t.cols = integer_field(json, "cols", source);
    const std::string what = "transition " + t.from + " -> " + t.to;
    const int from = space_named(character, t.from), to = space_named(character, t.to);
    if (from < 0 || to < 0) throw core::bad_input(source, what + ": unknown space");
    const auto& a = character.spaces[from];
    const auto& b = character.spaces[to];
    if (t.rows != a.node_count() * a.frames || t.cols != b.node_count() * b.frames)
      throw core::bad_input(source, what + ": similarity must be (R_from·T_from) × (R_to·T_to)");
    t.similarity = read_optional<float>(accessors, json, "similarity", f32, TINYGLTF_TYPE_SCALAR,
                                        shape(t.rows, t.cols, accessors, what), what);
    character.transitions.push_back(std::move(t));
  }
}

void read_parts(const core::Json& extension, const GlbAccessors& accessors, Character& character) {
  if (!extension.contains("parts")) return;
  const auto& source = accessors.source();
  const core::Json& json = extension["parts"];
  const long vertices = character.vertex_count();
  learn::LearntModel model;
  model.template_mesh = character.template_mesh;
  if (const int rest = optional_accessor(json, "restPositions", source); rest >= 0) {
    const auto values = accessors.read<float>(rest, f32, TINYGLTF_TYPE_VEC3, vertices, "part rest positions");
    for (long i = 0; i < 3 * vertices; ++i) model.template_mesh.V(i / 3, i % 3) = values[i];
  }
  for (const core::Json& p : core::get_field<core::Json>(json, "parts", source)) {
    learn::PartModel part;
    part.part.name = core::get_field<std::string>(p, "name", source);
    const std::string what = "part '" + part.part.name + "'";
    part.part.parent = integer_field(p, "parent", source);
    if (part.part.parent < -1 || part.part.parent >= static_cast<int>(model.parts.size()) ||
        (part.part.parent < 0) != model.parts.empty())
      throw core::bad_input(source, what + ": parents must come first and only the first part is the root");
    const auto indices = accessors.read<std::uint32_t>(integer_field(p, "vertices", source), u32,
                                                       TINYGLTF_TYPE_SCALAR, -1, what + " vertices");
    part.part.vertices = checked_indices(indices, vertices, accessors, what);
    part.part.frontier = checked_indices(read_optional<std::uint32_t>(accessors, p, "frontier", u32, TINYGLTF_TYPE_SCALAR, -1, what),
                                         vertices, accessors, what);
    const long values = 3 * static_cast<long>(part.part.vertices.size());
    const long kept = integer_field(p, "kept", source);
    const auto mean = accessors.read<float>(integer_field(p, "mean", source), f32, TINYGLTF_TYPE_SCALAR, values, what + " mean");
    part.mean = Eigen::Map<const Eigen::VectorXf>(mean.data(), values).cast<double>();
    if (p.contains("basisExponents")) {  // the compressed form (glb_trajectory.hpp)
      const core::Json& list = p["basisExponents"];
      if (!list.is_array() || static_cast<long>(list.size()) != kept)
        throw core::bad_input(source, what + ": basisExponents is not one exponent per kept component");
      std::vector<int> exponents;
      for (const core::Json& e : list)
        exponents.push_back(static_cast<int>(std::clamp<long>(core::checked_integer(e, what + " basis exponent", source), -99, 99)));
      const auto codes = read_optional<std::int16_t>(accessors, p, "basis", i16, TINYGLTF_TYPE_VEC4,
                                                     shape(values / 3, kept, accessors, what), what);
      part.basis = dequantise_basis(codes, exponents, values, source, what);
    } else {
      const auto basis = read_optional<float>(accessors, p, "basis", f32, TINYGLTF_TYPE_SCALAR,
                                              shape(values, kept, accessors, what), what);
      part.basis.resize(values, kept);
      for (long r = 0; r < values; ++r)
        for (long c = 0; c < kept; ++c) part.basis(r, c) = basis[r * kept + c];
    }
    part.energy = core::get_field<double>(p, "energy", source);
    const auto singular = p.value("singularValues", std::vector<double>{});
    part.singular_values = Eigen::Map<const Eigen::VectorXd>(singular.data(), static_cast<long>(singular.size()));
    model.parts.push_back(std::move(part));
  }
  if (json.contains("regions"))
    for (const core::Json& r : json["regions"]) {
      const std::string name = core::get_field<std::string>(r, "name", source);
      model.regions[name] = checked_indices(
          read_optional<std::uint32_t>(accessors, r, "vertices", u32, TINYGLTF_TYPE_SCALAR, -1, "region " + name),
          vertices, accessors, "region " + name);
    }
  if (json.contains("examples"))
    for (const core::Json& e : json["examples"])
      model.examples.emplace_back(core::get_field<std::string>(e, "sequence", source), integer_field(e, "frame", source));
  character.parts = std::move(model);
}

}  // namespace surfcap::asset::detail
