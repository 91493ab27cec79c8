"""The head collider from a mesh object, in head space (the mesh's rigid frame at the bake's
first frame): a fitted sphere or capsule, or a sampled signed distance field."""

import numpy as np
from mathutils import Matrix, Vector
from mathutils.bvhtree import BVHTree

import wethair

from .curves import transform


def rigid(matrix_world) -> Matrix:
    """The matrix's turn and offset without its scale: the head frame wethair moves."""
    loc, rot, _ = matrix_world.decompose()
    return Matrix.Translation(loc) @ rot.to_matrix().to_4x4()


def head_space_vertices(obj) -> np.ndarray:
    """The mesh's vertices in head space (scale applied, turn and offset taken out)."""
    mesh = obj.data
    v = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", v)
    v = v.reshape(-1, 3)
    head = rigid(obj.matrix_world).inverted() @ obj.matrix_world
    return transform(head, v)


def fit_sphere(v: np.ndarray):
    c = v.mean(axis=0)
    r = float(np.linalg.norm(v - c, axis=1).mean())
    return wethair.sphere(c.tolist(), r), (c, r)


def fit_capsule(v: np.ndarray):
    c = v.mean(axis=0)
    _, _, vt = np.linalg.svd(v - c, full_matrices=False)
    axis = vt[0]
    t = (v - c) @ axis
    perp = np.linalg.norm((v - c) - np.outer(t, axis), axis=1)
    # The radius of the middle half of the length (the ends are the caps): a sphere's mesh
    # gives its own sphere, a limb's the limb.
    extent = float(np.abs(t).max())
    r = float(perp[np.abs(t) <= 0.5 * extent].max())
    half = max(0.0, extent - r)
    a, b = c - half * axis, c + half * axis
    return wethair.capsule(a.tolist(), b.tolist(), r), (a, b, r)


def sample_sdf(obj, resolution: int) -> wethair.Sdf:
    """Distances to the mesh (head space) on a grid of ``resolution`` cells along its longest
    side plus two cells of margin; negative inside (the side the nearest face's normal faces
    away from)."""
    v = head_space_vertices(obj)
    polys = [tuple(p.vertices) for p in obj.data.polygons]
    bvh = BVHTree.FromPolygons([Vector(x) for x in v.tolist()], polys)
    lo, hi = v.min(axis=0), v.max(axis=0)
    cell = float((hi - lo).max()) / resolution
    lo = lo - 2 * cell
    dims = np.ceil((hi + 2 * cell - lo) / cell).astype(int) + 1
    values = np.empty((dims[2], dims[1], dims[0]), dtype=np.float32)
    for k in range(dims[2]):
        for j in range(dims[1]):
            for i in range(dims[0]):
                p = Vector((lo[0] + i * cell, lo[1] + j * cell, lo[2] + k * cell))
                loc, normal, _, dist = bvh.find_nearest(p)
                values[k, j, i] = dist if (p - loc).dot(normal) >= 0 else -dist
    return wethair.Sdf(values=values, origin=lo.tolist(), cell_size=cell)
