#include "surfcap/asset/vertex_order.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <numeric>
#include <utility>

#include "surfcap/core/error.hpp"

namespace surfcap::asset::detail {
namespace {

/// new_of_old[v] = the new index of vertex v.
std::vector<int> new_indices(const std::vector<std::uint32_t>& order) {
  std::vector<int> new_of_old(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) new_of_old[order[i]] = static_cast<int>(i);
  return new_of_old;
}

Eigen::MatrixXd rows_in_order(const Eigen::MatrixXd& matrix, const std::vector<std::uint32_t>& order) {
  if (matrix.rows() != static_cast<long>(order.size())) return matrix;  // absent (0 rows) or not per vertex
  Eigen::MatrixXd out(matrix.rows(), matrix.cols());
  for (std::size_t i = 0; i < order.size(); ++i) out.row(static_cast<long>(i)) = matrix.row(order[i]);
  return out;
}

core::Mesh mesh_in_order(const core::Mesh& mesh, const std::vector<std::uint32_t>& order,
                         const std::vector<int>& new_of_old) {
  core::Mesh out = mesh;
  out.V = rows_in_order(mesh.V, order);
  out.colors = rows_in_order(mesh.colors, order);
  out.uvs = rows_in_order(mesh.uvs, order);
  for (long i = 0; i < out.F.size(); ++i) out.F.data()[i] = new_of_old[static_cast<std::size_t>(mesh.F.data()[i])];
  return out;
}

void renumber(std::vector<int>& indices, const std::vector<int>& new_of_old) {
  for (int& v : indices) v = new_of_old[static_cast<std::size_t>(v)];
}

/// References [N][T][V][3] in the new order and each displacement row renumbered, ascending again.
void space_in_order(CharacterSpace& space, const std::vector<std::uint32_t>& order, const std::vector<int>& new_of_old) {
  const std::size_t vertices = order.size(), block = 3 * vertices;
  std::vector<float> references(space.references.size());
  for (std::size_t start = 0; start + block <= references.size(); start += block)
    for (std::size_t i = 0; i < vertices; ++i)
      for (int k = 0; k < 3; ++k) references[start + 3 * i + k] = space.references[start + 3 * order[i] + k];
  space.references = std::move(references);
  std::vector<std::pair<std::int32_t, std::size_t>> row;
  std::vector<std::int32_t> row_vertices;
  std::vector<std::uint16_t> row_values;
  for (std::size_t r = 0; r + 1 < space.displacement_offsets.size(); ++r) {
    const auto begin = static_cast<std::size_t>(space.displacement_offsets[r]);
    const auto end = static_cast<std::size_t>(space.displacement_offsets[r + 1]);
    row.clear();
    for (std::size_t k = begin; k < end; ++k)
      row.emplace_back(new_of_old[static_cast<std::size_t>(space.displacement_vertices[k])], k);
    std::sort(row.begin(), row.end());
    row_vertices.clear();
    row_values.clear();
    for (const auto& [vertex, k] : row) {
      row_vertices.push_back(vertex);
      row_values.insert(row_values.end(), space.displacement_values.begin() + static_cast<long>(3 * k),
                        space.displacement_values.begin() + static_cast<long>(3 * k + 3));
    }
    std::copy(row_vertices.begin(), row_vertices.end(), space.displacement_vertices.begin() + static_cast<long>(begin));
    std::copy(row_values.begin(), row_values.end(), space.displacement_values.begin() + static_cast<long>(3 * begin));
  }
}

}  // namespace

std::vector<std::uint32_t> compression_vertex_order(const Eigen::MatrixXi& faces, long vertices) {
  std::vector<unsigned int> indices(static_cast<std::size_t>(faces.size()));
  for (long f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) indices[static_cast<std::size_t>(3 * f + k)] = static_cast<unsigned int>(faces(f, k));
  const auto n = static_cast<std::size_t>(vertices);
  std::vector<unsigned int> optimised(indices.size()), remap(n);
  meshopt_optimizeVertexCache(optimised.data(), indices.data(), indices.size(), n);
  const std::size_t used = meshopt_optimizeVertexFetchRemap(remap.data(), optimised.data(), optimised.size(), n);
  std::vector<std::uint32_t> order(n);
  std::size_t next = used;  // vertices no face uses (remap ~0u) go last, in their own order
  for (std::size_t v = 0; v < n; ++v) order[remap[v] == ~0u ? next++ : remap[v]] = static_cast<std::uint32_t>(v);
  return order;
}

Character reorder_vertices(const Character& character, const std::vector<std::uint32_t>& order) {
  const std::vector<int> new_of_old = new_indices(order);
  Character out = character;
  out.template_mesh = mesh_in_order(character.template_mesh, order, new_of_old);
  for (auto& sequence : out.sequences)
    for (Eigen::MatrixXd& frame : sequence.frames) frame = rows_in_order(frame, order);
  for (CharacterSpace& space : out.spaces) space_in_order(space, order, new_of_old);
  if (out.parts) {
    out.parts->template_mesh = mesh_in_order(character.parts->template_mesh, order, new_of_old);
    for (learn::PartModel& part : out.parts->parts) {
      renumber(part.part.vertices, new_of_old);
      renumber(part.part.frontier, new_of_old);
    }
    for (auto& [name, region] : out.parts->regions) renumber(region, new_of_old);
  }
  return out;
}

std::vector<std::uint32_t> inverse_order(const std::vector<std::uint32_t>& order, long vertices,
                                         const std::filesystem::path& source) {
  if (static_cast<long>(order.size()) != vertices)
    throw core::bad_input(source, "vertexOrder does not list every template vertex");
  std::vector<std::uint32_t> inverse(order.size(), ~0u);
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (order[i] >= order.size() || inverse[order[i]] != ~0u)
      throw core::bad_input(source, "vertexOrder is not a permutation of the template vertices");
    inverse[order[i]] = static_cast<std::uint32_t>(i);
  }
  return inverse;
}

}  // namespace surfcap::asset::detail
