// The input policy (docs/reliability.md "Input policy"): paths in documents stay in their folder
// unless opted in, names that become paths are identifiers, only regular files are opened, JSON
// nesting is bounded, integers are checked, and requests are held to the memory budget.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/core/cli.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/json_integer.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using testing::TemporaryDirectory;
using testing::write_text;

/// The message of the core::Error `run` throws; fails unless it throws one with `code`.
template <class Run>
std::string error_of(Run run, core::ExitCode code = core::ExitCode::bad_input) {
  try {
    run();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return {};
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Restores the process-wide policy a test changes.
struct PolicyGuard {
  core::InputPolicy saved = core::input_policy();
  ~PolicyGuard() { core::input_policy() = saved; }
};

TEST(InputPolicy, DocumentPathsStayInTheirFolderUnlessOptedIn) {
  PolicyGuard guard;
  const std::filesystem::path document = "/data/capture/capture.json";
  EXPECT_EQ(core::resolve_document_path(document, "cameras", "cameras.json"), "/data/capture/cameras.json");
  EXPECT_EQ(core::resolve_document_path(document, "frames", "walk/./mesh/../mesh/0.ply"),
            "/data/capture/walk/./mesh/../mesh/0.ply");
  for (const std::string escaping : {"../x.ply", "walk/../../x.ply", "/etc/passwd", "a/../../../etc/shadow", ".."}) {
    const std::string message = error_of([&] { core::resolve_document_path(document, "cameras", escaping); });
    EXPECT_TRUE(contains(message, "capture.json")) << message;
    EXPECT_TRUE(contains(message, "\"cameras\"")) << message;
    EXPECT_TRUE(contains(message, "--allow-outside-paths")) << message;
  }
  EXPECT_TRUE(contains(error_of([&] { core::resolve_document_path(document, "cameras", ""); }), "empty path"));
  // Another base: paths of a space entry are relative to the output folder, not space.json's.
  EXPECT_EQ(core::resolve_document_path("/out/spaces/a/space.json", "references", "spaces/a/references.npy", "/out"),
            "/out/spaces/a/references.npy");
  core::input_policy().allow_outside_paths = true;
  EXPECT_EQ(core::resolve_document_path(document, "cameras", "/etc/passwd"), "/etc/passwd");
  EXPECT_EQ(core::resolve_document_path(document, "cameras", "../calib/cameras.json"), "/data/capture/../calib/cameras.json");
}

TEST(InputPolicy, NamesThatBecomePathsAreIdentifiers) {
  for (const std::string good : {"walk", "jump_low", "arm-l", "v1.2", "A0"})
    EXPECT_EQ(core::check_name("g.json", "name", good), good);
  for (const std::string& bad : std::vector<std::string>{"", "..", "../../escaped_space", "/abs", "a/b", "a\\b", ".hidden",
                                                         "with space", std::string(129, 'a'), std::string("nul\0x", 5),
                                                         "tab\t"}) {
    const std::string message = error_of([&] { core::check_name("g.json", "name", bad); });
    EXPECT_TRUE(contains(message, "g.json") && contains(message, "\"name\"")) << message;
  }
}

TEST(InputPolicy, OnlyRegularFilesAreOpened) {
  TemporaryDirectory dir("input_policy_files");
  write_text(dir / "a.json", "{}");
  EXPECT_EQ(core::check_regular_file(dir / "a.json"), 2u);
  EXPECT_TRUE(contains(error_of([&] { core::read_file(dir / "missing.json"); }, core::ExitCode::io), "no such file"));
  EXPECT_TRUE(contains(error_of([&] { core::read_file(dir.path()); }), "a directory"));
  ASSERT_EQ(::mkfifo((dir / "fifo.ply").c_str(), 0600), 0);
  // Nobody writes the FIFO: opening it would block for ever. Each reader refuses it at once.
  EXPECT_TRUE(contains(error_of([&] { core::read_file(dir / "fifo.ply"); }), "FIFO"));
  EXPECT_TRUE(contains(error_of([&] { core::read_mesh(dir / "fifo.ply", {}, 7); }), "(frame 7)"));
  EXPECT_TRUE(contains(error_of([&] { core::png_size(dir / "fifo.ply", 3); }), "FIFO"));
  EXPECT_TRUE(contains(error_of([&] { core::read_npy("/dev/zero"); }), "character device"));
  EXPECT_TRUE(contains(error_of([&] { core::read_json_file("/dev/urandom"); }), "character device"));
}

TEST(InputPolicy, JsonNestingIsBounded) {
  TemporaryDirectory dir("input_policy_json");
  const std::string deep = std::string(1'000'000, '[') + std::string(1'000'000, ']');
  write_text(dir / "deep.json", R"({"format": "surfcap.capture/1", "sequences": )" + deep + "}");
  const std::string message = error_of([&] { core::read_json_document(dir / "deep.json", "capture", 1); });
  EXPECT_TRUE(contains(message, "deep.json") && contains(message, "nested deeper than")) << message;
  // Brackets inside strings do not count; exactly the limit parses.
  const std::string at_limit = std::string(core::kMaxJsonDepth, '[') + std::string(core::kMaxJsonDepth, ']');
  EXPECT_NO_THROW(core::parse_json_text(at_limit, "x.json"));
  EXPECT_NO_THROW(core::parse_json_text(R"({"a": ")" + std::string(1000, '[') + R"(\" ["})", "x.json"));
  EXPECT_THROW(core::parse_json_text("[" + at_limit + "]", "x.json"), core::Error);
}

TEST(InputPolicy, TypedFieldsNameTheFileAndTheField) {
  const core::Json object = {{"count", 2147483648.0}, {"half", 2.5}, {"big", 4294967296}, {"name", 3}, {"ok", 7}};
  EXPECT_EQ(core::integer_field(object, "ok", "f.json", 0, 10), 7);
  EXPECT_EQ(core::integer_field_or(object, "absent", "f.json", 0, 10, 3), 3);
  for (const char* key : {"count", "half", "big"}) {
    const std::string message = error_of([&] { core::integer_field(object, key, "f.json", 0, 2147483647); });
    EXPECT_TRUE(contains(message, "f.json") && contains(message, key) && contains(message, "integer")) << message;
  }
  const std::string message = error_of([&] { core::get_field<std::string>(object, "name", "f.json"); });
  EXPECT_TRUE(contains(message, "f.json") && contains(message, "\"name\"")) << message;
  const std::string wrapped = error_of([&] {
    core::read_document_fields("g.json", [&] { return object.at("missing").get<int>(); });
  });
  EXPECT_TRUE(contains(wrapped, "g.json")) << wrapped;
  EXPECT_FALSE(contains(wrapped, "[json.exception")) << wrapped;
}

TEST(InputPolicy, NumbersAreFiniteAndPlausible) {
  const core::Json object = {{"fps", -25}, {"zero", 0}, {"huge", 1e308}, {"text", "x"}, {"ok", 30}};
  EXPECT_EQ(core::number_field(object, "ok", "c.json", 0, core::kMaxFps), 30);
  EXPECT_EQ(core::number_field(object, "absent", "c.json", 0, 1, 0.5), 0.5);
  for (const char* key : {"fps", "huge", "text", "absent"})
    EXPECT_TRUE(contains(error_of([&] { core::number_field(object, key, "c.json", 0, core::kMaxFps); }), "c.json"));
  EXPECT_TRUE(contains(error_of([&] { core::check_magnitude("e.json", "\"translate\"", 1e308, core::kMaxCoordinate); }),
                       "beyond the plausible magnitude"));
}

TEST(InputPolicy, RequestsAreHeldToTheMemoryBudget) {
  PolicyGuard guard;
  EXPECT_EQ(core::parse_memory_size("512M"), 512ull << 20);
  EXPECT_EQ(core::parse_memory_size("2G"), 2ull << 30);
  EXPECT_EQ(core::parse_memory_size("1000"), 1000u);
  EXPECT_THROW(core::parse_memory_size("lots"), core::Error);
  EXPECT_THROW(core::parse_memory_size("5X"), core::Error);
  EXPECT_GT(core::memory_budget(), 0u);
  core::input_policy().max_memory_bytes = 1 << 20;
  EXPECT_NO_THROW(core::check_memory("s.json", "a space", 1000));
  const std::string message = error_of([&] { core::check_memory("s.json", "space 'x' (1000000000 frames)", 1e12); });
  EXPECT_TRUE(contains(message, "s.json") && contains(message, "1000000000 frames") && contains(message, "--max-memory"))
      << message;
  // A whole-file read is a request too.
  TemporaryDirectory dir("input_policy_memory");
  write_text(dir / "big.json", std::string(2 << 20, ' '));
  EXPECT_TRUE(contains(error_of([&] { core::read_file(dir / "big.json"); }), "memory budget"));
}

}  // namespace
}  // namespace surfcap
