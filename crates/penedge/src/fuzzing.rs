//! The bodies of the fuzz targets (`fuzz/`, see `docs/fuzzing.md`), shared with their
//! regression tests (`tests/fuzz_regressions.rs`) so that a saved crash input runs through
//! exactly the code that found it. Not part of the API.
//!
//! Each target decodes arbitrary bytes into an input (a [`Bytes`] reader never fails: past
//! the end it reads zeros), runs one entry point and panics only when something the crate
//! guarantees does not hold: a valid block is closed, convex and finite and reads back from
//! its file bit for bit; swapping the blocks of a pair swaps the result; a file that reads
//! can be written and read again, and so can a generated system. Errors are fine; panics,
//! hangs and overflows are findings.

use crate::block::ConvexBlock;
use crate::classify::{Feature, PairResult};
use crate::contact::Detector;
use crate::contact_geometry::{ContactGeometry, ContactPoints};
use crate::cutting::split_block;
use crate::generation::{self, JointKind, Spec};
use crate::geometry::{DVec3, Plane};
use crate::io::{json, spec as spec_io, vtp, vtu};
use crate::system::BlockSystem;
use crate::tolerance::Tolerance;
use glam::DQuat;

/// A reader of fuzz bytes that never fails: past the end it reads zeros.
#[derive(Clone, Debug)]
pub struct Bytes<'a> {
    data: &'a [u8],
}

/// Numbers that break naive code: signed zeros, NaN, infinities, the extremes of `f64`,
/// subnormals, mine-grid and far-away magnitudes.
const SPECIAL: [f64; 18] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    1e300,
    -1e300,
    1e-300,
    f64::MAX,
    f64::MIN_POSITIVE,
    5e-324,
    1e15,
    4e6,
    0.1,
    1e-9,
    1e150,
];

impl<'a> Bytes<'a> {
    /// A reader of `data`.
    pub fn new(data: &'a [u8]) -> Self {
        Bytes { data }
    }

    /// The next byte (0 past the end).
    pub fn u8(&mut self) -> u8 {
        match self.data.split_first() {
            Some((&b, rest)) => {
                self.data = rest;
                b
            }
            None => 0,
        }
    }

    /// A number in `0..n` (`1 <= n <= 256`).
    pub fn below(&mut self, n: usize) -> usize {
        self.u8() as usize % n
    }

    /// Eight bytes, little-endian.
    pub fn u64(&mut self) -> u64 {
        let mut b = [0u8; 8];
        for x in &mut b {
            *x = self.u8();
        }
        u64::from_le_bytes(b)
    }

    /// A number: mostly a multiple of 1/4 in [-32, 32), sometimes a fraction with three
    /// decimals, a special value ([`SPECIAL`]) or any 64 bits.
    pub fn number(&mut self) -> f64 {
        match self.u8() {
            0..=199 => (self.u8() as i8) as f64 * 0.25,
            200..=229 => {
                let v = i16::from_le_bytes([self.u8(), self.u8()]);
                v as f64 / 1000.0
            }
            230..=244 => SPECIAL[self.below(SPECIAL.len())],
            _ => f64::from_bits(self.u64()),
        }
    }

    /// Three numbers.
    pub fn point(&mut self) -> [f64; 3] {
        [self.number(), self.number(), self.number()]
    }

    /// Whether the input is used up.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }
}

/// A mesh: vertices and faces (vertex index lists).
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex coordinates.
    pub vertices: Vec<[f64; 3]>,
    /// Faces, counter-clockwise seen from outside when the mesh is valid.
    pub faces: Vec<Vec<usize>>,
}

impl Mesh {
    fn of(vertices: &[[f64; 3]], faces: &[&[usize]]) -> Mesh {
        Mesh {
            vertices: vertices.to_vec(),
            faces: faces.iter().map(|f| f.to_vec()).collect(),
        }
    }

