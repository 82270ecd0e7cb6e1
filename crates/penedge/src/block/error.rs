//! Errors raised when a block cannot be built.

use crate::tolerance::ROUNDING_FLOOR;
use std::fmt;
use thiserror::Error;

/// A length or magnitude as people read it in a message: three significant digits in
/// scientific notation, trailing zeros dropped (`5.55e-17`, `1e300`, `3.6e0`), not the 17
/// digits that reproduce an `f64`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Readable(pub(crate) f64);

impl fmt::Display for Readable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text = format!("{:.2e}", self.0);
        match text.split_once('e') {
            Some((mantissa, exponent)) if mantissa.contains('.') => {
                let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
                write!(f, "{mantissa}e{exponent}")
            }
            _ => f.write_str(&text), // NaN, inf
        }
    }
}

/// [`Readable`] of a field (thiserror passes fields by reference).
pub(crate) fn readable(x: &f64) -> Readable {
    Readable(*x)
}

/// The end of [`BlockError::RepeatedVertex`]'s message: nothing when the block's own size set
/// the distance within which vertices coincide; otherwise the rounding of its coordinates
/// set it (ten times [`ROUNDING_FLOOR`] times their magnitude), and the message says that the
/// coordinates are too large for the block's size.
fn rounding_note(within: f64, magnitude: f64, size: f64) -> String {
    if within > 10.0 * (ROUNDING_FLOOR * magnitude) {
        return String::new();
    }
    format!(
        " (within {}): its coordinates, up to {} in magnitude, are too large for double \
         precision at the block's size ({} across), which rounds them too coarsely to keep \
         its vertices apart there; move the block nearer the origin",
        Readable(within),
        Readable(magnitude),
        Readable(size)
    )
}

