//! Building a [`ConvexBlock`] from vertices and faces, with validation.
//!
//! The checks run from the cheapest to the most geometric, so the first error reported is the
//! most basic one: input shape, finite coordinates, repeated or unused vertices, closed
//! manifold surface with consistent orientation and sphere topology, orientation (positive
//! volume), then planar convex faces and a convex block. Adjacent coplanar faces (a
//! triangulated box face, say) are merged into one polygon first: the contact types speak of
//! geometric faces, not of the triangles that happen to describe them.

use super::assemble::volume_and_centroid;
use super::{BlockError, ConvexBlock, Edge};
use crate::geometry::{newell_normal, Aabb, DVec3, Plane};
use crate::tolerance::Tolerance;
use std::cmp::Ordering;
use std::collections::HashMap;

impl ConvexBlock {
    /// Builds a block from vertices and faces (vertex index lists, counter-clockwise seen
    /// from outside) with the default [`Tolerance`].
    pub fn new<F: AsRef<[usize]>>(
        vertices: &[[f64; 3]],
        faces: &[F],
    ) -> Result<ConvexBlock, BlockError> {
        ConvexBlock::with_tolerance(vertices, faces, &Tolerance::default())
    }

    /// Builds a block; `tol.length()` (relative to the block's size) is the distance within
    /// which vertices coincide and a vertex counts as lying on a plane.
    pub fn with_tolerance<F: AsRef<[usize]>>(
        vertices: &[[f64; 3]],
        faces: &[F],
        tol: &Tolerance,
    ) -> Result<ConvexBlock, BlockError> {
        let faces: Vec<Vec<usize>> = faces.iter().map(|f| f.as_ref().to_vec()).collect();
        let points = check_points(vertices)?;
        check_range(&points)?;
        let eps = tol.for_box(&Aabb::of_points(&points)).length;
        check_face_lists(&faces, points.len())?;
        check_repeated_vertices(&points, eps)?;
        let edges = check_closed_solid(&points, &faces, eps)?;
        match merge_coplanar_faces(&points, &faces, &edges, eps)? {
            // The faces as given: their edges and planes are known already.
            Merged::Kept(planes) => build_checked(points, faces, edges, planes, eps),
            Merged::Into(merged) => {
                let edges = check_closed_solid(&points, &merged, eps)?;
                let planes = face_planes(&points, &merged, eps)?;
                build_checked(points, merged, edges, planes, eps)
            }
        }
    }
}

pub(super) fn check_points(vertices: &[[f64; 3]]) -> Result<Vec<DVec3>, BlockError> {
    vertices
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let p = DVec3::from_array(*v);
            if p.is_finite() {
                Ok(p)
            } else {
                Err(BlockError::NonFiniteVertex { vertex: i })
            }
        })
        .collect()
}

/// Coordinates within [`super::MAX_COORDINATE`] and a size of at least [`super::MIN_SIZE`]
/// (a size of zero is left to the repeated-vertex check, which names the vertices).
pub(super) fn check_range(points: &[DVec3]) -> Result<(), BlockError> {
    if points.is_empty() {
        return Ok(()); // too small, which the shape check says
    }
    let aabb = Aabb::of_points(points);
    let magnitude = aabb.magnitude();
    // The diagonal underflows to 0 below about 1e-154; the longest side does not.
    let size = aabb.diagonal().max((aabb.max - aabb.min).max_element());
    if magnitude > super::MAX_COORDINATE {
        return Err(BlockError::OutOfRange {
            what: "largest coordinate",
            value: magnitude,
        });
    }
    if size > 0.0 && size < super::MIN_SIZE {
        return Err(BlockError::OutOfRange {
            what: "size",
            value: size,
        });
    }
    Ok(())
}

