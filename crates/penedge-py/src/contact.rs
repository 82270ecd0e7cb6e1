//! `detect_pair` and its answer `PairContact` (core [`Detector`]).

use crate::arrays::{self, Real};
use crate::block::Block;
use crate::classify::{feature_tuple, type_code};
use crate::tolerance::tolerance;
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use penedge::classify::PairResult;
use penedge::contact_geometry::ContactGeometry;
use penedge::penetration::{EdgeEnd, PenetrationEdge, Side};
use penedge::Detector;
use pyo3::prelude::*;

/// The contact of two blocks, as found by :func:`detect_pair`.
///
/// Attributes
/// ----------
/// outcome : str
///     One of :data:`CONTACT_TYPES`, ``"separated"`` or ``"penetrating"``.
/// touching : bool
///     Whether the blocks touch within the gap (one of the seven types).
/// type_code : int
///     1..7 (index into :data:`CONTACT_TYPES` plus one), :data:`SEPARATED` (0) or
///     :data:`PENETRATING` (-1).
/// feature_a, feature_b : tuple of (str, int) or None
///     The smallest feature of each block that holds the contact: ``("vertex", i)`` (row of
///     ``Block.vertices``), ``("edge", i)`` (row of ``Block.edges``) or ``("face", i)`` (item
///     of ``Block.faces``); None unless touching.
/// penetration_edges : numpy.ndarray
///     One record per penetration edge (see the property).
/// penetration_points : numpy.ndarray
///     End points of the penetration edges, shape (k, 2, 3).
/// normal : numpy.ndarray, shape (3,), or None
///     Unit contact normal from `a` to `b` (None unless touching).
/// distance : float or None
///     Signed distance along the normal: a gap (> 0) or a depth (< 0).
/// points : numpy.ndarray, shape (k, 3), or None
///     Contact points: one point, the two ends of a segment (edge-face, edge-edge
///     superposition), or a convex polygon counter-clockwise about the normal (face-face).
/// area : float or None
///     Area of a face-face contact; 0 for a point or a segment.
#[pyclass(module = "penedge", name = "PairContact", frozen)]
pub struct PairContact {
    result: PairResult,
    geometry: Option<ContactGeometry>,
    edges: Vec<PenetrationEdge>,
    points: Vec<[[f64; 3]; 2]>,
    counts: ([[usize; 5]; 2], [usize; 2]),
}

/// Detects and classifies the contact of two blocks (penetration-edge method).
///
/// Every edge of `a` is clipped by the face planes of `b` moved out by the gap, and vice
/// versa; the surviving pieces (penetration edges) decide whether the blocks touch and how.
///
/// Parameters
/// ----------
/// a, b : Block
///     The two blocks.
/// gap : float, default 1e-12
///     Relative gap: blocks closer than ``gap * scale`` touch, and a penetration up to
///     ``gap * scale`` still counts as touching (scale: the smaller block's size). The default
///     only absorbs rounding. 0, or at least ``16 * 2**-52`` (3.6e-15): a smaller gap is
///     below the rounding of the coordinates (``docs/tolerance.md``).
/// length : float, optional
///     Relative length threshold ("no length", on a plane, parallel); at least ``10 * gap``.
///     Default ``max(1e-9, 10 * gap)``.
/// absolute_gap : float, optional
///     The gap as a length, in the model's unit, instead of the relative `gap` (leave `gap`
///     at its default): the same for every pair, up to 1 % of the pair's size, never below
///     the rounding of the coordinates; the length threshold is at least ten times it.
///
/// Returns
/// -------
/// PairContact
///
/// Raises
/// ------
/// InputError
///     A bool for `gap`, `length` or `absolute_gap` (kind ``dtype``): a bool is no number.
/// ToleranceError
///     `gap` not in [0, 0.01), a `gap` above 0 but below ``16 * 2**-52`` (kind
///     ``gap_below_rounding``), `length` not in [0, 0.1), ``length < 10 * gap``, a negative
///     or non-finite `absolute_gap`, or both `gap` and `absolute_gap`.
///
/// Examples
/// --------
/// >>> import penedge
/// >>> a = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
/// >>> b = penedge.Block.cuboid([1, 0, 0], [2, 1, 1])
/// >>> c = penedge.detect_pair(a, b)
/// >>> c.outcome, c.type_code, c.feature_a, c.feature_b
/// ('face-face', 7, ('face', 3), ('face', 5))
/// >>> apart = penedge.Block.cuboid([1.001, 0, 0], [2, 1, 1])
/// >>> penedge.detect_pair(a, apart).outcome
/// 'separated'
/// >>> penedge.detect_pair(a, apart, gap=1e-3).outcome
/// 'face-face'
/// >>> penedge.detect_pair(a, apart, absolute_gap=0.002).outcome  # a length: 2 mm
/// 'face-face'
/// >>> c.normal, c.area, c.distance
/// (array([1., 0., 0.]), 1.0, 0.0)
#[pyfunction]
#[pyo3(signature = (a, b, gap = Real::Value(1e-12), length = None, absolute_gap = None),
    text_signature = "(a, b, gap=1e-12, length=None, absolute_gap=None)")]
