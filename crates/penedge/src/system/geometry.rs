//! The geometry of every contact of a block system: normal, signed distance, area and
//! contact points, as flat arrays aligned with [`SystemContacts::contacts`].
//!
//! The pairs are the same as [`BlockSystem::detect`]'s ([`BlockSystem::contact_pairs`]: two
//! parts of one body are never a pair); each pair goes through
//! [`crate::Detector::detect_with_geometry`] in parallel (rayon), and the result keeps the pairs'
//! sorted order, so it is the same for any number of threads and `contacts` equals what
//! [`BlockSystem::detect`] returns. Conventions (normal from the smaller block id to the
//! larger, distance positive for a gap) are those of [`crate::contact_geometry`].

use super::detect::{narrow_phase, Cancelled, DetectProgress, PairContact, SystemContacts};
use super::BlockSystem;
use crate::classify::PairResult;
use crate::contact_geometry::ContactGeometry;
use crate::tolerance::Tolerance;
use std::ops::ControlFlow;

/// The geometry of `n` contacts as flat arrays; row `i` belongs to contact `i` of the
/// [`SystemContacts`] it came with.
///
/// Contact `i` has the points `points[point_offsets[i]..point_offsets[i + 1]]`: one point,
/// the two ends of a segment, or the vertices of a convex polygon counter-clockwise about
/// its normal (see [`crate::contact_geometry::ContactPoints`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactGeometries {
    /// Unit normals, from block `pair[0]` to block `pair[1]`.
    pub normals: Vec<[f64; 3]>,
    /// Signed distances along the normal: gap (> 0) or depth (< 0).
    pub distances: Vec<f64>,
    /// Areas of polygon contacts, 0 for points and segments.
    pub areas: Vec<f64>,
    /// Start of each contact's points in `points` (length: contacts + 1).
    pub point_offsets: Vec<u64>,
    /// The contact points of all contacts, contact after contact.
    pub points: Vec<[f64; 3]>,
}

impl ContactGeometries {
    /// Number of contacts.
    pub fn len(&self) -> usize {
        self.normals.len()
    }

    /// Whether there is no contact.
    pub fn is_empty(&self) -> bool {
        self.normals.is_empty()
    }

    /// The points of contact `i`.
    ///
    /// # Panics
    ///
    /// If there is no contact `i` (`i >= self.len()`).
    pub fn points_of(&self, i: usize) -> &[[f64; 3]] {
        let (start, end) = (self.point_offsets[i], self.point_offsets[i + 1]);
        &self.points[start as usize..end as usize]
    }

    fn with_capacity(n: usize) -> Self {
        let mut point_offsets = Vec::with_capacity(n + 1);
        point_offsets.push(0);
        ContactGeometries {
            normals: Vec::with_capacity(n),
            distances: Vec::with_capacity(n),
            areas: Vec::with_capacity(n),
            point_offsets,
            points: Vec::with_capacity(n),
        }
    }

    fn push(&mut self, g: &ContactGeometry) {
        self.normals.push(g.normal().to_array());
        self.distances.push(g.distance());
        self.areas.push(g.area());
        self.points.extend(g.points().iter().map(|p| p.to_array()));
        self.point_offsets.push(self.points.len() as u64);
    }
}

impl BlockSystem {
    /// Detects and classifies every contact ([`BlockSystem::detect`]) and computes its
    /// geometry ([`crate::Detector::detect_with_geometry`]); row `i` of the geometry belongs to
    /// `contacts[i]`.
    ///
    /// ```
    /// use penedge::system::{paper_example, PaperExample};
    /// use penedge::Tolerance;
    /// let system = paper_example(PaperExample::One).unwrap();
    /// let (found, geometry) = system.detect_with_geometry(&Tolerance::default());
    /// assert_eq!((found.contacts.len(), geometry.len()), (28, 28));
    /// let area: f64 = geometry.areas.iter().sum();
    /// assert!((area - 300.0).abs() < 1e-9); // the planes x, y, z = 5 across a 10 m cube
    /// ```
    pub fn detect_with_geometry(&self, tol: &Tolerance) -> (SystemContacts, ContactGeometries) {
        match self.detect_with_geometry_and_progress(tol, &mut |_| ControlFlow::Continue(())) {
            Ok(found) => found,
            Err(Cancelled) => unreachable!("never cancelled"),
        }
    }

