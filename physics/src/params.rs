//! Simulation parameters: LIBERO's timing plus the solver settings that make grasps hold.

/// Timing, gravity and solver settings of a [`crate::World`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimParams {
    /// Physics step in seconds (LIBERO / robosuite: 0.002 s, 500 Hz).
    pub dt: f64,
    /// Physics steps per control step (LIBERO: 25, i.e. 20 Hz control).
    pub substeps: u32,
    /// Gravity in world coordinates (z up).
    pub gravity: [f64; 3],
    /// rapier's TGS-soft substeps per physics step. Each one rebuilds every multibody's mass
    /// matrix (the Panda's is most of the arm's cost), so one substep of LIBERO's 2 ms, as
    /// MuJoCo takes, is 35-40 % faster than two. It also follows MuJoCo more closely: on the 40
    /// reference recordings the end effector stays within 0.062 mm (0.112 with two substeps),
    /// and dropped bottles come to rest within 0.5 mm of MuJoCo's (4-11 mm with two).
    pub solver_iterations: usize,
    /// Velocity (PGS) iterations inside each substep.
    pub pgs_iterations: usize,
    /// rapier's position-stabilization iterations per substep. One (rapier's default, with 4
    /// substeps) left light, low-inertia objects (a 16 g mug) rocking on their little contact
    /// patch until they tipped over. With a single substep, 2 velocity and 2 stabilization
    /// iterations let closed fingers pressing on a thin plate push it up to 4 mm into the
    /// table (the expert's push from inside it); 6 and 3 keep every object of the expert's
    /// 800-episode pass within 3 mm, and cost a few percent of the step.
    pub stabilization_iterations: usize,
    /// rapier's length unit (m). rapier fattens every broad-phase leaf by 4 % of it, so at 1 m
    /// the 1-5 cm boxes of neighbouring bowls and plates all paired up: libero_spatial's first
    /// task kept 1,740 candidate pairs, 144 of them touching, and the narrow phase tested each
    /// at every substep. At 0.1 m it keeps 326. The other lengths rapier scales by the unit
    /// (slop, corrective and maximum speed) keep their 1 m values; its sleep threshold does
    /// scale, so a resting body sleeps only below 5 mm/s.
    pub length_unit: f64,
    /// Gap (m) below which rapier computes a pair's contact points before the bodies touch, so
    /// that an approach within the step is caught before it penetrates. rapier's default, 20 mm
    /// at a 1 m unit, made the narrow phase compute points for every neighbour within 2 cm at
    /// every step. LIBERO's bodies move at most about 1.6 m/s (the expert's pass), 3.3 mm per
    /// 2 ms step, so 5 mm catches every approach: the expert's physics costs about 8 % less, and
    /// objects settle a little closer to MuJoCo (`vifo xval`: median 0.09 mm, 0.15 at 20 mm).
    pub prediction_distance: f64,
    /// Natural frequency (Hz) of contacts between two moving bodies. rapier's default of 30 Hz
    /// lets a 20 N finger sink millimetres into light objects; 100 Hz holds grasps (see the
    /// research notes on rapier grasping).
    pub contact_frequency: f64,
    /// Natural frequency (Hz) of contacts against fixed bodies (tables, floors, fixtures).
    pub static_contact_frequency: f64,
    /// Damping ratio of contacts.
    pub contact_damping_ratio: f64,
    /// Seconds a movable object must stay still (under rapier's sleep threshold) before rapier
    /// stops solving it until something touches it; rapier's default is 0.5 s. LIBERO's episodes
    /// start by dropping every object a few millimetres onto its support, and most objects never
    /// move again: at 0.2 s they sleep 0.3 s sooner, which cut 11-19 % of a physics-only step in
    /// the four reference replays, with the end effector and the settled objects as close to
    /// MuJoCo as before (`vifo xval`). An object still creeping faster than the threshold
    /// (5 mm/s at the 0.1 m length unit, 1 mm per 0.2 s) stays awake.
    pub sleep_after: f64,
}

impl SimParams {
    /// The settings used for every LIBERO task.
    pub const LIBERO: SimParams = SimParams {
        dt: 0.002,
        substeps: 25,
        gravity: [0.0, 0.0, -9.81],
        solver_iterations: 1,
        pgs_iterations: 6,
        stabilization_iterations: 3,
        length_unit: 0.1,
        prediction_distance: 0.005,
        contact_frequency: 100.0,
        static_contact_frequency: 200.0,
        contact_damping_ratio: 10.0,
        sleep_after: 0.2,
    };

    /// Duration of one control step in seconds (0.05 s for LIBERO).
    pub fn control_dt(&self) -> f64 {
        self.dt * f64::from(self.substeps)
    }
}

impl Default for SimParams {
    fn default() -> Self {
        Self::LIBERO
    }
}
