// Hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991, "A rapid hierarchical radiosity
// algorithm") with BF refinement, and clusters of input triangles as sources (Smits, Arvo & Greenberg
// 1994, "A clustering algorithm for radiosity in complex environments"), so that neither N² factors
// nor N² pairs are ever formed. Same equations and the same Solution as the dense solver
// (solver/radiosity.h):
//
//   B_i(λ) = M_i(λ) + ρ_i(λ) H_i(λ),   H_i = Σ_links at i and its ancestors F_link B_source + E_i^direct
//
// Elements: every input triangle, pre-split (conforming) so that no root exceeds 64 output patches,
// then split 1:4 down to meshing.max_patch_area; the leaves are the output patches. Clusters: a
// bounding-volume hierarchy over the roots.
//
// Links gather into elements, and into clusters whose roots' normals all face the source (see
// below). An element→element link carries the exact point-to-polygon kernel averaged over the
// receiver (adaptive cubature for near pairs) times a kernel-weighted ray-traced visible fraction
// (16 rays, 64 where they disagree; none where the shaft between two elements that are not both
// leaves is clear). A cluster→element link carries the cluster's radiant intensity
// I(ω) = Σ_k (ω·e_k)⁺ Φ_k / π, with Φ_k = Σ_j B_j A_j (n_j·e_k)⁺ the cluster's
// radiosity-weighted projected area on the six axis directions, scaled so that a cluster of uniform
// radiosity sends exactly the area it shows, Σ_j A_j (n_j·ω)⁺ (found through the clusters' normal
// cones; the bins alone overstate it up to √3 times wherever normals are not in ω's octant), over
// the squared distance, times a visible fraction from rays to points of the cluster's triangles.
// A link into a cluster (receivers clustered as well as sources, as clustering algorithms do) adds
// Ψ u to the cluster's vector irradiance V, Ψ being the irradiance on a surface facing the source in
// direction u; it is made only where every root's normal n lies in front of u, so that n·V is each
// root's Σ Ψ (n·u)⁺ with the clamp never acting. Without them every input triangle of a faceted
// object gathered the whole scene through links of its own.
//
// Element links are linear over the receiver: the point kernel at 10 receiver points is fitted by a
// linear function (least squares, shifted so that its mean is the exact receiver average), and
// push-down hands each child the parent's linear field at the child's vertices; a leaf takes the mean.
// This makes the push-down error second order in the element size (a constant push needed ~6× more
// links for the same closure).
//
// Refinement (the "BF oracle"): a link is kept when B_source × (its irradiance error bound per unit
// radiosity) × max(1, A_receiver / (4 patch areas)) ≤ ε = solver.accuracy × (mean radiosity);
// otherwise the larger side is split and the children are linked. The element link's error bound is
// the residual of the linear fit plus half the factor of a partly occluded link; the cluster link's is
// its whole transfer (distance shortened by both bounding radii) times the pair's relative size, and a
// link into a cluster's the same, needing the pair well separated (2.5 × the radii's sum). Up
// to three refine–solve rounds: the first with the first-bounce radiosity plus an ambient estimate,
// then with the solved one.
//
// Solve: the operator F is applied matrix-free (pull radiosity up to elements and clusters, gather
// over links, push irradiance down to the leaves) inside the lockstep GMRES of solver/linear_solve.h,
// one system per distinct spectral system. Closure and conservation: the operator is balanced as
// F' = D_r F D_c (Sinkhorn–Knopp with the transposed operator; its sweeps over-relaxed by an ω fitted
// to their observed rate, Young's SOR theory) so that each leaf whose hemisphere
// is closed (probe rays all hit front faces) gathers exactly a hemisphere (row sum 1: a furnace gives
// B = M/(1 − ρ) exactly) and has all its power gathered (area-weighted column sum 1: energy is
// conserved); the largest raw row-sum error is reported as stats.max_closure_error. The energy
// certificate counts as escaped what the links do not gather of each leaf (its column sum).
#pragma once

#include "solver/radiosity.h"

namespace lambert {

Solution solve_hierarchical(const Scene& scene, const SolveControl& control = {});

}  // namespace lambert