    /// [`BlockSystem::detect_with_geometry`] with progress reports and cancellation, as
    /// [`BlockSystem::detect_with_progress`].
    pub fn detect_with_geometry_and_progress(
        &self,
        tol: &Tolerance,
        progress: &mut dyn FnMut(DetectProgress) -> ControlFlow<()>,
    ) -> Result<(SystemContacts, ContactGeometries), Cancelled> {
        let pairs = self.contact_pairs(tol);
        let mut found = SystemContacts::default();
        let mut geometry = ContactGeometries::with_capacity(0);
        narrow_phase(
            self,
            &pairs,
            tol,
            progress,
            |det, _, a, b| det.detect_with_geometry(a, b),
            |slice, outcomes| {
                for (&pair, outcome) in slice.iter().zip(outcomes) {
                    match outcome {
                        (PairResult::Contact(contact), Some(g)) => {
                            let contact = *contact;
                            found.contacts.push(PairContact { pair, contact });
                            geometry.push(g);
                        }
                        (PairResult::Penetrating, _) => found.penetrating.push(pair),
                        (PairResult::Contact(_), None) => {
                            unreachable!("a contact always has a geometry")
                        }
                        (PairResult::Separated, _) => {}
                    }
                }
            },
        )?;
        Ok((found, geometry))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::ContactType;
    use crate::contact::Detector;
    use crate::system::{paper_example, PaperExample};
    use crate::ConvexBlock;

    fn cube(lo: [f64; 3], hi: [f64; 3]) -> ConvexBlock {
        ConvexBlock::cuboid(lo, hi).unwrap()
    }

    #[test]
    fn contacts_are_those_of_detect_and_rows_match_the_pair_query() {
        let tol = Tolerance::default();
        let system = paper_example(PaperExample::Three).unwrap();
        let (found, geometry) = system.detect_with_geometry(&tol);
        assert_eq!(found, system.detect(&tol));
        assert_eq!(geometry.len(), found.contacts.len());
        assert_eq!(geometry.point_offsets.len(), found.contacts.len() + 1);
        let mut det = Detector::new(tol);
        for (i, pc) in found.contacts.iter().enumerate() {
            let [a, b] = pc.pair.map(|k| &system.blocks()[k as usize]);
            let (_, g) = det.detect_with_geometry(a, b);
            let g = g.unwrap();
            assert_eq!(geometry.normals[i], g.normal().to_array());
            assert_eq!(geometry.distances[i].to_bits(), g.distance().to_bits());
            assert_eq!(geometry.areas[i].to_bits(), g.area().to_bits());
            let points: Vec<[f64; 3]> = g.points().iter().map(|p| p.to_array()).collect();
            assert_eq!(geometry.points_of(i), &points[..]);
        }
    }

    #[test]
    fn example_3_face_face_area_is_the_area_of_the_cuts() {
        let system = paper_example(PaperExample::Three).unwrap();
        let (found, geometry) = system.detect_with_geometry(&Tolerance::default());
        let face_face: f64 = found
            .contacts
            .iter()
            .zip(&geometry.areas)
            .filter(|(pc, _)| pc.contact.kind == ContactType::FaceFace)
            .map(|(_, area)| area)
            .sum();
        let exact = 300.0 + 300.0 * 2f64.sqrt();
        assert!((face_face - exact).abs() < 1e-9 * exact, "{face_face}");
        let all: f64 = geometry.areas.iter().sum();
        assert_eq!(all, face_face); // only polygons have an area
    }

    #[test]
    fn point_counts_follow_the_contact_type() {
        let system = BlockSystem::new(vec![
            cube([0.0; 3], [1.0; 3]),
            cube([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]), // 0-1 face-face: 4 corners
            cube([1.0, 1.0, 1.0], [2.0, 2.0, 2.0]), // 0-2 vertex-vertex, 1-2 edge-edge sup.
            cube([0.2, 0.2, -1.0], [0.8, 0.8, 0.5]), // penetrates 0
        ]);
        let (found, geometry) = system.detect_with_geometry(&Tolerance::default());
        let pairs: Vec<[u32; 2]> = found.contacts.iter().map(|c| c.pair).collect();
        assert_eq!(pairs, [[0, 1], [0, 2], [1, 2]]);
        assert_eq!(found.penetrating, [[0, 3]]);
        assert_eq!(geometry.point_offsets, [0, 4, 5, 7]);
        assert_eq!(geometry.normals[0], [1.0, 0.0, 0.0]);
        assert!((geometry.areas[0] - 1.0).abs() < 1e-12);
        assert_eq!(geometry.areas[1..], [0.0, 0.0]);
        assert_eq!(geometry.points_of(1), [[1.0, 1.0, 1.0]]);
    }

    #[test]
    fn the_result_does_not_depend_on_the_number_of_threads() {
        let system = paper_example(PaperExample::Three).unwrap();
        let tol = Tolerance::default();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let four = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        let a = one.install(|| system.detect_with_geometry(&tol));
        let b = four.install(|| system.detect_with_geometry(&tol));
        assert_eq!(a, b);
    }

    #[test]
    fn an_empty_system_has_no_geometry() {
        let (found, geometry) = BlockSystem::default().detect_with_geometry(&Tolerance::default());
        assert!(found.contacts.is_empty() && geometry.is_empty());
        assert_eq!(geometry.point_offsets, [0]);
    }
}
