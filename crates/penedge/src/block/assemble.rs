//! Assembling a block from parts whose topology and planes are already known: a piece made
//! by a cut (the planes are inherited, so neighbours share them exactly), or a block read back
//! from a file (nothing is recomputed that was stored, so the round trip is lossless).
//!
//! [`BlockParts::tidy`] drops faces left with fewer than 3 vertices and vertices left on a
//! straight edge (in fewer than 3 faces), then compacts the vertex list; assembling pairs the
//! half-edges (a closed, manifold, consistently oriented surface), checks the Euler
//! characteristic and a positive volume, and derives edges, volume, centroid and box.

use super::{BlockError, Bounds, ConvexBlock, Edge, FaceOrigin, LocalCoordinates};
use crate::geometry::{DVec3, Plane};

/// Vertices and face loops (flat, with offsets), one plane and one origin per face.
#[derive(Clone, Debug, Default)]
pub(crate) struct BlockParts {
    pub(crate) vertices: Vec<DVec3>,
    pub(crate) face_offsets: Vec<u32>,
    pub(crate) face_vertices: Vec<u32>,
    pub(crate) planes: Vec<Plane>,
    pub(crate) origins: Vec<FaceOrigin>,
}

impl BlockParts {
    /// Number of faces.
    pub(crate) fn n_faces(&self) -> usize {
        self.planes.len()
    }

