#include "surfcap/core/mesh_repair.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/surface_topology.hpp"

namespace surfcap::core {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Polygon = std::array<std::size_t, 3>;

/// Union-find over face corners (3 f + k).
class CornerSets {
 public:
  explicit CornerSets(std::size_t size) : parent_(size) {
    for (std::size_t i = 0; i < size; ++i) parent_[i] = i;
  }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace

long count_pinch_vertices(const Mesh& mesh, long* first) {
  struct Use {
    std::uint64_t key;  // min(a,b) << 32 | max(a,b)
    bool forward;       // a < b
    std::size_t corner; // 3 f + k: the edge runs from corner k of face f to the next corner
    bool operator<(const Use& other) const { return key != other.key ? key < other.key : corner < other.corner; }
  };
  const auto& F = mesh.F;
  std::vector<Use> uses;
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint32_t>(F(f, k)), b = static_cast<std::uint32_t>(F(f, (k + 1) % 3));
      uses.push_back({(std::uint64_t{std::min(a, b)} << 32) | std::max(a, b), a < b, static_cast<std::size_t>(3 * f + k)});
    }
  std::sort(uses.begin(), uses.end());
  // Corners at one vertex joined across every shared edge (manifold or not): more than one group
  // left at a vertex means separate fans meet there.
  CornerSets corners(uses.size());
  auto at = [](const Use& use, int step) { return use.corner - use.corner % 3 + (use.corner % 3 + step) % 3; };
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    for (std::size_t u = i + 1; u < j; ++u) {
      const bool same = uses[u].forward == uses[i].forward;
      corners.join(at(uses[i], 0), at(uses[u], same ? 0 : 1));
      corners.join(at(uses[i], 1), at(uses[u], same ? 1 : 0));
    }
    i = j;
  }
  std::vector<std::pair<long, std::size_t>> groups;  // (vertex, corner group)
  for (std::size_t c = 0; c < uses.size(); ++c) groups.emplace_back(F(static_cast<long>(c / 3), static_cast<long>(c % 3)), corners.find(c));
  std::sort(groups.begin(), groups.end());
  groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
  long count = 0;
  for (std::size_t i = 0; i < groups.size();) {
    std::size_t j = i;
    while (j < groups.size() && groups[j].first == groups[i].first) ++j;
    if (j - i > 1) {
      if (count == 0 && first) *first = groups[i].first;
      ++count;
    }
    i = j;
  }
  return count;
}