    fn of_block(b: &ConvexBlock) -> Mesh {
        Mesh {
            vertices: b.vertices().iter().map(|v| v.to_array()).collect(),
            faces: b
                .faces()
                .map(|f| f.iter().map(|&v| v as usize).collect())
                .collect(),
        }
    }

    fn map(&mut self, f: impl Fn(DVec3) -> DVec3) {
        for v in &mut self.vertices {
            *v = f(DVec3::from_array(*v)).to_array();
        }
    }

    fn build(&self, tol: &Tolerance) -> Option<ConvexBlock> {
        ConvexBlock::with_tolerance(&self.vertices, &self.faces, tol).ok()
    }
}

const CUBE_V: [[f64; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
    [0.0, 1.0, 1.0],
];
const CUBE_F: [&[usize]; 6] = [
    &[0, 3, 2, 1],
    &[4, 5, 6, 7],
    &[0, 1, 5, 4],
    &[1, 2, 6, 5],
    &[2, 3, 7, 6],
    &[3, 0, 4, 7],
];

/// A few valid convex blocks to start from: cube, tetrahedron, octahedron, triangular prism,
/// square pyramid, and the cube with every face split into two triangles.
pub fn base_shape(k: usize) -> Mesh {
    match k % 6 {
        0 => Mesh::of(&CUBE_V, &CUBE_F),
        1 => Mesh::of(
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            &[&[0, 2, 1], &[0, 1, 3], &[0, 3, 2], &[1, 2, 3]],
        ),
        2 => Mesh::of(
            &[
                [1.0, 0.0, 0.0],
                [-1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.0, 0.0, -1.0],
            ],
            &[
                &[0, 2, 4],
                &[2, 1, 4],
                &[1, 3, 4],
                &[3, 0, 4],
                &[2, 0, 5],
                &[1, 2, 5],
                &[3, 1, 5],
                &[0, 3, 5],
            ],
        ),
        3 => Mesh::of(
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [0.0, 1.0, 1.0],
            ],
            &[
                &[0, 2, 1],
                &[3, 4, 5],
                &[0, 1, 4, 3],
                &[1, 2, 5, 4],
                &[2, 0, 3, 5],
            ],
        ),
        4 => Mesh::of(
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.5, 0.5, 1.0],
            ],
            &[
                &[0, 3, 2, 1],
                &[0, 1, 4],
                &[1, 2, 4],
                &[2, 3, 4],
                &[3, 0, 4],
            ],
        ),
        _ => {
            let mut m = Mesh::of(&CUBE_V, &[]);
            for f in CUBE_F {
                m.faces.push(vec![f[0], f[1], f[2]]);
                m.faces.push(vec![f[0], f[2], f[3]]);
            }
            m
        }
    }
}

/// A tolerance: the default most of the time, else a coarse, a DEM-like or a zero one.
pub fn tolerance(bytes: &mut Bytes) -> Tolerance {
    let t = match bytes.below(8) {
        0 => Tolerance::new(1e-9, 1e-6),
        1 => Tolerance::with_gap(1e-3),
        2 => Tolerance::new(0.0, 0.0),
        _ => Ok(Tolerance::default()),
    };
    t.unwrap_or_default()
}

/// A rigid motion with scaling: rotation, scale about the origin, then translation.
#[derive(Clone, Copy, Debug)]
pub struct Placement {
    rotation: DQuat,
    scale: f64,
    translation: DVec3,
}

