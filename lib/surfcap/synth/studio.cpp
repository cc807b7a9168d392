#include "surfcap/synth/studio.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>

#include "surfcap/core/error.hpp"
#include "surfcap/geometry/surface_query.hpp"
#include "surfcap/render/rasterizer.hpp"

namespace surfcap::synth {
namespace {

/// Unmarks, at each vertex whose kept faces form several fans (faces linked through an edge at
/// that vertex), all but the largest fan; repeated until nothing changes (at most 8 passes).
void drop_extra_fans(const core::Mesh& mesh, std::vector<bool>& keep) {
  const long n = mesh.vertex_count();
  for (int pass = 0; pass < 8; ++pass) {
    std::vector<std::vector<int>> incident(static_cast<std::size_t>(n));
    for (long f = 0; f < mesh.face_count(); ++f)
      if (keep[static_cast<std::size_t>(f)])
        for (int k = 0; k < 3; ++k) incident[static_cast<std::size_t>(mesh.F(f, k))].push_back(static_cast<int>(f));
    bool changed = false;
    for (long v = 0; v < n; ++v) {
      const auto& faces = incident[static_cast<std::size_t>(v)];
      if (faces.size() < 2) continue;
      DisjointSets fan(faces.size());
      for (std::size_t a = 0; a < faces.size(); ++a)
        for (std::size_t b = a + 1; b < faces.size(); ++b) {
          int shared = 0;
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) shared += mesh.F(faces[a], i) == mesh.F(faces[b], j);
          if (shared >= 2) fan.unite(static_cast<int>(a), static_cast<int>(b));
        }
      std::map<int, int> sizes;
      for (std::size_t a = 0; a < faces.size(); ++a) ++sizes[fan.find(static_cast<int>(a))];
      if (sizes.size() < 2) continue;
      int largest = sizes.begin()->first;
      for (const auto& [root, size] : sizes)
        if (size > sizes[largest]) largest = root;
      for (std::size_t a = 0; a < faces.size(); ++a)
        if (fan.find(static_cast<int>(a)) != largest) keep[static_cast<std::size_t>(faces[a])] = false;
      changed = true;
    }
    if (!changed) break;
  }
}

/// Unmarks the components (through shared vertices) of fewer than `min_faces` kept faces.
void drop_small_components(const core::Mesh& mesh, std::vector<bool>& keep, long min_faces) {
  const long n = mesh.vertex_count();
  DisjointSets parent(static_cast<std::size_t>(n));
  for (long f = 0; f < mesh.face_count(); ++f)
    if (keep[static_cast<std::size_t>(f)])
      for (int k = 1; k < 3; ++k) parent.unite(mesh.F(f, k), mesh.F(f, 0));
  std::vector<long> component_faces(static_cast<std::size_t>(n), 0);
  for (long f = 0; f < mesh.face_count(); ++f)
    if (keep[static_cast<std::size_t>(f)]) ++component_faces[static_cast<std::size_t>(parent.find(mesh.F(f, 0)))];
  for (long f = 0; f < mesh.face_count(); ++f)
    if (keep[static_cast<std::size_t>(f)] &&
        component_faces[static_cast<std::size_t>(parent.find(mesh.F(f, 0)))] < min_faces)
      keep[static_cast<std::size_t>(f)] = false;
}

/// Keeps the faces marked in `keep`, then drops what would make the surface
/// non-manifold at a vertex (all but the largest fan of faces around it),
/// components of fewer than `min_faces` faces and unreferenced vertices;
/// per-vertex ground truth follows its vertex.
void keep_faces(Reconstruction& r, std::vector<bool> keep, long min_faces) {
  const long n = r.mesh.vertex_count();
  drop_extra_fans(r.mesh, keep);
  drop_small_components(r.mesh, keep, min_faces);
  std::vector<int> new_index(static_cast<std::size_t>(n), -1);
  long faces = 0;
  for (long f = 0; f < r.mesh.face_count(); ++f)
    if (keep[static_cast<std::size_t>(f)]) {
      ++faces;
      for (int k = 0; k < 3; ++k) new_index[static_cast<std::size_t>(r.mesh.F(f, k))] = 0;
    }
  long vertices = 0;
  for (auto& index : new_index)
    if (index == 0) index = static_cast<int>(vertices++);
  Eigen::MatrixXd V(vertices, 3), barycentric(vertices, 3);
  std::vector<int> face(static_cast<std::size_t>(vertices));
  std::vector<std::uint8_t> status(static_cast<std::size_t>(vertices));
  for (long v = 0; v < n; ++v) {
    const int i = new_index[static_cast<std::size_t>(v)];
    if (i < 0) continue;
    V.row(i) = r.mesh.V.row(v);
    barycentric.row(i) = r.barycentric.row(v);
    face[static_cast<std::size_t>(i)] = r.face[static_cast<std::size_t>(v)];
    status[static_cast<std::size_t>(i)] = r.status[static_cast<std::size_t>(v)];
  }
  Eigen::MatrixXi F(faces, 3);
  long row = 0;
  for (long f = 0; f < r.mesh.face_count(); ++f)
    if (keep[static_cast<std::size_t>(f)]) {
      for (int k = 0; k < 3; ++k) F(row, k) = new_index[static_cast<std::size_t>(r.mesh.F(f, k))];
      ++row;
    }
  r.mesh.V = std::move(V);
  r.mesh.F = std::move(F);
  r.barycentric = std::move(barycentric);
  r.face = std::move(face);
  r.status = std::move(status);
}

/// An icosahedron subdivided once and projected on the unit sphere (42
/// vertices, 80 faces).
core::Mesh unit_sphere() {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> V = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Eigen::Vector3i> F = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  std::map<std::pair<int, int>, int> midpoints;
  auto midpoint = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    const auto found = midpoints.find(key);
    if (found != midpoints.end()) return found->second;
    V.push_back((V[static_cast<std::size_t>(a)] + V[static_cast<std::size_t>(b)]) / 2);
    return midpoints[key] = static_cast<int>(V.size()) - 1;
  };
  std::vector<Eigen::Vector3i> subdivided;
  for (const auto& f : F) {
    const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
    subdivided.insert(subdivided.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
  }
  core::Mesh sphere;
  sphere.V.resize(static_cast<long>(V.size()), 3);
  for (std::size_t v = 0; v < V.size(); ++v) sphere.V.row(static_cast<long>(v)) = V[v].normalized().transpose();
  sphere.F.resize(static_cast<long>(subdivided.size()), 3);
  for (std::size_t f = 0; f < subdivided.size(); ++f) sphere.F.row(static_cast<long>(f)) = subdivided[f].transpose();
  return sphere;
}

/// A Poisson-distributed count (Knuth's method; small means).
int poisson(Gaussian& random, double mean) {
  const double limit = std::exp(-mean);
  int k = 0;
  double p = random.uniform();
  while (p > limit && k < 1000) {
    ++k;
    p *= random.uniform();
  }
  return k;
}

Eigen::Vector3d face_normal(const Eigen::MatrixXd &V, const Eigen::MatrixXi &F, long f) {
  const Eigen::Vector3d a = V.row(F(f, 0)).transpose(), b = V.row(F(f, 1)).transpose(), c = V.row(F(f, 2)).transpose();
  return (b - a).cross(c - a);
}

/// Spurious blobs near the body (not touching it or the reconstruction),
/// appended to `r`.
void add_blobs(Reconstruction& r, const core::Mesh& truth, Gaussian& random, const ReconstructionOptions& options) {
  const int count = poisson(random, options.blobs);
  if (count == 0) return;
  const core::Mesh sphere = unit_sphere();
  const geometry::SurfaceQuery truth_query(truth.V, truth.F);
  const geometry::SurfaceQuery reconstruction_query(r.mesh.V, r.mesh.F);
  for (int b = 0; b < count; ++b)
    for (int attempt = 0; attempt < 20; ++attempt) {
      const double radius = options.blob_radius * (0.5 + random.uniform());
      const long f = std::min<long>(truth.face_count() - 1, static_cast<long>(random.uniform() * truth.face_count()));
      double u = random.uniform(), v = random.uniform();
      if (u + v > 1) u = 1 - u, v = 1 - v;
      const Eigen::Vector3d on = (1 - u - v) * truth.V.row(truth.F(f, 0)).transpose() +
                                 u * truth.V.row(truth.F(f, 1)).transpose() +
                                 v * truth.V.row(truth.F(f, 2)).transpose();
      const Eigen::Vector3d normal = face_normal(truth.V, truth.F, f).normalized();
      const Eigen::Vector3d centre = on + normal * (radius + 0.015 + 0.06 * random.uniform());
      const geometry::SurfacePoint near_truth = truth_query.closest_point(centre);
      const bool outside = (centre - near_truth.position).dot(face_normal(truth.V, truth.F, near_truth.face)) > 0;
      if (!outside || (centre - near_truth.position).norm() < radius * 1.3 + 0.01) continue;
      if ((centre - reconstruction_query.closest_point(centre).position).norm() < radius * 1.3 + 0.008) continue;
      const long base = r.mesh.vertex_count();
      r.mesh.V.conservativeResize(base + sphere.vertex_count(), 3);
      for (long i = 0; i < sphere.vertex_count(); ++i)
        r.mesh.V.row(base + i) = centre.transpose() + radius * (1 + 0.15 * random.next()) * sphere.V.row(i);
      const long face_base = r.mesh.face_count();
      r.mesh.F.conservativeResize(face_base + sphere.face_count(), 3);
      r.mesh.F.bottomRows(sphere.face_count()) = sphere.F.array() + static_cast<int>(base);
      std::vector<int> face;
      Eigen::MatrixXd barycentric;
      closest_truth_points(truth, r.mesh.V.bottomRows(sphere.vertex_count()), face, barycentric);
      r.face.insert(r.face.end(), face.begin(), face.end());
      r.barycentric.conservativeResize(base + sphere.vertex_count(), 3);
      r.barycentric.bottomRows(sphere.vertex_count()) = barycentric;
      r.status.insert(r.status.end(), static_cast<std::size_t>(sphere.vertex_count()),
                      static_cast<std::uint8_t>(VertexStatus::blob));
      break;
    }
}


/// Per face over the cameras: the most frontal camera that sees it, the most frontal that faces
/// it at all, and the set of cameras (the first 64) that see it.
struct CameraChoice {
  std::vector<double> best_seen, best_any;
  std::vector<int> any_camera;
  std::vector<std::uint64_t> seen_by;
};

/// The faces camera c sees (facing it and not hidden in its depth map): their view counts and
/// best cameras.
void record_camera_views(const core::Mesh& mesh, const Eigen::MatrixXd& vertex_normals,
                         const std::vector<render::Camera>& cameras, std::size_t c, FaceVisibility& result,
                         CameraChoice& choice) {
  const render::Camera& camera = cameras[c];
  const render::Rendering rendering = render::render_mesh(mesh, camera);
  const Eigen::Vector3d centre = camera.centre();
  for (long f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d centroid =
        (mesh.V.row(mesh.F(f, 0)) + mesh.V.row(mesh.F(f, 1)) + mesh.V.row(mesh.F(f, 2))).transpose() / 3;
    if (!(face_normal(mesh.V, mesh.F, f).dot(centre - centroid) > 0)) continue;
    const Eigen::Vector3d normal =
        (vertex_normals.row(mesh.F(f, 0)) + vertex_normals.row(mesh.F(f, 1)) + vertex_normals.row(mesh.F(f, 2)))
            .transpose()
            .normalized();
    const double facing = normal.dot((centre - centroid).normalized());
    const std::size_t i = static_cast<std::size_t>(f);
    if (facing > choice.best_any[i]) choice.best_any[i] = facing, choice.any_camera[i] = static_cast<int>(c);
    const Eigen::Vector3d local = camera.to_camera(centroid);
    if (local.z() <= 0) continue;
    const Eigen::Vector2d pixel = camera.project(centroid);
    // 1 cm and two pixels' footprint: a face seen at a grazing angle is not
    // hidden by itself.
    const double tolerance = 0.01 + 2 * local.z() / camera.K(1, 1);
    const int x = static_cast<int>(std::lround(pixel.x())), y = static_cast<int>(std::lround(pixel.y()));
    bool visible = false;
    for (int dy = -1; dy <= 1 && !visible; ++dy)
      for (int dx = -1; dx <= 1 && !visible; ++dx) {
        const int px = x + dx, py = y + dy;
        if (px < 0 || py < 0 || px >= camera.width || py >= camera.height) continue;
        const float depth = rendering.depth[static_cast<std::size_t>(py) * static_cast<std::size_t>(camera.width) +
                                            static_cast<std::size_t>(px)];
        visible = depth >= local.z() - tolerance;
      }
    if (!visible) continue;
    ++result.views[i];
    if (c < 64) choice.seen_by[i] |= std::uint64_t{1} << c;
    if (facing > choice.best_seen[i]) choice.best_seen[i] = facing, result.best_camera[i] = static_cast<int>(c);
  }
}

/// The face across each edge k (F(f,k) → F(f,k+1)) of each face; −1 on the boundary.
std::vector<std::array<int, 3>> face_neighbours(const core::Mesh& mesh) {
  const long m = mesh.face_count();
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (long f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k)
      edge_faces[std::minmax(mesh.F(f, k), mesh.F(f, (k + 1) % 3))].push_back(static_cast<int>(f));
  std::vector<std::array<int, 3>> neighbours(static_cast<std::size_t>(m), {-1, -1, -1});
  for (long f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k)
      for (const int g : edge_faces[std::minmax(mesh.F(f, k), mesh.F(f, (k + 1) % 3))])
        if (g != f) neighbours[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)] = g;
  return neighbours;
}

