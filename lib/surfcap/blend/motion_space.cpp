#include "surfcap/blend/motion_space.hpp"

#include <chrono>
#include <cmath>
#include <random>

#include "surfcap/blend/time_warp.hpp"
#include "surfcap/blend/warp_plot.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/logging.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::blend {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// Root motion of source i at normalised frame k relative to its first frame, in its initial
/// heading frame: (forward x, height y, z, heading change).
Eigen::Vector4d local_root(const MotionSpace& space, std::size_t i, std::size_t k) {
  const core::RootMotion& first = space.roots[i].front();
  const core::RootMotion& now = space.roots[i][k];
  const double dx = now.x - first.x, dz = now.z - first.z, c = std::cos(first.heading), s = std::sin(first.heading);
  double turn = 0;
  for (std::size_t j = 1; j <= k; ++j)
    turn += std::remainder(space.roots[i][j].heading - space.roots[i][j - 1].heading, 2 * M_PI);
  return {c * dx - s * dz, now.y, s * dx + c * dz, turn};
}

/// Per-frame max vertex error of `a` against the exact blend over every frame.
double linear_max_error(const SourceSet& sources, const std::vector<double>& u, int threads) {
  std::vector<double> per_frame(static_cast<std::size_t>(sources.frame_count()));
  core::parallel_for(sources.frame_count(), threads, [&](long t) {
    per_frame[t] = (sources.linear(static_cast<int>(t), u) - sources.exact(static_cast<int>(t), u)).rowwise().norm().maxCoeff();
  });
  return *std::max_element(per_frame.begin(), per_frame.end());
}

/// The source ranges (the cycles to align) of a space, cut from the database sequences.
struct SourceRanges {
  std::vector<std::vector<Eigen::MatrixXd>> frames;
  std::vector<std::vector<core::RootMotion>> roots;
};

/// Cuts each configured range out of its database sequence; fills the space's frame counts and
/// durations.
SourceRanges read_source_ranges(const core::AlignedDatabase& database, MotionSpace& space) {
  const SpaceConfig& config = space.config;
  SourceRanges ranges;
  for (const SequenceRange& range : config.sequences) {
    const int index = database.sequence_index(range.name);
    if (index < 0) throw core::bad_input(config.source, "space '" + config.name + "': no sequence '" + range.name + "' in the database");
    const core::AlignedSequence& sequence = database.sequences[index];
    const int last = range.last < 0 ? sequence.frame_count() - 1 : range.last;
    if (range.first < 0 || last >= sequence.frame_count() || last - range.first < 1)
      throw core::bad_input(config.source, "space '" + config.name + "': bad frame range of '" + range.name + "'");
    ranges.frames.emplace_back(sequence.frames.begin() + range.first, sequence.frames.begin() + last + 1);
    ranges.roots.emplace_back(sequence.root_motion.begin() + range.first, sequence.root_motion.begin() + last + 1);
    space.source_frame_counts.push_back(last - range.first + 1);
    space.durations_s.push_back((last - range.first) / database.fps);
  }
  return ranges;
}

/// The memory a space of T normalised frames needs, and its parameters' vertex indices, against
/// the template of V vertices.
void check_space_request(const SpaceConfig& config, int T, std::size_t sources, long V) {
  // Warped frames, the source set's decomposition and the stored references: several copies of
  // [N, T, V, 3] doubles.
  core::check_memory(config.source, "space '" + config.name + "' (" + std::to_string(T) + " normalised frames of " +
                                        std::to_string(sources) + " sequences, " + std::to_string(V) + " vertices)",
                     4.0 * sizeof(double) * static_cast<double>(sources) * T * static_cast<double>(V) * 3);
  for (const ParameterSpec& spec : config.parameters)
    for (int v : spec.vertices)
      if (v < 0 || v >= V)
        throw core::bad_input(config.source, "space '" + config.name + "': parameter '" + spec.name + "' names vertex " +
                                                 std::to_string(v) + ", the template has " + std::to_string(V));
}

