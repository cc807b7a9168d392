#include "surfcap/learn/part_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_integer.hpp"
#include "surfcap/geometry/mesh_topology.hpp"

namespace surfcap::learn {
namespace {

std::vector<int> intersection(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> out;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

std::vector<int> sorted_unique(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

std::vector<int> vertex_list(const core::Json& value, long vertex_count, const std::filesystem::path& source,
                             const std::string& what) {
  if (!value.is_array()) throw core::bad_input(source, what + ": \"vertices\" must be an array of indices");
  std::vector<int> out;
  for (const auto& item : value) {
    if (!item.is_number_integer()) throw core::bad_input(source, what + ": vertex indices must be integers");
    const long v = item.get<long>();
    if (v < 0 || v >= vertex_count)
      throw core::bad_input(source, what + ": vertex " + std::to_string(v) + " out of range (template has " +
                                        std::to_string(vertex_count) + ")");
    out.push_back(static_cast<int>(v));
  }
  return sorted_unique(out);
}

}  // namespace

int PartSet::find(const std::string& name) const {
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (parts[i].name == name) return static_cast<int>(i);
  return -1;
}

void finalise_hierarchy(PartSet& set, long vertex_count, const std::filesystem::path& source) {
  const std::size_t count = set.parts.size();
  if (count == 0) throw core::bad_input(source, "no parts");
  int roots = 0;
  for (const Part& p : set.parts) {
    if (p.vertices.empty()) throw core::bad_input(source, "part '" + p.name + "' has no vertices");
    if (p.parent < 0) ++roots;
    if (p.parent >= static_cast<int>(count)) throw core::bad_input(source, "part '" + p.name + "': bad parent");
  }
  if (roots != 1) throw core::bad_input(source, "the part hierarchy must have exactly one root, found " +
                                                    std::to_string(roots));
  // Order: breadth first from the root, children in their original order.
  std::vector<int> order;
  for (std::size_t i = 0; i < count; ++i)
    if (set.parts[i].parent < 0) order.push_back(static_cast<int>(i));
  for (std::size_t k = 0; k < order.size(); ++k)
    for (std::size_t i = 0; i < count; ++i)
      if (set.parts[i].parent == order[k]) order.push_back(static_cast<int>(i));
  if (order.size() != count) throw core::bad_input(source, "the part hierarchy has a cycle");
  std::vector<int> new_index(count);
  for (std::size_t k = 0; k < count; ++k) new_index[order[k]] = static_cast<int>(k);
  std::vector<Part> sorted;
  for (int i : order) {
    Part p = set.parts[i];
    if (p.parent >= 0) p.parent = new_index[p.parent];
    sorted.push_back(std::move(p));
  }
  set.parts = std::move(sorted);
  std::vector<char> covered(static_cast<std::size_t>(vertex_count), 0);
  for (Part& p : set.parts) {
    p.vertices = sorted_unique(p.vertices);
    for (int v : p.vertices) covered.at(v) = 1;
    p.frontier.clear();
    if (p.parent >= 0) {
      p.frontier = intersection(p.vertices, set.parts[p.parent].vertices);
      if (p.frontier.empty())
        throw core::bad_input(source, "part '" + p.name + "' shares no vertex with its parent '" +
                                          set.parts[p.parent].name + "'");
    }
  }
  const long uncovered = std::count(covered.begin(), covered.end(), 0);
  if (uncovered > 0)
    throw core::bad_input(source, std::to_string(uncovered) + " template vertices belong to no part");
}

void build_hierarchy_by_sharing(PartSet& set, const std::string& root, long vertex_count) {
  const int count = static_cast<int>(set.parts.size());
  int root_index = root.empty() ? -1 : set.find(root);
  if (root_index < 0) {
    root_index = 0;
    for (int i = 1; i < count; ++i)
      if (set.parts[i].vertices.size() > set.parts[root_index].vertices.size()) root_index = i;
  }
  std::vector<char> placed(count, 0);
  placed[root_index] = 1;
  set.parts[root_index].parent = -1;
  // Prim-like: attach the unplaced part sharing most vertices with a placed part.
  for (int step = 1; step < count; ++step) {
    std::size_t best_shared = 0;
    int best_child = -1, best_parent = -1;
    for (int c = 0; c < count; ++c) {
      if (placed[c]) continue;
      for (int p = 0; p < count; ++p) {
        if (!placed[p]) continue;
        const std::size_t shared = intersection(set.parts[c].vertices, set.parts[p].vertices).size();
        if (shared > best_shared) best_shared = shared, best_child = c, best_parent = p;
      }
    }
    if (best_child < 0) throw core::bad_input("parts", "automatic parts do not overlap: cannot build a hierarchy");
    placed[best_child] = 1;
    set.parts[best_child].parent = best_parent;
  }
  finalise_hierarchy(set, vertex_count, "automatic parts");
}

Extremities find_extremities(const core::Mesh& mesh) {
  const auto adjacency = geometry::vertex_adjacency(mesh.F, mesh.vertex_count());
  const Eigen::RowVector3d centroid = mesh.V.colwise().mean();
  Extremities result;
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    const double d = (mesh.V.row(v) - centroid).squaredNorm();
    if (!adjacency[v].empty() && d < best) best = d, result.centre = static_cast<int>(v);
  }
  const std::vector<double> from_centre = geometry::edge_geodesic_distance(mesh.V, adjacency, {result.centre});
  // Farthest-point sampling on geodesic distance from {centre, extremities found so far}.
  std::vector<double> nearest = from_centre;
  std::vector<int> found;
  for (int k = 0; k < 5; ++k) {
    int far = -1;
    double far_distance = -1;
    for (std::size_t v = 0; v < nearest.size(); ++v)
      if (std::isfinite(nearest[v]) && nearest[v] > far_distance) far_distance = nearest[v], far = static_cast<int>(v);
    found.push_back(far);
    const auto d = geometry::edge_geodesic_distance(mesh.V, adjacency, {far});
    for (std::size_t v = 0; v < nearest.size(); ++v) nearest[v] = std::min(nearest[v], d[v]);
  }
  // Feet: the two lowest; head: the highest of the rest; hands: the other two; left = +x.
  std::sort(found.begin(), found.end(), [&](int a, int b) { return mesh.V(a, 1) < mesh.V(b, 1); });
  const double cx = mesh.V(result.centre, 0);
  auto side = [&](int a, int b, const std::string& stem) {
    const bool a_left = mesh.V(a, 0) - cx >= mesh.V(b, 0) - cx;
    result.vertices[stem + "_l"] = a_left ? a : b;
    result.vertices[stem + "_r"] = a_left ? b : a;
  };
  side(found[0], found[1], "foot");
  result.vertices["head"] = found[4];
  side(found[2], found[3], "hand");
  for (const auto& [name, v] : result.vertices) result.reach[name] = from_centre[v];
  return result;
}

namespace {

/// The vertex sets a part config names on the template: extremity regions (geodesic balls around
/// the extremities) and the overlap of a part into its neighbours.
class PartRegions {
 public:
  PartRegions(const core::Json& config, const core::Mesh& mesh, const std::filesystem::path& source)
      : mesh_(mesh), source_(source), adjacency_(geometry::vertex_adjacency(mesh.F, mesh.vertex_count())) {
    bool needs_extremities = false;
    for (const auto& p : config["parts"]) needs_extremities |= p.contains("extremity");
    if (config.contains("regions"))
      for (const auto& [name, r] : config["regions"].items()) needs_extremities |= r.contains("extremity");
    if (needs_extremities) extremities_ = find_extremities(mesh);
  }