/// Why a set of vertices and faces (or half-spaces) is not a valid convex block.
///
/// Each variant names the offending vertex or face by its index in the input.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BlockError {
    /// Fewer than 4 vertices or 4 faces.
    #[error(
        "a block needs at least 4 vertices and 4 faces, got {vertices} vertices and {faces} faces"
    )]
    TooSmall {
        /// Vertices given.
        vertices: usize,
        /// Faces given.
        faces: usize,
    },
    /// A rotation that is not a unit quaternion (a rigid move needs one: another scales and
    /// shears the block).
    #[error(
        "the rotation is not a unit quaternion (its length is {length}): normalise it (a \
         quaternion of another length scales and shears the block)"
    )]
    NotUnitRotation {
        /// The quaternion's length.
        length: f64,
    },
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a NaN or infinite coordinate")]
    NonFiniteVertex {
        /// Vertex index.
        vertex: usize,
    },
    /// A coordinate too large, or a block too small, for double precision to compute its
    /// volume, centroid and planes (see [`crate::block::MAX_COORDINATE`] and
    /// [`crate::block::MIN_SIZE`]).
    #[error("the block's {what} is {}, outside what double precision handles (coordinates up to 1e50 in magnitude, blocks at least 1e-50 across)", readable(.value))]
    OutOfRange {
        /// `"largest coordinate"` or `"size"`.
        what: &'static str,
        /// The value found.
        value: f64,
    },
    /// More half-spaces than [`crate::block::MAX_HALFSPACES`].
    #[error("a block from half-spaces takes at most {limit} of them, got {count}")]
    TooManyPlanes {
        /// Half-spaces given.
        count: usize,
        /// The limit.
        limit: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but there are only {count} vertices")]
    VertexIndexOutOfRange {
        /// Face index.
        face: usize,
        /// Index found.
        vertex: usize,
        /// Number of vertices.
        count: usize,
    },
    /// A face with fewer than 3 vertices, or with a vertex listed twice.
    #[error("face {face} is not a polygon: it needs 3 or more distinct vertices")]
    DegenerateFaceList {
        /// Face index.
        face: usize,
    },
    /// Two vertices at the same position: within `within` of each other, the distance
    /// below which vertices coincide (set by the block's size, or by the rounding of its
    /// coordinates when they are large for it, which the message then says).
    #[error("vertices {first} and {second} are at the same position{}", rounding_note(*.within, *.magnitude, *.size))]
    RepeatedVertex {
        /// First vertex.
        first: usize,
        /// Second vertex.
        second: usize,
        /// The distance within which vertices coincide.
        within: f64,
        /// The largest coordinate magnitude of the vertices.
        magnitude: f64,
        /// The vertices' size (bounding-box diagonal).
        size: f64,
    },
    /// A vertex that no face uses.
    #[error("vertex {vertex} belongs to no face")]
    UnusedVertex {
        /// Vertex index.
        vertex: usize,
    },
    /// An edge used by one face only: the surface has a hole.
    #[error("the surface is open: edge ({first}, {second}) belongs to one face only")]
    OpenSurface {
        /// One end.
        first: usize,
        /// Other end.
        second: usize,
    },
    /// An edge used by more than two faces.
    #[error(
        "the surface is not manifold: edge ({first}, {second}) belongs to more than two faces"
    )]
    NonManifoldEdge {
        /// One end.
        first: usize,
        /// Other end.
        second: usize,
    },
    /// Two faces run along an edge in the same direction.
    #[error("faces {first} and {second} have inconsistent orientation along edge ({a}, {b})")]
    InconsistentOrientation {
        /// One face.
        first: usize,
        /// The other face.
        second: usize,
        /// One end of the edge.
        a: usize,
        /// Other end of the edge.
        b: usize,
    },
    /// The surface is closed but not a sphere (several shells, a handle).
    #[error("the surface is not a single closed shell (V - E + F = {euler}, expected 2)")]
    NotASphere {
        /// The Euler characteristic found.
        euler: i64,
    },
    /// The faces are listed clockwise seen from outside (inward normals).
    #[error("the faces are clockwise seen from outside (the signed volume is negative); list them counter-clockwise")]
    WrongOrientation,
    /// The block has no volume.
    #[error("the block has zero volume")]
    ZeroVolume,
    /// A face with (almost) no area.
    #[error("face {face} has zero area")]
    ZeroAreaFace {
        /// Face index.
        face: usize,
    },
    /// A face whose vertices are not in one plane.
    #[error("face {face} is not planar: vertex {vertex} is {} off its plane", readable(.distance))]
    NonPlanarFace {
        /// Face index.
        face: usize,
        /// Vertex index.
        vertex: usize,
        /// Distance from the plane.
        distance: f64,
    },
    /// A face polygon that is not convex.
    #[error("face {face} is not convex at vertex {vertex}")]
    NonConvexFace {
        /// Face index.
        face: usize,
        /// Vertex index.
        vertex: usize,
    },
    /// The block is not convex: a vertex lies outside a face plane.
    #[error(
        "the block is not convex: vertex {vertex} is {} outside the plane of face {face}",
        readable(.distance)
    )]
    NotConvex {
        /// Face index.
        face: usize,
        /// Vertex index.
        vertex: usize,
        /// Distance outside.
        distance: f64,
    },
    /// A vertex that lies on a straight edge (it belongs to two faces only).
    #[error("vertex {vertex} is not a corner: it lies on the straight edge between two faces")]
    NotACorner {
        /// Vertex index.
        vertex: usize,
    },
    /// A box whose lower corner is not below its upper corner on one axis (or NaN).
    #[error("the box is empty: its lower corner is not below its upper corner along axis {axis}")]
    EmptyBox {
        /// 0 for x, 1 for y, 2 for z.
        axis: usize,
    },
    /// Half-spaces that do not bound a solid.
    #[error("the half-spaces do not bound a solid block ({reason})")]
    Unbounded {
        /// What went wrong.
        reason: &'static str,
    },
    /// Half-spaces given with as many normals as offsets: one of each is needed per plane.
    #[error(
        "{normals} normals but {offsets} offsets: each half-space needs one normal and one \
         offset"
    )]
    PlaneCount {
        /// Normals given.
        normals: usize,
        /// Offsets given.
        offsets: usize,
    },
    /// A half-space with a zero, NaN or infinite normal or offset.
    #[error("half-space {plane} has a zero, NaN or infinite normal or offset")]
    DegeneratePlane {
        /// Plane index.
        plane: usize,
    },
    /// A list with one entry per face has the wrong length.
    #[error("expected one entry per face ({expected}), got {got}")]
    OriginCount {
        /// Number of faces.
        expected: usize,
        /// Entries given.
        got: usize,
    },
    /// A stored face plane whose normal is not a finite unit vector.
    #[error("the plane of face {face} has no finite unit normal")]
    BadPlane {
        /// Face index.
        face: usize,
    },
    /// A cut whose pieces do not close: the plane passes within the tolerance of the block's
    /// features in a way that no consistent pair of pieces can represent.
    #[error("degenerate cut: {reason}")]
    DegenerateCut {
        /// What went wrong.
        reason: &'static str,
    },
}