/// Time warps every source range to T normalised frames (space.warps, space.roots); returns the
/// warped frames [N][T].
std::vector<std::vector<Eigen::MatrixXd>> warp_sources(MotionSpace& space, const SourceRanges& ranges, int T,
                                                       int threads) {
  space.warps = time_warps(ranges.frames, T, threads);
  std::vector<std::vector<Eigen::MatrixXd>> warped(ranges.frames.size());
  space.roots.resize(ranges.frames.size());
  for (std::size_t i = 0; i < ranges.frames.size(); ++i)
    for (int k = 0; k < T; ++k) {
      warped[i].push_back(sample_frame(ranges.frames[i], space.warps[i][k]));
      space.roots[i].push_back(sample_root(ranges.roots[i], space.warps[i][k]));
    }
  return warped;
}

HybridOptions hybrid_options_for(const SpaceConfig& config, const MotionSpaceOptions& options) {
  HybridOptions hybrid_options;
  hybrid_options.tolerance_m = config.tolerance_mm / 1000.0;
  hybrid_options.checks_per_interval = options.checks_per_interval;
  hybrid_options.max_depth = options.max_depth;
  hybrid_options.sparsity_fraction = options.sparsity_fraction;
  hybrid_options.threads = options.threads;
  return hybrid_options;
}

/// Sizes, memory and errors of the built hybrid blend into space.figures; the errors at random
/// weights (fixed seed): the hybrid must stay within ε, linear for contrast.
void record_hybrid_figures(MotionSpace& space, const core::Mesh& template_mesh, const MotionSpaceOptions& options) {
  const SourceSet& sources = *space.sources;
  const HybridBlend& hybrid = *space.hybrid;
  const int d = sources.dimensions(), T = sources.frame_count();
  std::mt19937 random(20110901);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double hybrid_error = 0, linear_error = 0;
  for (int s = 0; s < options.validation_samples; ++s) {
    std::vector<double> u(static_cast<std::size_t>(d));
    for (double& c : u) c = uniform(random);
    hybrid_error = std::max(hybrid_error, hybrid.max_error(sources, u));
    linear_error = std::max(linear_error, linear_max_error(sources, u, options.threads));
  }
  const double height = template_mesh.V.col(1).maxCoeff() - template_mesh.V.col(1).minCoeff();
  core::Json& f = space.figures;
  f["frames"] = T;
  f["sources"] = sources.source_count();
  f["vertices"] = sources.vertex_count();
  f["model_height_m"] = height;
  f["tolerance_mm"] = space.config.tolerance_mm;
  f["references"] = hybrid.reference_count();
  f["stored_vertices"] = hybrid.stored_vertices();
  f["memory_bytes"] = hybrid.memory_bytes();
  f["dense_float32_bytes"] = hybrid.reference_count() * T * sources.vertex_count() * 12;
  f["checked_max_error_mm"] = 1000 * hybrid.checked_max_error();
  f["validation"] = {{"samples", options.validation_samples}, {"hybrid_max_error_mm", 1000 * hybrid_error},
                     {"linear_max_error_mm", 1000 * linear_error}};
}

/// Evaluation costs per frame of the hybrid, linear and exact blends (informative; benchmarks
/// hold the targets).
void time_evaluation(MotionSpace& space) {
  const SourceSet& sources = *space.sources;
  const int T = sources.frame_count();
  core::Json& timings = space.figures["timings_s"];
  const std::vector<double> u(static_cast<std::size_t>(sources.dimensions()), 0.37);
  Eigen::MatrixXd mesh;
  auto t0 = Clock::now();
  for (int k = 0; k < T; ++k) space.hybrid->evaluate_into(sources, k, u, mesh);
  timings["hybrid_per_frame"] = seconds_since(t0) / T;
  t0 = Clock::now();
  for (int k = 0; k < T; ++k) sources.linear_into(k, u, mesh);
  timings["linear_per_frame"] = seconds_since(t0) / T;
  t0 = Clock::now();
  for (int k = 0; k < std::min(T, 5); ++k) mesh = sources.exact(k, u);
  timings["exact_per_frame"] = seconds_since(t0) / std::min(T, 5);
}