  long vertex_count() const { return mesh_.vertex_count(); }

  /// {"extremity": name, "extent": e}: the vertices within e × the extremity's reach of it.
  std::vector<int> extremity_region(const core::Json& rule, const std::string& what) const {
    const auto name = core::get_field<std::string>(rule, "extremity", source_);
    if (!extremities_.vertices.count(name))
      throw core::bad_input(source_, what + ": unknown extremity '" + name + "' (head, hand_l, hand_r, foot_l, foot_r)");
    const double extent = core::get_field<double>(rule, "extent", source_);
    const int seed = extremities_.vertices.at(name);
    const auto d = geometry::edge_geodesic_distance(mesh_.V, adjacency_, {seed});
    std::vector<int> out;
    for (long v = 0; v < vertex_count(); ++v)
      if (d[v] <= extent * extremities_.reach.at(name)) out.push_back(static_cast<int>(v));
    return out;
  }

  /// A part's core grown into its neighbours: by geodesic distance ("overlap", metres, survives
  /// remeshing) and/or by rings ("overlap_rings").
  std::vector<int> with_overlap(const core::Json& part, const std::vector<int>& core_vertices) const {
    std::vector<int> vertices = core_vertices;
    const double overlap = core::number_field(part, "overlap", source_, 0, core::kMaxCoordinate, 0.0);
    if (overlap > 0 && !core_vertices.empty()) {
      const auto d = geometry::edge_geodesic_distance(mesh_.V, adjacency_, core_vertices);
      vertices.clear();
      for (long v = 0; v < vertex_count(); ++v)
        if (d[v] <= overlap) vertices.push_back(static_cast<int>(v));
    }
    const int rings = static_cast<int>(core::integer_field_or(part, "overlap_rings", source_, 0, 1000, 0));
    if (rings > 0) vertices = geometry::grow_region(adjacency_, vertices, rings);
    return vertices;
  }