/// Fewer, larger charts: a face takes the camera most of its edge neighbours have when that
/// camera sees it too (three passes of a majority filter).
void smooth_best_cameras(const std::vector<std::array<int, 3>>& neighbours, const std::vector<std::uint64_t>& seen_by,
                         std::vector<int>& best_camera) {
  for (int pass = 0; pass < 3; ++pass) {
    std::vector<int> smoothed = best_camera;
    for (std::size_t f = 0; f < neighbours.size(); ++f) {
      const auto& n = neighbours[f];
      for (int a = 0; a < 3; ++a) {
        if (n[a] < 0) continue;
        const int camera = best_camera[static_cast<std::size_t>(n[a])];
        int votes = 0;
        for (int b = 0; b < 3; ++b) votes += n[b] >= 0 && best_camera[static_cast<std::size_t>(n[b])] == camera;
        if (votes >= 2 && camera >= 0 && camera < 64 && (seen_by[f] >> camera & 1)) {
          smoothed[f] = camera;
          break;
        }
      }
    }
    best_camera = std::move(smoothed);
  }
}

/// The undirected edges of a mesh with their face counts, its connected components and its
/// boundary half-edges.
struct MeshEdges {
  std::map<std::pair<int, int>, int> faces;       // undirected edge → faces
  std::map<int, std::vector<int>> boundary_next;  // boundary half-edge a → b
  DisjointSets components;
};

