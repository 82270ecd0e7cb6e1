//! `Block`: a convex block (core [`ConvexBlock`]), built from numpy arrays.

use crate::arrays;
use crate::errors::{input_error, to_py_err};
use numpy::{PyArray1, PyArray2};
use penedge::block::FaceOrigin;
use penedge::geometry::{DVec3, Plane};
use penedge::{ConvexBlock, Tolerance};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

/// A convex polyhedral block, validated on construction and immutable.
///
/// Faces are lists of vertex indices, counter-clockwise seen from outside (so that the face
/// normals point outwards). Adjacent coplanar faces (a triangulated box face, say) are merged
/// into one polygon. Tolerances are relative to the block's size (the diagonal of its
/// bounding box): vertices closer than 1e-9 x size are the same vertex, a vertex within
/// 1e-9 x size of a face plane lies on it.
///
/// Parameters
/// ----------
/// vertices : array_like, shape (n, 3)
///     Vertex coordinates (int or float; converted to float64).
/// faces : list of list of int
///     The vertex indices of each face, counter-clockwise seen from outside.
///
/// Raises
/// ------
/// InputError
///     `vertices` is not an (n, 3) array of real numbers or `faces` not lists of indices.
/// BlockError
///     The vertices and faces do not make a closed convex polyhedron (`kind` says why:
///     ``"non_finite_vertex"``, ``"open_surface"``, ``"wrong_orientation"``,
///     ``"not_convex"``, ...).
///
/// See Also
/// --------
/// Block.cuboid, Block.from_planes
///
/// Examples
/// --------
/// >>> import penedge
/// >>> tet = penedge.Block([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
/// ...                     [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
/// >>> tet
/// Block(4 vertices, 4 faces, 6 edges, volume=0.16666666666666666, centroid=[0.25, 0.25, 0.25])
/// >>> tet.face_normals[0]
/// array([ 0.,  0., -1.])
#[pyclass(module = "penedge", name = "Block", frozen)]
pub struct Block {
    /// The core block.
    pub inner: ConvexBlock,
}

impl Block {
    /// Wraps a core block.
    pub fn wrap(inner: ConvexBlock) -> Self {
        Block { inner }
    }
}

/// The corners of a box, checked (the core would report a swapped corner as a wrong
/// orientation, which is true but puzzling for a box).
pub fn cuboid(lo: &Bound<'_, PyAny>, hi: &Bound<'_, PyAny>) -> PyResult<ConvexBlock> {
    let (lo, hi) = (arrays::point(lo, "lo")?, arrays::point(hi, "hi")?);
    let ordered = (0..3).all(|k| lo[k].is_finite() && hi[k].is_finite() && lo[k] < hi[k]);
    if !ordered {
        let msg = format!(
            "a cuboid needs finite corners with lo < hi in x, y and z, got lo={lo:?}, hi={hi:?}"
        );
        return Err(input_error("corners", msg));
    }
    ConvexBlock::cuboid(lo, hi).map_err(to_py_err)
}