 private:
  const core::Mesh& mesh_;
  const std::filesystem::path& source_;
  std::vector<std::vector<int>> adjacency_;
  Extremities extremities_;
};

/// The vertices of no part's core (the "rest" part).
std::vector<int> vertices_outside(const std::vector<std::vector<int>>& cores, long vertex_count) {
  std::vector<char> taken(static_cast<std::size_t>(vertex_count), 0);
  for (const auto& core_vertices : cores)
    for (int v : core_vertices) taken[v] = 1;
  std::vector<int> rest;
  for (long v = 0; v < vertex_count; ++v)
    if (!taken[v]) rest.push_back(static_cast<int>(v));
  return rest;
}

/// Sets each part's parent from its configured parent name ("" for none).
void link_parents(PartSet& set, const std::vector<std::string>& parent_names, const std::filesystem::path& source) {
  for (std::size_t i = 0; i < set.parts.size(); ++i) {
    if (parent_names[i].empty()) continue;
    set.parts[i].parent = set.find(parent_names[i]);
    if (set.parts[i].parent < 0)
      throw core::bad_input(source, "part '" + set.parts[i].name + "': unknown parent '" + parent_names[i] + "'");
  }
}

}  // namespace

PartSet evaluate_part_config(const core::Json& config, const core::Mesh& mesh, const std::filesystem::path& source) {
  if (!config.contains("parts") || !config["parts"].is_array())
    throw core::bad_input(source, "missing \"parts\" array");
  const PartRegions regions(config, mesh, source);
  PartSet set;
  std::vector<std::string> parent_names;
  std::vector<std::vector<int>> cores;
  int rest_index = -1;
  for (const auto& p : config["parts"]) {
    Part part;
    part.name = core::name_field(p, "name", source);  // it names the part's model files
    const std::string what = "part '" + part.name + "'";
    parent_names.push_back(p.value("parent", std::string()));
    std::vector<int> core_vertices;
    if (p.contains("vertices")) {
      core_vertices = vertex_list(p["vertices"], regions.vertex_count(), source, what);
    } else if (p.contains("extremity")) {
      core_vertices = regions.extremity_region(p, what);
    } else if (p.value("rest", false)) {
      if (rest_index >= 0) throw core::bad_input(source, "only one part may be \"rest\"");
      rest_index = static_cast<int>(set.parts.size());
    } else {
      throw core::bad_input(source, what + ": give \"vertices\", \"extremity\"+\"extent\" or \"rest\": true");
    }
    part.vertices = regions.with_overlap(p, core_vertices);
    cores.push_back(core_vertices);
    set.parts.push_back(std::move(part));
  }
  if (rest_index >= 0) {
    const std::vector<int> rest = vertices_outside(cores, regions.vertex_count());
    auto& vertices = set.parts[rest_index].vertices;
    vertices.insert(vertices.end(), rest.begin(), rest.end());
  }
  link_parents(set, parent_names, source);
  if (config.contains("regions")) {
    for (const auto& [name, r] : config["regions"].items()) {
      const std::string what = "region '" + core::check_name(source, "regions", name) + "'";
      set.regions[name] = r.contains("vertices") ? vertex_list(r["vertices"], regions.vertex_count(), source, what)
                                                 : regions.extremity_region(r, what);
      if (set.regions[name].empty()) throw core::bad_input(source, what + " is empty");
    }
  }
  finalise_hierarchy(set, regions.vertex_count(), source);
  return set;
}

PartSet read_part_config(const std::filesystem::path& path, const core::Mesh& mesh) {
  const core::Json config = core::read_json_document(path, "part_config", 1);
  return core::read_document_fields(path, [&] { return evaluate_part_config(config, mesh, path); });
}

core::Json part_config_with_vertex_lists(const PartSet& set) {
  core::Json config = {{"format", core::format_tag("part_config", 1)}};
  config["parts"] = core::Json::array();
  for (const Part& p : set.parts) {
    core::Json part = {{"name", p.name}, {"vertices", p.vertices}};
    if (p.parent >= 0) part["parent"] = set.parts[p.parent].name;
    config["parts"].push_back(part);
  }
  config["regions"] = core::Json::object();
  for (const auto& [name, vertices] : set.regions) config["regions"][name] = {{"vertices", vertices}};
  return config;
}

Eigen::VectorXd frontier_blend_weights(const Part& part, const std::vector<std::vector<int>>& adjacency) {
  Eigen::VectorXd weights = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(part.vertices.size()));
  if (part.frontier.empty()) return weights;
  std::vector<int> own;
  std::set_difference(part.vertices.begin(), part.vertices.end(), part.frontier.begin(), part.frontier.end(),
                      std::back_inserter(own));
  if (own.empty()) return weights;
  const std::vector<int> rings = geometry::ring_distance(adjacency, own);
  int deepest = 0;
  for (int v : part.frontier) deepest = std::max(deepest, rings[v]);
  for (std::size_t i = 0; i < part.vertices.size(); ++i) {
    const int v = part.vertices[i];
    if (!std::binary_search(part.frontier.begin(), part.frontier.end(), v)) continue;
    // Ring 1 (touching the part's own region) keeps most of the part; the deepest ring none.
    const int r = rings[v] < 0 ? deepest : rings[v];
    weights[static_cast<Eigen::Index>(i)] = deepest > 0 ? 1.0 - static_cast<double>(r) / deepest : 0.0;
  }
  return weights;
}

}  // namespace surfcap::learn
