#pragma once
// The tri-dexel in-process workpiece as a closed triangle mesh (export, display, comparison with
// CAD), by marching cubes over the lattice where the three ray families meet.
//
// The lattice: with spacing s, the points g(i, j, k) = domain.min + (i + ½, j + ½, k + ½)·s lie
// on one ray of every family (the X ray (j, k), the Y ray (k, i), the Z ray (i, j)), and every
// lattice edge along axis a lies on a ray of family a. Marching cubes runs over this lattice,
// padded with one layer of empty points outside the domain so that the surface closes across
// the stock's faces.
//  - Inside/outside: one bit per lattice point, the two-of-three vote of its three rays (the
//    membership TriDexel::contains defines). In exact arithmetic the three rays agree at the
//    point they share; they differ only where a surface passes within float rounding (~1e-5 mm)
//    of the point or one family's chord erred, and the vote then outvotes the odd ray. The mesh's
//    topology comes from these bits alone.
//  - Crossings: on an edge along axis a whose end bits differ, the vertex sits at the family-a
//    ray's first material boundary after the edge's lower end: an exact surface point (float
//    rounding of the dexel). Where that ray disagrees with the bits at either end (the vote
//    overruled it), the vertex falls back to the edge's midpoint.
//  - Cases: the triangles of each of the 256 cube cases are generated, not transcribed: on every
//    face each run of inside corners is cut off by one segment (diagonal inside corners stay
//    separate), the segments link into loops around the cube, and each loop is fanned. A face's
//    segments depend only on that face's four bits, so the two cubes sharing it agree and the
//    surface has no cracks; every crossing edge lies on exactly one loop per cube, so with one
//    vertex per lattice edge the mesh is a closed 2-manifold (check_closure: closed).
//  - Orientation: counter-clockwise seen from outside (outward normals, positive volume).
//  - Order: cubes slab by slab along Z, row by row along Y, then along X; the vertices numbered
//    in the order the triangles first use them.
//
// Accuracy: vertices are exact surface points along lattice edges (to the dexel's float
// rounding), or within s/2 of one where the fallback applies. Between lattice edges the surface
// is interpolated: sharp edges and corners are chamfered by up to about s, and features thinner
// than s (walls, ribs, gaps that no lattice point sees) may vanish or be separated. The volume
// error is bounded by about area × s and is usually far smaller (on a box, only the chamfered
// edges are missing: at most s²/2 per millimetre of edge).
//
// Coarser export (stride k > 1): the lattice takes every k-th ray position along each axis, so
// its edges still lie on rays and its vertices are still exact surface points; the chamfering
// and the features lost grow to about k·s, and the triangle count falls as 1/k².
//
// Memory: bits and vertex indices for two lattice layers at a time (a few bytes per point of a
// layer) plus one cursor per ray along the slab axis; the output mesh is the only full-size data
// (reserved at once, from the lattice rays' interval ends, rather than grown by doubling).
// Cost: linear in the lattice points, (nx + 2)(ny + 2)(nz + 2).

#include <array>
#include <cstddef>
#include <functional>
#include <span>

#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"

namespace cwe {

// The workpiece's material as a closed, outward-facing, indexed triangle mesh in the stock's
// coordinates (mm), on the lattice of every `stride`-th ray position along each axis (lattice
// spacing stride × s, centred in the domain; stride 1 uses every ray). Empty when no lattice
// point holds material. Throws InputError for a stride below 1, or when the mesh would need more
// than 2^31 vertices (a spacing far too fine for the stock).
TriangleMesh dexel_mesh(const TriDexel& stock, int stride = 1);

// A run of a mesh's triangles as they are made, with the vertices made so far (which hold every
// vertex the run's triangles name). Both are views of the mesh being made: valid during the call.
using MeshFollower = std::function<void(std::span<const std::array<int, 3>> triangles,
                                        std::span<const Vec3> vertices)>;

// The mesh and how many of its first triangles were handed to the follower.
struct FollowedMesh {
  TriangleMesh mesh;
  std::size_t followed = 0;
};

// dexel_mesh, handing the triangles to `follow` in order, a run at a time, on a spare thread while
// the rest is being made (so that stock.stl is encoded and written while the stock is contoured).
// `follow` runs on one thread at a time and never after this returns. It may be given all the
// triangles, some of the first or none (no spare thread, or the mesh outgrew the room reserved
// for it): the caller takes the rest from the mesh, after `followed`. An exception `follow`
// throws ends the meshing and is thrown here.
FollowedMesh dexel_mesh(const TriDexel& stock, int stride, const MeshFollower& follow);

// The smallest stride for which dexel_mesh gives about `triangle_budget` triangles or fewer,
// estimated from the rays' material boundaries (a scan of the rays, no meshing): about
// 2 × (interval ends) / stride² triangles.
int dexel_mesh_stride(const TriDexel& stock, std::size_t triangle_budget);

}  // namespace cwe
