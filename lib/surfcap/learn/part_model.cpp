#include "surfcap/learn/part_model.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <atomic>
#include <limits>

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/parallel.hpp"
#include "surfcap/geometry/cotangent_laplacian.hpp"
#include "surfcap/geometry/mesh_topology.hpp"

namespace surfcap::learn {
namespace fs = std::filesystem;

void LearnOptions::validate() const {
  if (!(energy > 0 && energy <= 1)) throw core::bad_arguments("--energy must be in (0, 1]");
  if (max_vectors < 0) throw core::bad_arguments("--max-vectors must be ≥ 0");
}

PartSet LearntModel::part_set() const {
  PartSet set;
  for (const PartModel& p : parts) set.parts.push_back(p.part);
  set.regions = regions;
  return set;
}

Eigen::VectorXd part_differential_coordinates(const Eigen::SparseMatrix<double>& L, const std::vector<int>& vertices,
                                              const Eigen::MatrixXd& positions) {
  Eigen::MatrixXd local(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i) local.row(static_cast<Eigen::Index>(i)) = positions.row(vertices[i]);
  const Eigen::MatrixXd delta = L * local;
  return Eigen::Map<const Eigen::VectorXd>(delta.data(), delta.size());  // column-major: x, y, z blocks
}

namespace {

// Mean-centred SVD through the F×F Gram matrix (F examples ≪ 3 n_j), eqs. 5–6.
void learn_space(const Eigen::MatrixXd& data, const LearnOptions& options, PartModel& model) {
  const Eigen::Index F = data.rows();
  model.mean = data.colwise().mean().transpose();
  const Eigen::MatrixXd centred = data.rowwise() - model.mean.transpose();
  // lazyProduct: coefficient by coefficient, so the sums do not depend on Eigen's thread count
  // (its blocked parallel GEMM rounds differently with --threads).
  const Eigen::MatrixXd gram = centred.lazyProduct(centred.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
  const Eigen::VectorXd values = eigen.eigenvalues().reverse().cwiseMax(0.0);
  const Eigen::MatrixXd vectors = eigen.eigenvectors().rowwise().reverse();
  model.singular_values = values.cwiseSqrt();
  const double total = values.sum();
  const double floor = 1e-12 * (values.size() ? values[0] : 0.0);
  Eigen::Index kept = 0;
  double held = 0;
  while (kept < F && values[kept] > floor && (total <= 0 || held < options.energy * total) &&
         (options.max_vectors == 0 || kept < options.max_vectors))
    held += values[kept++];
  model.energy = total > 0 ? held / total : 1.0;
  model.basis.resize(data.cols(), kept);
  for (Eigen::Index k = 0; k < kept; ++k) {
    Eigen::VectorXd e = centred.transpose() * vectors.col(k) / std::sqrt(values[k]);
    Eigen::Index largest;
    e.cwiseAbs().maxCoeff(&largest);
    if (e[largest] < 0) e = -e;  // deterministic sign
    model.basis.col(k) = e.normalized();
  }
}

}  // namespace

LearntModel learn_part_models(const core::AlignedDatabase& database, const PartSet& parts,
                              const std::vector<ExampleFrame>& examples, const LearnOptions& options,
                              const core::ProgressCallback& progress) {
  options.validate();
  if (examples.empty()) throw core::bad_arguments("no example frames to learn from");
  LearntModel model;
  model.template_mesh = database.template_mesh;
  model.regions = parts.regions;
  for (const ExampleFrame& e : examples) model.examples.emplace_back(database.sequences[e.sequence].name, e.frame);
  model.parts.resize(parts.parts.size());
  const long n = database.template_mesh.vertex_count();
  std::atomic<std::size_t> done{0};
  core::parallel_for(static_cast<long>(parts.parts.size()), options.threads, [&](long j) {
    const Part& part = parts.parts[j];
    const auto sub = geometry::extract_submesh(database.template_mesh.F, n, part.vertices);
    Eigen::MatrixXd rest(static_cast<Eigen::Index>(sub.vertices.size()), 3);
    for (std::size_t i = 0; i < sub.vertices.size(); ++i)
      rest.row(static_cast<Eigen::Index>(i)) = database.template_mesh.V.row(sub.vertices[i]);
    const Eigen::SparseMatrix<double> L = geometry::cotangent_laplacian(rest, sub.F);
    Eigen::MatrixXd data(static_cast<Eigen::Index>(examples.size()), 3 * rest.rows());
    for (std::size_t i = 0; i < examples.size(); ++i)
      data.row(static_cast<Eigen::Index>(i)) =
          part_differential_coordinates(L, part.vertices, database.sequences[examples[i].sequence].frames[examples[i].frame])
              .transpose();
    model.parts[j].part = part;
    learn_space(data, options, model.parts[j]);
    if (progress) progress(++done, parts.parts.size());
  });
  return model;
}

PartSet whole_mesh_part(long vertex_count) {
  PartSet set;
  Part all;
  all.name = "global";
  for (long v = 0; v < vertex_count; ++v) all.vertices.push_back(static_cast<int>(v));
  set.parts.push_back(all);
  return set;
}

namespace {

void write_indices(const fs::path& path, const std::vector<int>& indices) {
  std::vector<std::int32_t> values(indices.begin(), indices.end());
  core::write_npy(path, values.data(), {values.size()});
}

std::vector<int> read_indices(const fs::path& path, long vertex_count) {
  const core::NpyArray array = core::read_npy(path, core::DType::int32, {-1});
  std::vector<int> out(array.data<std::int32_t>(), array.data<std::int32_t>() + array.size());
  for (int v : out)
    if (v < 0 || v >= vertex_count) throw core::bad_input(path, "vertex index out of range: " + std::to_string(v));
  return out;
}

}  // namespace

void write_learnt_model(const fs::path& directory, const LearntModel& model, const core::Json& provenance) {
  core::write_mesh(directory / "template.ply", model.template_mesh);
  core::Json doc = {{"format", core::format_tag("parts", 1)}, {"template", "template.ply"},
                    {"provenance", provenance}};
  doc["parts"] = core::Json::array();
  for (const PartModel& p : model.parts) {
    const std::string stem = "parts/" + p.part.name;
    write_indices(directory / (stem + ".vertices.npy"), p.part.vertices);
    write_indices(directory / (stem + ".frontier.npy"), p.part.frontier);
    const Eigen::VectorXf mean = p.mean.cast<float>();
    core::write_npy(directory / (stem + ".mean.npy"), mean.data(), {static_cast<std::size_t>(mean.size())});
    core::write_npy_matrix<float>(directory / (stem + ".basis.npy"), p.basis);
    doc["parts"].push_back({{"name", p.part.name},
                            {"parent", p.part.parent >= 0 ? core::Json(model.parts[p.part.parent].part.name) : core::Json()},
                            {"vertices", stem + ".vertices.npy"},
                            {"frontier", stem + ".frontier.npy"},
                            {"mean", stem + ".mean.npy"},
                            {"basis", stem + ".basis.npy"},
                            {"kept", p.basis.cols()},
                            {"energy", p.energy}});
  }
  doc["regions"] = core::Json::array();
  for (const auto& [name, vertices] : model.regions) {
    write_indices(directory / ("regions/" + name + ".npy"), vertices);
    doc["regions"].push_back({{"name", name}, {"vertices", "regions/" + name + ".npy"}});
  }
  doc["examples"] = core::Json::array();
  for (const auto& [sequence, frame] : model.examples) doc["examples"].push_back({{"sequence", sequence}, {"frame", frame}});
  core::write_json_file(directory / "parts.json", doc);
}

static LearntModel read_learnt_model_fields(const fs::path& parts_json) {
  const core::Json doc = core::read_json_document(parts_json, "parts", 1);
  LearntModel model;
  model.template_mesh = core::read_mesh(core::path_field(doc, "template", parts_json));
  const long n = model.template_mesh.vertex_count();
  PartSet set;
  std::vector<std::string> parents;
  for (const auto& p : doc.at("parts")) {
    PartModel pm;
    pm.part.name = core::name_field(p, "name", parts_json);
    pm.part.vertices = read_indices(core::path_field(p, "vertices", parts_json), n);
    const long nj = static_cast<long>(pm.part.vertices.size());
    const auto mean = core::read_npy_as_double(core::path_field(p, "mean", parts_json), {3 * nj});
    pm.mean = Eigen::Map<const Eigen::VectorXd>(mean.data(), 3 * nj);
    pm.basis = core::read_npy_matrix(core::path_field(p, "basis", parts_json), 3 * nj, -1);
    pm.energy = p.value("energy", 0.0);
    parents.push_back(p.contains("parent") && p["parent"].is_string() ? p["parent"].get<std::string>() : "");
    set.parts.push_back(pm.part);
    model.parts.push_back(std::move(pm));
  }
  for (std::size_t i = 0; i < parents.size(); ++i)
    if (!parents[i].empty()) {
      set.parts[i].parent = set.find(parents[i]);
      if (set.parts[i].parent < 0) throw core::bad_input(parts_json, "unknown parent '" + parents[i] + "'");
    }
  // Stored in hierarchy order already; finalise checks it and recomputes frontiers.
  PartSet checked = set;
  finalise_hierarchy(checked, n, parts_json);
  for (std::size_t i = 0; i < checked.parts.size(); ++i) {
    if (checked.parts[i].name != model.parts[i].part.name)
      throw core::bad_input(parts_json, "parts are not listed parents first");
    model.parts[i].part = checked.parts[i];
  }
  if (doc.contains("regions"))
    for (const auto& r : doc["regions"])
      model.regions[core::name_field(r, "name", parts_json)] =
          read_indices(core::path_field(r, "vertices", parts_json), n);
  if (doc.contains("examples"))
    for (const auto& e : doc["examples"])
      model.examples.emplace_back(e.value("sequence", std::string()),
                                  static_cast<int>(core::integer_field_or(e, "frame", parts_json, std::numeric_limits<int>::min(),
                                                                          std::numeric_limits<int>::max(), 0)));
  return model;
}

LearntModel read_learnt_model(const fs::path& parts_json) {
  return core::read_document_fields(parts_json, [&] { return read_learnt_model_fields(parts_json); });
}

}  // namespace surfcap::learn