/// The mesh's edges; marks the vertices on its boundary.
MeshEdges mesh_edges(const core::Mesh& mesh, std::vector<std::uint8_t>& boundary_vertex) {
  const long m = mesh.face_count();
  MeshEdges edges{{}, {}, DisjointSets(static_cast<std::size_t>(mesh.vertex_count()))};
  for (long f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a0 = mesh.F(f, k), b0 = mesh.F(f, (k + 1) % 3);
      ++edges.faces[std::minmax(a0, b0)];
      edges.components.unite(a0, b0);
    }
  for (long f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a0 = mesh.F(f, k), b0 = mesh.F(f, (k + 1) % 3);
      if (edges.faces[std::minmax(a0, b0)] == 1) {
        edges.boundary_next[a0].push_back(b0);
        boundary_vertex[static_cast<std::size_t>(a0)] = boundary_vertex[static_cast<std::size_t>(b0)] = 1;
      }
    }
  return edges;
}

/// Components (all-blob ones apart), their holes and genus.
void count_components(const core::Mesh& mesh, const std::vector<std::uint8_t>& status, MeshEdges& edges,
                      FrameArtefacts& a) {
  const long n = mesh.vertex_count();
  DisjointSets& parent = edges.components;
  // Per component: vertices, edges, faces, boundary loops → genus = (2 − χ − b)
  // / 2.
  std::map<int, std::array<long, 4>> component;  // root → V, E, F, loops
  std::map<int, bool> all_blob;
  for (long v = 0; v < n; ++v) {
    const int root = parent.find(static_cast<int>(v));
    ++component[root][0];
    const bool blob = v < static_cast<long>(status.size()) &&
                      status[static_cast<std::size_t>(v)] == static_cast<std::uint8_t>(VertexStatus::blob);
    all_blob[root] = all_blob.count(root) ? all_blob[root] && blob : blob;
  }
  for (const auto& [edge, count] : edges.faces) ++component[parent.find(edge.first)][1];
  for (long f = 0; f < mesh.face_count(); ++f) ++component[parent.find(mesh.F(f, 0))][2];
  // Boundary loops: components of the boundary edges (one loop each once
  // pinches are gone).
  DisjointSets loop(static_cast<std::size_t>(n));
  for (const auto& [from, targets] : edges.boundary_next)
    for (const int to : targets) loop.unite(from, to);
  for (const auto& [from, targets] : edges.boundary_next)
    if (loop.find(from) == from) ++component[parent.find(from)][3];
  for (const auto& [root, c] : component) {
    if (c[2] == 0) continue;  // unreferenced vertex
    if (all_blob[root]) {
      ++a.blob_components;
      continue;
    }
    ++a.components;
    a.holes += c[3];
    const long chi = c[0] - c[1] + c[2];
    a.genus += (2 - chi - c[3]) / 2;
  }
}

