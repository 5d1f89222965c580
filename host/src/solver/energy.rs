//! The energy balance of a run.

/// Energies of the whole model (J; axisymmetric models are integrated over 2 pi).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyBalance {
    /// Time (s).
    pub time: f64,
    /// Kinetic energy.
    pub kinetic: f64,
    /// Internal (stress work) energy of intact elements.
    pub internal: f64,
    /// Energy dissipated by the hourglass control.
    pub hourglass: f64,
    /// Energy dissipated by the bulk viscosity.
    pub viscous: f64,
    /// Energy absorbed by rigid walls and contact (normal stop and friction).
    pub contact: f64,
    /// Energy removed by nodal damping.
    pub damping: f64,
    /// Internal and kinetic energy carried away by eroded elements.
    pub eroded: f64,
    /// Kinetic energy dissipated by an Eulerian run's remap of nodal momentum (0 in
    /// Lagrangian runs; [`crate::euler`]).
    pub remap: f64,
    /// Work done on the model by prescribed velocities.
    pub external_work: f64,
    /// Total energy at the start.
    pub initial: f64,
}

impl EnergyBalance {
    /// `kinetic + internal + hourglass + viscous + contact + damping + eroded + remap`.
    pub fn total(&self) -> f64 {
        self.kinetic
            + self.internal
            + self.hourglass
            + self.viscous
            + self.contact
            + self.damping
            + self.eroded
            + self.remap
    }

    /// Energy error in percent: `(total - initial - external work) / reference`, with the
    /// reference the larger of the initial energy and the external work.
    pub fn error_percent(&self) -> f64 {
        let reference = self.initial.abs().max(self.external_work.abs()).max(1e-300);
        100.0 * (self.total() - self.initial - self.external_work) / reference
    }

    /// A human-readable report.
    pub fn report(&self) -> String {
        let remap = if self.remap != 0.0 {
            format!("\n  remap        {:>14.6e}", self.remap)
        } else {
            String::new()
        };
        format!(
            "energy balance at t = {:.4e} s (J)\n  kinetic      {:>14.6e}\n  internal     {:>14.6e}\n  hourglass    {:>14.6e}\n  viscous      {:>14.6e}\n  contact      {:>14.6e}\n  damping      {:>14.6e}\n  eroded       {:>14.6e}{}\n  external     {:>14.6e}\n  initial      {:>14.6e}\n  energy error {:>+13.3}%",
            self.time,
            self.kinetic,
            self.internal,
            self.hourglass,
            self.viscous,
            self.contact,
            self.damping,
            self.eroded,
            remap,
            self.external_work,
            self.initial,
            self.error_percent()
        )
    }
}