impl Placement {
    /// A placement drawn from the bytes: quarter turns, any rotation or a tiny one; scales
    /// from 1e-150 to 1e300; translations to mine-grid or far-away coordinates.
    pub fn decode(bytes: &mut Bytes) -> Placement {
        let rotation = match bytes.below(4) {
            0 => DQuat::IDENTITY,
            1 => {
                let quarter = std::f64::consts::FRAC_PI_2;
                let turns = [bytes.below(4), bytes.below(4), bytes.below(4)].map(|t| t as f64);
                DQuat::from_rotation_x(turns[0] * quarter)
                    * DQuat::from_rotation_y(turns[1] * quarter)
                    * DQuat::from_rotation_z(turns[2] * quarter)
            }
            2 => {
                let q = DQuat::from_xyzw(
                    bytes.number(),
                    bytes.number(),
                    bytes.number(),
                    bytes.number(),
                );
                if q.is_finite() && q.length() > 1e-6 && q.length() < 1e6 {
                    q.normalize()
                } else {
                    DQuat::IDENTITY
                }
            }
            _ => DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 1e-12),
        };
        const SCALES: [f64; 10] = [
            1.0,
            1.0,
            1.0,
            1e-3,
            1e3,
            1e-150,
            1e150,
            1e300,
            0.001953125,
            3.0,
        ];
        let scale = SCALES[bytes.below(SCALES.len())];
        let translation = match bytes.below(5) {
            0 => DVec3::ZERO,
            1 => DVec3::from_array(bytes.point()),
            2 => DVec3::new(512_345.25, 4_123_456.5, 1_250.0) + DVec3::from_array(bytes.point()),
            3 => DVec3::splat(1e15) + DVec3::from_array(bytes.point()),
            _ => DVec3::splat(bytes.number()),
        };
        Placement {
            rotation,
            scale,
            translation,
        }
    }

    /// Where the placement takes `p`.
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.rotation * (p * self.scale) + self.translation
    }
}

/// A mesh from the bytes: either raw (any vertices, any index lists) or a base shape with
/// edits (moved, broken or non-finite vertices, reversed, rotated, dropped, doubled,
/// triangulated faces, bad indices, T-junctions, collapsed edges), then placed.
pub fn decode_mesh(bytes: &mut Bytes) -> Mesh {
    let mut mesh = if bytes.below(4) == 0 {
        raw_mesh(bytes)
    } else {
        base_shape(bytes.below(6))
    };
    for _ in 0..bytes.below(6) {
        edit(&mut mesh, bytes);
    }
    let placement = Placement::decode(bytes);
    mesh.map(|p| placement.apply(p));
    mesh
}

fn raw_mesh(bytes: &mut Bytes) -> Mesh {
    let n = 4 + bytes.below(9);
    let vertices = (0..n).map(|_| bytes.point()).collect();
    let faces = (0..4 + bytes.below(9))
        .map(|_| {
            (0..3 + bytes.below(3))
                .map(|_| bytes.below(n + 1))
                .collect()
        })
        .collect();
    Mesh { vertices, faces }
}

fn edit(mesh: &mut Mesh, bytes: &mut Bytes) {
    let op = bytes.below(13);
    let nv = mesh.vertices.len();
    if nv == 0 || mesh.faces.is_empty() {
        return;
    }
    let v = bytes.below(nv.min(256));
    let f = bytes.below(mesh.faces.len().min(256));
    let len = mesh.faces[f].len();
    match op {
        0 => {
            const SIZES: [f64; 5] = [1e-12, 1e-9, 1e-6, 1e-3, 0.1];
            let size = SIZES[bytes.below(SIZES.len())];
            let d = bytes.point();
            for (c, d) in mesh.vertices[v].iter_mut().zip(d) {
                *c += d * size;
            }
        }
        1 => mesh.vertices[v][bytes.below(3)] = bytes.number(),
        2 => mesh.faces[f].reverse(),
        3 => mesh.faces[f].rotate_left(1),
        4 if len > 0 => {
            let (i, j) = (bytes.below(len), bytes.below(len));
            mesh.faces[f].swap(i, j);
        }
        5 => {
            mesh.faces.remove(f);
        }
        6 => mesh.faces.push(mesh.faces[f].clone()),
        7 if len > 0 => {
            let i = bytes.below(len);
            mesh.faces[f][i] = bytes.below(nv + 2);
        }
        8 if len > 3 => {
            let face = mesh.faces.remove(f);
            for k in 1..len - 1 {
                mesh.faces.push(vec![face[0], face[k], face[k + 1]]);
            }
        }
        9 => {
            mesh.vertices.push(bytes.point());
            if len > 0 && bytes.below(2) == 0 {
                mesh.faces[f].insert(bytes.below(len), nv);
            }
        }
        10 | 11 if len > 0 => {
            // A new vertex at the middle of an edge of face f: in face f only (a T-junction)
            // or in both faces along the edge (a vertex on a straight edge).
            let i = bytes.below(len);
            let (a, b) = (mesh.faces[f][i], mesh.faces[f][(i + 1) % len]);
            if a >= nv || b >= nv {
                return;
            }
            let mid =
                (DVec3::from_array(mesh.vertices[a]) + DVec3::from_array(mesh.vertices[b])) * 0.5;
            mesh.vertices.push(mid.to_array());
            mesh.faces[f].insert(i + 1, nv);
            if op == 11 {
                for g in &mut mesh.faces {
                    let n = g.len();
                    if let Some(j) = (0..n).find(|&j| g[j] == b && g[(j + 1) % n] == a) {
                        g.insert(j + 1, nv);
                        break;
                    }
                }
            }
        }
        12 => {
            let w = bytes.below(nv);
            for g in &mut mesh.faces {
                for x in g.iter_mut() {
                    if *x == v {
                        *x = w;
                    }
                }
            }
        }
        _ => {}
    }
}

