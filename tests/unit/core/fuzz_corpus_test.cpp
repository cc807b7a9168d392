// Every input of the fuzz seed corpus (tests/fuzz/corpus: valid seeds and the inputs that once
// crashed a reader) goes through the same readers as the fuzz targets: each must either load or
// fail with a core::Error (exit code 3 or 4), never crash or throw anything else.
#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <sstream>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/cli.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/mesh_repair.hpp"
#include "surfcap/core/npy.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

std::vector<std::filesystem::path> corpus(const std::string& target) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(SURFCAP_SOURCE_DIR) / "tests" /
                                                                 "fuzz" / "corpus" / target))
    files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes_of(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

/// Runs `read` and accepts success or a core::Error with a data/IO exit code.
template <class Read>
void expect_clean(const std::filesystem::path& input, Read read) {
  try {
    read();
  } catch (const core::Error& e) {
    EXPECT_TRUE(e.code() == core::ExitCode::bad_input || e.code() == core::ExitCode::io) << input << ": " << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << input << " threw a non-surfcap exception: " << e.what();
  }
}

/// Mesh seeds: the first byte picks the extension from `extensions` (as the fuzz target does),
/// the rest is the file; `read` gets the written path.
template <class Read>
void for_each_mesh_seed(const std::string& target, const std::array<const char*, 3>& extensions, Read read) {
  testing::TemporaryDirectory dir("fuzz_" + target);
  for (const auto& input : corpus(target)) {
    const std::string bytes = bytes_of(input);
    if (bytes.empty()) continue;
    const auto path = dir / (std::string("input") + extensions[static_cast<unsigned char>(bytes[0]) % 3]);
    testing::write_text(path, bytes.substr(1));
    expect_clean(input, [&] { read(input, path); });
  }
}

TEST(FuzzCorpus, MeshInputs) {
  for_each_mesh_seed("mesh", {".ply", ".obj", ".off"},
                     [](const std::filesystem::path&, const std::filesystem::path& path) { core::read_mesh(path); });
}

TEST(FuzzCorpus, RepairInputs) {
  for_each_mesh_seed("repair", {".obj", ".ply", ".off"},
                     [](const std::filesystem::path& input, const std::filesystem::path& path) {
                       const core::Mesh mesh = core::read_reconstruction(path, 1);
                       const core::MeshCheck check = core::check_mesh(mesh);
                       EXPECT_TRUE(check.closed() && check.manifold() && core::count_pinch_vertices(mesh) == 0)
                           << input << ": " << check.summary();
                     });
}

TEST(FuzzCorpus, NpyInputs) {
  for (const auto& input : corpus("npy")) expect_clean(input, [&] { core::read_npy(input); });
}

TEST(FuzzCorpus, JsonInputs) {
  testing::TemporaryDirectory dir("fuzz_json");
  for (const auto& input : corpus("json")) {
    const std::string bytes = bytes_of(input);
    if (bytes.empty()) continue;
    const auto path = dir / "input.json";
    testing::write_text(path, bytes.substr(1));
    switch (static_cast<unsigned char>(bytes[0]) % 4) {
      case 0: expect_clean(input, [&] { core::read_json_document(path, "graph", 1); }); break;
      case 1: expect_clean(input, [&] { core::read_capture(path); }); break;
      case 2: expect_clean(input, [&] { core::read_database(path); }); break;
      default: {
        std::istringstream stream(bytes.substr(1));
        expect_clean(input, [&] { core::JsonConfig().from_config(stream); });
      }
    }
  }
}

}  // namespace
}  // namespace surfcap