pub fn detect_pair(
    a: &Bound<'_, Block>,
    b: &Bound<'_, Block>,
    gap: Real,
    length: Option<Real>,
    absolute_gap: Option<Real>,
) -> PyResult<PairContact> {
    let (a, b) = (&a.get().inner, &b.get().inner);
    let mut detector = Detector::new(tolerance(gap, length, absolute_gap)?);
    let (result, geometry) = detector.detect_with_geometry(a, b);
    let edges = detector.penetration_edges().to_vec();
    let points = edges
        .iter()
        .map(|pe| {
            let owner = if pe.side == Side::A { a } else { b };
            pe.points(owner).map(|p| p.to_array())
        })
        .collect();
    Ok(PairContact {
        result,
        geometry,
        edges,
        points,
        counts: detector.table1_counts(),
    })
}

fn end_fields(end: EdgeEnd) -> (&'static str, i64) {
    match end {
        EdgeEnd::Vertex(v) => ("vertex", i64::from(v)),
        EdgeEnd::Cut(f) => ("cut", i64::from(f)),
    }
}

#[pymethods]
impl PairContact {
    /// The outcome: a contact type name, ``"separated"`` or ``"penetrating"``.
    #[getter]
    fn outcome(&self) -> &'static str {
        self.result.name()
    }

    /// Whether the blocks touch (one of the seven types).
    #[getter]
    fn touching(&self) -> bool {
        matches!(self.result, PairResult::Contact(_))
    }

    /// 1..7 for a contact, 0 (SEPARATED) or -1 (PENETRATING).
    #[getter]
    fn type_code(&self) -> i8 {
        type_code(&self.result)
    }

    /// The feature of `a` holding the contact, ``(kind, index)``, or None.
    #[getter]
    fn feature_a(&self) -> Option<(&'static str, i64)> {
        match self.result {
            PairResult::Contact(c) => Some(feature_tuple(c.feature_a)),
            _ => None,
        }
    }

    /// The feature of `b` holding the contact, ``(kind, index)``, or None.
    #[getter]
    fn feature_b(&self) -> Option<(&'static str, i64)> {
        match self.result {
            PairResult::Contact(c) => Some(feature_tuple(c.feature_b)),
            _ => None,
        }
    }

    /// Unit contact normal from `a` to `b`, shape (3,); None unless touching.
    #[getter]
    fn normal<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        let g = self.geometry.as_ref()?;
        Some(arrays::vector(py, g.normal().to_array().to_vec()))
    }

    /// Signed distance along the normal: gap (> 0) or depth (< 0); None unless touching.
    #[getter]
    fn distance(&self) -> Option<f64> {
        self.geometry.as_ref().map(ContactGeometry::distance)
    }

    /// Contact points, shape (k, 3): one point, a segment's two ends or a polygon's
    /// vertices (counter-clockwise about the normal); None unless touching.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f64>>> {
        let g = self.geometry.as_ref()?;
        let rows: Vec<[f64; 3]> = g.points().iter().map(|p| p.to_array()).collect();
        Some(arrays::rows3(py, &rows))
    }

    /// Contact area (face-face; 0 for a point or a segment); None unless touching.
    #[getter]
    fn area(&self) -> Option<f64> {
        self.geometry.as_ref().map(ContactGeometry::area)
    }

    /// The penetration edges, a structured array with one record per edge.
    ///
    /// Fields: ``side`` (``"A"`` or ``"B"``: the block owning the parent edge), ``edge``
    /// (parent edge, row of that block's ``edges``), ``t0 <= t1`` (the piece's ends as
    /// parameters along the parent edge, 0 at ``edges[edge, 0]``), ``end0_kind`` /
    /// ``end1_kind`` (``"vertex"``: an original vertex, ``end0`` / ``end1`` its index in the
    /// owner; ``"cut"``: cut by a face plane of the other block, ``end0`` / ``end1`` that
    /// face), ``type`` (paper Table 1: 1 two vertices; 2 / 3 one vertex and one cut, with /
    /// without length; 4 / 5 two cuts, with / without length). Empty when a face plane
    /// separates the blocks before any clipping.
    #[getter]
    fn penetration_edges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let records: Vec<_> = self
            .edges
            .iter()
            .map(|pe| {
                let (k0, e0) = end_fields(pe.ends[0]);
                let (k1, e1) = end_fields(pe.ends[1]);
                let side = if pe.side == Side::A { "A" } else { "B" };
                let edge = i64::from(pe.edge);
                (side, edge, pe.t[0], pe.t[1], k0, e0, k1, e1, pe.kind as i8)
            })
            .collect();
        let dtype = [
            ("side", "U1"),
            ("edge", "i8"),
            ("t0", "f8"),
            ("t1", "f8"),
            ("end0_kind", "U6"),
            ("end0", "i8"),
            ("end1_kind", "U6"),
            ("end1", "i8"),
            ("type", "i1"),
        ];
        let numpy = py.import("numpy")?;
        numpy.getattr("array")?.call1((records, dtype.to_vec()))
    }

    /// End points of the penetration edges, shape (k, 2, 3), in the order of
    /// ``penetration_edges``.
    #[getter]
    fn penetration_points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        let p = &self.points;
        Array3::from_shape_fn((p.len(), 2, 3), |(i, j, k)| p[i][j][k]).into_pyarray(py)
    }

    /// The counts of the paper's Table 2: penetration edges of each block by Table 1 type,
    /// shape (2, 5) (row 0 block A, column ``t - 1`` type t), and the number of distinct
    /// original vertices of each block among them, shape (2,).
    fn table1_counts<'py>(
        &self,
        py: Python<'py>,
    ) -> (Bound<'py, PyArray2<i64>>, Bound<'py, PyArray1<i64>>) {
        let (by_type, originals) = self.counts;
        let by_type = numpy::ndarray::Array2::from_shape_fn((2, 5), |(s, t)| by_type[s][t] as i64);
        let originals = originals.iter().map(|&n| n as i64).collect();
        (by_type.into_pyarray(py), arrays::vector(py, originals))
    }

    fn __repr__(&self) -> String {
        let features = match self.result {
            PairResult::Contact(c) => {
                let (ka, ia) = feature_tuple(c.feature_a);
                let (kb, ib) = feature_tuple(c.feature_b);
                format!(", feature_a=('{ka}', {ia}), feature_b=('{kb}', {ib})")
            }
            _ => String::new(),
        };
        format!(
            "PairContact('{}'{features}, {} penetration edges)",
            self.result.name(),
            self.edges.len()
        )
    }
}
