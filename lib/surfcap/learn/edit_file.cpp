#include "surfcap/learn/edit_file.hpp"

#include <algorithm>
#include <set>

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"

namespace surfcap::learn {
static std::vector<Constraint> edit_constraints_unchecked(const core::Json& edit, const PartSet& parts,
                                                          const Eigen::MatrixXd& reference,
                                                          const std::filesystem::path& source);

std::vector<int> select_vertices(const core::Json& selector, const PartSet& parts, long vertex_count,
                                 const std::filesystem::path& source) {
  std::vector<int> out;
  if (selector.contains("vertices")) {
    for (const auto& v : selector["vertices"]) {
      if (!v.is_number_integer() || v.get<long>() < 0 || v.get<long>() >= vertex_count)
        throw core::bad_input(source, "vertex index " + v.dump() + " out of range");
      out.push_back(v.get<int>());
    }
  } else if (selector.contains("region")) {
    const auto name = core::get_field<std::string>(selector, "region", source);
    auto found = parts.regions.find(name);
    if (found == parts.regions.end()) throw core::bad_input(source, "unknown region '" + name + "'");
    out = found->second;
  } else if (selector.contains("part") || selector.contains("part_core")) {
    const bool core_only = selector.contains("part_core");
    const auto name = core::get_field<std::string>(selector, core_only ? "part_core" : "part", source);
    const int j = parts.find(name);
    if (j < 0) throw core::bad_input(source, "unknown part '" + name + "'");
    std::set<int> others;
    if (core_only)
      for (std::size_t k = 0; k < parts.parts.size(); ++k)
        if (static_cast<int>(k) != j) others.insert(parts.parts[k].vertices.begin(), parts.parts[k].vertices.end());
    for (int v : parts.parts[j].vertices)
      if (!others.count(v)) out.push_back(v);
  } else {
    throw core::bad_input(source, "a handle or anchor needs \"vertices\", \"region\", \"part\" or \"part_core\"");
  }
  if (out.empty()) throw core::bad_input(source, "a handle or anchor selects no vertex");
  return out;
}

std::vector<Constraint> edit_constraints(const core::Json& edit, const PartSet& parts, const Eigen::MatrixXd& reference,
                                         const std::filesystem::path& source) {
  return core::read_document_fields(source, [&] { return edit_constraints_unchecked(edit, parts, reference, source); });
}

std::vector<Constraint> edit_constraints_unchecked(const core::Json& edit, const PartSet& parts,
                                                   const Eigen::MatrixXd& reference, const std::filesystem::path& source) {
  std::vector<Constraint> constraints;
  const long n = reference.rows();
  auto vector3 = [&](const core::Json& value, const std::string& what) {
    if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() || !value[2].is_number())
      throw core::bad_input(source, what + " must be [x, y, z] (numbers)");
    Eigen::Vector3d vector;
    for (int k = 0; k < 3; ++k) vector(k) = core::check_magnitude(source, what, value[k].get<double>(), core::kMaxCoordinate);
    return vector;
  };
  for (const auto& anchor : edit.value("anchors", core::Json::array())) {
    const double weight = core::number_field(anchor, "weight", source, 0, 1e9, 1.0);
    for (int v : select_vertices(anchor, parts, n, source)) constraints.push_back({v, reference.row(v).transpose(), weight});
  }
  for (const auto& handle : edit.value("handles", core::Json::array())) {
    const double weight = core::number_field(handle, "weight", source, 0, 1e9, 1.0);
    if (!(weight > 0)) throw core::bad_input(source, "handle weight must be > 0");
    const std::vector<int> vertices = select_vertices(handle, parts, n, source);
    if (handle.contains("positions")) {
      const auto& positions = handle["positions"];
      if (!positions.is_array() || positions.size() != vertices.size())
        throw core::bad_input(source, "\"positions\" must hold one [x, y, z] per selected vertex");
      for (std::size_t i = 0; i < vertices.size(); ++i)
        constraints.push_back({vertices[i], vector3(positions[i], "a position"), weight});
    } else {
      const Eigen::Vector3d shift = handle.contains("translate") ? vector3(handle["translate"], "\"translate\"")
                                                                 : Eigen::Vector3d::Zero();
      for (int v : vertices) constraints.push_back({v, reference.row(v).transpose() + shift, weight});
    }
  }
  if (constraints.empty()) throw core::bad_input(source, "the edit has no handles or anchors");
  return constraints;
}

}  // namespace surfcap::learn