/// Memory and error against ε (casas2013 Fig. 4): the hybrid rebuilt at each tolerance.
core::Json tolerance_sweep(const SourceSet& sources, const HybridOptions& hybrid_options,
                           const std::vector<double>& tolerances_mm) {
  core::Json sweep = core::Json::array();
  for (double tolerance_mm : tolerances_mm) {
    HybridOptions sweep_options = hybrid_options;
    sweep_options.tolerance_m = tolerance_mm / 1000.0;
    const HybridBlend swept = HybridBlend::build(sources, sweep_options);
    sweep.push_back({{"tolerance_mm", tolerance_mm}, {"references", swept.reference_count()},
                     {"memory_bytes", swept.memory_bytes()}, {"checked_max_error_mm", 1000 * swept.checked_max_error()}});
  }
  return sweep;
}

/// The parameter map w = h⁻¹(p): the parameters measured on a grid of weights and fitted.
void fit_space_parameter_map(MotionSpace& space, const MotionSpaceOptions& options) {
  const auto start = Clock::now();
  const int d = space.sources->dimensions();
  const auto samples = weight_samples(d, options.sample_step);
  Eigen::MatrixXd u(static_cast<long>(samples.size()), d), p(static_cast<long>(samples.size()), d);
  std::vector<std::vector<double>> measured(samples.size());
  core::parallel_for(static_cast<long>(samples.size()), options.threads,
                     [&](long s) { measured[s] = measure_parameters(space, samples[s]); });
  for (std::size_t s = 0; s < samples.size(); ++s)
    for (int a = 0; a < d; ++a) {
      u(static_cast<long>(s), a) = samples[s][a];
      p(static_cast<long>(s), a) = measured[s][a];
    }
  std::vector<std::string> names;
  for (const auto& spec : space.config.parameters) names.push_back(spec.name);
  space.parameter_map = fit_parameter_map(u, p, space.config.degree, names);
  space.figures["parameter_map"] = {{"samples", samples.size()}, {"residual_rms", space.parameter_map->residual_rms},
                                    {"residual_max", space.parameter_map->residual_max}};
  space.figures["timings_s"]["parameter_map"] = seconds_since(start);
}

/// references.npy [N, T, V, 3], root.npy [N, T, 4] and warp.npy [N, T], float32.
void write_source_arrays(const std::filesystem::path& directory, const MotionSpace& space) {
  const SourceSet& sources = *space.sources;
  const auto N = static_cast<std::size_t>(sources.source_count()), T = static_cast<std::size_t>(sources.frame_count()),
             V = static_cast<std::size_t>(sources.vertex_count());
  std::vector<float> references(N * T * V * 3);
  std::vector<float> roots(N * T * 4), warp(N * T);
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t t = 0; t < T; ++t) {
      const Eigen::MatrixXd& frame = sources.frame(static_cast<int>(i), static_cast<int>(t));
      float* out = references.data() + ((i * T + t) * V) * 3;
      for (std::size_t v = 0; v < V; ++v)
        for (int c = 0; c < 3; ++c) out[v * 3 + c] = static_cast<float>(frame(static_cast<long>(v), c));
      const core::RootMotion& r = space.roots[i][t];
      float* root = roots.data() + (i * T + t) * 4;
      root[0] = static_cast<float>(r.x);
      root[1] = static_cast<float>(r.y);
      root[2] = static_cast<float>(r.z);
      root[3] = static_cast<float>(r.heading);
      warp[i * T + t] = static_cast<float>(space.warps[i][t]);
    }
  core::write_npy(directory / "references.npy", references.data(), {N, T, V, 3});
  core::write_npy(directory / "root.npy", roots.data(), {N, T, 4});
  core::write_npy(directory / "warp.npy", warp.data(), {N, T});
}