/// The guarantees of a valid block: at least 4 vertices and faces, finite coordinates,
/// sphere topology, unit outward planes, a finite positive volume, indices in range.
pub fn check_block(b: &ConvexBlock) {
    let (nv, nf, ne) = (b.vertices().len(), b.n_faces(), b.edges().len());
    assert!(nv >= 4 && nf >= 4, "{nv} vertices, {nf} faces");
    assert!(
        b.vertices().iter().all(|v| v.is_finite()),
        "non-finite vertex"
    );
    assert_eq!(nv + nf, ne + 2, "Euler characteristic");
    for f in 0..nf {
        let face = b.face(f);
        assert!(face.len() >= 3, "face {f} has {} vertices", face.len());
        assert!(face.iter().all(|&v| (v as usize) < nv), "face {f}: index");
    }
    for (f, p) in b.planes().iter().enumerate() {
        assert!(p.normal.is_finite() && p.point.is_finite(), "plane {f}");
        assert!((p.normal.length() - 1.0).abs() < 1e-9, "plane {f} not unit");
    }
    for e in b.edges() {
        assert!(e.vertices.iter().all(|&v| (v as usize) < nv), "edge vertex");
        assert!(e.faces.iter().all(|&f| (f as usize) < nf), "edge face");
    }
    assert_eq!(b.face_origins().len(), nf, "one origin per face");
    let volume = b.volume();
    assert!(volume.is_finite() && volume > 0.0, "volume {volume}");
    assert!(b.centroid().is_finite(), "centroid {}", b.centroid());
    assert!(b.size().is_finite() && b.size() > 0.0, "size {}", b.size());
}

/// Whether two blocks are the same, bit for bit.
pub fn same_block(a: &ConvexBlock, b: &ConvexBlock) -> bool {
    let bits = |v: &DVec3| v.to_array().map(f64::to_bits);
    a.vertices()
        .iter()
        .map(bits)
        .eq(b.vertices().iter().map(bits))
        && a.faces().eq(b.faces())
        && a.edges() == b.edges()
        && a.planes()
            .iter()
            .zip(b.planes())
            .all(|(p, q)| bits(&p.normal) == bits(&q.normal) && bits(&p.point) == bits(&q.point))
        && a.planes().len() == b.planes().len()
        && a.face_origins() == b.face_origins()
        && a.volume().to_bits() == b.volume().to_bits()
        && bits(&a.centroid()) == bits(&b.centroid())
}

