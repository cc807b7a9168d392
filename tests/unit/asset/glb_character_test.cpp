// character.glb round trip (uncompressed: bit-exact arrays; compressed: within the stated
// rounding, rewritten to the same bytes), its standard glTF content (what viewers play: normals,
// linear colours, morph targets, root motion) and the reader's refusals (exit 3 naming the file).
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <limits>

#include "surfcap/asset/glb_character.hpp"
#include "surfcap/asset/glb_container.hpp"
#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/render/png.hpp"
#include "synthetic_character.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

asset::Character test_character() {
  asset::Character c = testing::synthetic_character(testing::make_sphere(8, 12, 0.5));
  // A template coordinate and a frame coordinate whose float32 difference loses bits
  // (template + (frame − template) ≠ frame): the reader needs the writer's correction.
  float b = 0, f = 0;
  for (int i = 1; b + (f - b) == f; ++i) b = 1e-3f * i / 7, f = 0.3f + i * 1e-4f;
  c.template_mesh.V(1, 0) = b;
  c.sequences[0].frames[0](1, 0) = f;
  render::Image texture(4, 2, Eigen::Vector3d(0.2, 0.4, 0.6));
  c.texture_png = render::encode_png(texture);
  return c;
}

template <class Matrix>
bool identical(const Matrix& a, const Matrix& b) {
  if (a.size() == 0 || b.size() == 0) return a.size() == b.size();  // absent: 0×0 and 0×3 alike
  return a.rows() == b.rows() && a.cols() == b.cols() && a == b;
}

void expect_same_mesh(const core::Mesh& a, const core::Mesh& b) {
  EXPECT_TRUE(identical(a.V, b.V));
  EXPECT_TRUE(identical(a.F, b.F));
  EXPECT_TRUE(identical(a.colors, b.colors));
  EXPECT_TRUE(identical(a.uvs, b.uvs));
}

void expect_same_space(const asset::CharacterSpace& a, const asset::CharacterSpace& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.cyclic, b.cyclic);
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_EQ(a.dimensions, b.dimensions);
  ASSERT_EQ(a.sources.size(), b.sources.size());
  for (std::size_t i = 0; i < a.sources.size(); ++i) {
    EXPECT_EQ(a.sources[i].sequence, b.sources[i].sequence);
    EXPECT_EQ(a.sources[i].first, b.sources[i].first);
    EXPECT_EQ(a.sources[i].frames, b.sources[i].frames);
    EXPECT_EQ(a.sources[i].duration_s, b.sources[i].duration_s);
  }
  EXPECT_EQ(a.parameter_names, b.parameter_names);
  EXPECT_EQ(a.parameter_measures, b.parameter_measures);
  EXPECT_EQ(a.breakpoints, b.breakpoints);
  EXPECT_EQ(a.node_coordinates, b.node_coordinates);
  EXPECT_EQ(a.references, b.references);
  EXPECT_EQ(a.root_motion, b.root_motion);
  EXPECT_EQ(a.time_warp, b.time_warp);
  EXPECT_EQ(a.displacement_offsets, b.displacement_offsets);
  EXPECT_EQ(a.displacement_vertices, b.displacement_vertices);
  EXPECT_EQ(a.displacement_values, b.displacement_values);
  EXPECT_EQ(a.displacement_threshold_m, b.displacement_threshold_m);
  EXPECT_EQ(a.tolerance_mm, b.tolerance_mm);
  EXPECT_EQ(a.max_error_mm, b.max_error_mm);
  ASSERT_EQ(a.parameter_map.has_value(), b.parameter_map.has_value());
  if (a.parameter_map) {
    EXPECT_EQ(a.parameter_map->degree, b.parameter_map->degree);
    EXPECT_EQ(a.parameter_map->parameters, b.parameter_map->parameters);
    EXPECT_EQ(a.parameter_map->monomials, b.parameter_map->monomials);
    EXPECT_TRUE(identical(a.parameter_map->coefficients, b.parameter_map->coefficients));
    EXPECT_TRUE(identical(a.parameter_map->parameter_range, b.parameter_map->parameter_range));
    EXPECT_EQ(a.parameter_map->residual_rms, b.parameter_map->residual_rms);
    EXPECT_EQ(a.parameter_map->residual_max, b.parameter_map->residual_max);
  }
}

