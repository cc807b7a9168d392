// Writing the SURFCAP_motion_graph extension (docs/formats.md): metadata as JSON, arrays as
// accessors. Representations of what glTF lacks: int64 CSR offsets → UNSIGNED_INT (a GLB
// addresses < 4 GiB, so every offset fits), int32 indices → UNSIGNED_INT, float16 displacement
// values → UNSIGNED_SHORT VEC3 holding the IEEE 754 half-precision bits.
#include <cmath>

#include "surfcap/asset/glb_extension.hpp"
#include "surfcap/asset/glb_morph.hpp"
#include "surfcap/asset/glb_trajectory.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::asset::detail {
namespace {

void require(bool condition, const std::string& what) {
  if (!condition) throw core::internal_error("cannot export the character: " + what);
}

/// Sets object[key] to the accessor of `values` unless it is empty (glTF accessors are never empty).
void put_accessor(core::Json& object, const std::string& key, int accessor) {
  if (accessor >= 0) object[key] = accessor;
}

std::vector<std::uint32_t> unsigned_indices(const std::vector<int>& values, long limit, const std::string& what) {
  std::vector<std::uint32_t> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    require(values[i] >= 0 && values[i] < limit, what + " has an index out of range");
    out[i] = static_cast<std::uint32_t>(values[i]);
  }
  return out;
}

template <class Matrix>
bool same(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && a == b;
}

core::Json parameter_map_json(const blend::ParameterMap& map) {
  core::Json json = {{"degree", map.degree}, {"parameters", map.parameters}, {"monomials", map.monomials},
                     {"residualRms", map.residual_rms}, {"residualMax", map.residual_max}};
  json["coefficients"] = core::Json::array();
  for (long a = 0; a < map.coefficients.rows(); ++a) {
    core::Json row = core::Json::array();
    for (long k = 0; k < map.coefficients.cols(); ++k) row.push_back(map.coefficients(a, k));
    json["coefficients"].push_back(row);
  }
  json["parameterRange"] = core::Json::array();
  for (long j = 0; j < map.parameter_range.rows(); ++j)
    json["parameterRange"].push_back({map.parameter_range(j, 0), map.parameter_range(j, 1)});
  return json;
}

/// w(u) of every grid node (docs/blend.md: w_i = Π_a bit_a(i) ? u_a : 1 − u_a), for consumers
/// that do not want to recompute them.
std::vector<float> node_weights(const CharacterSpace& space) {
  std::vector<float> weights;
  for (const auto& u : space.node_coordinates)
    for (int i = 0; i < space.source_count(); ++i) {
      double w = 1;
      for (int a = 0; a < space.dimensions; ++a) w *= (i >> a) & 1 ? u[a] : 1 - u[a];
      weights.push_back(static_cast<float>(w));
    }
  return weights;
}

core::Json displacements_json(GlbBuilder& builder, const CharacterSpace& space, long vertices) {
  const std::size_t rows = static_cast<std::size_t>(space.node_count()) * space.frames;
  require(space.displacement_offsets.size() == rows + 1, "space '" + space.name + "' has " +
          std::to_string(space.displacement_offsets.size()) + " displacement offsets, expected R·T + 1");
  const std::size_t stored = space.displacement_vertices.size();
  require(space.displacement_offsets.front() == 0 && space.displacement_offsets.back() == static_cast<long>(stored) &&
              space.displacement_values.size() == 3 * stored,
          "space '" + space.name + "' has inconsistent displacement arrays");
  core::Json json = {{"thresholdM", space.displacement_threshold_m}};
  DisplacementCodes codes;
  const int exponent = builder.compressed() ? displacement_step_exponent(space.tolerance_mm) : 0;
  if (exponent != 0 && encode_displacements(space, vertices, exponent, codes)) {
    // Trajectory coding (glb_trajectory.hpp): one frame mask per node and vertex, the values in
    // row order as fixed-point differences from each vertex's previous stored frame.
    const int words = (space.frames + 31) / 32;
    json["valueExponent"] = exponent;
    json["frameMasks"] = builder.add_u32(codes.masks, "displacements", no_target, exact_codec(words <= 64 ? 4 * words : 4));
    put_accessor(json, "valueTrajectories", builder.add_accessor(codes.values.data(), codes.values.size() / 3, u32,
                                                                 TINYGLTF_TYPE_VEC3, "displacements", no_target, false,
                                                                 exact_codec(12)));
    return json;
  }
  std::vector<std::uint32_t> offsets(rows + 1);
  for (std::size_t r = 0; r <= rows; ++r) offsets[r] = static_cast<std::uint32_t>(space.displacement_offsets[r]);
  std::vector<int> indices(space.displacement_vertices.begin(), space.displacement_vertices.end());
  json["offsets"] = builder.add_u32(offsets, "displacements", no_target, exact_codec(4));
  put_accessor(json, "vertices", builder.add_u32(unsigned_indices(indices, vertices, "displacements"), "displacements",
                                                no_target, exact_codec(4)));
  put_accessor(json, "values", builder.add_accessor(space.displacement_values.data(), stored, u16,
                                                    TINYGLTF_TYPE_VEC3, "displacements"));
  return json;
}

