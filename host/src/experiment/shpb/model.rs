//! The finite-element split Hopkinson bar (see [`super`] for the model): the bars' material,
//! the striker's pulse, the mesh with its gauge and specimen elements, and the run that
//! analyses the simulated gauges ([`super::kolsky`]).

use super::{Analysis, ShpbResult, ShpbSpec, INTERFACE_PENALTY_SCALE, SAMPLING};
use crate::measure::StateHistory;
use crate::mesh::{Grading, QuadMesh};
use crate::solver::{
    Amplitude, AxisymmetricModel, AxisymmetricRun, ContactPair, SolverError, SolverSettings,
    VelocityConstraint,
};
use stoss_kernel::eos::{Eos, LinearEos};
use stoss_kernel::strength::JohnsonCook;
use stoss_kernel::{Heating, Material};

/// Element indices of the model's tracked points.
#[derive(Clone, Debug)]
struct Layout {
    incident_gauge: usize,
    transmitter_gauge: usize,
    gauge_distances: (f64, f64),
    /// Specimen mid-row elements and their reference annulus areas.
    mid_row: Vec<(usize, f64)>,
}

impl ShpbSpec {
    /// The elastic bar material: `G = E / 2(1 + nu)`, linear EoS `K = E / 3(1 - 2 nu)`, an
    /// unreachable yield stress, isothermal.
    pub fn bar_material(&self) -> Material {
        let (e, nu) = (self.bar_young_modulus, self.bar_poisson_ratio);
        let mut strength = JohnsonCook::STEEL_4340;
        strength.yield_stress = 1.0e3 * e;
        Material {
            density: self.bar_density,
            shear_modulus: e / (2.0 * (1.0 + nu)),
            specific_heat: 460.0,
            heating: Heating::Isothermal,
            eos: Eos::Linear(LinearEos {
                bulk_modulus: e / (3.0 * (1.0 - 2.0 * nu)),
            }),
            ..Material::STEEL_4340.with_strength(strength)
        }
    }

    /// The prescribed velocity of the incident bar's free end (toward the specimen, +z).
    pub fn loading(&self) -> Amplitude {
        let (v, rise, duration) = (
            0.5 * self.striker_velocity,
            self.rise_time,
            self.pulse_duration(),
        );
        if rise > 0.0 {
            Amplitude {
                points: vec![(0.0, 0.0), (rise, v), (duration, v), (duration + rise, 0.0)],
            }
        } else {
            Amplitude {
                points: vec![(0.0, v), (duration, v), (duration * (1.0 + 1e-9), 0.0)],
            }
        }
    }

    fn mesh(&self) -> (QuadMesh, Layout) {
        let bar_radius = 0.5 * self.bar_diameter;
        let specimen_radius = 0.5 * self.specimen_diameter;
        let nr_bar = self.bar_radial_elements;
        let bar_size = bar_radius / nr_bar as f64;
        let nz_incident = ((self.incident_length / bar_size).round() as usize).max(2);
        let nz_transmitter = ((self.transmitter_length / bar_size).round() as usize).max(2);
        let nr_specimen = self.specimen_radial_elements;
        let specimen_size = specimen_radius / nr_specimen as f64;
        let mut nz_specimen = ((self.specimen_length / specimen_size).round() as usize).max(3);
        if nz_specimen.is_multiple_of(2) {
            nz_specimen += 1;
        }
        let block = |name: &str, material: usize, r: f64, z: (f64, f64), nr: usize, nz: usize| {
            QuadMesh::block(
                name,
                material,
                (0.0, r),
                z,
                nr,
                nz,
                Grading::UNIFORM,
                Grading::UNIFORM,
            )
        };
        let l_s = self.specimen_length;
        let mut mesh = block(
            "incident",
            0,
            bar_radius,
            (-self.incident_length, 0.0),
            nr_bar,
            nz_incident,
        );
        mesh.append(block(
            "specimen",
            1,
            specimen_radius,
            (0.0, l_s),
            nr_specimen,
            nz_specimen,
        ));
        mesh.append(block(
            "transmitter",
            0,
            bar_radius,
            (l_s, l_s + self.transmitter_length),
            nr_bar,
            nz_transmitter,
        ));
        let incident_size = self.incident_length / nz_incident as f64;
        let transmitter_size = self.transmitter_length / nz_transmitter as f64;
        // Outer-column element whose centre is nearest the gauge distance.
        let row = |distance: f64, size: f64, rows: usize| {
            ((distance / size - 0.5).round().max(0.0) as usize).min(rows - 1)
        };
        let incident_row = row(self.incident_gauge, incident_size, nz_incident);
        let transmitter_row = row(self.transmitter_gauge, transmitter_size, nz_transmitter);
        // Incident rows count from the loaded end: row j has its centre at
        // -L_i + (j + 1/2) h, i.e. at distance L_i - (j + 1/2) h from the specimen.
        let incident_j = nz_incident - 1 - incident_row;
        let incident_elements = nr_bar * nz_incident;
        let specimen_elements = nr_specimen * nz_specimen;
        let mid = nz_specimen / 2;
        let mid_row = (0..nr_specimen)
            .map(|i| {
                let (r0, r1) = (i as f64 * specimen_size, (i + 1) as f64 * specimen_size);
                (incident_elements + mid * nr_specimen + i, r1 * r1 - r0 * r0)
            })
            .collect();
        let layout = Layout {
            incident_gauge: incident_j * nr_bar + nr_bar - 1,
            transmitter_gauge: incident_elements
                + specimen_elements
                + transmitter_row * nr_bar
                + nr_bar
                - 1,
            gauge_distances: (
                (incident_row as f64 + 0.5) * incident_size,
                (transmitter_row as f64 + 0.5) * transmitter_size,
            ),
            mid_row,
        };
        (mesh, layout)
    }

