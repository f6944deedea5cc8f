//! The motion vocabulary every skill is written in. A manipulation is a short list of stages:
//! approach at cruise height ([`rise`], [`cross`], [`over`]), [`descend`], [`grasp`], lift
//! ([`lift_failure`]), [`carry`], [`set_down`], [`release`], [`retreat`], and following a hinge
//! ([`swing`]) or a slide, with [`Progress`] telling when the moving part has stopped. Each stage
//! says what one control step does ([`Leg`]) in terms of the arm-agnostic interface of
//! [`crate::arm`]: a grip-site pose target and a gripper command. [`reach`] is the plain leg
//! the others build on.

use vifo_robots::action::Action;
use vifo_robots::spatial::{Mat3, Vec3, axis_angle};
use vifo_scenes::sim::Sim;

use crate::arm;
use crate::geometry::horizontal;
use crate::motion::{self, Servo, Waypoint};

/// Gripper commands.
pub const OPEN: f64 = -1.0;
pub const CLOSE: f64 = 1.0;

/// What a skill reports each step.
pub enum Step {
    Act(Action),
    Done,
    /// The skill cannot succeed from here (e.g. lost the object); the planner may retry.
    Failed(&'static str),
}

impl Step {
    /// The step of a stage just played: its action, or, where that stage was already over, the
    /// step of the stage after it (`then`).
    pub fn after(action: Option<Action>, then: impl FnOnce() -> Step) -> Step {
        match action {
            Some(a) => Step::Act(a),
            None => then(),
        }
    }
}

/// A skill's current stage and how many control steps it has run.
#[derive(Clone, Copy, Debug)]
pub struct Stages<S> {
    pub now: S,
    pub steps: usize,
    /// A stage lasting longer than this fails the skill: the hand is stuck or chasing a target
    /// it cannot reach.
    limit: usize,
}

/// "Stage step n", for traces.
impl<S: std::fmt::Debug> std::fmt::Display for Stages<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?} step {}", self.now, self.steps)
    }
}

impl<S: Copy> Stages<S> {
    pub fn new(first: S, limit: usize) -> Self {
        Stages { now: first, steps: 0, limit }
    }

    /// Counts a step of the current stage: false once the stage has run past its limit.
    pub fn tick(&mut self) -> bool {
        self.steps += 1;
        self.steps <= self.limit
    }

    pub fn next(&mut self, stage: S) {
        self.now = stage;
        self.steps = 0;
    }

    /// Plays one step of a stage: the leg's action, moving on to `then` after its last step;
    /// `None` where the stage was already over (the skill then plays `then` at once).
    pub fn play(&mut self, sim: &Sim, leg: Leg, then: S) -> Option<Action> {
        match leg {
            Leg::Go(m) => Some(m.act(sim)),
            Leg::Last(m) => {
                self.next(then);
                Some(m.act(sim))
            }
            Leg::Over => {
                self.next(then);
                None
            }
        }
    }
}

/// How fast the hand goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pace {
    Travel,
    Fine,
    /// Full speed while more than a few centimetres off, fine near (see [`Servo::closing_in`]).
    ClosingIn,
}

impl Pace {
    fn servo(self, distance: f64) -> Servo {
        match self {
            Pace::Travel => Servo::TRAVEL,
            Pace::Fine => Servo::FINE,
            Pace::ClosingIn => Servo::closing_in(distance),
        }
    }
}

/// One control step's motion: a grip-site pose target, the servo's gains, the gripper command.
#[derive(Clone, Copy, Debug)]
pub struct Move {
    pub to: Waypoint,
    pub servo: Servo,
    pub grip: f64,
}

impl Move {
    pub fn act(&self, sim: &Sim) -> Action {
        self.servo.act(sim, &self.to, self.grip)
    }
}

/// What a stage does this control step.
#[derive(Clone, Copy, Debug)]
pub enum Leg {
    /// Move; the stage goes on.
    Go(Move),
    /// Move once more: the stage has done what it was for, the next one starts on the next step.
    Last(Move),
    /// The stage has nothing left to do: the next one acts this step.
    Over,
}