void expect_same_parts(const learn::LearntModel& a, const learn::LearntModel& b) {
  expect_same_mesh(a.template_mesh, b.template_mesh);
  ASSERT_EQ(a.parts.size(), b.parts.size());
  for (std::size_t p = 0; p < a.parts.size(); ++p) {
    EXPECT_EQ(a.parts[p].part.name, b.parts[p].part.name);
    EXPECT_EQ(a.parts[p].part.parent, b.parts[p].part.parent);
    EXPECT_EQ(a.parts[p].part.vertices, b.parts[p].part.vertices);
    EXPECT_EQ(a.parts[p].part.frontier, b.parts[p].part.frontier);
    EXPECT_TRUE(identical(a.parts[p].mean, b.parts[p].mean));
    EXPECT_TRUE(identical(a.parts[p].basis, b.parts[p].basis));
    EXPECT_TRUE(identical(a.parts[p].singular_values, b.parts[p].singular_values));
    EXPECT_EQ(a.parts[p].energy, b.parts[p].energy);
  }
  EXPECT_EQ(a.regions, b.regions);
  EXPECT_EQ(a.examples, b.examples);
}

void expect_same_character(const asset::Character& a, const asset::Character& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.fps, b.fps);
  EXPECT_EQ(a.units, b.units);
  expect_same_mesh(a.template_mesh, b.template_mesh);
  EXPECT_EQ(a.texture_png, b.texture_png);
  ASSERT_EQ(a.sequences.size(), b.sequences.size());
  for (std::size_t s = 0; s < a.sequences.size(); ++s) {
    EXPECT_EQ(a.sequences[s].name, b.sequences[s].name);
    ASSERT_EQ(a.sequences[s].frame_count(), b.sequences[s].frame_count());
    for (int t = 0; t < a.sequences[s].frame_count(); ++t) {
      EXPECT_TRUE(identical(a.sequences[s].frames[t], b.sequences[s].frames[t])) << a.sequences[s].name << " frame " << t;
      const auto& ra = a.sequences[s].root_motion[t];
      const auto& rb = b.sequences[s].root_motion[t];
      EXPECT_TRUE(ra.x == rb.x && ra.y == rb.y && ra.z == rb.z && ra.heading == rb.heading);
    }
  }
  ASSERT_EQ(a.spaces.size(), b.spaces.size());
  for (std::size_t s = 0; s < a.spaces.size(); ++s) expect_same_space(a.spaces[s], b.spaces[s]);
  ASSERT_EQ(a.transitions.size(), b.transitions.size());
  for (std::size_t t = 0; t < a.transitions.size(); ++t) {
    EXPECT_EQ(a.transitions[t].from, b.transitions[t].from);
    EXPECT_EQ(a.transitions[t].to, b.transitions[t].to);
    EXPECT_EQ(a.transitions[t].rows, b.transitions[t].rows);
    EXPECT_EQ(a.transitions[t].cols, b.transitions[t].cols);
    EXPECT_EQ(a.transitions[t].similarity, b.transitions[t].similarity);
  }
  ASSERT_EQ(a.parts.has_value(), b.parts.has_value());
  if (a.parts) expect_same_parts(*a.parts, *b.parts);
  EXPECT_EQ(a.provenance, b.provenance);
}

core::Json json_of(const std::string& glb) { return core::Json::parse(asset::unpack_glb(glb, "test").json); }

std::string with_json(const std::string& glb, const core::Json& json) {
  const auto chunks = asset::unpack_glb(glb, "test");
  return asset::pack_glb(json.dump(), {reinterpret_cast<const std::uint8_t*>(chunks.bin.data()), chunks.bin.size()});
}

