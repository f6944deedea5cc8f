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
    /// rapier's TGS-soft substeps per physics step. Each one re-solves every contact, so this
    /// and the next setting set most of the cost of a step: 2 x 2 simulates libero_spatial
    /// expert episodes 42 % faster than 4 x 4, and the expert succeeds at least as often, the
    /// arm follows MuJoCo as closely and squeezed light boxes are pressed into the table less.
    pub solver_iterations: usize,
    /// rapier's position-stabilization iterations per substep. One (rapier's default, with 4
    /// substeps) left light, low-inertia objects (a 16 g mug) rocking on their little contact
    /// patch until they tipped over; 2 settles them at rest.
    pub stabilization_iterations: usize,
    /// Natural frequency (Hz) of contacts between two moving bodies. rapier's default of 30 Hz
    /// lets a 20 N finger sink millimetres into light objects; 100 Hz holds grasps (see the
    /// research notes on rapier grasping).
    pub contact_frequency: f64,
    /// Natural frequency (Hz) of contacts against fixed bodies (tables, floors, fixtures).
    pub static_contact_frequency: f64,
    /// Damping ratio of contacts.
    pub contact_damping_ratio: f64,
}

impl SimParams {
    /// The settings used for every LIBERO task.
    pub const LIBERO: SimParams = SimParams {
        dt: 0.002,
        substeps: 25,
        gravity: [0.0, 0.0, -9.81],
        solver_iterations: 2,
        stabilization_iterations: 2,
        contact_frequency: 100.0,
        static_contact_frequency: 200.0,
        contact_damping_ratio: 10.0,
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
