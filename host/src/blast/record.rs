//! The wall's pressure record: the mean overpressure on the bottom wall over fixed record
//! intervals, formed from the Euler solver's accumulated wall impulse
//! ([`EulerSolver::bottom_impulse`]) without shortening its steps to land on the record
//! times.
//!
//! Within one Godunov step the wall's momentum flux is constant, so the impulse it delivers
//! grows linearly over the step; the impulse at a record time inside a step is that line's
//! value there, and a record is the impulse between two record times over the interval, less
//! the ambient pressure. Every record is therefore the scheme's own wall impulse, as when the
//! step was cut at the record time, and the solver takes its stable step throughout: a step cut
//! at every record time (0.25 us on seed 000's plates, steps of 0.07-0.2 us) cost 20-24 % more
//! steps (docs/benchmarks.md, "The blast load's steps").

use super::euler::{EulerError, EulerSolver};

/// Forms the wall records of an [`EulerSolver`] step by step.
#[derive(Clone, Debug)]
pub struct WallRecorder {
    interval: f64,
    ambient: f64,
    /// Records formed so far.
    made: usize,
    /// Wall impulse (Pa s) at the end of the last record.
    at_last_record: Vec<f64>,
    /// Wall impulse (Pa s) at the start of the step being taken.
    before_step: Vec<f64>,
}

impl WallRecorder {
    /// A recorder of `solver`'s wall from its present state (time 0, no impulse), records of
    /// `interval` (s), overpressure above `ambient` (Pa).
    pub fn new(solver: &EulerSolver, interval: f64, ambient: f64) -> Self {
        Self {
            interval,
            ambient,
            made: 0,
            at_last_record: solver.bottom_impulse.clone(),
            before_step: solver.bottom_impulse.clone(),
        }
    }

    /// Records formed so far.
    pub fn made(&self) -> usize {
        self.made
    }

    /// End time (s) of record `k` (0-based).
    fn record_end(&self, k: usize) -> f64 {
        (k + 1) as f64 * self.interval
    }

    /// Take one stable step of `solver` (`courant` times the stable one) and pass each record
    /// the step completed, up to `limit` records in all, to `emit`.
    pub fn step(
        &mut self,
        solver: &mut EulerSolver,
        courant: f64,
        limit: usize,
        emit: &mut dyn FnMut(Vec<f64>),
    ) -> Result<(), EulerError> {
        self.before_step.copy_from_slice(&solver.bottom_impulse);
        let start = solver.time;
        solver.step(courant, f64::INFINITY)?;
        let end = solver.time;
        // A record ends in this step when its end time is reached to round-off (the
        // tolerance of the record loop this replaces).
        while self.made < limit && end >= self.record_end(self.made) * (1.0 - 1e-12) {
            let fraction = ((self.record_end(self.made) - start) / (end - start)).clamp(0.0, 1.0);
            let row = self
                .at_last_record
                .iter_mut()
                .zip(&self.before_step)
                .zip(&solver.bottom_impulse)
                .map(|((last, &before), &after)| {
                    let at_end = before + fraction * (after - before);
                    let mean = (at_end - *last) / self.interval - self.ambient;
                    *last = at_end;
                    mean
                })
                .collect();
            self.made += 1;
            emit(row);
        }
        Ok(())
    }
}