/// Runs `read` and expects bad_input whose message names `file`.
template <class Read>
void expect_bad_input(const std::string& file, Read read, const std::string& what) {
  try {
    read();
    ADD_FAILURE() << what << ": accepted";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ExitCode::bad_input) << what << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << what << ": " << e.what();
  }
}

const asset::GlbWriteOptions uncompressed{.generator = "", .compress = false};

TEST(CharacterGlb, RoundTripIsBitExact) {
  testing::TemporaryDirectory dir("glb_round_trip");
  const asset::Character character = test_character();
  const asset::GlbSummary summary = asset::write_character_glb(dir / "character.glb", character, uncompressed);
  EXPECT_EQ(summary.file_bytes, std::filesystem::file_size(dir / "character.glb"));
  EXPECT_EQ(testing::count_hidden_files(dir.path()), 0);
  expect_same_character(character, asset::read_character_glb(dir / "character.glb"));
}

TEST(CharacterGlb, SameCharacterSameBytes) {
  const asset::Character character = test_character();
  for (const asset::GlbWriteOptions& options : {asset::GlbWriteOptions{}, uncompressed}) {
    const std::string first = asset::character_glb_bytes(character, options);
    EXPECT_EQ(first, asset::character_glb_bytes(asset::parse_character_glb(first, "first"), options));
    EXPECT_EQ(first, asset::character_glb_bytes(character, options));
  }
}

double max_difference(const std::vector<float>& a, const std::vector<float>& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) d = std::max(d, std::abs(double(a[i]) - b[i]));
  return d;
}

TEST(CharacterGlb, CompressedFormIsSmallerAndWithinItsRounding) {
  asset::Character character = testing::synthetic_character(testing::make_sphere(24, 32, 0.5), {.frames = 12});
  asset::GlbSummary small, large;
  const std::string compressed = asset::character_glb_bytes(character, {}, &small);
  asset::character_glb_bytes(character, uncompressed, &large);
  EXPECT_TRUE(small.compressed);
  // Random test arrays hardly compress; the quantised morph targets and fixed-point arrays still do.
  EXPECT_LT(3 * small.file_bytes, 2 * large.file_bytes) << small.file_bytes << " vs " << large.file_bytes;
  const core::Json json = json_of(compressed);
  EXPECT_EQ(json["extensionsRequired"], core::Json({"EXT_meshopt_compression", "KHR_mesh_quantization"}));
  EXPECT_TRUE(json["buffers"][1]["extensions"]["EXT_meshopt_compression"]["fallback"].get<bool>());
  const core::Json& target = json["meshes"][0]["primitives"][0]["targets"][0];
  EXPECT_EQ(json["accessors"][target["POSITION"].get<int>()]["componentType"], 5122);  // normalized SHORT
  const asset::Character read = asset::parse_character_glb(compressed, "compressed.glb");
  // Morph targets: template + round(delta · 32767) / 32767.
  for (std::size_t s = 0; s < character.sequences.size(); ++s)
    for (int t = 0; t < character.sequences[s].frame_count(); ++t)
      EXPECT_LE((read.sequences[s].frames[t] - character.sequences[s].frames[t]).cwiseAbs().maxCoeff(), 0.5 / 32767 + 1e-6);
  // Morph normals: normalized BYTE.
  EXPECT_EQ(json["accessors"][target["NORMAL"].get<int>()]["componentType"], 5120);
  // References and displacement values: trajectory-coded multiples of 2^-16 m and 2^-13 m
  // (ε = 5 mm: ε/256 and ε/32; displacements stay float16 values).
  auto halves = [](const std::vector<std::uint16_t>& bits) {
    std::vector<float> values;
    for (const auto half : bits) values.push_back(core::half_to_float(half));
    return values;
  };
  for (std::size_t s = 0; s < character.spaces.size(); ++s) {
    const core::Json& space = json["extensions"]["SURFCAP_motion_graph"]["spaces"][s];
    EXPECT_EQ(space["referenceExponent"], -16);
    EXPECT_EQ(space["displacements"]["valueExponent"], -13);
    EXPECT_FALSE(space.contains("references"));
    EXPECT_FALSE(space["displacements"].contains("offsets"));
    EXPECT_LE(max_difference(read.spaces[s].references, character.spaces[s].references), std::ldexp(1.0, -17));
    EXPECT_LE(max_difference(halves(read.spaces[s].displacement_values), halves(character.spaces[s].displacement_values)),
              std::ldexp(1.0, -14));
    EXPECT_EQ(read.spaces[s].displacement_offsets, character.spaces[s].displacement_offsets);
    EXPECT_EQ(read.spaces[s].displacement_vertices, character.spaces[s].displacement_vertices);
    EXPECT_EQ(read.spaces[s].time_warp, character.spaces[s].time_warp);
  }
  EXPECT_EQ(read.transitions[0].similarity, character.transitions[0].similarity);
  EXPECT_TRUE(identical(read.template_mesh.V, character.template_mesh.V));
  EXPECT_TRUE(identical(read.template_mesh.colors, character.template_mesh.colors));
  // A corrupt compressed stream is refused naming the file.
  std::string corrupt = compressed;
  const std::size_t bin = 20 + json.dump().size();
  for (std::size_t i = bin + 64; i < corrupt.size(); i += 7) corrupt[i] = static_cast<char>(corrupt[i] ^ 0x5A);
  expect_bad_input("corrupt.glb", [&] { asset::parse_character_glb(corrupt, "corrupt.glb"); }, "corrupt stream");
}