/// The system written as JSON reads back, the same bit for bit; the other writers run.
pub fn check_files(system: &BlockSystem) {
    let text = json::to_json_string(system);
    let back = json::from_json_str(&text)
        .unwrap_or_else(|e| panic!("a written system does not read back: {e}"));
    assert_eq!(back.len(), system.len());
    for (a, b) in system.blocks().iter().zip(back.blocks()) {
        assert!(same_block(a, b), "a block changed through its file");
    }
    assert_eq!(back.domain().len(), system.domain().len());
    assert_eq!(back.joints(), system.joints());
    assert_eq!(back.sets(), system.sets());
    let mut out = Vec::new();
    vtu::write_blocks_to(system, &mut out).expect("writing to memory");
    vtu::write_faces_to(system, &mut out).expect("writing to memory");
    crate::io::csv::write_block_table_to(system, &mut out).expect("writing to memory");
}

/// Target `block_from_mesh`: [`ConvexBlock::with_tolerance`] on a decoded mesh; a block
/// built is valid and (with the default tolerance) reads back from its file bit for bit.
pub fn block_from_mesh(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let default = bytes.below(2) == 0;
    let tol = if default {
        Tolerance::default()
    } else {
        tolerance(&mut bytes)
    };
    let mesh = decode_mesh(&mut bytes);
    if let Some(block) = mesh.build(&tol) {
        check_block(&block);
        if tol == Tolerance::default() {
            check_files(&BlockSystem::new(vec![block]));
        }
    }
}

/// Target `block_from_planes`: [`ConvexBlock::from_planes`] on up to 16 half-spaces (small
/// integer normals and offsets most of the time, so that corners coincide and planes repeat).
pub fn block_from_planes(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let (normals, offsets) = decode_planes(&mut bytes, 17);
    if let Ok(block) = ConvexBlock::from_planes(&normals, &offsets) {
        check_block(&block);
        check_files(&BlockSystem::new(vec![block]));
    }
}

/// Up to `max - 1` half-spaces (normals, offsets), sometimes of different lengths.
pub fn decode_planes(bytes: &mut Bytes, max: usize) -> (Vec<[f64; 3]>, Vec<f64>) {
    let m = bytes.below(max);
    let mut normals = Vec::with_capacity(m);
    let mut offsets = Vec::with_capacity(m);
    for _ in 0..m {
        if bytes.below(4) == 0 {
            normals.push(bytes.point());
            offsets.push(bytes.number());
        } else {
            let small = |b: &mut Bytes| (b.below(5) as f64) - 2.0;
            normals.push([small(bytes), small(bytes), small(bytes)]);
            offsets.push(small(bytes) + 3.0);
        }
    }
    if offsets.len() > 1 && bytes.below(8) == 0 {
        offsets.pop(); // a length mismatch
    }
    (normals, offsets)
}

/// A block for a pair: a base shape stretched along the axes, or the hull of a few
/// half-spaces; `None` when the bytes make no block.
fn pair_mesh(bytes: &mut Bytes) -> Option<Mesh> {
    if bytes.below(3) == 0 {
        let (normals, offsets) = decode_planes(bytes, 11);
        let block = ConvexBlock::from_planes(&normals, &offsets).ok()?;
        return Some(Mesh::of_block(&block));
    }
    let mut mesh = base_shape(bytes.below(6));
    const STRETCH: [f64; 6] = [1.0, 2.0, 0.5, 1e-3, 10.0, 1e3];
    let s = [0, 1, 2].map(|_| STRETCH[bytes.below(STRETCH.len())]);
    mesh.map(|p| p * DVec3::from_array(s));
    Some(mesh)
}

/// A point of a mesh to put in contact: a vertex, the middle of an edge or a face's centre.
fn anchor(mesh: &Mesh, bytes: &mut Bytes) -> DVec3 {
    let f = &mesh.faces[bytes.below(mesh.faces.len().min(256))];
    let at = |i: usize| DVec3::from_array(mesh.vertices[f[i % f.len()]]);
    let i = bytes.below(f.len().min(256));
    match bytes.below(3) {
        0 => at(i),
        1 => (at(i) + at(i + 1)) * 0.5,
        _ => {
            f.iter()
                .map(|&v| DVec3::from_array(mesh.vertices[v]))
                .sum::<DVec3>()
                / f.len() as f64
        }
    }
}

