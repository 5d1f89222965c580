//! The seed 001 sec. 3.4.1 tension test: an axisymmetric cylinder (4 mm x 1 mm radius,
//! 0.2 mm elements), one end held axially, the other pulled at a velocity giving a constant
//! true strain rate (with a short linear rise to avoid a shock, as the seed smooths its
//! pulse). Both ends are free radially (frictionless grips). Quantity `axial_stress` (Pa):
//! the area-weighted mean axial stress over the mid cross-section, at `position` = true axial
//! strain `ln(L/L0)` of the cylinder.
//!
//! Low rates are run with **mass scaling** (density times `s`, specific heat divided by `s`,
//! so `rho c_p` and hence adiabatic heating are unchanged; real time and so the material's
//! rate are unchanged), as LS-DYNA users do with DT2MS, when the run would otherwise exceed
//! `max_steps`. The kinetic energy stays a small fraction of the internal energy.
//!
//! The cylinder has no imperfection, but it still necks once Considère's condition is met
//! (for 4340 JC at rates <= 1 /s, where the JC rate term gives no stabilisation, beyond a true
//! strain of about 0.12); past that the mid-section stress is no longer uniaxial.

use super::default_temperature;
use super::{Check, FieldOutput, Outcome, SimulationError};
use crate::experiment::SummaryValue;
use crate::input::recording::RecordedPoint;
use crate::input::InputError;
use crate::measure::{interpolate, StateHistory};
use crate::mesh::{Grading, QuadMesh};
use crate::solver::{Amplitude, AxisymmetricModel, SolverSettings, VelocityConstraint};
use serde::{Deserialize, Serialize};
use stoss_kernel::{update, Material, MaterialState, StepInput};

/// Quantities a tension test records.
pub const QUANTITIES: &[&str] = &["axial_stress"];

fn default_radius() -> f64 {
    1.0e-3
}
fn default_length() -> f64 {
    4.0e-3
}
fn default_element_size() -> f64 {
    0.2e-3
}
fn default_rise() -> f64 {
    0.02
}
fn default_max_steps() -> usize {
    20_000
}

/// The FE tension cylinder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TensionSpec {
    /// Cylinder radius (m).
    #[serde(default = "default_radius")]
    pub radius: f64,
    /// Cylinder length (m).
    #[serde(default = "default_length")]
    pub length: f64,
    /// Element size (m).
    #[serde(default = "default_element_size")]
    pub element_size: f64,
    /// Nominal true strain rate (1/s).
    pub strain_rate: f64,
    /// Final true axial strain.
    pub final_strain: f64,
    /// Initial temperature (K).
    #[serde(default = "default_temperature")]
    pub temperature: f64,
    /// Rise time of the pulling velocity as a fraction of the test duration.
    #[serde(default = "default_rise")]
    pub rise_fraction: f64,
    /// Mass scaling keeps the run at or below this many steps.
    #[serde(default = "default_max_steps")]
    pub max_steps: usize,
}

/// A tension run's curve and mass scaling.
#[derive(Clone, Debug)]
pub struct TensionCurve {
    /// `(true axial strain, mean mid-section axial stress)`.
    pub curve: Vec<(f64, f64)>,
    /// Mass-scaling factor used (1 = none).
    pub mass_scaling: f64,
    /// Histories of the mid-section elements.
    pub mid_section: Vec<StateHistory>,
}

