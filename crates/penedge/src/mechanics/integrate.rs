//! Time integration: central difference for translation, the DLM splitting of Euler's
//! equations for rotation, damping, and the critical time step (docs/mechanics.md,
//! "Integration").

use super::bodies::{stiffness_bounds, Bodies, Fixity, Inertia};
use crate::block::Pose;
use crate::geometry::DVec3;
use glam::DQuat;

/// Damping of the unbalanced forces.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Damping {
    /// Local non-viscous damping coefficient α in [0, 1) (3DEC's default 0.8 for
    /// quasi-static runs).
    pub local: f64,
    /// Mass-proportional viscous damping rate β (1/s): `F -= β m v`, `M -= β I ω`.
    pub viscous: f64,
}

/// The free rotation of a rigid body over `h` with world angular momentum `momentum`
/// (constant), principal moments `inertia`, from orientation `q`: the DLM splitting
/// `x(h/2) y(h/2) z(h) y(h/2) x(h/2)`, each an exact rotation about a body axis.
pub fn free_rotation(q: DQuat, momentum: DVec3, inertia: DVec3, h: f64) -> DQuat {
    let mut q = q;
    let mut pi = q.conjugate() * momentum; // body frame
    for (axis, fraction) in [(0, 0.5), (1, 0.5), (2, 1.0), (1, 0.5), (0, 0.5)] {
        let angle = fraction * h * pi[axis] / inertia[axis];
        let unit = DVec3::AXES[axis];
        let r = DQuat::from_axis_angle(unit, angle);
        q = (q * r).normalize();
        // The body turns by `angle` about the axis: the (constant) world momentum's body
        // components turn by the opposite angle.
        pi = r.conjugate() * pi;
    }
    q
}

/// Local non-viscous damping of one vector: each component reduced by `α |F_k|`, against
/// the sign of the velocity component (no damping where the velocity is zero).
fn local_damping(f: DVec3, v: DVec3, alpha: f64) -> DVec3 {
    let sign = DVec3::select(v.cmpgt(DVec3::ZERO), DVec3::ONE, DVec3::ZERO)
        - DVec3::select(v.cmplt(DVec3::ZERO), DVec3::ONE, DVec3::ZERO);
    f - alpha * f.abs() * sign
}

/// The unbalanced force and moment of free body `i` after damping: contact forces plus
/// gravity and the applied force; `motion` is its motion at the start of the step.
pub(super) fn damped(
    inertia: &Inertia,
    i: usize,
    motion: &Motion,
    [force, moment]: [DVec3; 2],
    gravity: DVec3,
    damping: &Damping,
) -> (DVec3, DVec3) {
    let f = force + gravity * inertia.mass(i) + inertia.applied_force(i);
    let v = motion.velocity;
    let w = inertia.spin(i, motion.pose.rotation, motion.momentum);
    let mut f = local_damping(f, v, damping.local);
    let mut m = local_damping(moment, w, damping.local);
    if damping.viscous > 0.0 {
        f -= v * (damping.viscous * inertia.inertial_mass(i));
        m -= inertia.world_inertia(i, motion.pose.rotation) * w * damping.viscous;
    }
    (f, m)
}

/// One body's motion: pose, velocity of the centroid, angular momentum (world frame).
#[derive(Clone, Copy, Debug)]
pub(super) struct Motion {
    pub pose: Pose,
    pub velocity: DVec3,
    pub momentum: DVec3,
}

/// The motion of body `i` after `dt` from `motion` under the damped unbalanced force `f` and
/// moment `m`; `kick` is the fraction of `dt` of the velocity update (1, or 1/2 when
/// velocities are at the whole step, right after they were set). A function of body `i`
/// alone, so that the bodies advance in parallel.
pub(super) fn advanced(
    inertia: &Inertia,
    i: usize,
    motion: Motion,
    [f, m]: [DVec3; 2],
    dt: f64,
    kick: f64,
) -> Motion {
    let Motion {
        mut pose,
        mut velocity,
        mut momentum,
    } = motion;
    match inertia.fixity(i) {
        Fixity::Free => {
            let mass = inertia.inertial_mass(i);
            velocity += f * (kick * dt / mass);
            momentum += m * (kick * dt);
            let moments = inertia.inertial_moments(i);
            pose.translation += velocity * dt;
            pose.rotation = free_rotation(pose.rotation, momentum, moments, dt);
        }
        Fixity::Fixed => {}
        Fixity::Prescribed { velocity, spin } => {
            pose.translation += velocity * dt;
            let angle = spin.length() * dt;
            if angle > 0.0 {
                let r = DQuat::from_axis_angle(spin.normalize(), angle);
                pose.rotation = (r * pose.rotation).normalize();
            }
        }
    }
    Motion {
        pose,
        velocity,
        momentum,
    }
}

/// The critical time step bound of free body `i` for the largest joint stiffness `k`
/// (docs/mechanics.md): `2 / √(max(K_t / m, K_r / I_min))`, with its inertia scaled by
/// `scale` (its mass-scaling factor, or 1 for the true bound).
pub(super) fn critical_step(bodies: &Bodies, i: usize, k: f64, scale: f64) -> f64 {
    let [surface, rotational] = stiffness_bounds(bodies.shape(i));
    let kt = 2.0 * k * surface / (bodies.mass(i) * scale);
    let kr = 2.0 * k * rotational / (bodies.moments(i).min_element() * scale);
    2.0 / kt.max(kr).sqrt()
}