/// Edges joining vertices of different body parts that were far apart at rest: surfaces merged
/// by the reconstruction (the skirt over the thighs apart).
void count_merged_edges(const core::Mesh& mesh, const MeshEdges& edges, const Eigen::MatrixXd& rest_points,
                        const std::vector<int>& parts, FrameArtefacts& a) {
  const auto is_leg = [](int p) {
    return p == static_cast<int>(BodyPart::leg_l) || p == static_cast<int>(BodyPart::leg_r);
  };
  const int garment = static_cast<int>(BodyPart::garment);
  for (const auto& [edge, count] : edges.faces) {
    const auto [i, j] = edge;
    const int pi = parts[static_cast<std::size_t>(i)], pj = parts[static_cast<std::size_t>(j)];
    if (pi < 0 || pj < 0 || pi == pj) continue;
    if ((pi == garment && is_leg(pj)) || (pj == garment && is_leg(pi))) continue;  // the skirt over the thighs
    const double length = (mesh.V.row(i) - mesh.V.row(j)).norm();
    const double apart = (rest_points.row(i) - rest_points.row(j)).norm();
    if (apart > std::max(0.05, 4 * length)) {
      ++a.merged_edges;
      a.merged_vertex[static_cast<std::size_t>(i)] = a.merged_vertex[static_cast<std::size_t>(j)] = 1;
    }
  }
}