TEST(CharacterGlb, CompressedFormScalesLargeMotionsAndQuantisesPartBases) {
  asset::Character character = testing::synthetic_character(testing::make_sphere(24, 32, 0.5), {.frames = 12});
  // Frames 1.5 m from the template (centred frames of a template standing away from the origin):
  // normalized SHORT reaches 1 node unit, so the node takes a scale of 2.
  for (auto& sequence : character.sequences)
    for (Eigen::MatrixXd& frame : sequence.frames) frame.col(2).array() += 1.5;
  const std::string compressed = asset::character_glb_bytes(character, {});
  const core::Json json = json_of(compressed);
  EXPECT_EQ(json["nodes"][0]["scale"], core::Json({2.0, 2.0, 2.0}));
  const core::Json& target = json["meshes"][0]["primitives"][0]["targets"][0];
  EXPECT_EQ(json["accessors"][target["POSITION"].get<int>()]["componentType"], 5122);
  const asset::Character read = asset::parse_character_glb(compressed, "compressed.glb");
  EXPECT_TRUE(identical(read.template_mesh.V, character.template_mesh.V));
  for (std::size_t s = 0; s < character.sequences.size(); ++s)
    for (int t = 0; t < character.sequences[s].frame_count(); ++t)
      EXPECT_LE((read.sequences[s].frames[t] - character.sequences[s].frames[t]).cwiseAbs().maxCoeff(), 1.0 / 32767 + 1e-6);
  // Part bases: int16 codes of 2^e per column, within half a step of the float basis.
  ASSERT_TRUE(read.parts && character.parts);
  const core::Json& parts = json["extensions"]["SURFCAP_motion_graph"]["parts"]["parts"];
  for (std::size_t p = 0; p < character.parts->parts.size(); ++p) {
    const Eigen::MatrixXd& exact = character.parts->parts[p].basis;
    const Eigen::MatrixXd& decoded = read.parts->parts[p].basis;
    ASSERT_EQ(decoded.rows(), exact.rows());
    ASSERT_EQ(decoded.cols(), exact.cols());
    const auto exponents = parts[p]["basisExponents"].get<std::vector<int>>();
    EXPECT_EQ(json["accessors"][parts[p]["basis"].get<int>()]["componentType"], 5122);
    for (long c = 0; c < exact.cols(); ++c) {
      const double step = std::ldexp(1.0, exponents[static_cast<std::size_t>(c)]);
      EXPECT_LE(step, exact.col(c).cwiseAbs().maxCoeff() / 16384 + 1e-300);  // 15+ significant bits
      EXPECT_LE((decoded.col(c) - exact.col(c)).cwiseAbs().maxCoeff(), step / 2 + 1e-7 * exact.col(c).cwiseAbs().maxCoeff());
    }
  }
  // Vertices travel in the codec's order (neighbours on the surface in a row) and come back in
  // the character's own: faces, part lists and regions as written.
  const core::Json& extension = json["extensions"]["SURFCAP_motion_graph"];
  const std::size_t vertices = static_cast<std::size_t>(character.vertex_count());
  const auto& order_accessor = json["accessors"][extension["vertexOrder"].get<int>()];
  EXPECT_EQ(order_accessor["count"].get<std::size_t>(), vertices);
  EXPECT_TRUE(identical(read.template_mesh.F, character.template_mesh.F));
  EXPECT_TRUE(identical(read.template_mesh.colors, character.template_mesh.colors));
  EXPECT_TRUE(identical(read.template_mesh.uvs, character.template_mesh.uvs));
  for (std::size_t p = 0; p < character.parts->parts.size(); ++p) {
    EXPECT_EQ(read.parts->parts[p].part.vertices, character.parts->parts[p].part.vertices);
    EXPECT_EQ(read.parts->parts[p].part.frontier, character.parts->parts[p].part.frontier);
  }
  EXPECT_EQ(read.parts->regions, character.parts->regions);
  for (std::size_t s = 0; s < character.spaces.size(); ++s) {
    EXPECT_EQ(read.spaces[s].displacement_vertices, character.spaces[s].displacement_vertices);
    EXPECT_LE(max_difference(read.spaces[s].references, character.spaces[s].references), std::ldexp(1.0, -17));
  }
  // What the reader decodes writes the same file.
  EXPECT_EQ(asset::character_glb_bytes(read, {}), compressed);
  // A node scale that is not a uniform power of two is refused.
  core::Json bad = json;
  bad["nodes"][0]["scale"] = {3.0, 3.0, 3.0};
  expect_bad_input("scaled.glb", [&] { asset::parse_character_glb(with_json(compressed, bad), "scaled.glb"); }, "scale");
  // A vertex order that is not a permutation (an index twice) is refused.
  bad = json;
  bad["extensions"]["SURFCAP_motion_graph"]["vertexOrder"] = bad["meshes"][0]["primitives"][0]["indices"];
  expect_bad_input("order.glb", [&] { asset::parse_character_glb(with_json(compressed, bad), "order.glb"); }, "order");
}

