//! The physics guard: a state no task reaches means the simulation blew up.
//!
//! A solver that diverges (a NaN from a degenerate contact, an object launched by a deep
//! penetration) would otherwise keep stepping and its predicates would read garbage: a bottle
//! at NaN is "not in the basket", an object flung through the table may land "on the plate".
//! Episodes check [`Sim::blow_up`] after every control step and end as errors, never as
//! successes or failures.
//!
//! The limits sit far above what the scripted expert produces (`vifo expert` prints the maxima
//! over its episodes next to these limits; `vifo expert --episodes 4`, 160 episodes over the 40
//! tasks, all solved: body speed 1.65 m/s, angular speed 22.4 rad/s, penetration 9.0 mm,
//! distance from the origin 1.78 m), each limit 10 to 30 times higher, yet far below a
//! divergence, which reaches hundreds of m/s within a few steps.

use super::Sim;

/// Fastest linear speed of any body, m/s (an object falling 1 m reaches 4.4 m/s).
pub const MAX_LINEAR_SPEED: f64 = 20.0;
/// Fastest angular speed of any body, rad/s.
pub const MAX_ANGULAR_SPEED: f64 = 300.0;
/// Deepest interpenetration of two touching colliders, m.
pub const MAX_PENETRATION: f64 = 0.10;
/// Farthest any body may be from the world origin, m (the arena is about 2 m across).
pub const MAX_DISTANCE: f64 = 50.0;

/// The largest speeds and penetration in the world now (what the guard compares).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Extremes {
    pub linear_speed: f64,
    pub angular_speed: f64,
    pub penetration: f64,
    pub distance: f64,
}

impl Extremes {
    /// The larger of each figure (NaN wins, so a NaN is never hidden by a max).
    pub fn max(self, other: Extremes) -> Extremes {
        let m = |a: f64, b: f64| if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) };
        Extremes {
            linear_speed: m(self.linear_speed, other.linear_speed),
            angular_speed: m(self.angular_speed, other.angular_speed),
            penetration: m(self.penetration, other.penetration),
            distance: m(self.distance, other.distance),
        }
    }
}

impl Sim {
    /// The extremes of the current state over every dynamic body and active contact.
    pub fn extremes(&self) -> Extremes {
        let rapier = self.world().rapier();
        let mut e = Extremes::default();
        for (_, body) in rapier.bodies.iter().filter(|(_, b)| b.is_dynamic()) {
            let pos = body.position();
            let finite = pos.translation.is_finite() && pos.rotation.is_finite();
            e = e.max(Extremes {
                linear_speed: body.linvel().length(),
                angular_speed: body.angvel().length(),
                penetration: 0.0,
                distance: if finite { pos.translation.length() } else { f64::NAN },
            });
        }
        for pair in rapier.narrow_phase.contact_pairs().filter(|p| p.has_any_active_contact()) {
            for m in pair.manifolds() {
                for p in &m.points {
                    e = e.max(Extremes { penetration: -p.dist, ..Extremes::default() });
                }
            }
        }
        e
    }

    /// Why the state cannot be a task's (a non-finite or exploding value), or `None` when it is
    /// within the limits.
    // `!(v <= max)`, not `v > max`: a NaN value must fail the check.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    pub fn blow_up(&self) -> Option<String> {
        let e = self.extremes();
        let checks = [
            ("body speed", e.linear_speed, MAX_LINEAR_SPEED, "m/s"),
            ("body angular speed", e.angular_speed, MAX_ANGULAR_SPEED, "rad/s"),
            ("contact penetration", e.penetration, MAX_PENETRATION, "m"),
            ("body distance from the origin", e.distance, MAX_DISTANCE, "m"),
        ];
        checks.into_iter().find(|(_, v, max, _)| !(v <= max)).map(|(what, v, max, unit)| {
            if v.is_finite() {
                format!("{what} {v:.3} {unit} exceeds {max} {unit}")
            } else {
                format!("{what} is {v}")
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_keeps_nan() {
        let a = Extremes { linear_speed: f64::NAN, ..Extremes::default() };
        let b = Extremes { linear_speed: 3.0, angular_speed: 1.0, ..Extremes::default() };
        assert!(a.max(b).linear_speed.is_nan());
        assert!(b.max(a).linear_speed.is_nan());
        assert_eq!(b.max(a).angular_speed, 1.0);
    }
}