namespace {

/// Records which input vertex each duplicated one copies, and how many faces were flipped.
struct OrientationRecorder : PMP::Default_orientation_visitor {
  std::vector<std::pair<std::size_t, std::size_t>>* duplicates = nullptr;  // (original, copy)
  long* reversed = nullptr;
  void duplicated_vertex(std::size_t original, std::size_t copy) { duplicates->emplace_back(original, copy); }
  void polygon_orientation_reversed(std::size_t) { ++*reversed; }
};

/// Oriented, manifold polygon soup of `mesh`; `source_of[v]` is the input vertex of soup vertex v.
struct Soup {
  std::vector<Point> points;
  std::vector<Polygon> polygons;
  std::vector<long> source_of;
};

Soup oriented_soup(const Mesh& mesh, RepairReport& report) {
  Soup soup;
  for (long v = 0; v < mesh.V.rows(); ++v) soup.points.emplace_back(mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
  for (long f = 0; f < mesh.F.rows(); ++f)
    soup.polygons.push_back({static_cast<std::size_t>(mesh.F(f, 0)), static_cast<std::size_t>(mesh.F(f, 1)),
                             static_cast<std::size_t>(mesh.F(f, 2))});
  std::vector<std::pair<std::size_t, std::size_t>> duplicates;
  OrientationRecorder recorder;
  recorder.duplicates = &duplicates;
  recorder.reversed = &report.faces_reoriented;
  PMP::orient_polygon_soup(soup.points, soup.polygons, CGAL::parameters::visitor(recorder));
  soup.source_of.resize(soup.points.size());
  for (long v = 0; v < mesh.V.rows(); ++v) soup.source_of[static_cast<std::size_t>(v)] = v;
  for (const auto& [original, copy] : duplicates)
    soup.source_of[copy] = soup.source_of[original];  // copies of copies resolve to the input vertex
  report.vertices_duplicated = static_cast<long>(duplicates.size());
  return soup;
}

/// Surface mesh whose vertex i is soup point i (so source_of keeps holding).
SurfaceMesh surface_of(const Soup& soup, const std::filesystem::path& source, std::optional<long> frame) {
  if (!PMP::is_polygon_soup_a_polygon_mesh(soup.polygons))
    throw bad_input(source, "non-manifold surface that could not be split into a manifold one", frame);
  SurfaceMesh surface;
  for (const Point& p : soup.points) surface.add_vertex(p);
  for (const Polygon& polygon : soup.polygons) {
    const auto face = surface.add_face(SurfaceMesh::Vertex_index(static_cast<SurfaceMesh::size_type>(polygon[0])),
                                       SurfaceMesh::Vertex_index(static_cast<SurfaceMesh::size_type>(polygon[1])),
                                       SurfaceMesh::Vertex_index(static_cast<SurfaceMesh::size_type>(polygon[2])));
    if (face == SurfaceMesh::null_face())
      throw bad_input(source, "non-manifold surface that could not be split into a manifold one", frame);
  }
  return surface;
}

/// Connected pieces of a surface; a piece of at most max_debris_faces beside a larger one is debris.
struct Pieces {
  SurfaceMesh::Property_map<SurfaceMesh::Face_index, std::size_t> of;
  std::vector<char> debris;
};

Pieces find_pieces(SurfaceMesh& surface, const RepairLimits& limits, RepairReport& report) {
  Pieces pieces;
  pieces.of = surface.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:surfcap_piece", 0).first;
  const std::size_t count = PMP::connected_components(surface, pieces.of);
  std::vector<long> faces_of(count, 0);
  for (const auto f : surface.faces()) ++faces_of[pieces.of[f]];
  const long biggest = count == 0 ? 0 : *std::max_element(faces_of.begin(), faces_of.end());
  pieces.debris.assign(count, 0);
  for (std::size_t c = 0; c < count; ++c)
    if (faces_of[c] <= limits.max_debris_faces && biggest > limits.max_debris_faces) {
      pieces.debris[c] = 1;
      ++report.debris_components;
      report.debris_faces += faces_of[c];
    }
  return pieces;
}

/// Fills the holes of every piece but debris; the new faces join the hole's piece. Holes beyond
/// the limits are refused, or left open with keep_large_holes_open.
void fill_holes(SurfaceMesh& surface, Pieces& pieces, const Eigen::MatrixXd& input_vertices, const RepairLimits& limits,
                RepairReport& report, const std::filesystem::path& source, std::optional<long> frame) {
  std::vector<SurfaceMesh::Halfedge_index> all, holes;
  PMP::extract_boundary_cycles(surface, std::back_inserter(all));
  for (const auto h : all)
    if (!pieces.debris[pieces.of[surface.face(surface.opposite(h))]]) holes.push_back(h);
  const bool keep_open = limits.keep_large_holes_open;
  if (!keep_open && static_cast<long>(holes.size()) > limits.max_holes)
    throw bad_input(source, "open surface with " + std::to_string(holes.size()) + " holes: too many to fill (up to " +
                                std::to_string(limits.max_holes) + " are repaired)", frame);
  std::vector<long> sizes;
  std::vector<double> perimeters;
  for (const auto h : holes) {
    double perimeter = 0;
    for (const auto e : CGAL::halfedges_around_face(h, surface))
      perimeter += std::sqrt(CGAL::squared_distance(surface.point(surface.source(e)), surface.point(surface.target(e))));
    sizes.push_back(static_cast<long>(CGAL::halfedges_around_face(h, surface).size()));
    perimeters.push_back(perimeter);
  }
  const double diagonal = bounding_box_diagonal(input_vertices);
  auto large = [&](std::size_t k) {
    return sizes[k] > limits.max_hole_edges || perimeters[k] > limits.max_hole_perimeter * diagonal;
  };
  if (!keep_open) {
    const long largest = sizes.empty() ? 0 : *std::max_element(sizes.begin(), sizes.end());
    const double largest_perimeter = perimeters.empty() ? 0 : *std::max_element(perimeters.begin(), perimeters.end());
    if (largest > limits.max_hole_edges || largest_perimeter > limits.max_hole_perimeter * diagonal) {
      char figures[160];
      std::snprintf(figures, sizeof figures, "a hole of %ld boundary edges, %.3g m around (%.0f%% of the bounding-box diagonal)",
                    largest, largest_perimeter, 100 * largest_perimeter / diagonal);
      char bounds[120];
      std::snprintf(bounds, sizeof bounds, "holes of up to %ld edges and %.0f%% are repaired", limits.max_hole_edges,
                    100 * limits.max_hole_perimeter);
      throw bad_input(source, std::string("open surface with ") + figures + ": too large to fill (" + bounds + ")", frame);
    }
  }
  for (std::size_t k = 0; k < holes.size(); ++k) {
    if (large(k)) {  // only with keep_large_holes_open
      ++report.holes_open;
      report.largest_open_hole_edges = std::max(report.largest_open_hole_edges, sizes[k]);
      report.largest_open_hole_perimeter = std::max(report.largest_open_hole_perimeter, perimeters[k]);
      continue;
    }
    const std::size_t piece = pieces.of[surface.face(surface.opposite(holes[k]))];
    std::vector<SurfaceMesh::Face_index> added;
    PMP::triangulate_hole(surface, holes[k], std::back_inserter(added));
    // Where CGAL finds no triangulation it may close the loop with one polygon (or a two-sided
    // face for a loop of two edges): that is no repair.
    const bool triangles = std::all_of(added.begin(), added.end(), [&](SurfaceMesh::Face_index f) {
      return CGAL::halfedges_around_face(surface.halfedge(f), surface).size() == 3;
    });
    if (added.empty() || !triangles)
      throw bad_input(source, "a hole of " + std::to_string(sizes[k]) + " boundary edges could not be triangulated",
                      frame);
    for (const auto f : added) pieces.of[f] = piece;
    report.faces_added += static_cast<long>(added.size());
    ++report.holes_filled;
    report.largest_hole_edges = std::max(report.largest_hole_edges, sizes[k]);
    report.largest_hole_perimeter = std::max(report.largest_hole_perimeter, perimeters[k]);
  }
}

/// Faces of `surface` (minus debris) as a Mesh over the referenced vertices, in index order;
/// `piece` receives each output face's piece.
Mesh extract(const SurfaceMesh& surface, const Pieces& pieces, const Soup& soup, const Mesh& input,
             RepairReport& report, std::vector<std::size_t>& piece) {
  std::vector<std::array<long, 3>> faces;
  std::vector<long> new_index(surface.number_of_vertices(), -1);
  for (const auto f : surface.faces()) {
    if (pieces.debris[pieces.of[f]]) continue;
    std::array<long, 3> corners{};
    std::size_t k = 0;
    for (const auto v : CGAL::vertices_around_face(surface.halfedge(f), surface)) {
      if (k == corners.size()) throw internal_error("mesh repair: a face with more than three corners");
      corners[k++] = v.idx();
    }
    if (k != corners.size()) throw internal_error("mesh repair: a face with fewer than three corners");
    for (const long v : corners) new_index[static_cast<std::size_t>(v)] = 0;
    faces.push_back(corners);
    piece.push_back(pieces.of[f]);
  }
  long kept = 0;
  for (auto& index : new_index)
    if (index == 0) index = kept++;
  report.vertices_dropped = input.V.rows() + report.vertices_duplicated - kept;

  Mesh mesh;
  mesh.V.resize(kept, 3);
  if (input.has_colors()) mesh.colors.resize(kept, 3);
  if (input.has_uvs()) mesh.uvs.resize(kept, 2);
  for (std::size_t v = 0; v < new_index.size(); ++v) {
    if (new_index[v] < 0) continue;
    const long from = soup.source_of[v];
    mesh.V.row(new_index[v]) = input.V.row(from);
    if (input.has_colors()) mesh.colors.row(new_index[v]) = input.colors.row(from);
    if (input.has_uvs()) mesh.uvs.row(new_index[v]) = input.uvs.row(from);
  }
  mesh.F.resize(static_cast<long>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k) mesh.F(static_cast<long>(f), k) = static_cast<int>(new_index[faces[f][k]]);
  return mesh;
}

/// Reorientation follows the first face of each piece; a piece that ended up enclosing a
/// negative volume is turned outward again (an open piece counts with its holes closed by fans).
void orient_outward(Mesh& mesh, const std::vector<std::size_t>& piece) {
  const std::size_t count = piece.empty() ? 0 : *std::max_element(piece.begin(), piece.end()) + 1;
  std::vector<double> volume(count, 0.0);
  std::vector<std::size_t> vertex_piece(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (long f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) vertex_piece[static_cast<std::size_t>(mesh.F(f, k))] = piece[static_cast<std::size_t>(f)];
  const Mesh closed = close_holes(mesh);  // the original faces first, then the fans over the holes
  for (long f = 0; f < closed.F.rows(); ++f) {
    const Eigen::Vector3d a = closed.V.row(closed.F(f, 0)), b = closed.V.row(closed.F(f, 1)), c = closed.V.row(closed.F(f, 2));
    // A fan face belongs to the piece of its loop's vertices (corner 0 is one of them).
    volume[vertex_piece[static_cast<std::size_t>(closed.F(f, 0))]] += a.dot(b.cross(c)) / 6.0;
  }
  for (long f = 0; f < mesh.F.rows(); ++f)
    if (volume[piece[static_cast<std::size_t>(f)]] < 0) std::swap(mesh.F(f, 1), mesh.F(f, 2));
}

}  // namespace

bool RepairReport::changed() const {
  return holes_filled + vertices_duplicated + faces_reoriented + debris_components + vertices_dropped > 0;
}

std::string RepairReport::summary() const {
  std::vector<std::string> parts;
  if (holes_filled > 0)
    parts.push_back("filled " + std::to_string(holes_filled) + " hole" + (holes_filled > 1 ? "s" : "") + " (largest " +
                    std::to_string(largest_hole_edges) + " edges, " + std::to_string(faces_added) + " faces added)");
  if (non_manifold_edges + non_manifold_vertices > 0)
    parts.push_back("split " + std::to_string(non_manifold_edges) + " non-manifold edges and " +
                    std::to_string(non_manifold_vertices) + " pinch vertices (" + std::to_string(vertices_duplicated) +
                    " vertices duplicated)");
  if (faces_reoriented > 0) parts.push_back("reoriented " + std::to_string(faces_reoriented) + " faces");
  if (debris_components > 0)
    parts.push_back("dropped " + std::to_string(debris_components) + " loose pieces (" + std::to_string(debris_faces) +
                    " faces)");
  if (vertices_dropped > 0) parts.push_back("dropped " + std::to_string(vertices_dropped) + " unreferenced vertices");
  if (holes_open > 0) {
    char figures[120];
    std::snprintf(figures, sizeof figures, " (largest %ld edges, %.3g m around)", largest_open_hole_edges,
                  largest_open_hole_perimeter);
    parts.push_back("left " + std::to_string(holes_open) + " large hole" + (holes_open > 1 ? "s" : "") + " open" + figures);
  }
  std::string text;
  for (const auto& part : parts) text += (text.empty() ? "" : ", ") + part;
  return text.empty() ? "nothing to repair" : text;
}

RepairReport repair_mesh(Mesh& mesh, const RepairLimits& limits, const std::filesystem::path& source,
                         std::optional<long> frame) {
  RepairReport report;
  const MeshCheck before = check_mesh(mesh);
  const long pinches = count_pinch_vertices(mesh);
  if (before.closed() && before.manifold() && pinches == 0 && before.unreferenced_vertices == 0) return report;
  report.non_manifold_edges = before.non_manifold_edges;
  report.non_manifold_vertices = pinches;
  if (before.non_manifold_edges + pinches > limits.max_non_manifold)
    throw bad_input(source, std::to_string(before.non_manifold_edges) + " non-manifold edges and " +
                                std::to_string(pinches) + " pinch vertices: too many to repair (up to " +
                                std::to_string(limits.max_non_manifold) + " are split)", frame);

  const Soup soup = oriented_soup(mesh, report);
  SurfaceMesh surface = surface_of(soup, source, frame);
  Pieces pieces = find_pieces(surface, limits, report);
  fill_holes(surface, pieces, mesh.V, limits, report, source, frame);
  std::vector<std::size_t> piece;
  Mesh repaired = extract(surface, pieces, soup, mesh, report, piece);
  if (report.faces_reoriented > 0) orient_outward(repaired, piece);

  const MeshCheck after = check_mesh(repaired);
  const bool closed_enough = after.closed() || report.holes_open > 0;
  if (!closed_enough || !after.manifold() || count_pinch_vertices(repaired) > 0 || after.vertices == 0)
    throw bad_input(source, std::string("could not be repaired into a ") + (limits.keep_large_holes_open ? "" : "closed ") +
                                "manifold surface (" + before.summary() + "; after repair: " + after.summary() + ")", frame);
  mesh = std::move(repaired);
  return report;
}

Mesh read_reconstruction(const std::filesystem::path& path, std::optional<long> frame, const RepairLimits& limits,
                         RepairReport* report) {
  MeshRequirements tolerant;
  tolerant.allow_non_manifold = true;
  tolerant.allow_zero_area_faces = true;
  tolerant.allow_open = true;
  Mesh mesh = read_mesh(path, tolerant, frame);
  const RepairReport repair = repair_mesh(mesh, limits, path, frame);
  if (repair.changed()) spdlog::warn("{}: repaired: {}", where(path, frame), repair.summary());
  else if (repair.holes_open > 0) spdlog::info("{}: {}", where(path, frame), repair.summary());
  if (report) *report = repair;
  return mesh;
}

}  // namespace surfcap::core