TEST(CharacterGlb, ColoursAreLinearInTheFileAndCapturedOnRead) {
  asset::Character character = test_character();
  const long vertices = character.vertex_count();
  for (long v = 0; v < vertices; ++v)  // every 8-bit sRGB value
    for (int k = 0; k < 3; ++k) character.template_mesh.colors(v, k) = ((v * 3 + k) * 37 % 256) / 255.0;
  character.template_mesh.colors.row(0) << 51 / 255.0, 88 / 255.0, 166 / 255.0;
  for (const asset::GlbWriteOptions& options : {asset::GlbWriteOptions{}, uncompressed}) {
    const std::string glb = asset::character_glb_bytes(character, options);
    const core::Json json = json_of(glb);
    const core::Json& colour = json["accessors"][json["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"].get<int>()];
    EXPECT_EQ(colour["componentType"], 5123);
    EXPECT_TRUE(colour["normalized"].get<bool>());
    const asset::Character read = asset::parse_character_glb(glb, "colours.glb");
    EXPECT_TRUE(identical(read.template_mesh.colors, character.template_mesh.colors));
  }
  // The decoded COLOR_0 value of (51, 88, 166): what a viewer multiplies into its lighting.
  const std::string glb = asset::character_glb_bytes(character, uncompressed);
  const core::Json json = json_of(glb);
  const core::Json& colour = json["accessors"][json["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"].get<int>()];
  const auto chunks = asset::unpack_glb(glb, "colours.glb");
  const core::Json& view = json["bufferViews"][colour["bufferView"].get<int>()];
  std::uint16_t rgba[4];
  std::memcpy(rgba, chunks.bin.data() + view.value("byteOffset", 0), sizeof rgba);
  EXPECT_NEAR(rgba[0] / 65535.0, 0.0331, 1e-4);  // sRGB 51 → linear 0.0331 (IEC 61966-2-1)
  EXPECT_NEAR(rgba[1] / 65535.0, 0.0976, 1e-4);
  EXPECT_NEAR(rgba[2] / 65535.0, 0.3813, 1e-4);
  EXPECT_EQ(rgba[3], 65535);
}

