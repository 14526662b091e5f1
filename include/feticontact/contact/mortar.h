#pragma once

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <array>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

/**
 * Dual mortar coupling of two triangulated surfaces (doc/contact.md, "Non-matching meshes:
 * mortar rows"). Geometry only: nothing here knows meshes, bodies or friction.
 *
 * On a P1 slave triangle the dual basis ψ_i = 4φ_i − 1 = 3φ_i − φ_j − φ_k is biorthogonal to
 * the nodal basis, ∫_T ψ_i φ_j = δ_ij ∫_T φ_j, and sums to 1. For a slave node k and a master
 * node j the coupling integrals are
 *
 *   D_kk = ∫ ψ_k φ_k = ∫ φ_k,  M_kj = ∫ ψ_k φ_j^master,  g̃_k = ∫ ψ_k g,
 *
 * over the part of the slave surface that the master surface covers (the segments of
 * Puso–Laursen and Popp et al.): every slave triangle is clipped against every master triangle
 * projected on its plane along its normal, the clipped polygon is cut into triangles and
 * integrated with a Gauss rule of degree 5. g is the distance from the slave triangle to the
 * master triangle along the slave triangle's normal, times the cosine with the interpolated
 * nodal normal.
 *
 * A node whose support the master covers only in part (at the edge of the contact region, or a
 * slave surface that reaches past the master) is weighted by φ_k instead of ψ_k over the covered
 * part: D_kk = ∫ φ_k, M_kj = ∫ φ_k φ_j, g̃_k = ∫ φ_k g. Its weights M_kj / D_kk are then positive
 * and sum to 1, so its row holds the node against a mean of master displacements and a rigid
 * translation of both bodies leaves it satisfied. For a fully covered node Σ_j M_kj = D_kk holds
 * as well (Σ_j φ_j = 1), and on matching meshes M = D, so the rows equal the node-to-node rows.
 */
namespace FetiContact::Mortar
{
  /** A triangulated surface with outward unit normals per triangle and per vertex. */
  struct Surface
  {
    std::vector<dealii::Point<3>>            points;
    std::vector<std::array<unsigned int, 3>> triangles;
    /** The outward unit normal of each triangle (pointing out of its body). */
    std::vector<dealii::Tensor<1, 3>> triangle_normals;
    /** The outward unit normal at each point: the area-weighted mean of its triangles'. */
    std::vector<dealii::Tensor<1, 3>> point_normals;
  };

  /** The coupling of one slave point with the master surface. */
  struct NodeCoupling
  {
    /**
     * The outward unit normal of the node's rows: the point normal, or at a fold of the slave
     * surface the mean over the triangles on the side of the fold that keeps the node.
     */
    dealii::Tensor<1, 3> normal;
    /** ∫ φ_k over the slave surface (on the covered side of a fold): the area lumped at the node.
     */
    double area = 0;
    /** ∫ φ_k over the part of the slave surface that the master covers. */
    double covered = 0;
    /** Whether the node is weighted by ψ_k (covered) or φ_k (covered in part). */
    bool dual = true;
    /** D_kk = Σ_j M_kj. */
    double D = 0;
    /** g̃_k: the weighted gap ∫ w_k g (w_k = ψ_k or φ_k). */
    double weighted_gap = 0;
    /** (master point j, M_kj). */
    std::vector<std::pair<unsigned int, double>> M;
  };

  /** What the coupling found: for the log and for messages. */
  struct Statistics
  {
    /** Slave and master triangle pairs whose bounding boxes meet within the search distance. */
    unsigned int n_candidate_pairs = 0;
    /** Of these, the pairs that face each other and overlap: the segments integrated. */
    unsigned int n_segments = 0;
    /** Candidate pairs that overlap but whose triangles do not face each other. */
    unsigned int n_facing_away = 0;
    /**
     * The smallest distance of a master triangle in front of a slave triangle that it overlaps
     * and faces (negative: behind it, an initial overlap of the bodies); +∞ if there is none.
     */
    double min_distance = std::numeric_limits<double>::infinity();
    /** A slave point where min_distance occurs. */
    dealii::Point<3> deepest_point;
    /**
     * The region searched behind the slave triangles without a segment for a master surface
     * deeper than the search distance (the union of their boxes); unset if there was none.
     */
    std::optional<dealii::BoundingBox<3>> searched_behind;
  };

  /**
   * What part of a slave surface couple() reports on, for a surface that is a rank's share of a
   * larger one (doc/contact.md, "The contact search on several ranks").
   */
  struct Share
  {
    /**
     * Per slave triangle: whether its pairs count in the statistics and its region behind is
     * searched (every triangle if empty). A triangle that several ranks hold counts on one.
     */
    std::vector<bool> counted;
    /**
     * How far behind a slave triangle a master surface that overlaps the slave body is looked
     * for; 0: the size of the bounding box of both surfaces (pass that of the whole surfaces).
     */
    double depth = 0;
  };

  /**
   * The coupling of every point of @p slave with @p master: master triangles within
   * @p search_distance of a slave triangle (bounding boxes widened by it, found through an
   * R-tree) that face it (opposite normals) are clipped and integrated, except where the master
   * triangle lies farther than @p search_distance in front of the slave triangle. A point that no
   * segment covers gets covered = 0 and no M.
   *
   * A point at a fold of the slave surface (its triangles turn by more than 30°: a slave surface
   * that runs round the edge of its body) belongs to one side: the covered side if the master
   * covers only one, else the side whose segments come nearest to the master (the other side's
   * segments are left out of its integrals). Its normal and its area ∫ φ_k are those of its
   * triangles within 30° of that side, so a point whose side the master covers whole stays
   * weighted by ψ_k.
   */
  std::vector<NodeCoupling>
  couple(const Surface &slave,
         const Surface &master,
         const double   search_distance,
         Statistics    &statistics,
         const Share   &share = {});

  /**
   * Fills triangle_normals (from the vertex order, flipped where @p outward says the other way)
   * and point_normals of @p surface.
   */
  void
  compute_normals(Surface &surface, const std::vector<dealii::Tensor<1, 3>> &outward);
} // namespace FetiContact::Mortar