/// The tolerance and the two blocks of a `detect_pair` input (`None`: no blocks).
pub fn decode_pair(data: &[u8]) -> Option<(Tolerance, ConvexBlock, ConvexBlock)> {
    let mut bytes = Bytes::new(data);
    let tol = tolerance(&mut bytes);
    let (mut ma, mut mb) = (pair_mesh(&mut bytes)?, pair_mesh(&mut bytes)?);
    let turn = Placement {
        translation: DVec3::ZERO,
        scale: 1.0,
        ..Placement::decode(&mut bytes)
    };
    mb.map(|p| turn.apply(p));
    let (pa, pb) = (anchor(&ma, &mut bytes), anchor(&mb, &mut bytes));
    const NUDGE: [f64; 8] = [0.0, 0.0, 0.0, 1e-13, -1e-13, 1e-10, -1e-10, 1e-3];
    let nudge = DVec3::from_array(bytes.point()) * NUDGE[bytes.below(NUDGE.len())];
    mb.map(|p| p - pb + pa + nudge);
    let common = Placement::decode(&mut bytes);
    ma.map(|p| common.apply(p));
    mb.map(|p| common.apply(p));
    let (a, b) = ma.build(&tol).zip(mb.build(&tol))?;
    Some((tol, a, b))
}

/// Target `detect_pair`: two blocks placed so that a vertex, edge middle or face centre of
/// one meets one of the other (nudged by a multiple of the gap, or anywhere), then moved
/// together far away, scaled or rotated. [`Detector::detect`] and
/// [`Detector::detect_with_geometry`] agree; (B, A) gives the swapped result; a contact's
/// normal is the exact opposite and its distance the same; everything is finite.
pub fn detect_pair(data: &[u8]) {
    let Some((tol, a, b)) = decode_pair(data) else {
        return;
    };
    let mut det = Detector::new(tol);
    let (ab, gab) = det.detect_with_geometry(&a, &b);
    assert_eq!(
        det.detect(&a, &b),
        ab,
        "detect and detect_with_geometry differ"
    );
    let (ba, gba) = det.detect_with_geometry(&b, &a);
    match (ab, ba) {
        (PairResult::Separated, PairResult::Separated)
        | (PairResult::Penetrating, PairResult::Penetrating) => {
            assert!(gab.is_none() && gba.is_none(), "geometry without a contact")
        }
        (PairResult::Contact(x), PairResult::Contact(y)) => {
            assert_eq!(x.kind, y.kind, "(A, B) and (B, A) give different types");
            assert_eq!((x.feature_a, x.feature_b), (y.feature_b, y.feature_a));
            for (feature, block) in [(x.feature_a, &a), (x.feature_b, &b)] {
                check_feature(feature, block);
            }
            let (gab, gba) = (gab.expect("geometry"), gba.expect("geometry"));
            check_geometry(&gab);
            check_geometry(&gba);
            // Exactly opposite and equal (as numbers: 0 and -0 are one value).
            assert_eq!(gab.normal(), -gba.normal(), "normals not opposite");
            assert_eq!(gab.distance(), gba.distance(), "distances differ");
        }
        _ => panic!("(A, B) gives {} but (B, A) gives {}", ab.name(), ba.name()),
    }
}

fn check_feature(feature: Feature, block: &ConvexBlock) {
    let ok = match feature {
        Feature::Vertex(v) => (v as usize) < block.vertices().len(),
        Feature::Edge(e) => (e as usize) < block.edges().len(),
        Feature::Face(f) => (f as usize) < block.n_faces(),
    };
    assert!(ok, "{feature:?} out of range");
}