impl Leg {
    /// `m`, and the stage's last step once `arrived`.
    pub fn until(m: Move, arrived: bool) -> Leg {
        if arrived { Leg::Last(m) } else { Leg::Go(m) }
    }

    /// `m`, unless the stage is already `over`.
    pub fn unless(over: bool, m: Move) -> Leg {
        if over { Leg::Over } else { Leg::Go(m) }
    }

    pub fn is_last(&self) -> bool {
        matches!(self, Leg::Last(_))
    }
}

/// How close a stage must bring the grip site to its target: position (m) and, where the
/// stage cares, orientation (rad).
#[derive(Clone, Copy, Debug)]
pub struct Tol {
    pos: f64,
    rot: Option<f64>,
}

impl Tol {
    pub const fn pos(pos: f64) -> Tol {
        Tol { pos, rot: None }
    }

    pub const fn pose(pos: f64, rot: f64) -> Tol {
        Tol { pos, rot: Some(rot) }
    }

    fn met(&self, d: f64, r: f64) -> bool {
        d < self.pos && self.rot.is_none_or(|tol| r < tol)
    }
}

/// The plain leg: toward `to` at `pace`, until within `tol` of it.
pub fn reach(sim: &Sim, to: Waypoint, pace: Pace, tol: Tol, grip: f64) -> Leg {
    let (d, r) = motion::error(sim, &to);
    Leg::until(Move { to, servo: pace.servo(d), grip }, tol.met(d, r))
}

/// The gripper command that brings the fingers to `half_gap` (half their spread): open or
/// close toward it, and hold the gripper's ramp (command 0) once there.
pub fn gripper_toward(sim: &Sim, half_gap: f64) -> f64 {
    let opening = 0.5 * arm::of(sim).finger_gap();
    if opening < half_gap - 0.002 {
        OPEN
    } else if opening > half_gap + 0.002 {
        CLOSE
    } else {
        0.0
    }
}

/// Approach at cruise height, first leg: straight up to `cruise_z` (see
/// [`crate::geometry::cruise_height`]), turning to `rot` on the way; over once within 2 cm of
/// it, where the crossing may start.
// `!(z < …)`, not `z >= …`: a NaN height must fail the "still below" check.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn rise(sim: &Sim, cruise_z: f64, rot: Mat3, grip: f64) -> Leg {
    let ee = arm::of(sim).grip_site().pos;
    Leg::unless(!(ee.z < cruise_z - 0.02), Move { to: Waypoint { pos: Vec3::new(ee.x, ee.y, cruise_z), rot }, servo: Servo::TRAVEL, grip })
}

/// Approach at cruise height, second leg: across at `cruise_z` to over `to`.
pub fn cross(sim: &Sim, to: &Vec3, cruise_z: f64, rot: Mat3, tol: Tol, grip: f64) -> Leg {
    reach(sim, Waypoint { pos: Vec3::new(to.x, to.y, cruise_z), rot }, Pace::Travel, tol, grip)
}

/// Approach at cruise height, coming over a grasp: the point over `at` at `cruise_z` while more
/// than 3 cm off it sideways, then at `low` (the stand-off over the grasp), so the hand only
/// comes down once over it.
pub fn over(ee: &Vec3, at: &Vec3, cruise_z: f64, low: f64) -> Vec3 {
    Vec3::new(at.x, at.y, if horizontal(ee, at) > 0.03 { cruise_z } else { low })
}

/// Descend onto a grasp no faster than the horizontal error allows, so that the fingers arrive
/// centred on it: held at the current height while more than `within` off it sideways; there
/// within `within` of it.
pub fn descend(sim: &Sim, grasp: &Vec3, rot: Mat3, within: f64, grip: f64) -> Leg {
    let ee = arm::of(sim).grip_site().pos;
    let z = if horizontal(&ee, grasp) > within { ee.z.max(grasp.z) } else { grasp.z };
    let d = (ee - grasp).norm();
    Leg::until(Move { to: Waypoint { pos: Vec3::new(grasp.x, grasp.y, z), rot }, servo: Servo::closing_in(d), grip }, d < within)
}

