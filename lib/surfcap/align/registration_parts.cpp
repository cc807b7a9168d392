#include "surfcap/align/registration_parts.hpp"

#include <cstdint>
#include <cstdio>
#include <span>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/similarity/similarity_files.hpp"

namespace surfcap::align {

namespace {

constexpr int kPartVersion = 2;

/// FNV-1a (64 bit) of bytes, as 16 hex digits: enough to tell two files apart, not a signature.
std::string checksum(std::span<const std::byte> bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const std::byte b : bytes) hash = (hash ^ static_cast<std::uint64_t>(b)) * 0x100000001b3ULL;
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::string file_checksum(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) return "none";
  const std::string bytes = core::read_file(path);
  return checksum(std::as_bytes(std::span(bytes.data(), bytes.size())));
}

core::Json record_to_json(const FrameRecord& record) {
  const PairwiseResult& a = record.alignment;
  core::Json attempts = core::Json::array();
  for (const auto& attempt : record.failed_attempts)
    attempts.push_back({{"parent", attempt.parent}, {"mean_residual", attempt.mean_residual},
                        {"uncovered_fraction", attempt.uncovered_fraction},
                        {"stacked_fraction", attempt.stacked_fraction}, {"failure", attempt.failure}});
  return {{"sequence", record.sequence}, {"frame", record.frame}, {"node", record.node}, {"parent", record.parent},
          {"depth", record.depth}, {"seconds", record.seconds}, {"features", record.features},
          {"failed_attempts", attempts}, {"unrecovered", record.unrecovered},
          {"entry_attempts", record.entry_attempts},
          {"alignment",
           {{"patch_constraints", a.patch_constraints}, {"dense_constraints", a.dense_constraints},
            {"feature_constraints", a.feature_constraints}, {"color_constraints", a.color_constraints},
            {"coverage_constraints", a.coverage_constraints}, {"flow_pixels", a.flow_pixels},
            {"flow_vertices", a.flow_vertices}, {"accepted_patches", a.accepted_patches},
            {"total_patches", a.total_patches}, {"color_patches", a.color_patches}, {"predicted", a.predicted},
            {"predicted_patches", a.predicted_patches}, {"hinged_patches", a.hinged_patches},
            {"carried_patches", a.carried_patches}, {"heading_change", a.heading_change},
            {"mean_residual", a.mean_residual}, {"max_residual", a.max_residual},
            {"uncovered_fraction", a.uncovered_fraction}, {"stacked_fraction", a.stacked_fraction},
            {"merged_regions", a.merged_regions}, {"merged_fraction", a.merged_fraction},
            {"crease_constraints", a.crease_constraints}, {"holes", a.holes},
            {"largest_hole_perimeter", a.largest_hole_perimeter}, {"unobserved_fraction", a.unobserved_fraction},
            {"timings", {{"matching", a.timings.matching}, {"factorisation", a.timings.factorisation},
                         {"solves", a.timings.solves}}}}}};
}

FrameRecord record_from_json(const core::Json& j) {
  FrameRecord record;
  j.at("sequence").get_to(record.sequence);
  j.at("frame").get_to(record.frame);
  j.at("node").get_to(record.node);
  j.at("parent").get_to(record.parent);
  j.at("depth").get_to(record.depth);
  j.at("seconds").get_to(record.seconds);
  j.at("features").get_to(record.features);
  for (const auto& attempt : j.at("failed_attempts"))
    record.failed_attempts.push_back({attempt.at("parent").get<long>(), attempt.at("mean_residual").get<double>(),
                                      attempt.at("uncovered_fraction").get<double>(),
                                      attempt.at("stacked_fraction").get<double>(),
                                      attempt.at("failure").get<std::string>()});
  j.at("unrecovered").get_to(record.unrecovered);
  j.at("entry_attempts").get_to(record.entry_attempts);
  const core::Json& s = j.at("alignment");
  PairwiseResult& a = record.alignment;
  s.at("patch_constraints").get_to(a.patch_constraints);
  s.at("dense_constraints").get_to(a.dense_constraints);
  s.at("feature_constraints").get_to(a.feature_constraints);
  s.at("color_constraints").get_to(a.color_constraints);
  s.at("coverage_constraints").get_to(a.coverage_constraints);
  s.at("flow_pixels").get_to(a.flow_pixels);
  s.at("flow_vertices").get_to(a.flow_vertices);
  s.at("accepted_patches").get_to(a.accepted_patches);
  s.at("total_patches").get_to(a.total_patches);
  s.at("color_patches").get_to(a.color_patches);
  s.at("predicted").get_to(a.predicted);
  s.at("predicted_patches").get_to(a.predicted_patches);
  s.at("hinged_patches").get_to(a.hinged_patches);
  s.at("carried_patches").get_to(a.carried_patches);
  s.at("heading_change").get_to(a.heading_change);
  s.at("mean_residual").get_to(a.mean_residual);
  s.at("max_residual").get_to(a.max_residual);
  s.at("uncovered_fraction").get_to(a.uncovered_fraction);
  s.at("stacked_fraction").get_to(a.stacked_fraction);
  s.at("merged_regions").get_to(a.merged_regions);
  s.at("merged_fraction").get_to(a.merged_fraction);
  s.at("crease_constraints").get_to(a.crease_constraints);
  s.at("holes").get_to(a.holes);
  s.at("largest_hole_perimeter").get_to(a.largest_hole_perimeter);
  s.at("unobserved_fraction").get_to(a.unobserved_fraction);
  const core::Json& t = s.at("timings");
  t.at("matching").get_to(a.timings.matching);
  t.at("factorisation").get_to(a.timings.factorisation);
  t.at("solves").get_to(a.timings.solves);
  return record;
}

std::filesystem::path positions_path(const std::filesystem::path& path) {
  return std::filesystem::path(path).replace_extension(".npy");
}

/// Where two values differ, e.g. "/retries: 2, expected 3" (the first three JSON pointers).
std::string differences(const core::Json& found, const core::Json& expected) {
  const core::Json a = found.flatten(), b = expected.flatten();
  std::string text;
  int listed = 0;
  for (const auto& [pointer, value] : b.items()) {
    if (a.contains(pointer) && a.at(pointer) == value) continue;
    if (listed++ == 3) return text + ", …";
    text += (text.empty() ? "" : ", ") + (pointer.empty() ? "" : pointer + ": ") +
            (a.contains(pointer) ? a.at(pointer).dump() : "none") + ", expected " + value.dump();
  }
  for (const auto& [pointer, value] : a.items())
    if (!b.contains(pointer) && listed++ < 3) text += (text.empty() ? "" : ", ") + pointer + ": " + value.dump() + ", expected none";
  return text;
}

std::string producer(const PartLabel& label) {
  return label.shard == 0 ? "`surfcap-align register --trunk`"
                          : "`surfcap-align register --shard " + std::to_string(label.shard) + "/" +
                                std::to_string(label.shards) + "`";
}

}  // namespace