TEST(CharacterGlb, NormalsShadeTheTemplateAndFollowTheTargets) {
  asset::Character character = test_character();
  // Frame 0 of "walk": the template squashed to half its height — its normals tilt towards ±y.
  character.sequences[0].frames[0] = character.template_mesh.V;
  character.sequences[0].frames[0].col(1) *= 0.5;
  character.sequences[0].frames[0] = character.sequences[0].frames[0].cast<float>().cast<double>();
  const std::string glb = asset::character_glb_bytes(character, uncompressed);
  const core::Json json = json_of(glb);
  const auto chunks = asset::unpack_glb(glb, "normals.glb");
  auto floats = [&](int accessor) {
    const core::Json& view = json["bufferViews"][json["accessors"][accessor]["bufferView"].get<int>()];
    std::vector<float> values(json["accessors"][accessor]["count"].get<std::size_t>() * 3);
    std::memcpy(values.data(), chunks.bin.data() + view.value("byteOffset", 0), values.size() * sizeof(float));
    return values;
  };
  const core::Json& primitive = json["meshes"][0]["primitives"][0];
  const std::vector<float> normals = floats(primitive["attributes"]["NORMAL"].get<int>());
  const std::vector<float> delta = floats(primitive["targets"][0]["NORMAL"].get<int>());
  const Eigen::MatrixXd expected = core::vertex_normals(character.sequences[0].frames[0], character.template_mesh.F);
  const Eigen::MatrixXd V = character.template_mesh.V;
  for (long v = 0; v < character.vertex_count(); ++v) {
    const Eigen::Vector3d n(normals[v * 3], normals[v * 3 + 1], normals[v * 3 + 2]);
    EXPECT_NEAR(n.norm(), 1.0, 1e-6);
    // The sphere's vertex normals point away from its centre.
    EXPECT_GT(n.dot((V.row(v) - V.colwise().mean()).normalized().transpose()), 0.8) << "vertex " << v;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(n(k) + delta[v * 3 + k], expected(v, k), 1e-5) << "vertex " << v;
  }
}

TEST(CharacterGlb, SequencesAreMorphTargetAnimations) {
  const asset::Character character = test_character();
  const core::Json json = json_of(asset::character_glb_bytes(character, uncompressed));
  const core::Json& primitive = json["meshes"][0]["primitives"][0];
  const int frames = character.sequences[0].frame_count() + character.sequences[1].frame_count();
  ASSERT_EQ(primitive["targets"].size(), static_cast<std::size_t>(frames));
  EXPECT_EQ(json["meshes"][0]["extras"]["targetNames"][0], "walk/0000");
  ASSERT_EQ(json["animations"].size(), 2u);
  for (int s = 0; s < 2; ++s) {
    const core::Json& animation = json["animations"][s];
    EXPECT_EQ(animation["name"], character.sequences[s].name);
    const core::Json& weights = json["accessors"][animation["samplers"][0]["output"].get<int>()];
    EXPECT_EQ(weights["count"], character.sequences[s].frame_count() * frames);
    const core::Json& times = json["accessors"][animation["samplers"][0]["input"].get<int>()];
    EXPECT_FLOAT_EQ(times["max"][0].get<double>(), (character.sequences[s].frame_count() - 1) / character.fps);
  }
  EXPECT_TRUE(primitive["attributes"].contains("COLOR_0"));
  EXPECT_TRUE(primitive["attributes"].contains("TEXCOORD_0"));
  EXPECT_EQ(json["images"][0]["mimeType"], "image/png");
  EXPECT_EQ(json["extensionsUsed"][0], "SURFCAP_motion_graph");
  // The coordinate of test_character() that loses bits in frame − template travels as a correction.
  EXPECT_TRUE(json["extensions"]["SURFCAP_motion_graph"]["sequences"][0].contains("corrections"));
  EXPECT_FALSE(json.contains("extensionsRequired"));  // viewers may ignore it
  EXPECT_EQ(json["scenes"][0]["extras"]["fps"], character.fps);  // where clients read the frame rate
  EXPECT_TRUE(primitive["targets"][0].contains("NORMAL"));
}