pub(super) fn check_face_lists(faces: &[Vec<usize>], n_vertices: usize) -> Result<(), BlockError> {
    if n_vertices < 4 || faces.len() < 4 {
        return Err(BlockError::TooSmall {
            vertices: n_vertices,
            faces: faces.len(),
        });
    }
    let mut used = vec![false; n_vertices];
    for (f, face) in faces.iter().enumerate() {
        if face.len() < 3 {
            return Err(BlockError::DegenerateFaceList { face: f });
        }
        for (k, &v) in face.iter().enumerate() {
            if v >= n_vertices {
                return Err(BlockError::VertexIndexOutOfRange {
                    face: f,
                    vertex: v,
                    count: n_vertices,
                });
            }
            if face[..k].contains(&v) {
                return Err(BlockError::DegenerateFaceList { face: f });
            }
            used[v] = true;
        }
    }
    match used.iter().position(|u| !u) {
        Some(v) => Err(BlockError::UnusedVertex { vertex: v }),
        None => Ok(()),
    }
}

/// Pairs of vertices closer than `eps`, found by a sweep along x.
pub(super) fn check_repeated_vertices(points: &[DVec3], eps: f64) -> Result<(), BlockError> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a].x.total_cmp(&points[b].x));
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if points[j].x - points[i].x > eps {
                break;
            }
            if points[i].distance(points[j]) <= eps {
                let (first, second) = (i.min(j), i.max(j));
                let aabb = Aabb::of_points(points);
                return Err(BlockError::RepeatedVertex {
                    first,
                    second,
                    within: eps,
                    magnitude: aabb.magnitude(),
                    size: aabb.diagonal(),
                });
            }
        }
    }
    Ok(())
}

/// A hasher for vertex indices: a multiply and a rotate per word (as rustc's FxHasher), much
/// cheaper than the default SipHash for the few dozen keys of a block, whose construction
/// it dominated. Keys are a block's own vertex indices, so collisions cost at most that
/// block's size.
#[derive(Default)]
struct IndexHasher(u64);

impl std::hash::Hasher for IndexHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_usize(&mut self, word: usize) {
        self.write_u64(word as u64);
    }
}

/// A hash map keyed by vertex indices, with [`IndexHasher`].
type IndexMap<K, V> = HashMap<K, V, std::hash::BuildHasherDefault<IndexHasher>>;

/// Undirected edges with the faces on each side; checks a closed, manifold, consistently
/// oriented surface.
fn build_edges(faces: &[Vec<usize>]) -> Result<Vec<Edge>, BlockError> {
    let mut index: IndexMap<(usize, usize), usize> = IndexMap::default();
    let mut edges: Vec<(Edge, bool)> = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            let key = (a.min(b), a.max(b));
            match index.get(&key) {
                None => {
                    index.insert(key, edges.len());
                    let e = Edge {
                        vertices: [a as u32, b as u32],
                        faces: [f as u32, u32::MAX],
                    };
                    edges.push((e, false));
                }
                Some(&i) => {
                    let (e, paired) = &mut edges[i];
                    if *paired {
                        return Err(BlockError::NonManifoldEdge {
                            first: key.0,
                            second: key.1,
                        });
                    }
                    if e.vertices[0] as usize == a {
                        return Err(BlockError::InconsistentOrientation {
                            first: e.faces[0] as usize,
                            second: f,
                            a,
                            b,
                        });
                    }
                    e.faces[1] = f as u32;
                    *paired = true;
                }
            }
        }
    }
    match edges.iter().find(|(_, paired)| !paired) {
        Some((e, _)) => Err(BlockError::OpenSurface {
            first: e.vertices[0].min(e.vertices[1]) as usize,
            second: e.vertices[0].max(e.vertices[1]) as usize,
        }),
        None => Ok(edges.into_iter().map(|(e, _)| e).collect()),
    }
}

fn face_plane(points: &[DVec3], face: &[usize], f: usize, eps: f64) -> Result<Plane, BlockError> {
    let n = newell_normal(face.iter().map(|&v| points[v]));
    let len = n.length();
    let perimeter: f64 = (0..face.len())
        .map(|k| points[face[k]].distance(points[face[(k + 1) % face.len()]]))
        .sum();
    // Twice the area against the perimeter: the face's mean width must exceed eps.
    // Negated so that a NaN (overflowing coordinates) is rejected too.
    if len.partial_cmp(&(eps * perimeter)) != Some(Ordering::Greater) {
        return Err(BlockError::ZeroAreaFace { face: f });
    }
    let centre = face.iter().map(|&v| points[v]).sum::<DVec3>() / face.len() as f64;
    Ok(Plane {
        normal: n / len,
        point: centre,
    })
}