/// Moves each vertex onto its closest point of the true surface; a visual hull's vertices farther
/// than the tolerance only partly (phantom surface).
void snap_to_truth(Reconstruction& r, const core::Mesh& truth, const ReconstructionOptions& options) {
  closest_truth_points(truth, r.mesh.V, r.face, r.barycentric);
  const Eigen::MatrixXd exact = surface_points(truth.V, truth.F, r.face, r.barycentric);
  r.status.assign(static_cast<std::size_t>(r.mesh.vertex_count()), static_cast<std::uint8_t>(VertexStatus::on_surface));
  const double tolerance = options.surface_tolerance;
  for (long v = 0; v < r.mesh.vertex_count(); ++v) {
    const double distance = (r.mesh.V.row(v) - exact.row(v)).norm();
    if (!options.visual_hull || distance <= tolerance) {
      r.mesh.V.row(v) = exact.row(v);  // seen surface: the true point (refined by photo-consistency)
    } else {
      // Blend over [tolerance, 2·tolerance] so the surface stays continuous.
      const double w = std::min(1.0, (distance - tolerance) / std::max(tolerance, 1e-9));
      r.mesh.V.row(v) = exact.row(v) + w * (r.mesh.V.row(v) - exact.row(v));
      r.status[static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(VertexStatus::phantom);
    }
  }
}

/// Drops the faces below the floor cut and, per options.unseen, those seen by too few cameras
/// (or marks their vertices rough).
void cut_faces(Reconstruction& r, const std::vector<render::Camera>& cameras, const ReconstructionOptions& options) {
  std::vector<bool> keep(static_cast<std::size_t>(r.mesh.face_count()), true);
  if (options.floor_cut)
    for (long f = 0; f < r.mesh.face_count(); ++f)
      if ((r.mesh.V(r.mesh.F(f, 0), 1) + r.mesh.V(r.mesh.F(f, 1), 1) + r.mesh.V(r.mesh.F(f, 2), 1)) / 3 <
          options.floor_height)
        keep[static_cast<std::size_t>(f)] = false;
  std::vector<bool> unseen_vertex;
  if (options.unseen != UnseenMode::keep) {
    const FaceVisibility visibility = face_visibility(r.mesh, cameras);
    unseen_vertex.assign(static_cast<std::size_t>(r.mesh.vertex_count()), false);
    for (long f = 0; f < r.mesh.face_count(); ++f)
      if (visibility.views[static_cast<std::size_t>(f)] < options.min_views) {
        if (options.unseen == UnseenMode::remove)
          keep[static_cast<std::size_t>(f)] = false;
        else
          for (int k = 0; k < 3; ++k) unseen_vertex[static_cast<std::size_t>(r.mesh.F(f, k))] = true;
      }
    for (long v = 0; v < r.mesh.vertex_count(); ++v)
      if (unseen_vertex[static_cast<std::size_t>(v)] &&
          r.status[static_cast<std::size_t>(v)] == static_cast<std::uint8_t>(VertexStatus::on_surface))
        r.status[static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(VertexStatus::rough);
  }
  keep_faces(r, keep, 12);
}

/// Gaussian noise along the normals; rough vertices get more.
void add_noise(Reconstruction& r, const Eigen::MatrixXd& normals, std::uint64_t seed,
               const ReconstructionOptions& options) {
  Gaussian gaussian{std::mt19937_64(seed ^ 0x5eed5eed5eedULL)};
  for (long v = 0; v < r.mesh.vertex_count(); ++v) {
    double offset = options.noise_sigma * gaussian.next();
    if (r.status[static_cast<std::size_t>(v)] == static_cast<std::uint8_t>(VertexStatus::rough))
      offset += options.rough_sigma * gaussian.next();
    r.mesh.V.row(v) += offset * normals.row(v);
  }
}

/// A fraction of the vertices, drawn without replacement, pushed off the surface along ± normal.
void add_outliers(Reconstruction& r, const Eigen::MatrixXd& normals, Gaussian& random,
                  const ReconstructionOptions& options) {
  const long n = r.mesh.vertex_count();
  const long outliers = std::lround(options.outlier_fraction * static_cast<double>(n));
  if (outliers <= 0) return;
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  for (long i = 0; i < outliers; ++i) {
    const long j = i + std::min<long>(n - i - 1, static_cast<long>(random.uniform() * static_cast<double>(n - i)));
    std::swap(order[static_cast<std::size_t>(i)], order[static_cast<std::size_t>(j)]);
    const int v = order[static_cast<std::size_t>(i)];
    const double sign = random.uniform() < 0.5 ? -1.0 : 1.0;
    r.mesh.V.row(v) += sign * options.outlier_distance * (0.5 + random.uniform()) * normals.row(v);
    r.status[static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(VertexStatus::outlier);
  }
}

}  // namespace

double surface_area(const core::Mesh& mesh) {
  double area = 0;
  for (long f = 0; f < mesh.face_count(); ++f) area += face_normal(mesh.V, mesh.F, f).norm() / 2;
  return area;
}

double edge_for_vertices(double area, int vertices) {
  // A closed mesh of n vertices has about 2n faces; an equilateral face of edge
  // e covers √3/4 e².
  return std::sqrt(2 * area / (std::sqrt(3.0) * std::max(vertices, 1)));
}

FaceVisibility face_visibility(const core::Mesh& mesh, const std::vector<render::Camera>& cameras) {
  const auto m = static_cast<std::size_t>(mesh.face_count());
  FaceVisibility result;
  result.views.assign(m, 0);
  result.best_camera.assign(m, -1);
  CameraChoice choice{std::vector<double>(m, 0), std::vector<double>(m, 0), std::vector<int>(m, -1),
                      std::vector<std::uint64_t>(m, 0)};
  // Facing is judged on the mean of the corners' vertex normals: less noisy
  // than the face's own.
  const Eigen::MatrixXd vertex_normals = core::vertex_normals(mesh.V, mesh.F);
  for (std::size_t c = 0; c < cameras.size(); ++c) record_camera_views(mesh, vertex_normals, cameras, c, result, choice);
  smooth_best_cameras(face_neighbours(mesh), choice.seen_by, result.best_camera);
  for (std::size_t f = 0; f < m; ++f)
    if (result.best_camera[f] < 0) result.best_camera[f] = choice.any_camera[f];
  return result;
}

Reconstruction reconstruct_studio(const core::Mesh& truth, const std::vector<render::Camera>& cameras,
                                  std::vector<Silhouette> silhouettes, double edge, std::uint64_t seed,
                                  const ReconstructionOptions& options) {
  Reconstruction r;
  const double edge_target = options.vertices > 0 ? edge_for_vertices(surface_area(truth), options.vertices) : edge;
  if (options.visual_hull) {
    if (silhouettes.empty())
      for (const auto& camera : cameras) silhouettes.push_back(silhouette_of(truth, camera));
    const VoxelGrid grid = carve_visual_hull(silhouettes, truth.V.colwise().minCoeff().transpose(),
                                             truth.V.colwise().maxCoeff().transpose(), options.voxel);
    Gaussian random{std::mt19937_64(seed)};
    r.target_edge = edge_target * (1.0 + options.edge_jitter * (2 * random.uniform() - 1));
    r.mesh = remesh_surface(marching_tetrahedra(grid), r.target_edge, options.iterations);
  } else {
    r.mesh = remesh_truth(truth, edge_target, seed, options, r.target_edge);
  }
  snap_to_truth(r, truth, options);
  cut_faces(r, cameras, options);
  const Eigen::MatrixXd normals = core::vertex_normals(r.mesh.V, r.mesh.F);
  add_noise(r, normals, seed, options);
  Gaussian random{std::mt19937_64(seed ^ 0x0b1e0b1e0b1eULL)};
  add_outliers(r, normals, random, options);
  if (options.blobs > 0) add_blobs(r, truth, random, options);
  return r;
}

FrameArtefacts measure_artefacts(const core::Mesh& mesh, const std::vector<std::uint8_t>& status,
                                 const Eigen::MatrixXd& rest_points, const std::vector<int>& parts) {
  FrameArtefacts a;
  const long n = mesh.vertex_count();
  a.vertices = n;
  a.faces = mesh.face_count();
  a.merged_vertex.assign(static_cast<std::size_t>(n), 0);
  a.boundary_vertex.assign(static_cast<std::size_t>(n), 0);
  for (const auto s : status) {
    a.phantom += s == static_cast<std::uint8_t>(VertexStatus::phantom);
    a.outliers += s == static_cast<std::uint8_t>(VertexStatus::outlier);
    a.blob_vertices += s == static_cast<std::uint8_t>(VertexStatus::blob);
    a.rough += s == static_cast<std::uint8_t>(VertexStatus::rough);
  }
  MeshEdges edges = mesh_edges(mesh, a.boundary_vertex);
  count_components(mesh, status, edges, a);
  if (rest_points.rows() == n && static_cast<long>(parts.size()) == n)
    count_merged_edges(mesh, edges, rest_points, parts, a);
  return a;
}

}  // namespace surfcap::synth
