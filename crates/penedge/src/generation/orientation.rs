//! Orientation of planes: dip and dip direction, normals, and the frames data come in.
//!
//! Axes: x East, y North, z up (right-handed). Dip is the angle from the horizontal, in
//! [0, 90] degrees; dip direction the azimuth of the line of steepest descent, clockwise from
//! North, in [0, 360). The upward unit normal of a plane with dip `δ` and dip direction `α` is
//! `(sin δ sin α, sin δ cos α, cos δ)`. A horizontal plane (dip 0) has normal `+z`; a plane
//! dipping 90° towards East (α = 90) has normal `+x`.

use crate::geometry::DVec3;

/// Dip and dip direction of a plane, in degrees.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Attitude {
    /// Dip: angle from the horizontal, 0 to 90 degrees.
    pub dip: f64,
    /// Dip direction: azimuth clockwise from North, 0 to 360 degrees.
    pub dip_direction: f64,
}

impl Attitude {
    /// An attitude (not checked: see [`crate::generation::SpecError`] for the checks).
    pub fn new(dip: f64, dip_direction: f64) -> Attitude {
        Attitude { dip, dip_direction }
    }

    /// The upward unit normal `(sin δ sin α, sin δ cos α, cos δ)`.
    pub fn normal(self) -> DVec3 {
        let (sd, cd) = sin_cos_degrees(self.dip);
        let (sa, ca) = sin_cos_degrees(self.dip_direction);
        DVec3::new(sd * sa, sd * ca, cd)
    }

    /// The attitude of the plane with this normal (not normalised needed). `None` for a zero
    /// or non-finite normal. Either sense of a plane that is not vertical gives the same
    /// attitude; a vertical plane (`normal.z == 0`) has two dip directions, 180° apart, and
    /// gets the one its normal points to (`(-1, 0, 0)`: 270), so that [`Attitude::normal`]
    /// gives the normal back (a joint record's stored normal and its dip direction agree).
    pub fn from_normal(normal: DVec3) -> Option<Attitude> {
        let n = normal.try_normalize()?;
        let n = if n.z < 0.0 { -n } else { n };
        let dip = n.z.clamp(-1.0, 1.0).acos().to_degrees();
        let horizontal = n.x.hypot(n.y);
        if horizontal == 0.0 {
            return Some(Attitude::new(0.0, 0.0));
        }
        let dd = n.x.atan2(n.y).to_degrees().rem_euclid(360.0);
        Some(Attitude::new(dip, dd))
    }

    /// This attitude tilted by `d_dip` and turned by `d_dir` (degrees), kept in range: a dip
    /// pushed past 90 (or below 0) is reflected and the dip direction turned by 180.
    pub fn deviated(self, d_dip: f64, d_dir: f64) -> Attitude {
        let mut dip = self.dip + d_dip;
        let mut dir = self.dip_direction + d_dir;
        if dip < 0.0 {
            dip = -dip;
            dir += 180.0;
        }
        if dip > 90.0 {
            dip = 180.0 - dip;
            dir += 180.0;
        }
        Attitude::new(dip, dir.rem_euclid(360.0))
    }
}

/// Sine and cosine of an angle in degrees, exact at multiples of 90.
pub fn sin_cos_degrees(angle: f64) -> (f64, f64) {
    let quarter = angle / 90.0;
    if quarter == quarter.round() && quarter.abs() < 1e15 {
        return match (quarter as i64).rem_euclid(4) {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        };
    }
    angle.to_radians().sin_cos()
}

/// A frame that coordinates (points and normals) may be given in.
///
/// penedge works in East-North-Up; dip and dip direction are the same numbers in every frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    /// x East, y North, z up: penedge's own frame, and that of 3DEC 7 and later.
    EastNorthUp,
    /// x North, y East, z down (a right-handed frame, as in YADE set-ups that use it).
    NorthEastDown,
    /// x East, y up, z North, as drawn in the manuals of 3DEC 5 and older (`JSET`). It is
    /// left-handed: face vertex lists given in it must be reversed.
    EastUpNorth,
}

impl Frame {
    /// A point or vector in this frame, expressed in East-North-Up.
    pub fn to_enu(self, v: [f64; 3]) -> [f64; 3] {
        match self {
            Frame::EastNorthUp => v,
            Frame::NorthEastDown => [v[1], v[0], -v[2]],
            Frame::EastUpNorth => [v[0], v[2], v[1]],
        }
    }