/// The faces after [`merge_coplanar_faces`]: kept as given (with their planes), or merged.
enum Merged {
    Kept(Vec<Plane>),
    Into(Vec<Vec<usize>>),
}

/// The plane of each face.
fn face_planes(points: &[DVec3], faces: &[Vec<usize>], eps: f64) -> Result<Vec<Plane>, BlockError> {
    (0..faces.len())
        .map(|f| face_plane(points, &faces[f], f, eps))
        .collect()
}

/// Merges faces that share an edge (of `edges`, the faces' edges) and lie in one plane.
fn merge_coplanar_faces(
    points: &[DVec3],
    faces: &[Vec<usize>],
    edges: &[Edge],
    eps: f64,
) -> Result<Merged, BlockError> {
    let planes = face_planes(points, faces, eps)?;
    let mut group: Vec<usize> = (0..faces.len()).collect();
    let mut merged_any = false;
    for e in edges {
        let (f, g) = (e.faces[0] as usize, e.faces[1] as usize);
        let coplanar = planes[f].normal.dot(planes[g].normal) > 0.0
            && faces[g]
                .iter()
                .all(|&v| planes[f].distance(points[v]).abs() <= eps)
            && faces[f]
                .iter()
                .all(|&v| planes[g].distance(points[v]).abs() <= eps);
        if coplanar {
            let (rf, rg) = (find(&mut group, f), find(&mut group, g));
            if rf != rg {
                group[rg] = rf;
                merged_any = true;
            }
        }
    }
    if !merged_any {
        return Ok(Merged::Kept(planes));
    }
    let roots: Vec<usize> = (0..faces.len()).map(|f| find(&mut group, f)).collect();
    let mut merged = Vec::new();
    for root in 0..faces.len() {
        if roots[root] == root {
            merged.push(boundary_loop(faces, &roots, root)?);
        }
    }
    Ok(Merged::Into(merged))
}

fn find(group: &mut [usize], mut f: usize) -> usize {
    while group[f] != f {
        group[f] = group[group[f]];
        f = group[f];
    }
    f
}

/// The outer boundary of the faces in one group, as one counter-clockwise loop.
fn boundary_loop(
    faces: &[Vec<usize>],
    roots: &[usize],
    root: usize,
) -> Result<Vec<usize>, BlockError> {
    let mut directed: HashMap<(usize, usize), ()> = HashMap::new();
    for (f, face) in faces.iter().enumerate().filter(|(f, _)| roots[*f] == root) {
        let _ = f;
        for k in 0..face.len() {
            directed.insert((face[k], face[(k + 1) % face.len()]), ());
        }
    }
    let mut next: HashMap<usize, usize> = HashMap::new();
    for &(a, b) in directed.keys() {
        if !directed.contains_key(&(b, a)) && next.insert(a, b).is_some() {
            return Err(BlockError::NotConvex {
                face: root,
                vertex: a,
                distance: 0.0,
            });
        }
    }
    let start = *next
        .keys()
        .min()
        .ok_or(BlockError::ZeroAreaFace { face: root })?;
    let mut loop_ = vec![start];
    let mut v = next[&start];
    while v != start {
        if loop_.len() > next.len() {
            return Err(BlockError::NotConvex {
                face: root,
                vertex: v,
                distance: 0.0,
            });
        }
        loop_.push(v);
        v = *next.get(&v).ok_or(BlockError::OpenSurface {
            first: v,
            second: v,
        })?;
    }
    if loop_.len() != next.len() {
        // A coplanar group with a hole or two boundary loops is not a convex face.
        return Err(BlockError::NotConvex {
            face: root,
            vertex: start,
            distance: 0.0,
        });
    }
    Ok(loop_)
}