fn face_lists(faces: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<usize>>> {
    faces.extract::<Vec<Vec<usize>>>().map_err(|e| {
        let msg =
            format!("faces must be a list of lists of vertex indices (non-negative ints): {e}");
        input_error("faces", msg)
    })
}

#[pymethods]
impl Block {
    #[new]
    fn new(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<Self> {
        let vertices = arrays::points(vertices, "vertices")?;
        let faces = face_lists(faces)?;
        ConvexBlock::new(&vertices, &faces)
            .map(Block::wrap)
            .map_err(to_py_err)
    }

    /// The block ``{x : normals[i] . x <= offsets[i] for all i}``.
    ///
    /// Normals need not be unit vectors; redundant half-spaces are allowed.
    ///
    /// Parameters
    /// ----------
    /// normals : array_like, shape (m, 3)
    ///     Outward normals of the half-spaces.
    /// offsets : array_like, shape (m,)
    ///     Right-hand sides.
    ///
    /// Returns
    /// -------
    /// Block
    ///
    /// Raises
    /// ------
    /// InputError
    ///     Wrong shapes or dtypes, or ``len(normals) != len(offsets)``.
    /// BlockError
    ///     A zero or NaN normal (``kind == "degenerate_plane"``), or half-spaces that bound no
    ///     solid (``kind == "unbounded"``).
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> tet = penedge.Block.from_planes([[-1, 0, 0], [0, -1, 0], [0, 0, -1], [1, 1, 1]],
    /// ...                                 [0, 0, 0, 1])
    /// >>> len(tet.vertices), len(tet.faces), round(tet.volume, 12)
    /// (4, 4, 0.166666666667)
    #[staticmethod]
    fn from_planes(normals: &Bound<'_, PyAny>, offsets: &Bound<'_, PyAny>) -> PyResult<Self> {
        let (normals, offsets) = arrays::planes(normals, offsets)?;
        ConvexBlock::from_planes(&normals, &offsets)
            .map(Block::wrap)
            .map_err(to_py_err)
    }

    /// A rectangular box with lower corner `lo` and upper corner `hi`.
    ///
    /// Parameters
    /// ----------
    /// lo, hi : array_like, shape (3,)
    ///     Corners, with ``lo < hi`` in every coordinate.
    ///
    /// Returns
    /// -------
    /// Block
    ///     8 vertices, 6 faces.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     Not three finite numbers each, or ``lo >= hi`` in some coordinate.
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> penedge.Block.cuboid([0, 0, 0], [2, 1, 1]).aabb
    /// array([[0., 0., 0.],
    ///        [2., 1., 1.]])
    #[staticmethod]
    fn cuboid(lo: &Bound<'_, PyAny>, hi: &Bound<'_, PyAny>) -> PyResult<Self> {
        cuboid(lo, hi).map(Block::wrap)
    }

    /// The convex hull of points.
    ///
    /// The block's vertices are the hull's corners among `points`, in the order given;
    /// points inside, on a face or an edge, or within 1e-9 x size of another point are left
    /// out (every point left out is inside the block or within 1e-9 x size of it).
    /// Coplanar hull triangles make one face. The tolerance decides only which points
    /// become vertices; the hull of those is exact (exact orientation tests), so a dense
    /// cloud (a scan, 25,600 points on a sphere) gives a convex block like any other.
    /// The block's own validation, every vertex against every face plane, takes most of
    /// the time for such a cloud (some 5 s for 25,600 points on a sphere).
    ///
    /// Parameters
    /// ----------
    /// points : array_like, shape (n, 3)
    ///     At least 4 points, not all in one plane.
    ///
    /// Returns
    /// -------
    /// Block
    ///
    /// Raises
    /// ------
    /// InputError
    ///     `points` is not an (n, 3) array of real numbers.
    /// BlockError
    ///     Fewer than 4 points (``kind == "too_small"``), points all in one plane or on one
    ///     line (``kind == "zero_volume"``), a NaN or infinite coordinate.
    ///
    /// Examples
    /// --------
    /// >>> import itertools, penedge
    /// >>> lattice = list(itertools.product([0, 1, 2], repeat=3))  # and edge, face midpoints
    /// >>> cube = penedge.Block.from_hull(lattice)
    /// >>> len(cube.vertices), len(cube.faces), round(cube.volume, 12)
    /// (8, 6, 8.0)
    #[staticmethod]
    fn from_hull(points: &Bound<'_, PyAny>) -> PyResult<Self> {
        let points = arrays::points(points, "points")?;
        ConvexBlock::hull(&points)
            .map(Block::wrap)
            .map_err(to_py_err)
    }

    /// A copy moved by `offset`.
    ///
    /// Parameters
    /// ----------
    /// offset : array_like, shape (3,)
    ///
    /// Returns
    /// -------
    /// Block
    ///     The same faces and face origins, every vertex moved by `offset`.
    ///
    /// Raises
    /// ------
    /// BlockError
    ///     The moved block is not one a :class:`Block` can be: coordinates beyond 1e50 or
    ///     not finite, or vertices rounded together (a unit cube moved by 1e17).
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> penedge.Block.cuboid([0, 0, 0], [1, 1, 1]).translated([2, 0, 0]).aabb.tolist()
    /// [[2.0, 0.0, 0.0], [3.0, 1.0, 1.0]]
    fn translated(&self, offset: &Bound<'_, PyAny>) -> PyResult<Self> {
        let offset = finite_vector(offset, "offset")?;
        self.inner
            .try_translated(offset)
            .map(Block::wrap)
            .map_err(to_py_err)
    }

    /// A copy turned about its centroid, or about the point `about`.
    ///
    /// Parameters
    /// ----------
    /// rotation : array_like, shape (4,) or (3, 3)
    ///     A quaternion ``x, y, z, w`` (normalised here, as :meth:`ContactTracker.update`
    ///     takes them) or a rotation matrix (orthonormal with determinant 1, within 1e-9).
    /// about : array_like, shape (3,), optional
    ///     The fixed point of the rotation; the block's centroid when None.
    ///
    /// Returns
    /// -------
    /// Block
    ///     The same faces and face origins; a point ``x`` goes to
    ///     ``about + R (x - about)``.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     A zero or non-finite quaternion, a matrix that is not a rotation, or a wrong shape.
    /// BlockError
    ///     The turned block is not one a :class:`Block` can be (as :meth:`translated`: about
    ///     a point 1e300 away).
    ///
    /// Examples
    /// --------
    /// >>> import numpy as np, penedge
    /// >>> box = penedge.Block.cuboid([0, 0, 0], [2, 1, 1])
    /// >>> quarter = [0, 0, np.sin(np.pi / 4), np.cos(np.pi / 4)]  # 90 degrees about z
    /// >>> box.rotated(quarter).aabb.round(12) + 0.0  # about the centroid (1, 0.5, 0.5)
    /// array([[ 0.5, -0.5,  0. ],
    ///        [ 1.5,  1.5,  1. ]])
    /// >>> turned = box.rotated([[0, -1, 0], [1, 0, 0], [0, 0, 1]], about=[0, 0, 0])
    /// >>> turned.aabb.round(12) + 0.0  # (+ 0.0: no negative zeros)
    /// array([[-1.,  0.,  0.],
    ///        [ 0.,  2.,  1.]])
    #[pyo3(signature = (rotation, about=None))]
    fn rotated(
        &self,
        rotation: &Bound<'_, PyAny>,
        about: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let rotation = arrays::rotation(rotation, "rotation")?;
        let about = match about {
            Some(p) => finite_vector(p, "about")?,
            None => self.inner.centroid(),
        };
        self.inner
            .try_rotated(rotation, about)
            .map(Block::wrap)
            .map_err(to_py_err)
    }

    /// Equality by value: the same vertices (exactly, in the same order) and the same faces
    /// (the same vertex loops, in the same order). Where the faces come from (a joint, the
    /// domain boundary) is provenance, not shape, and is not compared.
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<Block>()
            .is_ok_and(|other| self.inner == other.get().inner)
    }

    /// A hash consistent with ``==`` (of the vertices' bits and the faces).
    fn __hash__(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for v in self.inner.vertices() {
            v.to_array().map(f64::to_bits).hash(&mut h);
        }
        for f in self.inner.faces() {
            f.hash(&mut h);
        }
        h.finish()
    }

    /// Vertex coordinates, shape (n, 3) float64 (a copy).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let rows: Vec<[f64; 3]> = self.inner.vertices().iter().map(|v| v.to_array()).collect();
        arrays::rows3(py, &rows)
    }

    /// Faces as lists of vertex indices, counter-clockwise seen from outside.
    #[getter]
    fn faces(&self) -> Vec<Vec<u32>> {
        self.inner.faces().map(|f| f.to_vec()).collect()
    }

    /// Edges as vertex index pairs, shape (e, 2) int64; feature ``("edge", i)`` is row i.
    #[getter]
    fn edges<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        let rows: Vec<[i64; 2]> = self
            .inner
            .edges()
            .iter()
            .map(|e| e.vertices.map(i64::from))
            .collect();
        arrays::pairs(py, &rows)
    }

    /// The two faces along each edge, shape (e, 2) int64 (the first runs from ``edges[i, 0]``
    /// to ``edges[i, 1]`` counter-clockwise).
    #[getter]
    fn edge_faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        let rows: Vec<[i64; 2]> = self
            .inner
            .edges()
            .iter()
            .map(|e| e.faces.map(i64::from))
            .collect();
        arrays::pairs(py, &rows)
    }

    /// Outward unit face normals, shape (f, 3) float64.
    #[getter]
    fn face_normals<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let rows: Vec<[f64; 3]> = self
            .inner
            .planes()
            .iter()
            .map(|p| p.normal.to_array())
            .collect();
        arrays::rows3(py, &rows)
    }

    /// Volume.
    #[getter]
    fn volume(&self) -> f64 {
        self.inner.volume()
    }

    /// Centroid (centre of volume), shape (3,).
    #[getter]
    fn centroid<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::vector(py, self.inner.centroid().to_array().to_vec())
    }

    /// Axis-aligned bounding box ``[lower corner, upper corner]``, shape (2, 3).
    #[getter]
    fn aabb<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let b = self.inner.aabb();
        arrays::rows3(py, &[b.min.to_array(), b.max.to_array()])
    }

    /// Characteristic length: the diagonal of the bounding box (tolerances scale with it).
    #[getter]
    fn size(&self) -> f64 {
        self.inner.size()
    }

    fn __repr__(&self) -> String {
        let b = &self.inner;
        format!(
            "Block({}, {}, {}, volume={:?}, centroid={:?})",
            crate::counted(b.vertices().len(), "vertex", "vertices"),
            crate::counted(b.n_faces(), "face", "faces"),
            crate::counted(b.edges().len(), "edge", "edges"),
            b.volume(),
            b.centroid().to_array(),
        )
    }

    /// Pickling: the vertices, the faces and each face's origin (domain boundary or joint,
    /// as `(code, a, b)` in the numbering of `BlockArrays.face_origin_*`), so that a block of
    /// a generated system keeps its provenance through a round trip.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let me = slf.get();
        let block = &me.inner;
        let origins: Vec<(u8, i64, i64)> = block
            .face_origins()
            .iter()
            .map(|o| {
                let (a, b) = o.ids();
                (o.code(), a, b)
            })
            .collect();
        let plane_rows =
            |f: fn(&Plane) -> [f64; 3]| -> Vec<[f64; 3]> { block.planes().iter().map(f).collect() };
        let normals = arrays::rows3(py, &plane_rows(|p| p.normal.to_array()));
        let points = arrays::rows3(py, &plane_rows(|p| p.point.to_array()));
        let args = (
            me.vertices(py),
            me.faces(),
            origins,
            normals,
            points,
            length_needed(block),
        );
        PyTuple::new(
            py,
            [
                py.get_type::<Block>().getattr("_restore")?,
                args.into_pyobject(py)?.into_any(),
            ],
        )
    }

    /// The block of [`Block::__reduce__`]'s parts (not a public constructor): its
    /// vertices, faces and face origins, and its planes (normals and points) with the
    /// relative length threshold that its faces need, kept as they were (the block comes back
    /// bit for bit). Without the planes (a pickle of an earlier version), the block is built
    /// from its vertices and faces.
    #[staticmethod]
    #[pyo3(signature = (vertices, faces, origins, normals=None, points=None, length=None))]
    fn _restore(
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        origins: Vec<(Bound<'_, PyAny>, Bound<'_, PyAny>, Bound<'_, PyAny>)>,
        normals: Option<&Bound<'_, PyAny>>,
        points: Option<&Bound<'_, PyAny>>,
        length: Option<f64>,
    ) -> PyResult<Self> {
        let origins = origins
            .iter()
            .map(|(code, a, b)| face_origin(number(code)?, number(a)?, number(b)?))
            .collect::<PyResult<Vec<_>>>()?;
        let (Some(normals), Some(points)) = (normals, points) else {
            let block = Block::new(vertices, faces)?;
            return block
                .inner
                .with_face_origins(origins)
                .map(Block::wrap)
                .map_err(to_py_err);
        };
        let tol = Tolerance::new(0.0, length.unwrap_or(Tolerance::default().length()))
            .map_err(to_py_err)?;
        let vertices = arrays::points(vertices, "vertices")?;
        let faces: Vec<Vec<u32>> = face_lists(faces)?
            .into_iter()
            .map(|f| f.into_iter().map(|v| v as u32).collect())
            .collect();
        let normals = arrays::points(normals, "normals")?;
        let points = arrays::points(points, "points")?;
        if normals.len() != points.len() {
            let msg = format!("{} normals and {} points", normals.len(), points.len());
            return Err(input_error("planes", msg));
        }
        let planes: Vec<Plane> = normals
            .iter()
            .zip(&points)
            .map(|(n, p)| Plane {
                normal: DVec3::from_array(*n),
                point: DVec3::from_array(*p),
            })
            .collect();
        ConvexBlock::from_parts(&vertices, &faces, &planes, &origins, &tol)
            .map(Block::wrap)
            .map_err(to_py_err)
    }
}

