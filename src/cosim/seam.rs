//! The extension seam of a co-simulated drive: further bodies, scalar
//! states and force elements, as [`crate::sim::Simulation`] takes them.
//!
//! An element added here is evaluated with the links and the contact in
//! every substep of every frame (after them and the elements added before
//! it), so its forces act on the chain at the chain's dt, inside the user's
//! rapier step; further bodies and scalar states are advanced in the same
//! substeps (symplectic Euler, explicit Euler). What it does not do: give an
//! element a rapier body (its forces act on the chain's coordinates and its
//! own, not on the user's bodies), or reach an element after it was added
//! (it reports through [`crate::forces::Forces`] and the state's `q`, `u`, `z`).

use super::ChainDrive;
use crate::forces::{ForceElement, Forces};
use crate::model::{BodyModel, ScalarModel};

impl ChainDrive {
    /// Adds a further body coordinate ([`BodyModel`]) at coordinate `q` and
    /// speed `u`; returns its index in [`crate::model::DriveState::q`]. Its
    /// forces come from force elements ([`Self::add_force_element`]).
    pub fn add_body(&mut self, body: BodyModel, q: f64, u: f64) -> usize {
        let i = self.model.push_body(&mut self.state, body, q, u);
        self.refit();
        i
    }

    /// Adds a scalar state ([`ScalarModel`]) at `z`; returns its index in
    /// [`crate::model::DriveState::z`].
    pub fn add_scalar(&mut self, scalar: ScalarModel, z: f64) -> usize {
        let i = self.model.push_scalar(&mut self.state, scalar, z);
        self.refit();
        i
    }

    /// Adds a force element, evaluated in every substep after the links,
    /// the contact and the elements added before it.
    pub fn add_force_element(&mut self, element: Box<dyn ForceElement>) {
        self.forces.add(element);
        self.refit();
    }

    /// The forces at [`Self::state`], the end of the last substep: roller
    /// forces, the chain's torque on each sprocket, further bodies'
    /// generalised forces and scalar rates (as `Simulation::forces`).
    pub fn forces(&self) -> &Forces {
        self.forces.output()
    }

    /// After the drive's make-up changed: outputs sized anew, forces
    /// evaluated at the current state.
    fn refit(&mut self) {
        self.forces.fit(&self.model);
        self.forces.evaluate(&self.model, &self.state);
    }
}