    fn face(&self, f: usize) -> &[u32] {
        &self.face_vertices[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// Drops faces with fewer than 3 vertices and vertices in fewer than 3 faces, and keeps
    /// only the vertices used: the face loops index `points`, and `vertices` is rebuilt from
    /// it. `scratch` is a reusable buffer.
    pub(crate) fn tidy(&mut self, points: &[DVec3], scratch: &mut Vec<u32>) {
        loop {
            scratch.clear();
            scratch.resize(points.len(), 0);
            for &v in &self.face_vertices {
                scratch[v as usize] += 1;
            }
            let degree = &*scratch;
            let weak = |v: &u32| degree[*v as usize] < 3;
            let small = (0..self.n_faces()).any(|f| self.face(f).len() < 3);
            if !small && !self.face_vertices.iter().any(weak) {
                break;
            }
            self.keep_faces(|face| face.iter().filter(|v| !weak(v)).count() >= 3, degree);
        }
        self.compact(points, scratch);
    }

    /// Keeps the faces that `keep` accepts, without their weak (degree < 3) vertices.
    fn keep_faces(&mut self, keep: impl Fn(&[u32]) -> bool, degree: &[u32]) {
        let mut out = BlockParts {
            vertices: std::mem::take(&mut self.vertices),
            face_offsets: vec![0],
            ..BlockParts::default()
        };
        for f in 0..self.n_faces() {
            let face = self.face(f);
            if !keep(face) {
                continue;
            }
            let strong = face.iter().filter(|&&v| degree[v as usize] >= 3);
            out.face_vertices.extend(strong);
            out.face_offsets.push(out.face_vertices.len() as u32);
            out.planes.push(self.planes[f]);
            out.origins.push(self.origins[f]);
        }
        *self = out;
    }

    /// Renumbers the vertices in order of first use, taking them from `points`.
    fn compact(&mut self, points: &[DVec3], remap: &mut Vec<u32>) {
        remap.clear();
        remap.resize(points.len(), u32::MAX);
        self.vertices.clear();
        for v in self.face_vertices.iter_mut() {
            let r = &mut remap[*v as usize];
            if *r == u32::MAX {
                *r = self.vertices.len() as u32;
                self.vertices.push(points[*v as usize]);
            }
            *v = *r;
        }
    }
}

impl ConvexBlock {
    /// A block from parts with known planes; checks topology and volume, not geometry.
    pub(crate) fn assemble(parts: BlockParts) -> Result<ConvexBlock, BlockError> {
        ConvexBlock::assemble_with(parts, &mut Vec::new())
    }

    /// [`ConvexBlock::assemble`] with a reusable buffer for the half-edges.
    pub(crate) fn assemble_with(
        parts: BlockParts,
        half: &mut Vec<(u64, u32, u32)>,
    ) -> Result<ConvexBlock, BlockError> {
        let n_faces = parts.n_faces();
        if parts.vertices.len() < 4 || n_faces < 4 {
            return Err(BlockError::TooSmall {
                vertices: parts.vertices.len(),
                faces: n_faces,
            });
        }
        let edges = pair_edges(&parts.face_offsets, &parts.face_vertices, half)?;
        let euler = parts.vertices.len() as i64 - edges.len() as i64 + n_faces as i64;
        if euler != 2 {
            return Err(BlockError::NotASphere { euler });
        }
        let (volume, centroid) = volume_and_centroid(
            &parts.vertices,
            parts.face_offsets.windows(2).map(|w| {
                parts.face_vertices[w[0] as usize..w[1] as usize]
                    .iter()
                    .map(|&v| v as usize)
            }),
        );
        if volume.is_nan() || volume <= 0.0 {
            return Err(if volume < 0.0 {
                BlockError::WrongOrientation
            } else {
                BlockError::ZeroVolume
            });
        }
        let vertex_faces = super::vertex_face_masks(
            parts.vertices.len(),
            &parts.face_offsets,
            &parts.face_vertices,
        );
        Ok(ConvexBlock {
            clearance: super::Clearance::of(&parts.vertices, &parts.planes, &vertex_faces),
            vertex_faces,
            bounds: Bounds::of(&parts.vertices),
            local: LocalCoordinates::of(&parts.vertices),
            vertices: parts.vertices,
            face_offsets: parts.face_offsets,
            face_vertices: parts.face_vertices,
            planes: parts.planes,
            origins: parts.origins,
            edges,
            volume,
            centroid,
        })
    }
}

/// Pairs each half-edge with its twin. Edges come in order of first appearance walking the
/// faces, each running as in the first face that has it (the order [`ConvexBlock::new`]
/// gives, so that a block read back from a file has the same edge ids).
fn pair_edges(
    offsets: &[u32],
    verts: &[u32],
    half: &mut Vec<(u64, u32, u32)>,
) -> Result<Vec<Edge>, BlockError> {
    half.clear();
    for f in 0..offsets.len() - 1 {
        let face = &verts[offsets[f] as usize..offsets[f + 1] as usize];
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            let key = ((a.min(b) as u64) << 32) | a.max(b) as u64;
            half.push((key, a, f as u32));
        }
    }
    // Stable: of two twins, the one met first stays first.
    half.sort_by_key(|h| h.0);
    let mut edges = Vec::with_capacity(half.len() / 2);
    let mut k = 0;
    while k < half.len() {
        let run = half[k..].iter().take_while(|h| h.0 == half[k].0).count();
        edges.push(twin_edge(&half[k..k + run])?);
        k += run;
    }
    let first_seen = |e: &Edge| (offsets[e.faces[0] as usize], e.vertices[0]);
    edges.sort_by_key(|e| position(verts, first_seen(e)));
    Ok(edges)
}

/// The position of the half-edge starting at vertex `v` in the face starting at `start`.
fn position(verts: &[u32], (start, v): (u32, u32)) -> usize {
    let face = &verts[start as usize..];
    start as usize + face.iter().position(|&x| x == v).unwrap_or(0)
}

/// The edge of two half-edges with the same vertex pair, run in opposite directions; the
/// first half-edge is the one met first.
fn twin_edge(run: &[(u64, u32, u32)]) -> Result<Edge, BlockError> {
    let (key, a, f) = run[0];
    let (lo, hi) = ((key >> 32) as usize, (key & 0xffff_ffff) as usize);
    match run {
        [_] => Err(BlockError::OpenSurface {
            first: lo,
            second: hi,
        }),
        [_, (_, a2, g)] if *a2 == a => Err(BlockError::InconsistentOrientation {
            first: f as usize,
            second: *g as usize,
            a: lo,
            b: hi,
        }),
        [_, (_, _, g)] => {
            let b = if a as usize == lo { hi } else { lo } as u32;
            Ok(Edge {
                vertices: [a, b],
                faces: [f, *g],
            })
        }
        _ => Err(BlockError::NonManifoldEdge {
            first: lo,
            second: hi,
        }),
    }
}

/// Signed volume and centroid by the divergence theorem (faces fanned from their first
/// vertex), in coordinates local to vertex 0.
pub(crate) fn volume_and_centroid<F, I>(points: &[DVec3], faces: F) -> (f64, DVec3)
where
    F: IntoIterator<Item = I>,
    I: IntoIterator<Item = usize>,
{
    let origin = points[0];
    let mut volume = 0.0;
    let mut moment = DVec3::ZERO;
    for face in faces {
        let mut corners = face.into_iter().map(|v| points[v] - origin);
        let (Some(a), Some(mut b)) = (corners.next(), corners.next()) else {
            continue;
        };
        for c in corners {
            let v6 = a.dot(b.cross(c));
            volume += v6;
            moment += v6 * (a + b + c);
            b = c;
        }
    }
    let centroid = if volume != 0.0 {
        origin + moment / (4.0 * volume)
    } else {
        origin
    };
    (volume / 6.0, centroid)
}