impl TensionSpec {
    pub(super) fn validate(&self, check: &Check) -> Result<(), InputError> {
        check("radius", self.radius > 0.0, "must be > 0 (m)")?;
        check("length", self.length > 0.0, "must be > 0 (m)")?;
        check(
            "element_size",
            self.element_size > 0.0 && self.element_size <= self.radius,
            "must be > 0 and <= radius (m)",
        )?;
        check(
            "strain_rate",
            self.strain_rate > 0.0 && self.strain_rate.is_finite(),
            "must be > 0 (1/s)",
        )?;
        check(
            "final_strain",
            self.final_strain > 0.0 && self.final_strain < 1.0,
            "must be in (0, 1)",
        )?;
        check(
            "rise_fraction",
            (0.0..0.5).contains(&self.rise_fraction),
            "must be in [0, 0.5)",
        )?;
        check("max_steps", self.max_steps >= 1000, "must be >= 1000")?;
        // Mass scaling caps the steps at max_steps: the run is at most elements x max_steps.
        let elements =
            (self.radius / self.element_size).ceil() * (self.length / self.element_size).ceil();
        super::check_run_budget_of(check, "element_size", self.max_steps as f64, 1.0, elements)
    }

    /// Test duration: the nominal `final_strain / rate`, lengthened by half the rise time so
    /// that the pull reaches `final_strain` despite the ramp.
    fn duration(&self) -> f64 {
        self.final_strain / self.strain_rate / (1.0 - 0.5 * self.rise_fraction)
    }

    /// Pull velocity for a constant true strain rate, `v = rate L0 exp(rate t)`, after a
    /// linear rise.
    fn pull(&self) -> Amplitude {
        let duration = self.duration();
        let rise = self.rise_fraction * duration;
        let mut points = vec![(0.0, 0.0)];
        let samples = 64;
        for k in 0..=samples {
            let t = rise + (duration - rise) * k as f64 / samples as f64;
            points.push((
                t.max(1e-300),
                self.strain_rate * self.length * libm::exp(self.strain_rate * t),
            ));
        }
        if rise == 0.0 {
            points.remove(0);
        }
        Amplitude { points }
    }

    /// Build the model (with mass scaling) for `material`.
    pub fn model(
        &self,
        material: &Material,
        settings: &SolverSettings,
    ) -> Result<(AxisymmetricModel, f64), SimulationError> {
        let radial = ((self.radius / self.element_size).round() as usize).max(1);
        let axial = ((self.length / self.element_size).round() as usize).max(2);
        let mesh = QuadMesh::block(
            "bar",
            0,
            (0.0, self.radius),
            (0.0, self.length),
            radial,
            axial,
            Grading::UNIFORM,
            Grading::UNIFORM,
        );
        // Unscaled stable step from the elastic wave speed.
        let mut probe = MaterialState::initial(self.temperature);
        let wave_speed = update(
            material,
            &mut probe,
            &StepInput {
                strain_increment: [0.0; 6],
                dt: 1.0,
                relative_volume: 1.0,
            },
        )
        .map_err(|error| {
            SimulationError::Solver(crate::solver::SolverError::Update {
                element: 0,
                part: "bar".into(),
                time: 0.0,
                relative_volume: 1.0,
                error,
            })
        })?
        .wave_speed;
        let dt0 =
            settings.time_step_safety * self.element_size / std::f64::consts::SQRT_2 / wave_speed;
        let steps0 = self.duration() / dt0;
        let mass_scaling = if steps0 > self.max_steps as f64 {
            (steps0 / self.max_steps as f64).powi(2)
        } else {
            1.0
        };
        let mut scaled = *material;
        scaled.density *= mass_scaling;
        scaled.specific_heat /= mass_scaling;
        let top = mesh.node_set("bar.top").unwrap_or(&[]).to_vec();
        let bottom = mesh.node_set("bar.bottom").unwrap_or(&[]).to_vec();
        let axis = mesh.node_set("bar.axis").unwrap_or(&[]).to_vec();
        let mid_row = axial / 2;
        let tracked = (0..radial).map(|i| mid_row * radial + i).collect();
        let model = AxisymmetricModel {
            mesh,
            materials: vec![scaled],
            initial_temperature: self.temperature,
            initial_velocity: Vec::new(),
            constraints: vec![
                VelocityConstraint {
                    nodes: axis,
                    dof: 0,
                    velocity: Amplitude::constant(0.0),
                },
                VelocityConstraint {
                    nodes: bottom,
                    dof: 1,
                    velocity: Amplitude::constant(0.0),
                },
                VelocityConstraint {
                    nodes: top,
                    dof: 1,
                    velocity: self.pull(),
                },
            ],
            walls: Vec::new(),
            contacts: Vec::new(),
            eroding_contact: None,
            rigid_parts: Vec::new(),
            pressure_loads: Vec::new(),
            body_acceleration: None,
            trusses: Vec::new(),
            node_contacts: Vec::new(),
            settings: SolverSettings {
                end_time: self.duration(),
                damping: None,
                output_interval: self.duration() / 400.0,
                ..settings.clone()
            },
            tracked_elements: tracked,
        };
        Ok((model, mass_scaling))
    }