/// The critical time step with mass-proportional viscous damping of rate `beta` (1/s), from
/// the undamped one `undamped` (docs/mechanics.md, "Integration"): the damping uses the
/// velocity at the start of the step, so an oscillator of frequency `ω = 2 / undamped`
/// steps as `x' = x + (1 - β dt) (x - x_) - ω² dt² x`, stable while `ω² dt² + 2 β dt < 4`,
/// i.e. `dt ≤ (2 / ω) (√(1 + ζ²) - ζ) = undamped / (ζ + √(1 + ζ²))` with `ζ = β / (2 ω)
/// = β undamped / 4`; without stiffness (ω → 0) that is `2 / β`, where a free body's velocity
/// is multiplied by `1 - β dt` at each step. `undamped` itself for `β = 0`, bit for bit.
pub(super) fn damped_step(undamped: f64, beta: f64) -> f64 {
    if beta == 0.0 {
        return undamped;
    }
    let zeta = 0.25 * beta * undamped;
    if !zeta.is_finite() {
        return 2.0 / beta; // no stiffness bound: the damping's alone
    }
    // (`hypot`: `ζ²` overflows for a huge rate, and the step would be 0; above 1, divided by
    // `ζ` first, as `ζ + √(1 + ζ²)` itself overflows for `ζ` near the largest number.)
    if zeta > 1.0 {
        return undamped / zeta / (1.0 + zeta.recip().hypot(1.0));
    }
    undamped / (zeta + zeta.hypot(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound is where the damped oscillator's step stops being stable: iterated at the
    /// bound times 0.999 its amplitude does not grow (undamped, it stays; damped, it
    /// decays), at 1.001 times it it grows without bound.
    #[test]
    fn the_damped_critical_step_is_the_stability_limit_of_the_damped_oscillator() {
        let omega: f64 = 100.0;
        for beta in [0.0, 10.0, 200.0, 1e4] {
            let dt = damped_step(2.0 / omega, beta);
            let zeta = beta / (2.0 * omega);
            let formula = 2.0 / omega * ((1.0 + zeta * zeta).sqrt() - zeta);
            assert!((dt - formula).abs() < 1e-12 * formula, "{dt} vs {formula}");
            // The largest |x| over the first and the last 1000 of 20000 steps (infinite
            // once it overflows), as the engine steps: the damping from the velocity at the
            // start of the step.
            let amplitudes = |h: f64| {
                let (mut x, mut v) = (1.0f64, 0.0f64);
                let (mut early, mut late) = (0.0f64, 0.0f64);
                for n in 0..20_000 {
                    v += h * (-omega * omega * x - beta * v);
                    x += h * v;
                    if !x.is_finite() {
                        return (early, f64::INFINITY);
                    }
                    if n < 1000 {
                        early = early.max(x.abs());
                    } else if n >= 19_000 {
                        late = late.max(x.abs());
                    }
                }
                (early, late)
            };
            let (early, late) = amplitudes(0.999 * dt);
            assert!(late <= 1.01 * early, "beta {beta}: {early} -> {late}");
            let (early, late) = amplitudes(1.001 * dt);
            assert!(late > 1e3 * early, "beta {beta}: {early} -> {late}");
        }
        // A rate so large that `ζ²` overflows: still about the damping's own bound (it was
        // 0: a run with a zero time step, whose `run_until` never ended).
        let huge = damped_step(1.0, 1e160);
        assert!((huge * 1e160 - 2.0).abs() < 1e-12, "{huge}");
        // And so large that `ζ + √(1 + ζ²)` overflowed (ζ about 1.2e308).
        let beta = 3.527e307;
        let huge = damped_step(13.608, beta);
        assert!(huge > 0.0 && (huge * beta - 2.0).abs() < 1e-12, "{huge}");
        // No stiffness: the damping's own bound, 2 / β.
        assert_eq!(damped_step(f64::INFINITY, 4.0), 0.5);
        assert!((damped_step(1e12, 4.0) - 0.5).abs() < 1e-9);
        assert_eq!(damped_step(0.25, 0.0), 0.25);
    }

    #[test]
    fn free_rotation_about_a_principal_axis_is_exact() {
        let inertia = DVec3::new(1.0, 2.0, 3.0);
        let l = DVec3::new(0.0, 0.0, 3.0 * 0.7); // ω = 0.7 about z
        let q = free_rotation(DQuat::IDENTITY, l, inertia, 2.0);
        let expected = DQuat::from_rotation_z(1.4);
        assert!(q.dot(expected).abs() > 1.0 - 1e-15);
    }

    #[test]
    fn local_damping_opposes_the_velocity() {
        let f = local_damping(DVec3::new(10.0, -10.0, 5.0), DVec3::new(1.0, 1.0, 0.0), 0.8);
        assert_eq!(f, DVec3::new(2.0, -18.0, 5.0));
    }
}