fn check_geometry(g: &ContactGeometry) {
    let n = g.normal();
    assert!(
        n.is_finite() && (n.length() - 1.0).abs() < 1e-9,
        "normal {n}"
    );
    assert!(g.distance().is_finite(), "distance {}", g.distance());
    assert!(g.points().iter().all(|p| p.is_finite()), "points");
    assert!(g.area().is_finite() && g.area() >= 0.0, "area {}", g.area());
    if let ContactPoints::Polygon(p) = g.shape() {
        assert!(
            p.vertices().len() >= 3,
            "a polygon of {}",
            p.vertices().len()
        );
    }
}

/// The tolerance, block and plane of a `cut_block` input (`None`: no block).
pub fn decode_cut(data: &[u8]) -> Option<(Tolerance, ConvexBlock, Plane)> {
    let mut bytes = Bytes::new(data);
    let tol = tolerance(&mut bytes);
    let mut mesh = pair_mesh(&mut bytes)?;
    let placement = Placement::decode(&mut bytes);
    mesh.map(|p| placement.apply(p));
    let block = mesh.build(&tol)?;
    let point = match bytes.below(4) {
        0 => block.centroid(),
        _ => anchor(&mesh, &mut bytes),
    };
    let normal = if bytes.below(2) == 0 {
        let small = |b: &mut Bytes| (b.below(5) as f64) - 2.0;
        DVec3::new(small(&mut bytes), small(&mut bytes), small(&mut bytes))
    } else {
        DVec3::from_array(bytes.point())
    };
    let normal = normal.try_normalize()?;
    let shift = block.size() * [0.0, 0.0, 1e-12, -1e-10, 0.25][bytes.below(5)];
    let plane = Plane {
        normal,
        point: point + normal * shift,
    };
    Some((tol, block, plane))
}

/// Target `cut_block`: [`split_block`] of a block (a base shape or the hull of a few
/// half-spaces, placed anywhere) by a plane through its centroid, a vertex, an edge's middle
/// or a face's centre, turned any way. Each piece is a valid block that reads back from its
/// file, and the pieces' volumes add up to the block's: vertices within the length threshold
/// `eps` of the plane move onto it, which changes the volume by at most `eps` times the
/// section's area (at most the block's size squared).
pub fn cut_block(data: &[u8]) {
    let Some((tol, block, plane)) = decode_cut(data) else {
        return;
    };
    let Ok(split) = split_block(&block, &plane, &tol) else {
        return;
    };
    let pieces: Vec<ConvexBlock> = [split.below, split.above].into_iter().flatten().collect();
    assert!(!pieces.is_empty(), "a cut lost the whole block");
    for p in &pieces {
        check_block(p);
    }
    let total: f64 = pieces.iter().map(ConvexBlock::volume).sum();
    let eps = tol.for_box(&block.aabb()).length;
    let allowed = 4.0 * eps * block.size().powi(2) + 1e-12 * block.volume();
    let error = (total - block.volume()).abs();
    assert!(
        error <= allowed,
        "pieces {total:e}, block {:e}: {error:e} > {allowed:e}",
        block.volume()
    );
    check_files(&BlockSystem::new(pieces));
}

/// Target `read_json`: [`json::from_json_str`] on any text; a system that reads writes and
/// reads back the same ([`check_files`]), and (when small) its contacts can be found and
/// written.
pub fn read_json(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(system) = json::from_json_str(text) else {
        return;
    };
    for b in system.blocks().iter().chain(system.domain()) {
        check_block(b);
    }
    check_files(&system);
    if system.len() <= 64 {
        let (found, geometry) = system.detect_with_geometry(&Tolerance::default());
        assert_eq!(found, system.detect(&Tolerance::default()));
        let mut out = Vec::new();
        vtp::write_contacts_vtp_to(&found, &geometry, &mut out).expect("writing to memory");
    }
}

/// The most joint planes a fuzzed spec may make, so that one input stays fast.
pub const SPEC_PLANES: usize = 32;