/// The sparse displacements D_NL of every node and frame as a CSR triple
/// displacements.{offsets,vertices,values}.npy, values float16 when the blend is quantised.
void write_displacements(const std::filesystem::path& directory, const HybridBlend& hybrid, int frames) {
  const auto nodes = static_cast<std::size_t>(hybrid.node_count()), T = static_cast<std::size_t>(frames);
  std::vector<std::int64_t> offsets{0};
  std::vector<std::int32_t> vertices;
  std::vector<std::uint16_t> values_half;
  std::vector<float> values_float;
  for (std::size_t node = 0; node < nodes; ++node)
    for (std::size_t t = 0; t < T; ++t) {
      const SparseDisplacement& field = hybrid.displacement(static_cast<long>(node), static_cast<int>(t));
      vertices.insert(vertices.end(), field.vertices.begin(), field.vertices.end());
      for (float value : field.values) {
        if (hybrid.options().quantise) values_half.push_back(core::float_to_half(value));
        else values_float.push_back(value);
      }
      offsets.push_back(static_cast<std::int64_t>(vertices.size()));
    }
  core::write_npy(directory / "displacements.offsets.npy", offsets.data(), {offsets.size()});
  core::write_npy(directory / "displacements.vertices.npy", vertices.data(), {vertices.size()});
  core::NpyArray values;
  values.shape = {vertices.size(), 3};
  if (hybrid.options().quantise) {
    values.dtype = core::DType::float16;
    const auto* bytes = reinterpret_cast<const std::byte*>(values_half.data());
    values.bytes.assign(bytes, bytes + values_half.size() * 2);
  } else {
    values.dtype = core::DType::float32;
    const auto* bytes = reinterpret_cast<const std::byte*>(values_float.data());
    values.bytes.assign(bytes, bytes + values_float.size() * 4);
  }
  core::write_npy(directory / "displacements.values.npy", values);
}

/// The space's entry of space.json and graph.json (docs/blend.md); paths relative to the output.
core::Json space_entry(const MotionSpace& space, const std::filesystem::path& relative) {
  const HybridBlend& hybrid = *space.hybrid;
  core::Json entry;
  entry["name"] = space.config.name;
  core::Json sequences = core::Json::array();
  for (std::size_t i = 0; i < space.config.sequences.size(); ++i)
    sequences.push_back({{"name", space.config.sequences[i].name}, {"first", space.config.sequences[i].first},
                         {"frames", space.source_frame_counts[i]}, {"duration_s", space.durations_s[i]}});
  entry["sequences"] = sequences;
  core::Json parameters = core::Json::array();
  for (const auto& spec : space.config.parameters)
    parameters.push_back({{"name", spec.name}, {"measure", measure_name(spec.measure)}});
  entry["parameters"] = parameters;
  entry["cyclic"] = space.config.cyclic;
  entry["frames"] = space.sources->frame_count();
  entry["dimensions"] = space.sources->dimensions();
  entry["breakpoints"] = hybrid.breakpoints();
  core::Json weights = core::Json::array(), coordinates = core::Json::array();
  for (long node = 0; node < hybrid.node_count(); ++node) {
    coordinates.push_back(hybrid.node_coordinates(node));
    weights.push_back(corner_weights(hybrid.node_coordinates(node)));
  }
  entry["weights"] = weights;
  entry["coordinates"] = coordinates;
  entry["references"] = (relative / "references.npy").generic_string();
  entry["root_motion"] = (relative / "root.npy").generic_string();
  entry["time_warp"] = (relative / "warp.npy").generic_string();
  entry["time_warp_plot"] = (relative / "warp.png").generic_string();
  entry["displacements"] = {{"offsets", (relative / "displacements.offsets.npy").generic_string()},
                            {"vertices", (relative / "displacements.vertices.npy").generic_string()},
                            {"values", (relative / "displacements.values.npy").generic_string()},
                            {"threshold_m", hybrid.options().tolerance_m * hybrid.options().sparsity_fraction}};
  entry["parameter_map"] = space.parameter_map ? space.parameter_map->to_json() : core::Json(nullptr);
  entry["tolerance_mm"] = space.config.tolerance_mm;
  entry["max_error_mm"] = 1000 * hybrid.checked_max_error();
  return entry;
}

}  // namespace

void MotionSpaceOptions::validate() const {
  if (!(sample_step > 0 && sample_step <= 0.5)) throw core::bad_arguments("--sample-step must be in (0, 0.5]");
  if (validation_samples < 0) throw core::bad_arguments("--validation-samples must be ≥ 0");
  for (double t : sweep_tolerances_mm)
    if (!(t > 0)) throw core::bad_arguments("--sweep-mm values must be positive");
}