core::Json space_json(GlbBuilder& builder, const CharacterSpace& space, long vertices) {
  const std::size_t n = space.source_count(), t = space.frames;
  require(space.dimensions >= 1 && space.dimensions <= 3 && space.sources.size() == n && space.frames > 0,
          "space '" + space.name + "' needs 2, 4 or 8 sources and frames");
  require(space.references.size() == n * t * vertices * 3 && space.root_motion.size() == n * t * 4 &&
              space.time_warp.size() == n * t,
          "space '" + space.name + "' has arrays of the wrong size");
  core::Json json = {{"name", space.name}, {"cyclic", space.cyclic}, {"frames", space.frames},
                     {"dimensions", space.dimensions}, {"breakpoints", space.breakpoints},
                     {"nodeCoordinates", space.node_coordinates}, {"toleranceMm", space.tolerance_mm},
                     {"maxErrorMm", space.max_error_mm}};
  json["sources"] = core::Json::array();
  for (const SpaceSource& s : space.sources)
    json["sources"].push_back({{"sequence", s.sequence}, {"first", s.first}, {"frames", s.frames}, {"durationS", s.duration_s}});
  if (!space.parameter_names.empty()) json["parameterNames"] = space.parameter_names;
  if (!space.parameter_measures.empty()) json["parameterMeasures"] = space.parameter_measures;
  for (const auto& u : space.node_coordinates)
    require(static_cast<int>(u.size()) == space.dimensions, "space '" + space.name + "' has a node of the wrong dimension");
  require(space.node_count() >= static_cast<long>(n), "space '" + space.name + "' lacks its corner nodes");
  put_accessor(json, "nodeWeights", builder.add_floats(node_weights(space), TINYGLTF_TYPE_SCALAR, "spaces", no_target,
                                                       false, exact_codec(4)));
  // The compressed form codes references and displacement fields as fixed-point trajectories;
  // arrays that do not fit 24 bits at their step stay plain and exact.
  std::vector<std::uint32_t> codes;
  const int reference_exponent = builder.compressed() ? reference_step_exponent(space.tolerance_mm) : 0;
  if (reference_exponent != 0 && encode_references(space.references, n, t, vertices, reference_exponent, codes)) {
    json["referenceExponent"] = reference_exponent;
    put_accessor(json, "referenceTrajectories", builder.add_accessor(codes.data(), codes.size() / 3, u32,
                                                                     TINYGLTF_TYPE_VEC3, "references", no_target,
                                                                     false, exact_codec(12)));
  } else {
    put_accessor(json, "references", builder.add_floats(space.references, TINYGLTF_TYPE_VEC3, "references", no_target,
                                                        false, exact_codec(12)));
  }
  put_accessor(json, "rootMotion", builder.add_floats(space.root_motion, TINYGLTF_TYPE_VEC4, "spaces", no_target, false,
                                                      exact_codec(16)));
  put_accessor(json, "timeWarp", builder.add_floats(space.time_warp, TINYGLTF_TYPE_SCALAR, "spaces", no_target, false,
                                                    exact_codec(4)));
  json["displacements"] = displacements_json(builder, space, vertices);
  if (space.parameter_map) json["parameterMap"] = parameter_map_json(*space.parameter_map);
  return json;
}

}  // namespace