/// Grasp: the fingers close, the hand held at `at`, for `n` steps (the gripper's ramp takes
/// about that long to pinch); `steps` is how long the stage has run.
pub fn grasp(steps: usize, n: usize, at: Waypoint) -> Leg {
    Leg::until(Move { to: at, servo: Servo::FINE, grip: CLOSE }, steps >= n)
}

/// Release: the fingers open, the hand held at `at`, for `n` steps.
pub fn release(steps: usize, n: usize, at: Waypoint) -> Leg {
    Leg::until(Move { to: at, servo: Servo::FINE, grip: OPEN }, steps >= n)
}

/// Lift: why the object is not coming up with the hand, if it is not: the fingers closed on
/// nothing, or after `patience` steps it has risen less than `min_rise` above `start_z`.
pub fn lift_failure(sim: &Sim, steps: usize, patience: usize, start_z: f64, z: f64, min_rise: f64) -> Option<&'static str> {
    if arm::of(sim).finger_gap() < 0.002 {
        return Some("the fingers closed on nothing");
    }
    (steps >= patience && z - start_z < min_rise).then_some("the object did not come up")
}

/// Carry: up to the cruise height of `over` first, then across to it (the cruise height keeps
/// 6 cm over everything on the way, so the crossing may start in the last 4); there within
/// 1 cm sideways and 3 cm in height.
pub fn carry(sim: &Sim, over: &Vec3, rot: Mat3) -> Leg {
    let ee = arm::of(sim).grip_site().pos;
    let pos = if ee.z < over.z - 0.04 { Vec3::new(ee.x, ee.y, over.z) } else { *over };
    let there = horizontal(&ee, over) < 0.01 && (ee.z - over.z).abs() < 0.03;
    Leg::until(Move { to: Waypoint { pos, rot }, servo: Servo::TRAVEL, grip: CLOSE }, there)
}

/// Set down: lower the held object toward `to` until within `within` of it, or until the way
/// down is blocked (the grip site sank less than `stall` over the last 3 steps: the object
/// already rests on something, or the hand meets a container's rim with the object inside).
pub fn set_down(sim: &Sim, heights: &mut Progress, to: Waypoint, pace: Pace, within: f64, stall: f64) -> Leg {
    let (d, _) = motion::error(sim, &to);
    heights.record(arm::of(sim).grip_site().pos.z);
    let stalled = heights.change(3, 6).is_some_and(|c| -c < stall);
    if d < within || stalled {
        heights.clear();
    }
    Leg::until(Move { to, servo: pace.servo(d), grip: CLOSE }, d < within || stalled)
}

/// Retreat: toward `to`, away from what was handled, for `n` steps; then over.
pub fn retreat(steps: usize, n: usize, to: Waypoint, grip: f64) -> Leg {
    Leg::unless(steps >= n, Move { to, servo: Servo::TRAVEL, grip })
}

/// Follow a hinge: where a point at `offset` from the hinge point `hinge` goes once turned by
/// `angle` about `axis` (the hand leading a knob or a door along its arc).
pub fn swing(hinge: &Vec3, axis: &Vec3, angle: f64, offset: &Vec3) -> Vec3 {
    hinge + axis_angle(axis, angle) * offset
}

/// A stage's readings over time (a joint position, a height), to notice when what the hand
/// drives (a knob, a door, a drawer, the hand itself) has stopped moving.
#[derive(Clone, Debug, Default)]
pub struct Progress(Vec<f64>);

impl Progress {
    pub fn clear(&mut self) {
        self.0.clear();
    }

    pub fn record(&mut self, reading: f64) {
        self.0.push(reading);
    }

    /// How much the reading changed over the last `lag` steps, once more than `after` readings
    /// have come (too early to tell before).
    pub fn change(&self, lag: usize, after: usize) -> Option<f64> {
        let n = self.0.len();
        (n > after).then(|| self.0[n - 1] - self.0[n - 1 - lag])
    }
}