std::filesystem::path trunk_part_path(const std::filesystem::path& database) {
  return database / "register" / "trunk.json";
}

std::filesystem::path shard_part_path(const std::filesystem::path& database, int shard, int shards) {
  return database / "register" / ("shard-" + std::to_string(shard) + "-of-" + std::to_string(shards) + ".json");
}

core::Json part_context(const std::filesystem::path& database, const std::string& capture,
                        const RegisterOptions& options, const TreePartition& partition) {
  return {{"alignment", options.to_json()},
          {"capture", capture},
          {"tree_checksum", file_checksum(database / "similarity" / "tree.json")},
          {"matrix_checksum", file_checksum(similarity::matrix_path(database))},
          {"partition", {{"trunk", partition.trunk_size}, {"units", partition.units()}, {"bound", partition.bound}}}};
}

void write_registration_part(const std::filesystem::path& path, const PartLabel& label, const core::Json& context,
                             const RegistrationPart& part, const Registration& summary) {
  const std::size_t count = part.nodes.size();
  const auto vertices = static_cast<std::size_t>(count > 0 ? part.positions.front().rows() : summary.volume_vertices);
  std::vector<double> values;
  values.reserve(count * vertices * 3);
  for (const auto& positions : part.positions) {
    if (static_cast<std::size_t>(positions.rows()) != vertices || positions.cols() != 3)
      throw core::internal_error("write_registration_part: positions of different sizes");
    for (long v = 0; v < positions.rows(); ++v)
      for (int c = 0; c < 3; ++c) values.push_back(positions(v, c));
  }
  core::NpyArray array;
  array.dtype = core::DType::float64;
  array.shape = {count, vertices, 3};
  const auto* begin = reinterpret_cast<const std::byte*>(values.data());
  array.bytes.assign(begin, begin + values.size() * sizeof(double));
  core::write_npy(positions_path(path), array);

  core::Json records = core::Json::array();
  for (const auto& record : part.records) records.push_back(record_to_json(record));
  core::Json document = {{"format", core::format_tag("register_part", kPartVersion)},
                         {"shard", label.shard},
                         {"shards", label.shards},
                         {"units", label.units},
                         {"context", context},
                         {"nodes", part.nodes},
                         {"records", records},
                         {"positions", {{"file", positions_path(path).filename().string()},
                                        {"shape", array.shape},
                                        {"checksum", checksum(array.bytes)}}}};
  if (label.shard == 0)
    document["template"] = {{"deformer", summary.deformer_model}, {"volume_vertices", summary.volume_vertices},
                            {"elements", summary.elements}, {"seconds", summary.seconds_template},
                            {"appearance_coverage", summary.appearance_coverage},
                            {"observed_vertices", summary.template_observed_vertices},
                            {"unseen_vertices", summary.template_unseen_vertices},
                            {"softened_elements", summary.softened_elements},
                            {"cut_elements", summary.cut_elements},
                            {"cut_vertices", summary.template_cut_vertices}};
  core::write_json_file(path, document);
}