std::vector<double> measure_parameters(const MotionSpace& space, const std::vector<double>& u) {
  const std::vector<double> w = corner_weights(u);
  const std::size_t T = space.roots.front().size();
  double duration = 0;
  for (std::size_t i = 0; i < w.size(); ++i) duration += w[i] * space.durations_s[i];
  std::vector<Eigen::Vector4d> root(T, Eigen::Vector4d::Zero());
  for (std::size_t k = 0; k < T; ++k)
    for (std::size_t i = 0; i < w.size(); ++i)
      if (w[i] != 0) root[k] += w[i] * local_root(space, i, k);
  const double travel = std::hypot(root.back()(0), root.back()(2));
  std::vector<double> values;
  for (const ParameterSpec& spec : space.config.parameters) {
    switch (spec.measure) {
      case Measure::root_speed: values.push_back(duration > 0 ? travel / duration : 0.0); break;
      case Measure::turning_rate: values.push_back(duration > 0 ? root.back()(3) / duration : 0.0); break;
      case Measure::jump_length: values.push_back(travel); break;
      case Measure::jump_height:
      case Measure::hand_height: {
        // Lowest vertex (clearance) or mean of the named vertices, in world height.
        std::vector<double> heights(T);
        Eigen::MatrixXd mesh;
        for (std::size_t k = 0; k < T; ++k) {
          space.hybrid->evaluate_into(*space.sources, static_cast<int>(k), u, mesh);
          double h = 0;
          if (spec.measure == Measure::jump_height) {
            h = mesh.col(1).minCoeff();
          } else {
            for (int v : spec.vertices) h += mesh(v, 1);
            h /= static_cast<double>(spec.vertices.size());
          }
          heights[k] = h + root[k](1);
        }
        const double top = *std::max_element(heights.begin(), heights.end());
        values.push_back(spec.measure == Measure::jump_height ? top - *std::min_element(heights.begin(), heights.end())
                                                              : top);
        break;
      }
    }
  }
  return values;
}

MotionSpace build_motion_space(const core::AlignedDatabase& database, const NonlinearBlender& blender,
                               const SpaceConfig& config, const MotionSpaceOptions& options,
                               const core::ProgressCallback& progress) {
  options.validate();
  MotionSpace space;
  space.config = config;
  auto start = Clock::now();
  const SourceRanges ranges = read_source_ranges(database, space);
  const int T = config.frames > 0 ? config.frames : space.source_frame_counts.front();
  if (T < 2) throw core::bad_input(config.source, "space '" + config.name + "' needs at least 2 frames");
  check_space_request(config, T, ranges.frames.size(), database.template_mesh.vertex_count());
  std::vector<std::vector<Eigen::MatrixXd>> warped = warp_sources(space, ranges, T, options.threads);
  space.figures["timings_s"]["time_warp"] = seconds_since(start);

  start = Clock::now();
  space.sources = std::make_unique<SourceSet>(blender, std::move(warped), options.threads);
  space.figures["timings_s"]["decompose"] = seconds_since(start);

  const HybridOptions hybrid_options = hybrid_options_for(config, options);
  start = Clock::now();
  space.hybrid = HybridBlend::build(*space.sources, hybrid_options, progress);
  space.figures["timings_s"]["bisection"] = seconds_since(start);

  record_hybrid_figures(space, database.template_mesh, options);
  time_evaluation(space);
  space.figures["tolerance_sweep"] = tolerance_sweep(*space.sources, hybrid_options, options.sweep_tolerances_mm);
  if (!config.parameters.empty()) fit_space_parameter_map(space, options);
  return space;
}

void write_motion_space(const std::filesystem::path& output, const MotionSpace& space) {
  const std::filesystem::path relative = std::filesystem::path("spaces") / space.config.name;
  const std::filesystem::path directory = output / relative;
  write_source_arrays(directory, space);
  write_displacements(directory, *space.hybrid, space.sources->frame_count());
  std::vector<std::string> names;
  for (const auto& range : space.config.sequences) names.push_back(range.name);
  write_warp_plot(directory / "warp.png", space.warps, space.source_frame_counts, names);
  core::Json document = {{"format", core::format_tag("space", 1)}, {"space", space_entry(space, relative)}};
  core::write_json_file(directory / "space.json", document);
}

}  // namespace surfcap::blend