    /// The finite-element model with `material` for the specimen.
    pub fn model(&self, material: &Material, settings: &SolverSettings) -> AxisymmetricModel {
        let (model, _) = self.model_and_layout(material, settings);
        model
    }

    fn model_and_layout(
        &self,
        material: &Material,
        settings: &SolverSettings,
    ) -> (AxisymmetricModel, Layout) {
        let (mesh, layout) = self.mesh();
        let set = |name: &str| mesh.node_set(name).unwrap_or(&[]).to_vec();
        let axis: Vec<usize> = ["incident", "specimen", "transmitter"]
            .iter()
            .flat_map(|part| set(&format!("{part}.axis")))
            .collect();
        // Master faces, counter-clockwise along each bar's boundary: the incident bar's top
        // face runs from the outer radius to the axis (normal +z), the transmitter's bottom
        // face from the axis outwards (normal -z).
        let incident_top = set("incident.top");
        let transmitter_bottom = set("transmitter.bottom");
        let incident_face = incident_top.windows(2).map(|w| [w[1], w[0]]).collect();
        let transmitter_face = transmitter_bottom
            .windows(2)
            .map(|w| [w[0], w[1]])
            .collect();
        let contacts = vec![
            ContactPair::new(set("specimen.bottom"), incident_face)
                .with_friction(self.friction)
                .with_penalty_scale(INTERFACE_PENALTY_SCALE),
            ContactPair::new(set("specimen.top"), transmitter_face)
                .with_friction(self.friction)
                .with_penalty_scale(INTERFACE_PENALTY_SCALE),
        ];
        let (_, window_end) = self.window();
        let c0 = self.bar_wave_speed();
        let end_time =
            window_end + layout.gauge_distances.0.max(layout.gauge_distances.1) / c0 + 1.0e-6;
        let incident_bottom = set("incident.bottom");
        let mut tracked = vec![layout.incident_gauge, layout.transmitter_gauge];
        tracked.extend(layout.mid_row.iter().map(|(e, _)| *e));
        let model = AxisymmetricModel {
            mesh,
            materials: vec![self.bar_material(), *material],
            initial_temperature: self.temperature,
            initial_velocity: Vec::new(),
            constraints: vec![
                VelocityConstraint {
                    nodes: axis,
                    dof: 0,
                    velocity: Amplitude::constant(0.0),
                },
                VelocityConstraint {
                    nodes: incident_bottom,
                    dof: 1,
                    velocity: self.loading(),
                },
            ],
            walls: Vec::new(),
            contacts,
            eroding_contact: None,
            rigid_parts: Vec::new(),
            pressure_loads: Vec::new(),
            body_acceleration: None,
            trusses: Vec::new(),
            node_contacts: Vec::new(),
            settings: SolverSettings {
                end_time,
                damping: None,
                output_interval: SAMPLING,
                rest_fraction: 0.0,
                ..settings.clone()
            },
            tracked_elements: tracked,
        };
        (model, layout)
    }

    /// Run the bar with `material` as the specimen and analyse the gauges.
    pub fn run(
        &self,
        material: &Material,
        settings: &SolverSettings,
    ) -> Result<(ShpbResult, AxisymmetricRun, AxisymmetricModel), SolverError> {
        let (model, layout) = self.model_and_layout(material, settings);
        let run = model.run(&mut |_, _| {})?;
        let young = self.bar_young_modulus;
        let gauge = |history: &StateHistory| -> Vec<(f64, f64)> {
            history
                .samples
                .iter()
                .map(|s| (s.time, -s.axial_stress / young))
                .collect()
        };
        let incident_gauge = gauge(&run.tracked[0]);
        let transmitter_gauge = gauge(&run.tracked[1]);
        let total_area: f64 = layout.mid_row.iter().map(|(_, a)| a).sum();
        let specimen_stress = (0..run.tracked[2].samples.len())
            .map(|k| {
                let stress = layout
                    .mid_row
                    .iter()
                    .enumerate()
                    .map(|(slot, (_, area))| {
                        let sample = &run.tracked[2 + slot].samples[k];
                        -sample.axial_stress * area * libm::exp(sample.plastic_strain)
                    })
                    .sum::<f64>()
                    / total_area;
                (run.tracked[2].samples[k].time, stress)
            })
            .collect();
        let bar = self.kolsky_bar();
        let waves = bar.separate(
            &incident_gauge,
            &transmitter_gauge,
            layout.gauge_distances,
            self.arrival_time(),
            self.window(),
        );
        let result = ShpbResult {
            one_wave: bar.analyse(&waves, Analysis::OneWave),
            two_wave: bar.analyse(&waves, Analysis::TwoWave),
            three_wave: bar.analyse(&waves, Analysis::ThreeWave),
            incident_gauge,
            transmitter_gauge,
            gauge_distances: layout.gauge_distances,
            waves,
            specimen_stress,
        };
        Ok((result, run, model))
    }
}