/// The relative length threshold that `block`'s own faces need: twice the farthest that a
/// vertex of a face is from the face's plane, or that any vertex is outside a plane,
/// relative to the block's size (at least the default threshold).
fn length_needed(block: &ConvexBlock) -> f64 {
    let mut farthest: f64 = 0.0;
    for (f, plane) in block.planes().iter().enumerate() {
        for &v in block.face(f) {
            farthest = farthest.max(plane.distance(block.vertices()[v as usize]).abs());
        }
        for &p in block.vertices() {
            farthest = farthest.max(plane.distance(p));
        }
    }
    let relative = 2.0 * farthest / block.size();
    relative.clamp(
        Tolerance::default().length(),
        0.5 * penedge::tolerance::MAX_LENGTH,
    )
}

/// Three finite numbers (an offset, a point), as an `InputError` when they are not.
fn finite_vector(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<DVec3> {
    let v = DVec3::from_array(arrays::point(obj, name)?);
    if !v.is_finite() {
        return Err(input_error(
            "not_finite",
            format!("{name} must be finite, got {v:?}"),
        ));
    }
    Ok(v)
}

/// A whole number of a face origin, as an `InputError` when it is none or too large.
fn number(x: &Bound<'_, PyAny>) -> PyResult<i64> {
    x.extract::<i64>().map_err(|_| {
        input_error(
            "origins",
            format!("face origin number {x} out of range or not an integer"),
        )
    })
}

/// A face origin from its code and two numbers ([`FaceOrigin::code`], [`FaceOrigin::ids`]).
pub(crate) fn face_origin(code: i64, a: i64, b: i64) -> PyResult<FaceOrigin> {
    let id = |x: i64| {
        u32::try_from(x)
            .map_err(|_| input_error("origins", format!("face origin number {x} out of range")))
    };
    match code {
        0 => Ok(FaceOrigin::Unknown),
        1 => Ok(FaceOrigin::Boundary {
            part: id(a)?,
            face: id(b)?,
        }),
        2 => Ok(FaceOrigin::Joint {
            set: id(a)?,
            joint: id(b)?,
        }),
        3 => Ok(FaceOrigin::Bridge {
            set: id(a)?,
            joint: id(b)?,
        }),
        _ => Err(input_error(
            "origins",
            format!(
                "face origin code {code} is not 0 (unknown), 1 (boundary), 2 (joint) or 3 (bridge)"
            ),
        )),
    }
}