TEST(CharacterGlb, NonByteColoursAndDoublesAreStoredAsFloat32) {
  asset::Character character = test_character();
  character.template_mesh.colors.setConstant(0.3);  // not k/255: float COLOR_0
  character.sequences[0].frames[0](0, 0) = 0.1;      // not a float: rounded
  const asset::Character read = asset::parse_character_glb(asset::character_glb_bytes(character, uncompressed), "c.glb");
  EXPECT_EQ(read.template_mesh.colors(5, 1), static_cast<double>(0.3f));
  EXPECT_EQ(asset::parse_character_glb(asset::character_glb_bytes(character), "c.glb").template_mesh.colors(5, 1),
            static_cast<double>(0.3f));
  EXPECT_EQ(read.sequences[0].frames[0](0, 0), static_cast<double>(0.1f));
}

TEST(CharacterGlb, MinimalAndPartRestPoseCharactersRoundTrip) {
  asset::Character minimal = test_character();
  minimal.template_mesh.colors.resize(0, 3);
  minimal.template_mesh.uvs.resize(0, 2);
  minimal.texture_png.clear();
  minimal.spaces.clear();
  minimal.transitions.clear();
  minimal.parts.reset();
  minimal.sequences.resize(1);
  expect_same_character(minimal, asset::parse_character_glb(asset::character_glb_bytes(minimal, uncompressed), "minimal.glb"));

  asset::Character posed = test_character();
  auto& rest = posed.parts->template_mesh.V;  // the parts' rest pose differs from the template
  rest = (rest.array() + 0.25).cast<float>().cast<double>();
  const std::string glb = asset::character_glb_bytes(posed, uncompressed);
  EXPECT_TRUE(json_of(glb)["extensions"]["SURFCAP_motion_graph"]["parts"].contains("restPositions"));
  expect_same_character(posed, asset::parse_character_glb(glb, "posed.glb"));
}

TEST(AnimationGlb, PlaysEveryFrameAsAMorphTargetWithRootMotionOnTheNode) {
  testing::TemporaryDirectory dir("glb_animation");
  const core::Mesh mesh = testing::make_sphere(6, 8, 0.3);
  std::vector<Eigen::MatrixXd> frames;
  std::vector<core::RootMotion> root;
  for (int t = 0; t < 5; ++t) {
    frames.push_back(mesh.V.rowwise() + Eigen::RowVector3d(0, 0.01 * t, 0));  // the centred shape
    root.push_back({1.5 * t, 0.9, -0.5 * t, 0.25 * t});                         // the path: on the node
  }
  const auto summary = asset::write_animation_glb(dir / "animation.glb", mesh, frames, root, 30, "play", uncompressed);
  EXPECT_EQ(summary.morph_targets, 5);
  EXPECT_EQ(summary.animations, 1);
  const core::Json json = json_of(core::read_file(dir / "animation.glb"));
  EXPECT_EQ(json["scenes"][0]["extras"]["fps"], 30.0);
  EXPECT_EQ(json["scenes"][0]["extras"]["frames"], 5);
  const core::Json& animation = json["animations"][0];
  EXPECT_EQ(animation["name"], "play");
  std::set<std::string> paths;
  for (const auto& channel : animation["channels"]) paths.insert(channel["target"]["path"].get<std::string>());
  EXPECT_EQ(paths, (std::set<std::string>{"weights", "translation", "rotation"}));
  const core::Json& target = json["accessors"][json["meshes"][0]["primitives"][0]["targets"][4]["POSITION"].get<int>()];
  EXPECT_NEAR(target["min"][1].get<double>(), 0.04, 1e-6);  // frame 4 = template + (0, 0.04, 0): no path
  EXPECT_NEAR(target["max"][1].get<double>(), 0.04, 1e-6);
  EXPECT_NEAR(target["max"][0].get<double>(), 0.0, 1e-6);
  const core::Json& times = json["accessors"][animation["samplers"][0]["input"].get<int>()];
  EXPECT_NEAR(times["max"][0].get<double>(), 4 / 30.0, 1e-6);
  // Not a character: no extension.
  expect_bad_input("animation.glb", [&] { asset::read_character_glb(dir / "animation.glb"); }, "animation as character");
}

