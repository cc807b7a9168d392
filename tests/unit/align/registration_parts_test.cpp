#include "surfcap/align/registration_parts.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::align {
namespace {

struct PartFolder {
  std::filesystem::path database =
      std::filesystem::temp_directory_path() / ("surfcap_parts_" + std::to_string(::getpid()));
  PartFolder() { std::filesystem::create_directories(database / "similarity"); }
  ~PartFolder() { std::filesystem::remove_all(database); }
};

RegistrationPart example_part(long volume_vertices) {
  RegistrationPart part;
  part.nodes = {2, 5};
  for (const long node : part.nodes) {
    FrameRecord record;
    record.sequence = "walk";
    record.frame = static_cast<int>(node);
    record.node = node;
    record.parent = node - 1;
    record.depth = 3;
    record.alignment.mean_residual = 1.0 / 3.0 + static_cast<double>(node) * 1e-17;
    record.alignment.max_residual = 0.1;
    record.alignment.patch_constraints = 17;
    record.alignment.predicted = true;
    record.failed_attempts.push_back({0, 0.004, 0.02, 0.0, "mean residual above the limit"});
    record.entry_attempts = 2;
    part.records.push_back(record);
    part.positions.push_back(Eigen::MatrixXd::Random(volume_vertices, 3) / 7.0);
  }
  return part;
}

/// The exit code and message of what `read` throws (0 when it does not).
template <class Read>
std::pair<int, std::string> refusal(const Read& read) {
  try {
    read();
  } catch (const core::Error& error) {
    return {error.exit_code(), error.what()};
  }
  return {0, ""};
}

TEST(RegistrationParts, APartReadsBackExactlyAndAMissingOrMismatchedPartIsRefusedByName) {
  const PartFolder folder;
  core::write_file_atomically(folder.database / "similarity" / "tree.json", std::string("{\"tree\": 1}\n"));
  RegisterOptions options;
  TreePartition partition;
  partition.trunk_size = 3;
  const core::Json context = part_context(folder.database, "capture", options, partition);
  const long vertices = 11;
  const RegistrationPart part = example_part(vertices);
  Registration summary;
  summary.volume_vertices = vertices;
  const PartLabel label{2, 3, {4, 6}};
  const auto path = shard_part_path(folder.database, 2, 3);
  EXPECT_EQ(path, folder.database / "register" / "shard-2-of-3.json");
  const auto read = [&](const PartLabel& expected, const core::Json& with, const std::vector<long>& nodes) {
    return read_registration_part(path, expected, with, nodes, vertices);
  };

  // Missing: I/O (4), naming the file and the job that writes it.
  auto [code, message] = refusal([&] { read(label, context, part.nodes); });
  EXPECT_EQ(code, 4);
  EXPECT_NE(message.find("shard-2-of-3.json"), std::string::npos) << message;
  EXPECT_NE(message.find("--shard 2/3"), std::string::npos) << message;

  write_registration_part(path, label, context, part, summary);
  const RegistrationPart back = read(label, context, part.nodes);
  ASSERT_EQ(back.nodes, part.nodes);
  for (std::size_t k = 0; k < part.nodes.size(); ++k) {
    EXPECT_EQ(back.positions[k], part.positions[k]) << "positions are exact doubles";
    EXPECT_EQ(back.records[k].alignment.mean_residual, part.records[k].alignment.mean_residual);
    EXPECT_EQ(back.records[k].alignment.patch_constraints, 17);
    EXPECT_TRUE(back.records[k].alignment.predicted);
    EXPECT_EQ(back.records[k].parent, part.records[k].parent);
    ASSERT_EQ(back.records[k].failed_attempts.size(), 1U);
    EXPECT_EQ(back.records[k].failed_attempts[0].failure, "mean residual above the limit");
    EXPECT_EQ(back.records[k].entry_attempts, 2);
  }

  // Mismatches: bad input (3), naming the file.
  RegisterOptions other_options;
  other_options.recovery.retries = 5;
  const core::Json other_context = part_context(folder.database, "capture", other_options, partition);
  std::tie(code, message) = refusal([&] { read(label, other_context, part.nodes); });
  EXPECT_EQ(code, 3);
  EXPECT_NE(message.find("shard-2-of-3.json"), std::string::npos) << message;
  EXPECT_NE(message.find("alignment"), std::string::npos) << message;
  std::tie(code, message) = refusal([&] { read({2, 4, {4, 6}}, context, part.nodes); });
  EXPECT_EQ(code, 3) << "another job count";
  std::tie(code, message) = refusal([&] { read(label, context, {2, 6}); });
  EXPECT_EQ(code, 3) << "other nodes";
  // Another tree (similarity/tree.json rewritten since): its checksum differs.
  core::write_file_atomically(folder.database / "similarity" / "tree.json", std::string("{\"tree\": 2}\n"));
  std::tie(code, message) = refusal(
      [&] { read(label, part_context(folder.database, "capture", options, partition), part.nodes); });
  EXPECT_EQ(code, 3);
  EXPECT_NE(message.find("tree_checksum"), std::string::npos) << message;
  // The .npy of another run of the job beside this JSON.
  RegistrationPart other = part;
  other.positions[1](3, 2) += 1e-12;
  const auto npy = folder.database / "register" / "shard-2-of-3.npy";
  const auto json = core::read_file(path);
  write_registration_part(path, label, context, other, summary);
  core::write_file_atomically(path, json);
  std::tie(code, message) = refusal([&] { read(label, context, part.nodes); });
  EXPECT_EQ(code, 3);
  EXPECT_NE(message.find("shard-2-of-3.npy"), std::string::npos) << message;
  std::filesystem::remove(npy);
  std::tie(code, message) = refusal([&] { read(label, context, part.nodes); });
  EXPECT_EQ(code, 4);
  EXPECT_NE(message.find("shard-2-of-3.npy"), std::string::npos) << message;
}

TEST(RegistrationParts, TheTrunkCarriesTheTemplatesFiguresAndRefusesCutVerticesOutsideIt) {
  const PartFolder folder;
  core::write_file_atomically(folder.database / "similarity" / "tree.json", std::string("{\"tree\": 1}\n"));
  TreePartition partition;
  partition.trunk_size = 3;
  const core::Json context = part_context(folder.database, "capture", RegisterOptions{}, partition);
  const long vertices = 11;
  const RegistrationPart part = example_part(vertices);
  Registration summary;
  summary.deformer_model = "tetrahedral";
  summary.volume_vertices = vertices;
  summary.elements = 40;
  summary.template_unseen_vertices = 2;
  summary.softened_elements = 3;
  summary.cut_elements = 4;
  summary.template_cut_vertices = {1, 6, 9};
  const PartLabel trunk{0, 0, {}};
  const auto path = trunk_part_path(folder.database);
  write_registration_part(path, trunk, context, part, summary);
  Registration back;
  read_registration_part(path, trunk, context, part.nodes, vertices, &back);
  EXPECT_EQ(back.deformer_model, "tetrahedral");
  EXPECT_EQ(back.elements, 40);
  EXPECT_EQ(back.softened_elements, 3);
  EXPECT_EQ(back.cut_elements, 4);
  EXPECT_EQ(back.template_cut_vertices, summary.template_cut_vertices);
  // A cut vertex beyond the volume (an edited or corrupted part): bad input (3), naming the file.
  for (const std::vector<long>& wrong : {std::vector<long>{1, 11}, std::vector<long>{-1, 2}, std::vector<long>{6, 1}}) {
    summary.template_cut_vertices = wrong;
    write_registration_part(path, trunk, context, part, summary);
    const auto [code, message] =
        refusal([&] { read_registration_part(path, trunk, context, part.nodes, vertices, &back); });
    EXPECT_EQ(code, 3);
    EXPECT_NE(message.find("cut_vertices"), std::string::npos) << message;
    EXPECT_NE(message.find("trunk.json"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace surfcap::align