RegistrationPart read_registration_part(const std::filesystem::path& path, const PartLabel& label,
                                        const core::Json& context, const std::vector<long>& nodes,
                                        long volume_vertices, Registration* summary) {
  if (!std::filesystem::exists(path)) throw core::io_error(path, "missing: " + producer(label) + " writes it");
  const core::Json document = core::read_json_document(path, "register_part", kPartVersion);
  RegistrationPart part;
  try {
    if (document.at("shard") != label.shard || document.at("shards") != label.shards ||
        document.at("units") != core::Json(label.units))
      throw core::bad_input(path, "is not the part " + producer(label) + " writes for this tree");
    const core::Json& found = document.at("context");
    for (const auto& [key, value] : context.items())
      if (!found.contains(key) || found.at(key) != value)
        throw core::bad_input(path, "was aligned with another " + key + " (" +
                                        differences(found.contains(key) ? found.at(key) : core::Json(), value) +
                                        "): run " + producer(label) + " again");
    if (document.at("nodes") != core::Json(nodes))
      throw core::bad_input(path, "holds other nodes than the partition gives its job");
    for (const auto& record : document.at("records")) part.records.push_back(record_from_json(record));
    if (part.records.size() != nodes.size()) throw core::bad_input(path, "has not one record per node");
    if (summary && label.shard == 0) {
      const core::Json& t = document.at("template");
      t.at("deformer").get_to(summary->deformer_model);
      t.at("volume_vertices").get_to(summary->volume_vertices);
      t.at("elements").get_to(summary->elements);
      t.at("seconds").get_to(summary->seconds_template);
      t.at("appearance_coverage").get_to(summary->appearance_coverage);
      t.at("observed_vertices").get_to(summary->template_observed_vertices);
      t.at("unseen_vertices").get_to(summary->template_unseen_vertices);
      t.at("softened_elements").get_to(summary->softened_elements);
      t.at("cut_elements").get_to(summary->cut_elements);
      t.at("cut_vertices").get_to(summary->template_cut_vertices);
      volume_vertices = summary->volume_vertices;
      const auto& cut = summary->template_cut_vertices;
      for (std::size_t k = 0; k < cut.size(); ++k)
        if (cut[k] < 0 || cut[k] >= volume_vertices || (k > 0 && cut[k] <= cut[k - 1]))
          throw core::bad_input(path, "template.cut_vertices: not increasing vertex indices below volume_vertices");
    }
    const auto npy = positions_path(path);
    if (!std::filesystem::exists(npy)) throw core::io_error(npy, "missing: " + producer(label) + " writes it");
    const core::NpyArray array = core::read_npy(npy, core::DType::float64,
                                                {static_cast<long>(nodes.size()), volume_vertices, 3});
    if (checksum(array.bytes) != document.at("positions").at("checksum").get<std::string>())
      throw core::bad_input(npy, "is not the file " + path.filename().string() + " was written with: run " +
                                     producer(label) + " again");
    const double* values = array.data<double>();
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      Eigen::MatrixXd positions(volume_vertices, 3);
      for (long v = 0; v < volume_vertices; ++v)
        for (int c = 0; c < 3; ++c) positions(v, c) = *values++;
      part.positions.push_back(std::move(positions));
    }
  } catch (const core::Json::exception& error) {
    throw core::bad_input(path, std::string("malformed registration part: ") + error.what());
  }
  part.nodes = nodes;
  return part;
}

}  // namespace surfcap::align