    /// A point or vector in East-North-Up, expressed in this frame.
    pub fn from_enu(self, v: [f64; 3]) -> [f64; 3] {
        match self {
            Frame::EastNorthUp => v,
            Frame::NorthEastDown => [v[1], v[0], -v[2]],
            Frame::EastUpNorth => [v[0], v[2], v[1]],
        }
    }

    /// Whether the frame is right-handed (face orientation survives the conversion).
    pub fn is_right_handed(self) -> bool {
        !matches!(self, Frame::EastUpNorth)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: [f64; 3]) -> bool {
        a.distance(DVec3::from_array(b)) < 1e-15
    }

    #[test]
    fn known_normals() {
        let s = 0.5f64.sqrt();
        assert!(close(Attitude::new(0.0, 123.0).normal(), [0.0, 0.0, 1.0]));
        assert!(close(Attitude::new(90.0, 90.0).normal(), [1.0, 0.0, 0.0]));
        assert!(close(Attitude::new(90.0, 0.0).normal(), [0.0, 1.0, 0.0]));
        assert!(close(Attitude::new(90.0, 180.0).normal(), [0.0, -1.0, 0.0]));
        assert!(close(Attitude::new(90.0, 270.0).normal(), [-1.0, 0.0, 0.0]));
        let n = Attitude::new(45.0, 90.0).normal();
        assert!((n - DVec3::new(s, 0.0, s)).length() < 1e-15);
        let n = Attitude::new(30.0, 225.0).normal();
        assert!((n - DVec3::new(-0.5 * s, -0.5 * s, 0.75f64.sqrt())).length() < 1e-15);
    }

    #[test]
    fn normals_give_back_their_attitude() {
        for (dip, dd) in [(10.0, 20.0), (60.0, 135.0), (89.0, 300.0), (45.0, 0.5)] {
            let a = Attitude::from_normal(Attitude::new(dip, dd).normal()).unwrap();
            assert!((a.dip - dip).abs() < 1e-12 && (a.dip_direction - dd).abs() < 1e-12);
            // The downward normal describes the same plane.
            let b = Attitude::from_normal(-Attitude::new(dip, dd).normal()).unwrap();
            assert!((b.dip - dip).abs() < 1e-12 && (b.dip_direction - dd).abs() < 1e-12);
        }
        assert_eq!(Attitude::from_normal(DVec3::ZERO), None);
    }

    #[test]
    fn a_vertical_normal_gives_the_dip_direction_it_points_to() {
        // Every dip direction of a vertical plane, both senses: the attitude's normal is
        // the normal given (it was folded into [0, 180), so that (-1, 0, 0) read 90).
        for dd in [0.0, 30.0, 90.0, 150.0, 180.0, 210.0, 270.0, 300.0, 359.0] {
            let n = Attitude::new(90.0, dd).normal();
            let a = Attitude::from_normal(n).unwrap();
            assert_eq!(a.dip, 90.0, "{dd}");
            assert!((a.dip_direction - dd).abs() < 1e-12, "{dd}: {a:?}");
            assert!((a.normal() - n).length() < 1e-15, "{dd}");
        }
        let v = Attitude::from_normal(DVec3::new(-1.0, 0.0, 0.0)).unwrap();
        assert_eq!((v.dip, v.dip_direction), (90.0, 270.0));
        let v = Attitude::from_normal(DVec3::new(0.0, -2.0, 0.0)).unwrap();
        assert_eq!((v.dip, v.dip_direction), (90.0, 180.0));
    }

    #[test]
    fn deviation_reflects_past_vertical() {
        let a = Attitude::new(85.0, 350.0).deviated(10.0, 20.0);
        assert!((a.dip - 85.0).abs() < 1e-12 && (a.dip_direction - 190.0).abs() < 1e-12);
        let b = Attitude::new(5.0, 10.0).deviated(-8.0, 0.0);
        assert!((b.dip - 3.0).abs() < 1e-12 && (b.dip_direction - 190.0).abs() < 1e-12);
    }

    #[test]
    fn frames_convert_both_ways() {
        let p = [1.0, 2.0, 3.0];
        for f in [Frame::EastNorthUp, Frame::NorthEastDown, Frame::EastUpNorth] {
            assert_eq!(f.from_enu(f.to_enu(p)), p);
        }
        // North-East-Down: a point 1 north, 2 east, 3 down is (2, 1, -3) in ENU.
        assert_eq!(Frame::NorthEastDown.to_enu(p), [2.0, 1.0, -3.0]);
    }
}