    /// Run and extract the mid-section stress-strain curve.
    pub fn run(
        &self,
        material: &Material,
        settings: &SolverSettings,
    ) -> Result<
        (
            TensionCurve,
            crate::solver::AxisymmetricRun,
            AxisymmetricModel,
        ),
        SimulationError,
    > {
        let (model, mass_scaling) = self.model(material, settings)?;
        let run = model.run(&mut |_, _| {})?;
        // Annulus areas of the mid-row elements (reference geometry) as weights.
        let weights: Vec<f64> = model
            .tracked_elements
            .iter()
            .map(|&e| {
                let rs = model.mesh.elements[e].map(|n| model.mesh.nodes[n][0]);
                let (lo, hi) = rs
                    .iter()
                    .fold((f64::INFINITY, 0.0_f64), |(a, b), &r| (a.min(r), b.max(r)));
                hi * hi - lo * lo
            })
            .collect();
        let total: f64 = weights.iter().sum();
        let pull = self.pull();
        let count = run.tracked.first().map_or(0, |h| h.samples.len());
        let mut curve = Vec::with_capacity(count);
        let mut displacement = 0.0;
        let mut last_time = 0.0;
        for k in 0..count {
            let time = run.tracked[0].samples[k].time;
            // Trapezoidal integral of the pull velocity (fine sub-steps).
            let sub = 16;
            for j in 0..sub {
                let a = last_time + (time - last_time) * j as f64 / sub as f64;
                let b = last_time + (time - last_time) * (j + 1) as f64 / sub as f64;
                displacement += 0.5 * (pull.at(a) + pull.at(b)) * (b - a);
            }
            last_time = time;
            let stress: f64 = run
                .tracked
                .iter()
                .zip(&weights)
                .map(|(h, w)| h.samples[k].axial_stress * w)
                .sum::<f64>()
                / total;
            curve.push((libm::log(1.0 + displacement / self.length), stress));
        }
        let mid_section = run.tracked.clone();
        Ok((
            TensionCurve {
                curve,
                mass_scaling,
                mid_section,
            },
            run,
            model,
        ))
    }

    pub(super) fn simulate(
        &self,
        material: &Material,
        settings: &SolverSettings,
        recording: &[RecordedPoint],
    ) -> Result<Outcome, SimulationError> {
        let (result, run, model) = self.run(material, settings)?;
        let predicted = recording
            .iter()
            .map(|p| interpolate(&result.curve, p.position))
            .collect();
        let last = result.curve.last().copied().unwrap_or((f64::NAN, f64::NAN));
        Ok(Outcome {
            field_3d: None,
            predicted,
            summary: vec![
                SummaryValue::new("final_true_strain", last.0, "-"),
                SummaryValue::new("final_axial_stress", last.1, "Pa"),
                SummaryValue::new("mass_scaling", result.mass_scaling, "-"),
            ],
            energy: Some(run.energy()),
            states: result.mid_section,
            element_cycles: run.element_cycles,
            report: None,
            field: Some(FieldOutput {
                time: run.final_time(),
                mesh: model.mesh,
                positions: run.positions,
                states: run.states,
                cell_data: Vec::new(),
                eroded: run.eroded,
            }),
        })
    }
}
