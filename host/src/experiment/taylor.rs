//! Taylor rod-on-anvil: a rod hits a rigid anvil; the final shape is measured (final length,
//! footprint diameter, diameter at given positions from the impact face).

use crate::mesh::{Grading, QuadMesh};
use crate::solver::{
    Amplitude, AxisymmetricModel, AxisymmetricRun, NodalDamping, RigidWall, SolverError,
    SolverSettings, VelocityConstraint,
};
use stoss_kernel::Material;

/// Geometry, loading and discretisation of a Taylor test.
#[derive(Clone, Debug, PartialEq)]
pub struct TaylorSetup {
    /// Initial rod length `L0` (m).
    pub length: f64,
    /// Initial rod diameter `D0` (m).
    pub diameter: f64,
    /// Impact velocity (m/s).
    pub velocity: f64,
    /// Initial temperature (K).
    pub temperature: f64,
    /// Elements across the radius.
    pub radial_elements: usize,
    /// Elements along the rod.
    pub axial_elements: usize,
    /// Coulomb friction between rod and anvil.
    pub anvil_friction: f64,
    /// Time at which nodal damping starts (s); the plastic event is over well before.
    pub damping_start: f64,
    /// End time (s).
    pub end_time: f64,
}

impl TaylorSetup {
    /// Default discretisation for a rod: square-ish elements, `radial` across the radius.
    pub fn new(length: f64, diameter: f64, velocity: f64, radial: usize) -> Self {
        let radius = 0.5 * diameter;
        let axial = ((length / (radius / radial as f64)).round() as usize).max(4);
        // Plastic event ~ 3-4 plastic-wave transits; elastic transit L/c ~ L/5000.
        let transit = length / 5000.0;
        Self {
            length,
            diameter,
            velocity,
            temperature: 298.0,
            radial_elements: radial,
            axial_elements: axial,
            anvil_friction: 0.0,
            damping_start: (4.0 * length / velocity.max(1.0) * 0.3).max(30.0 * transit),
            end_time: (4.0 * length / velocity.max(1.0) * 0.3).max(30.0 * transit) + 40.0 * transit,
        }
    }

    /// The finite-element model with `material` for the rod.
    pub fn model(&self, material: Material, settings: &SolverSettings) -> AxisymmetricModel {
        let radius = 0.5 * self.diameter;
        let mesh = QuadMesh::block(
            "rod",
            0,
            (0.0, radius),
            (0.0, self.length),
            self.radial_elements,
            self.axial_elements,
            Grading::UNIFORM,
            Grading::UNIFORM,
        );
        let axis = mesh.node_set("rod.axis").unwrap_or(&[]).to_vec();
        let initial_velocity = vec![[0.0, -self.velocity]; mesh.nodes.len()];
        let transit = self.length / 5000.0;
        let tracked = (0..mesh.elements.len()).collect();
        AxisymmetricModel {
            mesh,
            materials: vec![material],
            initial_temperature: self.temperature,
            initial_velocity,
            constraints: vec![VelocityConstraint {
                nodes: axis,
                dof: 0,
                velocity: Amplitude::constant(0.0),
            }],
            walls: vec![RigidWall {
                point: vec![0.0, 0.0],
                normal: vec![0.0, 1.0],
                friction: self.anvil_friction,
                nodes: Vec::new(),
            }],
            settings: SolverSettings {
                end_time: self.end_time,
                damping: Some(NodalDamping {
                    start_time: self.damping_start,
                    coefficient: 2.0 / transit,
                }),
                output_interval: self.end_time / 200.0,
                ..settings.clone()
            },
            tracked_elements: tracked,
        }
    }

    /// Run and measure.
    pub fn run(
        &self,
        material: Material,
        settings: &SolverSettings,
    ) -> Result<(TaylorResult, AxisymmetricRun), SolverError> {
        let model = self.model(material, settings);
        let run = model.run(&mut |_, _| {})?;
        Ok((TaylorResult::measure(&model.mesh, &run), run))
    }
}

/// Measured final shape.
#[derive(Clone, Debug, PartialEq)]
pub struct TaylorResult {
    /// Final length `Lf` (m).
    pub final_length: f64,
    /// Footprint (mushroom) diameter `Df` at the impact face (m).
    pub footprint_diameter: f64,
    /// Outer profile `(z, radius)` from the impact face, sorted by `z`.
    pub profile: Vec<(f64, f64)>,
}

impl TaylorResult {
    /// Measure the final shape from the outer-surface nodes.
    pub fn measure(mesh: &QuadMesh, run: &AxisymmetricRun) -> Self {
        let outer = mesh.node_set("rod.outer").unwrap_or(&[]);
        let mut profile: Vec<(f64, f64)> = outer
            .iter()
            .map(|&n| (run.positions[n][1], run.positions[n][0]))
            .collect();
        profile.sort_by(|a, b| a.0.total_cmp(&b.0));
        let final_length = run
            .positions
            .iter()
            .map(|p| p[1])
            .fold(f64::NEG_INFINITY, f64::max)
            - run
                .positions
                .iter()
                .map(|p| p[1])
                .fold(f64::INFINITY, f64::min);
        let footprint = run.positions.iter().map(|p| p[0]).fold(0.0, f64::max);
        Self {
            final_length,
            footprint_diameter: 2.0 * footprint,
            profile,
        }
    }

    /// Diameter of the outer profile at distance `z` from the impact face (linear
    /// interpolation between surface nodes).
    pub fn diameter_at(&self, z: f64) -> f64 {
        let p = &self.profile;
        for pair in p.windows(2) {
            if pair[0].0 <= z && z <= pair[1].0 {
                let f = if pair[1].0 > pair[0].0 {
                    (z - pair[0].0) / (pair[1].0 - pair[0].0)
                } else {
                    0.0
                };
                return 2.0 * (pair[0].1 + f * (pair[1].1 - pair[0].1));
            }
        }
        f64::NAN
    }
}