/// Target `read_spec`: [`spec_io::parse_toml`] and [`spec_io::parse_json`] on any text; a
/// spec that parses and makes at most [`SPEC_PLANES`] planes is generated, and the system is
/// valid and reads back from its file.
pub fn read_spec(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    for spec in [spec_io::parse_toml(text), spec_io::parse_json(text)] {
        let Ok(spec) = spec else {
            continue;
        };
        if !small_enough(&spec) {
            continue;
        }
        let Ok(out) = generation::generate(&spec) else {
            continue;
        };
        assert_eq!(out.report.blocks, out.system.len());
        for b in out.system.blocks() {
            check_block(b);
        }
        check_files(&out.system);
    }
}

/// Whether a spec makes at most [`SPEC_PLANES`] planes (checked on the spec's numbers
/// first, so that a huge set is not even expanded).
pub fn small_enough(spec: &Spec) -> bool {
    let size = spec.domain.size();
    let sets_small = spec.joints.iter().all(|j| match &j.kind {
        JointKind::Set(s) => {
            let gap = s.spacing - s.deviation.spacing;
            let origin = DVec3::from_array(s.origin);
            let far = origin.distance(spec.domain.aabb().min) + size;
            s.number.is_none_or(|n| n as usize <= SPEC_PLANES)
                && at_most(size / gap, SPEC_PLANES as f64)
                && at_most(far / gap, 1e4)
        }
        JointKind::Polygon { vertices } => vertices.len() <= 64,
        _ => true,
    });
    let excavations_small = spec.excavations.iter().all(|e| match &e.shape {
        generation::ExcavationShape::Slope { vertices, .. } => vertices.len() <= 64,
        generation::ExcavationShape::Topography { surface } => {
            surface.triangles.len() <= SURFACE_TRIANGLES
        }
        _ => true,
    });
    sets_small
        && excavations_small
        && spec.joints.len() <= SPEC_PLANES
        && generation::planned_planes(spec).is_ok_and(|n| n <= SPEC_PLANES)
}

/// The most triangles of a fuzzed surface excavated, so that one input stays fast.
pub const SURFACE_TRIANGLES: usize = 256;

/// Target `read_surface`: the first byte picks the kind of file (grid, ESRI grid, OBJ, STL),
/// the rest is parsed by [`crate::io::surface::parse_surface`]; a surface of at most
/// [`SURFACE_TRIANGLES`] triangles excavates a 10 m cube cut in 8: the rock left is valid
/// blocks, no more than the cube, and reads back from its file.
pub fn read_surface(data: &[u8]) {
    use crate::generation::{Excavation, ExcavationShape};
    use crate::io::surface::{parse_surface, Kind};
    let Some((&k, rest)) = data.split_first() else {
        return;
    };
    let kind = [Kind::Grid, Kind::Asc, Kind::Obj, Kind::Stl][k as usize % 4];
    let Ok(surface) = parse_surface(kind, rest, "fuzz") else {
        return;
    };
    if surface.triangles.len() > SURFACE_TRIANGLES {
        return;
    }
    let cubes = (0..8)
        .map(|c| {
            let lo = [0, 1, 2].map(|axis| 5.0 * ((c >> axis) & 1) as f64);
            ConvexBlock::cuboid(lo, lo.map(|x| x + 5.0)).expect("a cube")
        })
        .collect();
    let rock = BlockSystem::new(cubes);
    let ground = Excavation::new(ExcavationShape::Topography { surface });
    let Ok((left, _)) = rock.excavate(&ground, &Tolerance::default()) else {
        return;
    };
    let volume: f64 = left.blocks().iter().map(ConvexBlock::volume).sum();
    assert!(
        volume <= 1000.0 * (1.0 + 1e-9),
        "more rock than the cube: {volume}"
    );
    for b in left.blocks() {
        check_block(b);
    }
    check_files(&left);
}

/// `x <= limit`, or NaN (a spacing that `generate` will refuse by name).
fn at_most(x: f64, limit: f64) -> bool {
    x.is_nan() || x <= limit
}
