#include "surfcap/align/observed_surface.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/dense_targets.hpp"
#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/align/template_closing.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/geometry/mean_edge_length.hpp"
#include "test_support.hpp"

namespace surfcap::align {
namespace {

/// A unit sphere (rings × segments) without the faces above `cut_y`: an open cap.
core::Mesh cut_sphere(int rings, int segments, double cut_y) {
  const core::Mesh sphere = testing::make_sphere(rings, segments);
  return testing::with_faces(sphere, [&](long f) {
    double y = 0;
    for (int k = 0; k < 3; ++k) y += sphere.V(sphere.F(f, k), 1) / 3;
    return y < cut_y;
  });
}

/// `mesh` without its unreferenced vertices (the form read_reconstruction returns).
core::Mesh compacted(const core::Mesh& mesh) {
  std::vector<int> index(static_cast<std::size_t>(mesh.V.rows()), -1);
  int kept = 0;
  for (long f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (index[static_cast<std::size_t>(mesh.F(f, k))] < 0) index[static_cast<std::size_t>(mesh.F(f, k))] = 0;
  for (auto& i : index)
    if (i == 0) i = kept++;
  core::Mesh out;
  out.V.resize(kept, 3);
  for (long v = 0; v < mesh.V.rows(); ++v)
    if (index[static_cast<std::size_t>(v)] >= 0) out.V.row(index[static_cast<std::size_t>(v)]) = mesh.V.row(v);
  out.F = mesh.F;
  for (long f = 0; f < out.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) out.F(f, k) = index[static_cast<std::size_t>(mesh.F(f, k))];
  return out;
}

TEST(ObservedSurface, AClosedReconstructionIsObservedEverywhere) {
  const core::Mesh sphere = testing::make_sphere(12, 24);
  const ObservedSurface observed(sphere.V, sphere.F);
  EXPECT_FALSE(observed.partial());
  EXPECT_EQ(observed.holes(), 0);
  for (long v = 0; v < sphere.V.rows(); ++v) EXPECT_TRUE(observed.observed_vertex(v));
}

TEST(ObservedSurface, AHolesRimAndABandAroundItAreNotObserved) {
  const core::Mesh open = compacted(cut_sphere(24, 48, 0.7));
  const ObservedSurface observed(open.V, open.F);
  ASSERT_TRUE(observed.partial());
  EXPECT_EQ(observed.holes(), 1);
  EXPECT_NEAR(observed.largest_hole_perimeter(), 2 * M_PI * std::sin(std::acos(0.7)), 0.35);
  const double rim_y = open.V.col(1).maxCoeff();
  const double band = kBoundaryBandEdges * geometry::mean_edge_length(open.V, open.F);
  long unobserved = 0;
  for (long v = 0; v < open.V.rows(); ++v) {
    const double below_rim = rim_y - open.V(v, 1);  // ≤ the distance to the rim along the surface
    if (below_rim < 1e-9) EXPECT_FALSE(observed.observed_vertex(v)) << v;  // on the rim
    if (below_rim > 2 * band) EXPECT_TRUE(observed.observed_vertex(v)) << v;
    unobserved += observed.observed_vertex(v) ? 0 : 1;
  }
  EXPECT_GT(unobserved, 48);            // the rim and the ring below it
  EXPECT_LT(unobserved, open.V.rows() / 4);
  // A point on a face: observed where all its corners are far from the rim.
  for (long f = 0; f < open.F.rows(); ++f) {
    geometry::SurfacePoint centre;
    centre.face = f;
    centre.barycentric = Eigen::Vector3d::Constant(1.0 / 3);
    bool corners = true;
    for (int k = 0; k < 3; ++k) corners = corners && observed.observed_vertex(open.F(f, k));
    if (corners) EXPECT_TRUE(observed.observed(centre));
  }
}

TEST(ObservedSurface, ASmallLoosePieceIsNotObserved) {
  core::Mesh body = testing::make_sphere(24, 48);
  const core::Mesh blob = testing::make_sphere(3, 4, 0.05);  // 8 faces: under 2 % of the body's
  core::Mesh both;
  both.V.resize(body.V.rows() + blob.V.rows(), 3);
  both.V << body.V, (blob.V.rowwise() + Eigen::RowVector3d(1.5, 0, 0));
  both.F.resize(body.F.rows() + blob.F.rows(), 3);
  both.F << body.F, (blob.F.array() + static_cast<int>(body.V.rows())).matrix();
  const ObservedSurface observed(both.V, both.F);
  ASSERT_TRUE(observed.partial());
  EXPECT_EQ(observed.small_pieces(), 1);
  for (long v = 0; v < body.V.rows(); ++v) EXPECT_TRUE(observed.observed_vertex(v));
  for (long v = body.V.rows(); v < both.V.rows(); ++v) EXPECT_FALSE(observed.observed_vertex(v));
}

TEST(TemplateClosing, AFairedPatchClosesTheHoleAndKeepsTheObservedVertices) {
  const core::Mesh open = compacted(cut_sphere(24, 48, 0.7));
  const TemplateSurface closed = close_template(open);
  EXPECT_EQ(closed.holes, 1);
  EXPECT_EQ(closed.observed_vertices, open.vertex_count());
  EXPECT_EQ(closed.observed_faces, open.face_count());
  const core::MeshCheck check = core::check_mesh(closed.mesh);
  EXPECT_TRUE(check.closed());
  EXPECT_TRUE(check.manifold());
  EXPECT_GT(testing::signed_volume(closed.mesh), 0);
  EXPECT_EQ(closed.mesh.V.topRows(open.vertex_count()), open.V);
  EXPECT_EQ(closed.mesh.F.topRows(open.face_count()), open.F);
  ASSERT_GT(closed.mesh.vertex_count(), open.vertex_count());  // refined to the rim's density
  // The faired cap bulges out like the sphere it replaces: above the rim's plane, near the sphere.
  for (long v = open.vertex_count(); v < closed.mesh.vertex_count(); ++v) {
    EXPECT_GT(closed.mesh.V(v, 1), 0.7);
    EXPECT_NEAR(closed.mesh.V.row(v).norm(), 1.0, 0.08);
  }
  // A closed reconstruction is the template as it is.
  const core::Mesh sphere = testing::make_sphere(12, 24);
  const TemplateSurface same = close_template(sphere);
  EXPECT_EQ(same.holes, 0);
  EXPECT_EQ(same.mesh.V, sphere.V);
  EXPECT_EQ(same.mesh.F, sphere.F);
}

/// The pieces side by side in one mesh, each moved by its offset, with a colour per piece.
core::Mesh side_by_side(const std::vector<std::pair<core::Mesh, Eigen::RowVector3d>>& pieces) {
  core::Mesh all;
  long vertices = 0, faces = 0;
  for (const auto& [mesh, offset] : pieces) vertices += mesh.V.rows(), faces += mesh.F.rows();
  all.V.resize(vertices, 3);
  all.colors.resize(vertices, 3);
  all.F.resize(faces, 3);
  long v0 = 0, f0 = 0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const auto& [mesh, offset] = pieces[k];
    all.V.middleRows(v0, mesh.V.rows()) = mesh.V.rowwise() + offset;
    all.colors.middleRows(v0, mesh.V.rows()).setConstant(static_cast<double>(k) / 4);
    all.F.middleRows(f0, mesh.F.rows()) = (mesh.F.array() + static_cast<int>(v0)).matrix();
    v0 += mesh.V.rows(), f0 += mesh.F.rows();
  }
  return all;
}

TEST(TemplateClosing, ASmallLoosePieceIsLeftOutAndTheOthersKeepTheirOrder) {
  const core::Mesh blob = testing::make_sphere(3, 4, 0.05);     // 8 faces: under 2 % of the whole's
  const core::Mesh body = compacted(cut_sphere(24, 48, 0.7));  // open: its hole is closed after
  const core::Mesh hand = testing::make_sphere(6, 12, 0.3);     // 7 % of the faces: kept
  const core::Mesh reconstruction = side_by_side(
      {{blob, Eigen::RowVector3d(0, 1.6, 0)}, {body, Eigen::RowVector3d::Zero()}, {hand, Eigen::RowVector3d(2, 0, 0)}});
  const TemplateSurface closed = close_template(reconstruction);
  EXPECT_EQ(closed.loose_pieces, 1);
  ASSERT_EQ(static_cast<long>(closed.dropped_vertices.size()), blob.vertex_count());
  for (long v = 0; v < blob.vertex_count(); ++v) EXPECT_EQ(closed.dropped_vertices[static_cast<std::size_t>(v)], v);
  const long kept = body.vertex_count() + hand.vertex_count();
  EXPECT_EQ(closed.observed_vertices, kept);
  EXPECT_EQ(closed.observed_faces, body.face_count() + hand.face_count());
  EXPECT_EQ(closed.holes, 1);
  // The kept pieces' vertices and colours, in their order, then the closing surface's.
  EXPECT_EQ(closed.mesh.V.topRows(kept), reconstruction.V.bottomRows(kept));
  EXPECT_EQ(closed.mesh.colors.topRows(kept), reconstruction.colors.bottomRows(kept));
  const core::MeshCheck check = core::check_mesh(closed.mesh);
  EXPECT_TRUE(check.closed());
  EXPECT_TRUE(check.manifold());
  EXPECT_EQ(check.unreferenced_vertices, 0);
  for (long v = 0; v < closed.mesh.vertex_count(); ++v) EXPECT_LT(closed.mesh.V(v, 1), 1.3);  // nothing of the blob
}

TEST(DenseTargets, NoTargetOnTheClosingSurfaceNorOnAHolesRim) {
  const core::Mesh open = compacted(cut_sphere(24, 48, 0.7));
  PairwiseOptions options;
  const AlignmentTemplate model(close_template(open), options);
  ASSERT_TRUE(model.closed_by_fill());
  // The child: the template's own reconstruction with a second hole, at the bottom.
  const core::Mesh child = compacted(testing::with_faces(open, [&](long f) {
    return open.V(open.F(f, 0), 1) > -0.7 || open.V(open.F(f, 1), 1) > -0.7 || open.V(open.F(f, 2), 1) > -0.7;
  }));
  const geometry::SurfaceQuery query(child.V, child.F);
  const ObservedSurface observed(child.V, child.F);
  const DenseTargets dense(model, query, observed, nullptr, options);
  const Eigen::MatrixXd surface = model.mesh().V;
  TargetSet targets(surface);
  PairwiseResult result;
  const long matched = dense.add(surface, targets, result);
  EXPECT_GT(matched, surface.rows() / 3);  // the sphere between the two holes, less the bands
  const double band = kBoundaryBandEdges * geometry::mean_edge_length(child.V, child.F);
  for (long v = 0; v < surface.rows(); ++v) {
    if (!model.observed_vertex(v)) {
      EXPECT_EQ(targets.weights(v), 0) << "closing vertex " << v;
      continue;
    }
    const double y = surface(v, 1);
    if (y < -0.7 + band / 2 || y > 0.7 - band / 2) EXPECT_EQ(targets.weights(v), 0) << "vertex " << v << " at y " << y;
    if (y > -0.7 + 3 * band && y < 0.7 - 3 * band) EXPECT_GT(targets.weights(v), 0) << "vertex " << v << " at y " << y;
  }
}

}  // namespace
}  // namespace surfcap::align