TEST(CharacterGlb, RefusesTruncatedCorruptAndNewerFiles) {
  testing::TemporaryDirectory dir("glb_refusals");
  const std::string glb = asset::character_glb_bytes(test_character());
  auto write_and_read = [&](const std::string& bytes, const std::string& what) {
    testing::write_text(dir / "bad.glb", bytes);
    expect_bad_input("bad.glb", [&] { asset::read_character_glb(dir / "bad.glb"); }, what);
  };
  write_and_read(glb.substr(0, glb.size() / 2), "truncated");
  write_and_read(glb.substr(0, 10), "shorter than a header");
  std::string magic = glb;
  magic[0] = 'x';
  write_and_read(magic, "wrong magic");
  core::Json json = json_of(glb);
  json["extensions"]["SURFCAP_motion_graph"]["version"] = asset::motion_graph_extension_version + 1;
  write_and_read(with_json(glb, json), "newer version");
  json = json_of(glb);
  auto& space = json["extensions"]["SURFCAP_motion_graph"]["spaces"][0];
  space["referenceTrajectories"] = space["timeWarp"];  // an accessor of the wrong type and count
  write_and_read(with_json(glb, json), "wrong accessor shape");
  json = json_of(glb);
  json["extensions"]["SURFCAP_motion_graph"]["spaces"][0].erase("referenceExponent");
  write_and_read(with_json(glb, json), "trajectory codes without their step");
  json = json_of(glb);
  json["extensions"]["SURFCAP_motion_graph"]["spaces"][0]["displacements"]["valueExponent"] = 3;
  write_and_read(with_json(glb, json), "a step above 1/2 m");
  json = json_of(glb);
  auto& fields = json["extensions"]["SURFCAP_motion_graph"]["spaces"][0]["displacements"];
  fields["valueTrajectories"] = fields["frameMasks"];  // SCALAR, not VEC3
  write_and_read(with_json(glb, json), "values of the wrong accessor type");
  json = json_of(glb);
  json["extensions"]["SURFCAP_motion_graph"]["spaces"][0]["frames"] = 1000;
  write_and_read(with_json(glb, json), "frames disagreeing with the arrays");
  json = json_of(glb);
  json["accessors"][0]["count"] = 1 << 30;
  write_and_read(with_json(glb, json), "accessor beyond its bufferView");
  std::string nan = glb;  // the first float of the BIN chunk (x of template vertex 0) → NaN
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  const float not_a_number = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan.data() + 20 + json_length + 8, &not_a_number, 4);
  write_and_read(nan, "NaN position");
  json = json_of(glb);
  json["buffers"][0]["uri"] = "/etc/passwd";
  write_and_read(with_json(glb, json), "external buffer");
  write_and_read(std::string(glb).replace(glb.find("\"asset\""), 7, "\"ass\"\"\""), "malformed JSON");
  try {
    asset::read_character_glb(dir / "missing.glb");
    ADD_FAILURE() << "missing file accepted";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ExitCode::io);
  }
}

}  // namespace
}  // namespace surfcap