/// A closed, manifold, consistently oriented sphere with a positive volume; checked on the
/// faces as given, before coplanar faces are merged.
fn check_closed_solid(
    points: &[DVec3],
    faces: &[Vec<usize>],
    eps: f64,
) -> Result<Vec<Edge>, BlockError> {
    let edges = build_edges(faces)?;
    let euler = points.len() as i64 - edges.len() as i64 + faces.len() as i64;
    if euler != 2 {
        return Err(BlockError::NotASphere { euler });
    }
    let (volume, _) = volume_and_centroid(points, faces.iter().map(|f| f.iter().copied()));
    let size = Aabb::of_points(points).diagonal();
    if volume < 0.0 && volume.abs() > eps * size.powi(2) {
        return Err(BlockError::WrongOrientation);
    }
    // Negated so that a NaN (overflowing coordinates) is rejected too.
    if volume.partial_cmp(&(eps * size.powi(2))) != Some(Ordering::Greater) {
        return Err(BlockError::ZeroVolume);
    }
    Ok(edges)
}

/// The block of checked faces (a closed solid, [`check_closed_solid`]) with their edges and
/// planes, after the remaining checks.
fn build_checked(
    points: Vec<DVec3>,
    faces: Vec<Vec<usize>>,
    edges: Vec<Edge>,
    planes: Vec<Plane>,
    eps: f64,
) -> Result<ConvexBlock, BlockError> {
    check_corners(points.len(), &faces)?;
    let (volume, centroid) = volume_and_centroid(&points, faces.iter().map(|f| f.iter().copied()));
    let bounds = super::Bounds::of(&points);
    check_faces_planar_convex(&points, &faces, &planes, eps)?;
    check_block_convex(&points, &planes, eps)?;
    let face_offsets: Vec<u32> = std::iter::once(0)
        .chain(faces.iter().scan(0u32, |acc, f| {
            *acc += f.len() as u32;
            Some(*acc)
        }))
        .collect();
    let face_vertices: Vec<u32> = faces.iter().flatten().map(|&v| v as u32).collect();
    let vertex_faces = super::vertex_face_masks(points.len(), &face_offsets, &face_vertices);
    Ok(ConvexBlock {
        clearance: super::Clearance::of(&points, &planes, &vertex_faces),
        vertex_faces,
        origins: vec![super::FaceOrigin::Unknown; planes.len()],
        local: super::LocalCoordinates::of(&points),
        vertices: points,
        face_offsets,
        face_vertices,
        planes,
        edges,
        volume,
        centroid,
        bounds,
    })
}

/// Every vertex must be a corner, in three faces or more.
fn check_corners(n_vertices: usize, faces: &[Vec<usize>]) -> Result<(), BlockError> {
    let mut degree = vec![0usize; n_vertices];
    for &v in faces.iter().flatten() {
        degree[v] += 1;
    }
    match degree.iter().position(|&d| d < 3) {
        Some(vertex) => Err(BlockError::NotACorner { vertex }),
        None => Ok(()),
    }
}

fn check_faces_planar_convex(
    points: &[DVec3],
    faces: &[Vec<usize>],
    planes: &[Plane],
    eps: f64,
) -> Result<(), BlockError> {
    for (f, (face, plane)) in faces.iter().zip(planes).enumerate() {
        for (k, &v) in face.iter().enumerate() {
            let distance = plane.distance(points[v]);
            if distance.abs() > eps {
                return Err(BlockError::NonPlanarFace {
                    face: f,
                    vertex: v,
                    distance,
                });
            }
            let a = points[face[(k + face.len() - 1) % face.len()]];
            let b = points[v];
            let c = points[face[(k + 1) % face.len()]];
            let edge = b - a;
            // Signed distance of c from the line ab, positive on the inner (left) side.
            let inward = plane.normal.cross(edge).normalize_or_zero();
            if inward.dot(c - b) < -eps {
                return Err(BlockError::NonConvexFace { face: f, vertex: v });
            }
        }
    }
    Ok(())
}

fn check_block_convex(points: &[DVec3], planes: &[Plane], eps: f64) -> Result<(), BlockError> {
    for (f, plane) in planes.iter().enumerate() {
        for (v, &p) in points.iter().enumerate() {
            let distance = plane.distance(p);
            if distance > eps {
                return Err(BlockError::NotConvex {
                    face: f,
                    vertex: v,
                    distance,
                });
            }
        }
    }
    Ok(())
}