core::Json spaces_json(GlbBuilder& builder, const Character& character) {
  core::Json spaces = core::Json::array();
  for (const CharacterSpace& space : character.spaces) spaces.push_back(space_json(builder, space, character.vertex_count()));
  return spaces;
}

core::Json transitions_json(GlbBuilder& builder, const Character& character) {
  core::Json transitions = core::Json::array();
  for (const CharacterTransition& t : character.transitions) {
    require(t.rows >= 0 && t.cols >= 0 && t.similarity.size() == static_cast<std::size_t>(t.rows * t.cols),
            "transition " + t.from + " → " + t.to + " is not rows × cols");
    core::Json json = {{"from", t.from}, {"to", t.to}, {"rows", t.rows}, {"cols", t.cols}};
    put_accessor(json, "similarity", builder.add_floats(t.similarity, TINYGLTF_TYPE_SCALAR, "transitions", no_target,
                                                        false, exact_codec(4)));
    transitions.push_back(json);
  }
  return transitions;
}

core::Json parts_json(GlbBuilder& builder, const Character& character) {
  const learn::LearntModel& model = *character.parts;
  const long vertices = character.vertex_count();
  require(same(model.template_mesh.F, character.template_mesh.F), "the part models have another topology than the template");
  core::Json json = {{"parts", core::Json::array()}, {"regions", core::Json::array()}, {"examples", core::Json::array()}};
  if (!same(model.template_mesh.V, character.template_mesh.V))
    put_accessor(json, "restPositions",
                 builder.add_floats(row_major_floats(model.template_mesh.V), TINYGLTF_TYPE_VEC3, "parts", no_target,
                                    false, exact_codec(12)));
  for (const learn::PartModel& p : model.parts) {
    const long values = 3 * static_cast<long>(p.part.vertices.size());
    require(p.mean.size() == values && p.basis.rows() == values, "part '" + p.part.name + "' has a basis of the wrong size");
    core::Json part = {{"name", p.part.name}, {"parent", p.part.parent}, {"kept", p.basis.cols()},
                       {"energy", p.energy}, {"singularValues", core::Json::array()}};
    for (long k = 0; k < p.singular_values.size(); ++k) part["singularValues"].push_back(p.singular_values(k));
    put_accessor(part, "vertices", builder.add_u32(unsigned_indices(p.part.vertices, vertices, "part"), "parts",
                                                    no_target, exact_codec(4)));
    put_accessor(part, "frontier", builder.add_u32(unsigned_indices(p.part.frontier, vertices, "part"), "parts",
                                                    no_target, exact_codec(4)));
    std::vector<float> mean(p.mean.size());
    for (long i = 0; i < p.mean.size(); ++i) mean[i] = static_cast<float>(p.mean(i));
    put_accessor(part, "mean", builder.add_floats(mean, TINYGLTF_TYPE_SCALAR, "parts", no_target, false, exact_codec(4)));
    if (builder.compressed()) {
      const QuantisedBasis quantised = quantise_basis(p.basis);
      put_accessor(part, "basis", builder.add_accessor(quantised.codes.data(), quantised.codes.size() / 4, i16,
                                                       TINYGLTF_TYPE_VEC4, "parts", no_target, false, exact_codec(8)));
      part["basisExponents"] = quantised.exponents;
    } else {
      put_accessor(part, "basis", builder.add_floats(row_major_floats(p.basis), TINYGLTF_TYPE_SCALAR, "parts",
                                                     no_target, false, exact_codec(4)));
    }
    json["parts"].push_back(part);
  }
  for (const auto& [name, region] : model.regions) {
    core::Json entry = {{"name", name}};
    put_accessor(entry, "vertices", builder.add_u32(unsigned_indices(region, vertices, "region"), "parts", no_target,
                                                     exact_codec(4)));
    json["regions"].push_back(entry);
  }
  for (const auto& [sequence, frame] : model.examples) json["examples"].push_back({{"sequence", sequence}, {"frame", frame}});
  return json;
}

}  // namespace surfcap::asset::detail
