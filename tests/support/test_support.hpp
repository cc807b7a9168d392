#pragma once
// Helpers shared by the unit tests.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh.hpp"

namespace surfcap::testing {

/// A fresh empty directory under the build tree, removed when the object dies.
class TemporaryDirectory {
 public:
  explicit TemporaryDirectory(const std::string& name);
  ~TemporaryDirectory();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

/// Writes `text` to `path` (plain, non-atomic: for crafting bad inputs).
void write_text(const std::filesystem::path& path, const std::string& text);

/// A closed, manifold, genus-0 UV sphere of radius r (for tests that need a real surface).
core::Mesh make_sphere(int rings, int segments, double radius = 1.0);

/// Files in `directory` whose names start with '.' (leftover temporaries of atomic writes).
int count_hidden_files(const std::filesystem::path& directory);

/// Volume enclosed by the faces (positive when a closed surface faces outward).
double signed_volume(const core::Mesh& mesh);

/// `mesh` with only the faces f for which keep(f) holds (the vertices stay).
template <class Keep>
core::Mesh with_faces(const core::Mesh& mesh, Keep keep) {
  std::vector<long> kept;
  for (long f = 0; f < mesh.F.rows(); ++f)
    if (keep(f)) kept.push_back(f);
  core::Mesh out = mesh;
  out.F.resize(static_cast<long>(kept.size()), 3);
  for (std::size_t k = 0; k < kept.size(); ++k) out.F.row(static_cast<long>(k)) = mesh.F.row(kept[k]);
  return out;
}

/// Runs `action`, expecting bad_input (exit 3) with `needle` in its message.
template <class Action>
void expect_bad_input(Action action, const std::string& needle) {
  try {
    action();
    ADD_FAILURE() << "expected bad_input containing '" << needle << "'";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ExitCode::bad_input) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

}  // namespace surfcap::testing
