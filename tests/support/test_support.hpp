#pragma once
// Helpers shared by the unit tests.

#include <filesystem>
#include <string>

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

}  // namespace surfcap::testing
